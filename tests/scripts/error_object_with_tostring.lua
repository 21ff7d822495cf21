-- An error object with a __tostring metamethod is shown through it, after the file:line it
-- was raised at.
-- expect-exit: 2
-- expect-stderr: error_object_with_tostring.lua:9: disk on fire (code 7)
-- frames: 3
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local Failure = { __tostring = function(e) return e.what .. " (code " .. e.code .. ")" end }
function on_step(dt, t)
    error(setmetatable({ what = "disk on fire", code = 7 }, Failure))
end
