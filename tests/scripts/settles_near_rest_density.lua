-- Water poured in a tank settles: after 3 s the mean density is within 1 % of rho0 and
-- the densest particle within 5 % (boundaries contribute density, so the layer at the
-- walls is not compressed to make up for missing neighbours).
-- frames: 200
seiche.scene {
    name = "settle",
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 4, substeps = 2 },
    capacity = 4000,
    container = { min = { 0, 0, 0 }, max = { 0.4, 0.6, 0.4 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.4, 0.32, 0.4 } }  -- 10 x 8 x 10

function on_step(dt, t)
    if t >= 3.0 then
        local s = seiche.stats()
        local avg = s.rho_avg / s.rho0
        seiche.check(math.abs(avg - 1) < 0.01, string.format("mean density %.4f rho0, expected within 1%%", avg))
        seiche.check(s.rho_max < 1.05 * s.rho0, string.format("max density %.4f rho0", s.rho_max / s.rho0))
        seiche.quit()
    end
end
