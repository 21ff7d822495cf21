-- A block of water dropped into a pre-filled container (the seed report's second
-- scenario): tests incompressibility at impact and how the two bodies of water merge.
-- Particles are coloured by their initial height: the dropped block stands out.

seiche.scene {
    name = "prefilled_drop",
    fluid = {
        particle_radius = 0.0125,
        kernel_radius = 0.05,
        iterations = 2,             -- per substep ("small steps", docs/solver.md)
        substeps = 4,
    },
    capacity = 40000,
    container = { min = { 0, 0, 0 }, max = { 1.0, 1.2, 0.6 }, closed_top = false },
    camera = { eye = { 0.5, 1.2, 2.2 }, target = { 0.5, 0.35, 0.3 }, fov = 50 },
}

-- A pool 0.25 m deep, and a 0.3 m cube held 0.45 m above it.
seiche.block { min = { 0, 0, 0 }, max = { 1.0, 0.25, 0.6 } }
seiche.block { min = { 0.35, 0.7, 0.15 }, max = { 0.65, 1.0, 0.45 } }

function on_step(dt, t)
    seiche.check(seiche.stats().nan == 0, "no particle may become NaN")
end
