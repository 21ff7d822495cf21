-- An __index on _G with an endless loop never runs for a callback lookup (they are raw);
-- when the script itself reads a missing global, the budget stops the loop (in __index).
-- expect-exit: 2
-- expect-stderr: index_on_globals_loops.lua:13: on_step ran longer than its budget of 0.3 s
-- frames: 5
-- budget: 0.3
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local steps = 0
function on_step(dt, t)
    steps = steps + 1
    if steps == 3 then local x = undefined_name end
end
setmetatable(_G, { __index = function() while true do end end })
