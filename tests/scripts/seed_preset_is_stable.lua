-- The seed preset (the 2025 reproduction's parameters: 1 substep, 3 iterations, s_corr,
-- rho0 = 125) runs a small dam break without blowing up: no NaN, nothing outside the
-- domain, and the density after the impact within the reproduction's own spread.
-- frames: 120
seiche.scene {
    preset = "seed",
    capacity = 4000,
    container = { min = { 0, 0, 0 }, max = { 0.8, 0.6, 0.3 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.3, 0.45, 0.3 } }

function on_step(dt, t)
    local s = seiche.stats()
    seiche.check(s.rho0 == 125, "the seed preset's rest density is 125, got " .. s.rho0)
    seiche.check(seiche.param("iterations") == 3 and seiche.param("substeps") == 1, "3 iterations, 1 substep")
    seiche.check(s.nan == 0 and s.outside == 0, "NaN or lost particles")
    if t > 1.5 then
        seiche.check(s.rho_max < 1.6 * s.rho0, string.format("rho_max %.1f over 1.6 rho0", s.rho_max))
    end
end
