-- An endless loop in a callback is stopped by the time budget: exit status 2.
-- expect-exit: 2
-- expect-stderr: on_step ran longer than its budget
-- frames: 10
-- budget: 0.5
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }

function on_step(dt, t)
    while true do end
end
