-- An error inside a coroutine that coroutine.wrap passes on names its file:line.
-- expect-exit: 2
-- expect-stderr: coroutine_error_has_a_line.lua:6: (error object is a nil value, not a string)
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
coroutine.wrap(function() error() end)()
