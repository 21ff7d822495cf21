-- A __gc finaliser runs with Lua's hooks off, where no time budget stops it (an endless
-- loop in one hangs the runner at exit): the sandbox's setmetatable refuses it.
-- expect-exit: 2
-- expect-stderr: sandbox_finaliser_refused.lua:7: setmetatable: a metatable with __gc (a finaliser) is not allowed
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
setmetatable({}, { __gc = function() while true do end end })
