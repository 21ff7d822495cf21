-- A boat from a mesh file (assets/boat.obj, its convex hull) of 300 kg/m^3 set on a pool floats:
-- after it settles the water carries its weight (the fluid force averaged over half a second is
-- m g within 10 %), it bobs no faster than 5 cm/s, its keel is in the water and its deck above.
-- frames: 150
seiche.scene {
    fluid = { particle_radius = 0.015, kernel_radius = 0.06, iterations = 2, substeps = 4 },
    capacity = 4000,
    container = { min = { 0, 0, 0 }, max = { 1.0, 0.5, 0.5 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 1.0, 0.15, 0.5 } }
local boat = seiche.body { mesh = "assets/boat.obj", position = { 0.5, 0.14, 0.25 }, density = 300, hull_points = 64 }
local lift, frames = 0, 0

function on_step(dt, t)
    local f = seiche.frame()
    if f > 120 then
        lift = lift + boat:fluid_force().y
        frames = frames + 1
    end
    if f == 150 then
        local m, v, p = boat:mass(), boat:velocity(), boat:position()
        local surface = seiche.surface_height(0.1, 0.1, 0.05)
        print(string.format("boat: %.3f kg, centre of mass at y %.4f, water at %.4f, lift %.2f N for a weight of %.2f N, v.y %.4f",
                            m, p.y, surface, lift / frames, m * 9.81, v.y))
        seiche.check(math.abs(lift / frames - m * 9.81) < 0.1 * m * 9.81, "the water carries the boat's weight")
        seiche.check(math.abs(v.y) < 0.05, "it floats still")
        local q = boat:rotation()
        seiche.check(math.abs(q.x) < 0.1 and math.abs(q.z) < 0.1, "upright")
        -- The hull reaches about 0.1 m from the keel: with its centre of mass a little under half
        -- way, the keel is below the surface and the deck above.
        seiche.check(p.y < surface + 0.04 and p.y > surface - 0.06, "afloat, neither sunk nor lifted out")
    end
end
