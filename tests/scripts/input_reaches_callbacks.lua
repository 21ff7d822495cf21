-- Injected input goes the way real input does: in the next frame on_key, on_mouse and
-- on_mouse_move get the key names, buttons, actions and pixel positions; key_down,
-- mouse_down and mouse_position see the state; a press that on_mouse returns true for
-- is the script's, so dragging does not turn the camera, while an unclaimed drag does.
-- frames: 12
seiche.scene { capacity = 10, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } },
               camera = { eye = { 0, 1, 2 }, target = { 0, 0, 0 } } }

local log = {}
local claim = true

function on_key(key, action) log[#log + 1] = "key " .. key .. " " .. action end
function on_mouse(button, action, x, y)
    log[#log + 1] = string.format("mouse %d %s %g %g", button, action, x, y)
    return claim
end
function on_mouse_move(x, y, dx, dy) log[#log + 1] = string.format("move %g %g %g %g", x, y, dx, dy) end
function on_scroll(dx, dy) log[#log + 1] = string.format("scroll %g %g", dx, dy) end

local function eye() local e = seiche.camera().eye; return e.x, e.y, e.z end
local ex, ey, ez

function on_start()
    seiche.inject_key("a", "press")
    seiche.inject_mouse(1, "press", 100, 50) -- moves the pointer there first
    seiche.inject_motion(110, 70)
    seiche.inject_scroll(0, -1)
end

function on_step(dt, t)
    local f = seiche.frame()
    if f == 1 then
        local want = { "key a press", "move 100 50 0 0", "mouse 1 press 100 50", "move 110 70 10 20", "scroll 0 -1" }
        seiche.check(#log == #want, "got " .. #log .. " events: " .. table.concat(log, "; "))
        for i, w in ipairs(want) do seiche.check(log[i] == w, "event " .. i .. ": want '" .. w .. "', got '" .. tostring(log[i]) .. "'") end
        seiche.check(seiche.key_down("a") and not seiche.key_down("b"), "key_down")
        seiche.check(seiche.mouse_down(1) and not seiche.mouse_down(2), "mouse_down")
        local x, y = seiche.mouse_position()
        seiche.check(x == 110 and y == 70, "mouse_position " .. x .. ", " .. y)
        ex, ey, ez = eye()
        seiche.inject_motion(200, 120) -- a drag of the claimed press: the camera stays
        seiche.inject_key("a", "release")
    elseif f == 2 then
        local x, y, z = eye()
        seiche.check(x == ex and y == ey and z == ez, "a claimed drag moved the camera")
        seiche.check(not seiche.key_down("a"), "released key still down")
        seiche.inject_mouse(1, "release", 200, 120)
        claim = false
    elseif f == 3 then
        seiche.inject_mouse(1, "press", 200, 120) -- unclaimed: the camera orbits
    elseif f == 4 then
        seiche.inject_motion(300, 120)
    elseif f == 6 then
        local x, y, z = eye()
        seiche.check(x ~= ex or z ~= ez, "an unclaimed drag left the camera where it was")
        seiche.quit()
    end
end
