-- scripts/scenes/mill_wheel.lua with its flume turned off from the start (key e, injected
-- before the first step): no water falls on the paddles, and the wheel stays still on its
-- hinge, which holds it up at the axle. With mill_wheel_turns.lua: the water turns the wheel.
-- frames: 50
-- trusted: runs the shipped scripts/scenes/mill_wheel.lua as it is (dofile), then adds checks
local here = debug.getinfo(1, "S").source:match("^@(.*)/[^/]*$") or "."
dofile(here .. "/../../scripts/scenes/mill_wheel.lua")
seiche.inject_key("e", "press") -- the scene's key: the flume off

local scene_step = on_step
local wheel
for _, b in ipairs(seiche.bodies()) do
    if b:shape() == "compound" then wheel = b end
end

function on_step(dt, t)
    scene_step(dt, t)
    if seiche.frame() == 50 then
        local w, p, q = wheel:angular_velocity(), wheel:position(), wheel:rotation()
        local turned = 2 * math.atan(q.z, q.w)
        print(string.format("mill wheel without water: w.z = %.4f rad/s, turned %.4f rad, centre (%.4f, %.4f, %.4f)",
                            w.z, turned, p.x, p.y, p.z))
        seiche.check(math.abs(w.z) < 0.05 and math.abs(turned) < 0.02, "without water the wheel stays still")
        seiche.check(math.abs(p.y - 0.42) < 0.003 and math.abs(p.x - 0.55) < 0.003, "the hinge holds it up at its axle")
    end
end
