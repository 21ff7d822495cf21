-- A trusted script may have finalisers. One that calls a body's method at exit runs while
-- the Lua state closes, before the engine frees what handles point to, and the API
-- refuses it ("the scene is closing"): no crash, exit 0. The finaliser's error reaches
-- stderr as a warning (Lua cannot raise it).
-- trusted: __gc is only allowed with --trusted
-- frames: 3
-- expect-stderr: finaliser_calls_a_body_at_exit.lua: error in __gc (
-- expect-stderr: the scene is closing: a finaliser cannot use the seiche API or its handles
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } } }
local crate = seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, position = { 0.2, 0.2, 0.2 }, density = 500 }
setmetatable({}, { __gc = function() crate:set_velocity({ 0, 1, 0 }); print(crate:position().y) end })
keep = setmetatable({}, { __gc = function() print(seiche.particle_count(), crate:mass()) end })
