-- scripts/scenes/sandbox.lua as it ships, driven by injected input: key 1 drops a box, key 6
-- a boat (a body from scripts/scenes/assets/boat.obj: its convex hull), pressing the left button on a body grabs it and dragging the pointer up lifts it out
-- of the water, releasing lets it go, key x removes every body.
-- frames: 32
-- trusted: runs the shipped scripts/scenes/sandbox.lua as it is (dofile), then adds checks
local here = debug.getinfo(1, "S").source:match("^@(.*)/[^/]*$") or "."
dofile(here .. "/../../scripts/scenes/sandbox.lua")

local scene_step = on_step
local target, start_y, x, y

function on_step(dt, t)
    scene_step(dt, t)
    local f = seiche.frame()
    if f == 2 then
        seiche.check(#seiche.bodies() == 3, "the sandbox starts with 3 bodies, has " .. #seiche.bodies())
        seiche.inject_key("1", "press")
    elseif f == 4 then
        seiche.check(#seiche.bodies() == 4, "key 1 should drop a box: " .. #seiche.bodies() .. " bodies")
        seiche.inject_key("6", "press")
    elseif f == 6 then
        local bodies = seiche.bodies()
        seiche.check(#bodies == 5 and bodies[5]:shape() == "hull", "key 6 should drop a boat: " .. tostring(bodies[5]))
    elseif f == 8 then
        target = seiche.bodies()[1]
        start_y = target:position().y
        x, y = seiche.screen_point(target:position())
        seiche.inject_mouse(1, "press", x, y)
    elseif f == 9 then
        seiche.inject_motion(x, y - 60) -- drag upwards by 60 pixels
    elseif f == 28 then
        local lifted = target:position().y - start_y
        seiche.check(lifted > 0.05, string.format("a dragged body should rise; it moved %.3f m", lifted))
        seiche.inject_mouse(1, "release", x, y - 60)
        seiche.inject_key("x", "press")
    elseif f == 30 then
        seiche.check(#seiche.bodies() == 0, "key x should remove every body: " .. #seiche.bodies() .. " left")
        seiche.check(not target:is_valid(), "a removed body is not valid")
    end
end
