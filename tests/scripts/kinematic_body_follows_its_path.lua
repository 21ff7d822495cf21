-- A kinematic body driven by move_to is where it was told to be after every step (it
-- moves with the velocity that gets it there, which the water and bodies feel), stops
-- when no new target comes, and pushes the water: a paddle sweeping through a pool
-- raises the surface in front of it.
-- frames: 90
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 2, substeps = 2 },
    capacity = 3000,
    container = { min = { 0, 0, 0 }, max = { 1.0, 0.5, 0.3 } },
}
seiche.block { min = { 0.1, 0, 0 }, max = { 1.0, 0.12, 0.3 } }
local paddle = seiche.body { shape = "box", kind = "kinematic", size = { 0.04, 0.3, 0.28 }, position = { 0.06, 0.15, 0.15 } }
local target
local calm

function on_step(dt, t)
    local f = seiche.frame()
    if target then
        local p = paddle:position()
        seiche.check(math.abs(p.x - target) < 1e-4, string.format("frame %d: paddle at x = %.5f, target %.5f", f, p.x, target))
    end
    if f == 10 then calm = seiche.surface_height(0.4, 0.15, 0.08) end
    if f >= 10 and f < 40 then
        target = 0.06 + 0.2 * (f - 9) / 30 -- 0.4 m/s towards +x
        paddle:move_to({ target, 0.15, 0.15 })
        local v = paddle:velocity()
        if f > 10 then seiche.check(math.abs(v.x - 0.4) < 1e-3, "paddle velocity " .. v.x) end
    elseif f == 40 then
        target = nil -- no new target: it stops
        local h = seiche.surface_height(0.4, 0.15, 0.08)
        seiche.check(h > calm + 0.01, string.format("the surface ahead of the paddle rose from %.3f to %.3f only", calm, h))
    elseif f == 42 then
        local v = paddle:velocity()
        seiche.check(v.x == 0, "the paddle kept moving: " .. v.x)
        local ok, err = pcall(paddle.apply_force, paddle, { 1, 0, 0 })
        seiche.check(not ok and err:find("kinematic", 1, true), tostring(err))
        seiche.quit()
    end
end
