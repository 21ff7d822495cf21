-- Callbacks are looked up raw and under protection: an __index on _G that raises is never
-- run by the lookup (before, the runner aborted with a Lua panic). A strict-globals
-- metatable like this one works.
-- frames: 3
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local steps = 0
function on_step(dt, t)
    steps = steps + 1
    if steps == 3 then print("index_on_globals_errors: 3 steps") end
end
setmetatable(_G, { __index = function(_, name) error("undeclared global " .. tostring(name), 2) end })
