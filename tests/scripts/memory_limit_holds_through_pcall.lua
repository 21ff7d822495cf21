-- The memory limit (512 MiB) stops a script with its file:line, and pcall cannot swallow
-- that either.
-- expect-exit: 2
-- expect-stderr: used more than the script's 512 MiB of memory
-- expect-stderr: memory_limit_holds_through_pcall.lua:
-- The time budget is far beyond what reaching the limit takes, so the memory limit is what
-- stops it even under AddressSanitizer on a loaded machine.
-- frames: 1
-- budget: 120
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local keep = {}
while true do
    pcall(function()
        for i = 1, 1e6 do keep[#keep + 1] = string.rep("x", 1 << 20) .. i end
    end)
end
