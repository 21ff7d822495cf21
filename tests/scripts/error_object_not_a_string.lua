-- An error whose object is not a string still names the file and line first.
-- expect-exit: 2
-- expect-stderr: error_object_not_a_string.lua:8: (error object is a table value, not a string)
-- frames: 3
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }

function on_step(dt, t)
    error({ code = 7 })
end
