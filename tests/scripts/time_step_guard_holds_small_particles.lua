-- The time-step guard: the scene of diverged_solver_exits_4.lua (5 mm particles, one
-- substep asked for in a 1/60 s frame, a 0.15 m column collapsing) with the guard on at
-- its default (cfl 0.5: half a spacing per substep) takes more substeps as the water
-- speeds up and stays bounded: no NaN, nothing lost, the density within 25 % of rho0 once
-- the guard has seen the speeds (the first steps, before it has, are not judged).
-- frames: 20
seiche.scene {
    name = "guarded",
    fluid = { particle_radius = 0.0025, substeps = 1 },
    capacity = 20000,
    container = { min = { 0, 0, 0 }, max = { 0.3, 0.3, 0.3 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.1, 0.15, 0.1 } }
local most = 0
function on_step(dt, t)
    local s = seiche.stats()
    if s.step < 0 then return end
    most = math.max(most, s.substeps)
    seiche.check(s.nan == 0 and s.outside == 0, "no NaN, nothing outside")
    if s.step >= 4 then
        seiche.check(s.rho_max < 1.25 * s.rho0, string.format("step %d: rho_max %.0f at %d substeps", s.step, s.rho_max, s.substeps))
    end
    if seiche.frame() == 20 then
        seiche.check(most > 1, "the guard took more than the 1 substep asked for (most " .. most .. ")")
        print("most substeps:", most)
    end
end
