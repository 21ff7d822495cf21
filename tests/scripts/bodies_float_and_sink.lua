-- Two-way coupling: a box of 400 kg/m^3 dropped into water floats with its bottom
-- about 0.4 x its height below the surface and the water holding its weight up; a ball
-- of 3000 kg/m^3 sinks to the floor. Every shape is accepted.
-- frames: 150
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 3, substeps = 2 },
    capacity = 4000,
    container = { min = { 0, 0, 0 }, max = { 0.6, 0.6, 0.48 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.6, 0.28, 0.48 } } -- 15 x 7 x 12
local light = seiche.body { shape = "box", size = { 0.16, 0.12, 0.16 }, position = { 0.18, 0.45, 0.24 }, density = 400 }
local heavy = seiche.body { shape = "sphere", radius = 0.05, position = { 0.45, 0.45, 0.24 }, density = 3000 }

function on_step(dt, t)
    if seiche.frame() == 150 then
        local m = light:mass()
        seiche.check(math.abs(m - 400 * 0.16 * 0.12 * 0.16) < 1e-3, "mass from density x volume: " .. m)
        local f = light:fluid_force()
        local weight = m * 9.81
        seiche.check(math.abs(f.y - weight) < 0.25 * weight, string.format("water holds %.2f N of a %.2f N box", f.y, weight))
        local surface = seiche.surface_height(0.45, 0.1, 0.06)
        local bottom = light:position().y - 0.06
        local draft = surface - bottom
        seiche.check(draft > 0.02 and draft < 0.09, string.format("draft %.3f m, about 0.4 x 0.12 = 0.048 m expected", draft))
        seiche.check(heavy:position().y < 0.07, "the heavy ball is at y = " .. heavy:position().y)
        seiche.check(seiche.stats().nan == 0, "NaN particles")
    end
end
