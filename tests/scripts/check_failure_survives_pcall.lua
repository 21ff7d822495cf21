-- A failed seiche.check ends the run with status 1 even inside pcall: it is a stop, not an
-- ordinary error (before, the flag stayed set and the run exited 0, or later with the
-- wrong status).
-- expect-exit: 1
-- expect-stderr: check_failure_survives_pcall.lua:10: check failed: x
-- frames: 5
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }

function on_step(dt, t)
    local ok = pcall(seiche.check, false, "x")
    print("not reached", ok)
end
