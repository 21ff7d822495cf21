-- The memory limit (512 MiB) stops a script with its file:line, and pcall cannot swallow
-- that either.
-- expect-exit: 2
-- expect-stderr: used more than the script's 512 MiB of memory
-- expect-stderr: memory_limit_holds_through_pcall.lua:
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local keep = {}
while true do
    pcall(function()
        for i = 1, 1e6 do keep[#keep + 1] = string.rep("x", 1 << 20) .. i end
    end)
end
