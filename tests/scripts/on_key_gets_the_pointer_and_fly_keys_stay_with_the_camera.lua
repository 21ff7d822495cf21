-- on_key gets where the pointer is; in fly mode the camera's keys (W A S D Q E, Shift)
-- move the camera and do not reach the script, other keys still do.
-- frames: 6
seiche.scene { capacity = 10, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } },
               camera = { eye = { 0, 1, 2 }, target = { 0, 0, 0 } } }

local keys = {}
function on_key(key, action, x, y)
    if action == "press" then keys[#keys + 1] = string.format("%s %g %g", key, x, y) end
end

function on_start() seiche.inject_motion(30, 40) end

function on_step()
    local f = seiche.frame()
    if f == 1 then
        seiche.inject_key("k", "press")
    elseif f == 2 then
        seiche.check(keys[1] == "k 30 40", "on_key(k) should see the pointer at 30, 40: " .. tostring(keys[1]))
        seiche.set_camera { mode = "fly" }
    elseif f == 3 then
        seiche.inject_key("w", "press")
        seiche.inject_key("j", "press")
    elseif f == 4 then
        seiche.check(#keys == 2 and keys[2]:sub(1, 1) == "j",
                     "in fly mode w belongs to the camera, j to the script: " .. table.concat(keys, "; "))
    end
end
