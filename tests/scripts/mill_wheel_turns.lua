-- scripts/scenes/mill_wheel.lua as it ships: the flume's water falls on the paddles right
-- of the axle, so the wheel turns clockwise seen from the camera (angular velocity along
-- -z), about its hinge only: the hinge holds its centre up at the axle against its weight and
-- the water's push, and lets it turn about z alone. (mill_wheel_still_without_water.lua is the
-- same scene with the flume off: the wheel stays still, so the water is what turns it.)
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
local turned, last, worst_off = 0, 0, 0

function on_step(dt, t)
    scene_step(dt, t)
    -- The wheel's turn about z, from its rotation (unwrapped step by step).
    local q = wheel:rotation()
    local a = 2 * math.atan(q.z, q.w)
    local d = (a - last + math.pi) % (2 * math.pi) - math.pi
    turned, last = turned + d, a
    local p = wheel:position()
    worst_off = math.max(worst_off, math.sqrt((p.x - 0.55) ^ 2 + (p.y - 0.42) ^ 2 + (p.z - 0.3) ^ 2))
    if seiche.frame() == 50 then
        local w = wheel:angular_velocity()
        print(string.format("mill_wheel_turns: w.z = %.3f rad/s after %.2f s, turned %.2f rad; centre at most %.4f mm off the axle; w.x %.3g, w.y %.3g",
                            w.z, t, turned, 1000 * worst_off, w.x, w.y))
        seiche.check(w.z < -1.0 and w.z > -30.0,
                     string.format("the wheel should turn clockwise (w.z in [-30, -1] rad/s), w.z = %.3f", w.z))
        seiche.check(turned < -0.5, string.format("the wheel should have turned clockwise: %.3f rad", turned))
        seiche.check(math.abs(w.x) < 0.01 * math.abs(w.z) and math.abs(w.y) < 0.01 * math.abs(w.z),
                     string.format("the hinge lets it turn about z only: w = (%.2g, %.2g, %.3f)", w.x, w.y, w.z))
        seiche.check(worst_off < 0.003, string.format("the hinge holds the centre at (0.55, 0.42, 0.3): %.4f m off", worst_off))
    end
end
