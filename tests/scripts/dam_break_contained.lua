-- A small dam break over 4 simulated seconds keeps every particle in the container:
-- none lost, none outside, none NaN, and the density stays bounded after the impact.
-- frames: 240
seiche.scene {
    name = "dam_break_contained",
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 3, substeps = 2 },
    capacity = 4000,
    container = { min = { 0, 0, 0 }, max = { 0.8, 0.6, 0.32 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.32, 0.48, 0.32 } }   -- 8 x 12 x 8 = 768

local initial
function on_start()
    initial = seiche.particle_count()
    seiche.check(initial == 768, "the block holds 8 x 12 x 8 particles, got " .. initial)
end

function on_step(dt, t)
    local s = seiche.stats()
    seiche.check(seiche.particle_count() == initial, "particle count changed")
    seiche.check(s.nan == 0, "NaN particles: " .. s.nan)
    seiche.check(s.outside == 0, "particles outside the domain: " .. s.outside)
    if t > 2.0 then
        -- After the first impact the solver holds density within 25 % of rho0 at worst.
        seiche.check(s.rho_max < 1.25 * s.rho0, string.format("rho_max %.1f exceeds 1.25 rho0", s.rho_max))
    end
end
