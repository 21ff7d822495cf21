-- Dam break (Macklin & Mueller 2013, and the seed report's first scenario): a block of
-- water released at one end of an empty container. Particles are coloured by their
-- initial height, so the mixing is visible.
--
--   build/bin/seiche scripts/scenes/dam_break.lua
--   build/bin/seiche --headless --frames 240 --metrics dam.csv scripts/scenes/dam_break.lua

seiche.scene {
    name = "dam_break",
    fluid = {
        particle_radius = 0.0125,   -- m: 2.5 cm between particles
        kernel_radius = 0.05,       -- m: twice the spacing
        iterations = 2,             -- per substep ("small steps", docs/solver.md)
        substeps = 4,
    },
    gravity = { 0, -9.81, 0 },
    capacity = 40000,
    container = { min = { 0, 0, 0 }, max = { 1.6, 1.0, 0.6 }, closed_top = false },
    camera = { eye = { 0.8, 1.1, 2.4 }, target = { 0.8, 0.3, 0.3 }, fov = 50 },
}

-- 0.5 m x 0.6 m x 0.6 m of water against the left wall: 20 x 24 x 24 = 11520 particles.
seiche.block { min = { 0, 0, 0 }, max = { 0.5, 0.6, 0.6 } }

function on_step(dt, t)
    -- Stop a headless run early if the solver has failed.
    local s = seiche.stats()
    seiche.check(s.nan == 0, "no particle may become NaN")
end
