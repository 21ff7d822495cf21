-- The water's force on bodies the water does not move (measure_force, kinematic): a
-- static wall holding back a pool 0.2 m wide feels the hydrostatic force 1/2 rho g H^2 W,
-- with H the depth the particles fill (N s^3 / area: 0.14 m, 19.2 N); a kinematic paddle
-- standing in the water feels its buoyancy rho g V_submerged (the water it displaces
-- raises the level: 2.01 N measured for 1.77 N) and little sideways; a static body made
-- without measure_force refuses fluid_force with a message.
-- frames: 150
seiche.scene {
    fluid = { particle_radius = 0.01, kernel_radius = 0.04, iterations = 3, substeps = 2 },
    capacity = 12000,
    container = { min = { 0, 0, 0 }, max = { 0.5, 0.4, 0.2 } },
}
local H, W = 0.15, 0.2
seiche.block { min = { 0, 0, 0 }, max = { 0.2, H, W } }
local wall = seiche.body { shape = "box", size = { 0.04, 0.4, 0.2 }, position = { 0.22, 0.2, 0.1 }, kind = "static",
                           measure_force = true }
local floor_slab = seiche.body { shape = "box", size = { 0.1, 0.02, 0.2 }, position = { 0.4, 0.01, 0.1 }, kind = "static" }
local paddle = seiche.body { shape = "box", size = { 0.02, 0.1, 0.1 }, position = { 0.1, 0.1, 0.1 }, kind = "kinematic" }

local sum, n = { x = 0, y = 0, z = 0 }, 0
local psum, pup = 0, 0
function on_step(dt, t)
    local f = wall:fluid_force()
    local p = paddle:fluid_force()
    if t > 1.5 then
        sum.x, sum.y, sum.z, n = sum.x + f.x, sum.y + f.y, sum.z + f.z, n + 1
        psum, pup = psum + p.x, pup + p.y
    end
    if seiche.frame() == 150 then
        local s = 2 * seiche.param("particle_radius")
        local depth = seiche.stats().particles * s ^ 3 / (0.2 * W)
        local expected = 0.5 * 1000 * 9.81 * depth * depth * W
        local fx = sum.x / n
        seiche.check(math.abs(fx - expected) < 0.1 * expected,
                     string.format("wall: %.2f N sideways, 1/2 rho g H^2 W = %.2f N", fx, expected))
        seiche.check(math.abs(sum.z / n) < 0.05 * expected, string.format("wall: %.2f N along z", sum.z / n))
        local lift = 1000 * 9.81 * 0.02 * 0.1 * (depth - 0.05) -- the paddle's bottom is at y = 0.05
        seiche.check(math.abs(pup / n - lift) < 0.2 * lift,
                     string.format("paddle: %.3f N up, rho g V_submerged = %.3f N", pup / n, lift))
        seiche.check(math.abs(psum / n) < 0.1 * lift, string.format("paddle: %.3f N sideways", psum / n))
        local t1 = select(2, wall:fluid_force())
        local t2 = wall:fluid_torque()
        seiche.check(t1.x == t2.x and t1.y == t2.y and t1.z == t2.z, "fluid_torque is fluid_force's second result")
        local ok, err = pcall(floor_slab.fluid_force, floor_slab)
        seiche.check(not ok and err:find("measure_force = true", 1, true), "unmeasured static body: " .. tostring(err))
        print(string.format("wall %.2f N (expected %.2f N), paddle %.3f N up (expected %.3f N), %.3f N sideways", fx,
                            expected, pup / n, lift, psum / n))
    end
end
