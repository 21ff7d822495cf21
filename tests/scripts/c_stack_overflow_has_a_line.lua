-- A C stack overflow (metamethods calling themselves) reports a file:line first.
-- expect-exit: 2
-- expect-stderr: c_stack_overflow_has_a_line.lua:6: 
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local t = setmetatable({}, { __index = function(t, k) return t[k] end })
local x = t.x
