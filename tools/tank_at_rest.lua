-- Usage: build/bin/seiche --headless --frames 300 tools/tank_at_rest.lua [--set fluid.particle_radius=R]
-- (docs/validation.md, "Volume and walls", "Rest").
-- A tank 0.4 x 0.4 m filled 0.4 m deep, left alone. At the end it prints the level (the
-- median of the column tops over the tank, seiche.surface_height "level") against the
-- depth the particles fill (N s^3 / area), the particle count of the strip one spacing wide
-- along each side wall against the same strip's share of the bulk, and the rms speed.
local L, D = 0.4, 0.4
seiche.scene { capacity = 200000, container = { min = { 0, 0, 0 }, max = { L, 0.6, L } } }
seiche.block { min = { 0, 0, 0 }, max = { L, D, L } }
function on_step(dt, t)
    local f = seiche.frame()
    if f % 60 ~= 0 then return end
    local s = 2 * seiche.param("particle_radius")
    local d = seiche.particle_data { fields = { "position", "velocity" }, flat = true }
    local n, v2 = d.count, 0
    for i = 1, 3 * n do v2 = v2 + d.velocity[i] ^ 2 end
    local filled = n * s ^ 3 / (L * L)
    local level = seiche.surface_height(L / 2, L / 2, L / 2 - s, "level")
    -- Strips one spacing wide along x = 0 and x = L, below 0.8 of the depth, against the
    -- bulk's count per spacing of width in the middle half.
    local lo = seiche.particles_in({ 0, 0, s }, { s, 0.8 * filled, L - s })
    local hi = seiche.particles_in({ L - s, 0, s }, { L, 0.8 * filled, L - s })
    local mid = seiche.particles_in({ L / 4, 0, s }, { 3 * L / 4, 0.8 * filled, L - s }) * s / (L / 2)
    print(string.format("t %.1f s: level %.4f m vs N s^3/area %.4f m (%+.2f %% of depth), wall strips %+.1f %% %+.1f %%, rms %.1f mm/s",
                        t, level, filled, 100 * (level - filled) / filled, 100 * (lo / mid - 1), 100 * (hi / mid - 1),
                        1000 * math.sqrt(v2 / n)))
end
