-- A module name cannot climb out of the scene's folder with '..'.
-- expect-exit: 2
-- expect-stderr: sandbox_require_escape_refused.lua:6: require: bad module name '..scripts.scenes.dam_break'
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
require("..scripts.scenes.dam_break")
