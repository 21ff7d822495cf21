-- Usage: build/bin/seiche --headless --frames 241 tools/layer_profile.lua [--set fluid.particle_radius=R]
-- (docs/validation.md, "Volume and walls").
-- A tank 0.4 x 0.4 m filled 0.2 m deep, left 4 s. Then, away from the walls (two spacings
-- in), the particles are binned by height in slices a quarter spacing thick; for each
-- slice the script prints the number density times s^3 (1 for the initial lattice), the
-- mean SPH density, and the water above the slice's bottom as a depth (count x s^3 / area),
-- then the level (surface_height "level" and "mean") against N s^3 / area. Where the level
-- falls short, this shows which layers hold the missing volume.
local L, D = 0.4, 0.2
seiche.scene { capacity = 200000, container = { min = { 0, 0, 0 }, max = { L, 0.6, L } } }
seiche.block { min = { 0, 0, 0 }, max = { L, D, L } }
function on_step(dt, t)
    if seiche.frame() ~= 240 then return end
    local s = 2 * seiche.param("particle_radius")
    local d = seiche.particle_data { fields = { "position", "density" }, flat = true }
    local count, rho, top = {}, {}, 0
    local bw = s / 4
    for i = 0, d.count - 1 do
        local x, y, z = d.position[3 * i + 1], d.position[3 * i + 2], d.position[3 * i + 3]
        if x > 2 * s and x < L - 2 * s and z > 2 * s and z < L - 2 * s then
            local b = math.floor(y / bw)
            count[b] = (count[b] or 0) + 1
            rho[b] = (rho[b] or 0) + d.density[i + 1]
            if b > top then top = b end
        end
    end
    local area = (L - 4 * s) ^ 2
    local above = 0
    print("slice (m)            n s^3   rho (kg/m^3)   water above (m)")
    for b = top, 0, -1 do
        local c = count[b] or 0
        above = above + c
        print(string.format("%.4f-%.4f   %6.3f   %8.1f   %.4f", b * bw, (b + 1) * bw, c * s ^ 3 / (area * bw),
                            c > 0 and rho[b] / c or 0, above * s ^ 3 / area))
    end
    print(string.format("level %.4f m, mean %.4f m, N s^3 / area %.4f m", seiche.surface_height(L / 2, L / 2, L / 2 - s, "level"),
                        seiche.surface_height(L / 2, L / 2, L / 2 - s, "mean"), d.count * s ^ 3 / L ^ 2))
end
