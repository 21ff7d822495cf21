-- require loads Lua modules from the scene's own folder (dotted names: lib.waves is
-- lib/waves.lua), once: a second require returns the same value.
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local helpers = require("lib.helpers")
seiche.check(helpers.double(21) == 42, "the module's function works")
seiche.check(require("lib.helpers") == helpers, "a module loads once")
seiche.check(not pcall(require, "lib.missing"), "a missing module is an error")
