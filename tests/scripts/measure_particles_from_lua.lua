-- The measurement API agrees with itself and with physics: particle_data returns every
-- particle (as records and as flat arrays), region_stats of the whole world matches the
-- GPU's per-step statistics (kinetic energy, momentum, centre of mass), a block thrown
-- sideways in zero gravity keeps its momentum m v, and a box selects only what is inside.
-- frames: 12
seiche.scene {
    name = "measure",
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 2, substeps = 1 },
    capacity = 2000,
    gravity = { 0, 0, 0 },
    container = { min = { -1, -1, -1 }, max = { 1, 1, 1 } },
}
-- 5 x 5 x 5 particles moving at 0.5 m/s along x.
seiche.block { min = { -0.1, -0.1, -0.1 }, max = { 0.1, 0.1, 0.1 }, velocity = { 0.5, 0, 0 } }

local function close(a, b, tol, what)
    seiche.check(math.abs(a - b) <= tol, string.format("%s: %.6g vs %.6g (tolerance %.3g)", what, a, b, tol))
end

function on_step(dt, t)
    if seiche.frame() < 10 then return end
    local all = seiche.particle_data()
    local flat = seiche.particle_data { fields = { "position", "density" }, flat = true }
    local n = #all
    seiche.check(n == 125, "particle_data: " .. n .. " records, expected 125")
    seiche.check(flat.count == n and #flat.position == 3 * n and #flat.density == n and flat.velocity == nil,
                 "flat arrays hold 3n positions, n densities and no velocity")
    for i = 1, n do
        seiche.check(all[i].position[1] == flat.position[3 * i - 2], "record and flat position agree")
        seiche.check(all[i].density > 500 and all[i].density < 1500, "density " .. all[i].density .. " kg/m^3")
    end
    local whole = seiche.region_stats({ -1, -1, -1 }, { 1, 1, 1 })
    local mass = 125 * 1000 * 0.04 ^ 3
    close(whole.mass, mass, 1e-6 * mass, "mass")
    -- No gravity, no walls reached: the momentum stays m v.
    close(whole.momentum[1], mass * 0.5, 0.02 * mass * 0.5, "momentum x")
    close(whole.velocity[1], 0.5, 0.01, "mean velocity x")
    close(whole.kinetic_energy, 0.5 * mass * 0.25, 0.05 * 0.5 * mass * 0.25, "kinetic energy")
    -- The GPU statistics of the latest measured step (a step or two behind, same motion).
    local s = seiche.stats()
    close(s.mass, mass, 1e-6 * mass, "stats mass")
    close(s.momentum[1], whole.momentum[1], 0.02 * mass * 0.5, "stats momentum x")
    close(s.kinetic_energy, whole.kinetic_energy, 0.05 * whole.kinetic_energy, "stats kinetic energy")
    close(s.center_of_mass[2], whole.center_of_mass[2], 1e-3, "stats centre of mass y")
    seiche.check(s.speed_max >= 0.5 and s.speed_max < 1.0, "speed_max " .. s.speed_max)
    -- Half the block along x.
    local cx = whole.center_of_mass[1] + 0.01 -- between lattice columns (5 of them)
    local half = seiche.region_stats({ cx, -1, -1 }, { 1, 1, 1 })
    seiche.check(half.particles >= 40 and half.particles <= 60, "half the block: " .. half.particles)
    local boxed = seiche.particle_data { min = { cx, -1, -1 }, max = { 1, 1, 1 }, fields = { "position" } }
    seiche.check(#boxed == half.particles, "particle_data in a box agrees with region_stats")
    for _, p in ipairs(boxed) do seiche.check(p.position[1] >= cx and p.velocity == nil, "inside the box") end
    seiche.quit()
end
