-- An emitter with a negative rate, made in a callback: exit status 2, file:line, a
-- traceback through the callback, and the allowed range for that nozzle and speed.
-- expect-exit: 2
-- expect-stderr: emitter_negative_rate.lua:10: seiche.emitter: field 'rate' must be a number in [0, 520] particles/s (got -5)
-- expect-stderr: in function 'on_step'
-- frames: 5
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } } }
function on_step(dt, t)
    if seiche.frame() == 3 then
        seiche.emitter { position = { 0.2, 0.3, 0.2 }, speed = 1, radius = 0.05, rate = -5 }
    end
end
