-- A solver pushed past its stable step (one substep of 1/60 s at 5 mm spacing) must not
-- pass silently: the headless run stops with status 4 and says what diverged. The
-- time-step guard is off here (cfl = 0): with it, this scene takes more substeps and
-- holds (tests/scripts/time_step_guard_holds_small_particles.lua).
-- expect-exit: 4
-- expect-stderr: the solver diverged at step
-- expect-stderr: rho0
-- frames: 30
seiche.scene {
    name = "diverges",
    fluid = { particle_radius = 0.0025, substeps = 1, cfl = 0 },
    capacity = 20000,
    container = { min = { 0, 0, 0 }, max = { 0.3, 0.3, 0.3 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.1, 0.15, 0.1 } }
