-- scripts/scenes/mill_wheel.lua as it ships: the flume's water falls on the paddles right
-- of the axle, so the wheel turns clockwise seen from the camera (angular velocity along
-- -z), about its axle only, its centre fixed.
-- frames: 50
-- trusted: runs the shipped scripts/scenes/mill_wheel.lua as it is (dofile), then adds checks
local here = debug.getinfo(1, "S").source:match("^@(.*)/[^/]*$") or "."
dofile(here .. "/../../scripts/scenes/mill_wheel.lua")

local scene_step = on_step
local wheel
for _, b in ipairs(seiche.bodies()) do
    if b:shape() == "compound" then wheel = b end
end
seiche.check(wheel ~= nil, "the scene should have a compound body, the wheel")

function on_step(dt, t)
    scene_step(dt, t)
    if seiche.frame() == 50 then
        local w, p = wheel:angular_velocity(), wheel:position()
        seiche.check(w.z < -1.0 and w.z > -30.0,
                     string.format("the wheel should turn clockwise (w.z in [-30, -1] rad/s), w.z = %.3f", w.z))
        seiche.check(math.abs(w.x) < 1e-4 and math.abs(w.y) < 1e-4,
                     string.format("the axle lets it turn about z only: w = (%.2g, %.2g, %.3f)", w.x, w.y, w.z))
        seiche.check(math.abs(p.x - 0.55) < 1e-4 and math.abs(p.y - 0.42) < 1e-4 and math.abs(p.z - 0.3) < 1e-4,
                     string.format("the axle holds the centre at (0.55, 0.42, 0.3): (%.4f, %.4f, %.4f)", p.x, p.y, p.z))
        print(string.format("mill_wheel_turns: w.z = %.3f rad/s after %.2f s", w.z, t))
    end
end
