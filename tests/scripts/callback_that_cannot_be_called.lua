-- A callback global that is neither a function nor callable is an error that names it
-- (before, it was silently never called).
-- expect-exit: 2
-- expect-stderr: callback_that_cannot_be_called.lua: on_step must be a function or a table with a __call metamethod (got a number value)
-- frames: 3
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
on_step = 42
