-- 10,000 timers with a period of 1e-9 s would make 1.7e11 calls a frame: the frame stops
-- at 100000 timer calls with a message that names the limit (timers live in a heap, so
-- 10,000 ordinary timers cost little).
-- expect-exit: 2
-- expect-stderr: many_tiny_timers.lua:9: more than 100000 timer calls were due in one frame
-- frames: 3
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local calls = 0
local function tick(t) calls = calls + 1 end
for i = 1, 10000 do
    seiche.every(1e-9, tick)
end
