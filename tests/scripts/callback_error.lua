-- A runtime error inside a callback: file:line, a traceback, exit status 2.
-- expect-exit: 2
-- expect-stderr: callback_error.lua:11: attempt to perform arithmetic on a nil value
-- expect-stderr: stack traceback:
-- expect-stderr: in function 'on_step'
-- frames: 10
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }

function on_step(dt, t)
    local missing
    return missing + 1
end
