-- A failed seiche.check ends a headless run with exit status 1 and the script's file:line.
-- expect-exit: 1
-- expect-stderr: check_fails.lua:9: check failed: two and two make five
-- frames: 5
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
seiche.block { min = { 0, 0, 0 }, max = { 0.1, 0.1, 0.1 } }

function on_step(dt, t)
    seiche.check(2 + 2 == 5, "two and two make five")
end
