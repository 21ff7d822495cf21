-- A runtime error inside a timer callback: file:line, a traceback, exit status 2.
-- expect-exit: 2
-- expect-stderr: timer_callback_error.lua:8: attempt to index a nil value (global 'missing')
-- expect-stderr: stack traceback:
-- frames: 30
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
seiche.after(0.1, function(t)
    return missing.field
end)
