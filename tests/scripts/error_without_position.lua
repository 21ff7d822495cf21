-- error(msg, 0) gives no position; the runner adds the line the error was raised at.
-- expect-exit: 2
-- expect-stderr: error_without_position.lua:7: boom
-- frames: 3
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local function fail() 
    error("boom", 0)
end
function on_step(dt, t) fail() end
