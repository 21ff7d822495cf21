-- Forces and impulses move dynamic bodies by Newton's law: without gravity or water an
-- impulse J on a 2 kg box gives it J / m at once, a force F applied every step for 0.5 s
-- adds F / m x 0.5 s, a torque T about an axis of inertia I spins it at T / I x t.
-- Static and kinematic bodies refuse forces with a message.
-- frames: 40
seiche.scene {
    gravity = { 0, 0, 0 },
    capacity = 10,
    container = { min = { -2, -2, -2 }, max = { 2, 2, 2 } },
}
local box = seiche.body { shape = "box", size = { 0.2, 0.2, 0.2 }, mass = 2, position = { 0, 0, 0 } }
local wall = seiche.body { shape = "box", kind = "static", size = { 0.1, 0.1, 0.1 }, position = { 1, 1, 1 } }

function on_start()
    seiche.check(box:mass() == 2, "mass " .. box:mass())
    seiche.check(wall:mass() == math.huge, "a static body's mass is infinite")
    box:apply_impulse({ 2, 0, 0 }) -- 1 m/s along x
    local ok, err = pcall(wall.apply_force, wall, { 1, 0, 0 })
    seiche.check(not ok and err:find("the body is static", 1, true), tostring(err))
end

function on_step(dt, t)
    local f = seiche.frame()
    if f == 1 then
        local v = box:velocity()
        seiche.check(math.abs(v.x - 1) < 1e-4 and math.abs(v.y) < 1e-6, string.format("after J = 2 N s: v = %g, %g", v.x, v.y))
    end
    if f >= 1 and f <= 30 then box:apply_force({ 0, 4, 0 }) end -- 30 steps of 1/60 s: 0.5 s
    if f == 31 then
        local v = box:velocity()
        seiche.check(math.abs(v.y - 1.0) < 1e-3, string.format("4 N on 2 kg for 0.5 s: vy = %.5f, want 1", v.y))
        seiche.check(math.abs(v.x - 1.0) < 1e-3, "vx changed: " .. v.x)
        -- I = m (a^2 + b^2) / 12 = 2 x 0.08 / 12 about any axis of a cube of side 0.2 m
        box:apply_angular_impulse({ 0, 0, 2 * 0.08 / 12 }) -- 1 rad/s about z
    end
    if f == 32 then
        local w = box:angular_velocity()
        seiche.check(math.abs(w.z - 1) < 1e-3, "angular impulse: wz = " .. w.z)
        local p = box:position()
        seiche.check(math.abs(p.x - 32 / 60) < 0.02, "x after 32 steps at 1 m/s: " .. p.x)
        seiche.quit()
    end
end
