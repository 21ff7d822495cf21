-- Meshes from files (assets/ beside this script): seiche.body{mesh = ...} is the mesh's convex
-- hull when dynamic (its mass density x the hull's volume, its position the hull's centre of
-- mass, placed by where the script put the mesh's origin) and its triangles when static (a
-- static cup, hollow, holds a ball dropped into it on its inner bottom); seiche.fill{mesh = ...}
-- fills a closed mesh's inside with water on the particle lattice: a 0.2 m cube holds exactly
-- the particles of seiche.block over the same box, the cup's solid walls about their volume.
-- frames: 90
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 2, substeps = 4 },
    capacity = 4000,
    container = { min = { 0, 0, 0 }, max = { 1.6, 0.8, 0.6 } },
}
-- A crate from cube.obj (0.2 m, centred), standing on its base: the mesh's origin is put at
-- (0.3, 0.05, 0.3), its centre 0.1 m above.
local crate = seiche.body { mesh = "assets/cube.obj", centre = "base", position = { 0.3, 0.05, 0.3 }, density = 400,
                            hull_points = 8 }
seiche.check(crate:shape() == "hull" and crate:kind() == "dynamic", tostring(crate))
-- A cup (outer radius 0.1, 0.12 high, walls and bottom 0.03) standing on the floor, and a ball
-- dropped into it.
local cup = seiche.body { mesh = "assets/cup.obj", kind = "static", position = { 0.8, 0, 0.3 } }
seiche.check(cup:shape() == "mesh" and cup:kind() == "static", tostring(cup))
local ball = seiche.body { shape = "sphere", radius = 0.03, position = { 0.8, 0.4, 0.3 }, density = 1000 }
-- Water: a cube of it (0.2 m at 4 cm spacing: 5 x 5 x 5 = 125) and a block of the same box.
seiche.fill { mesh = "assets/cube.obj", position = { 1.3, 0.35, 0.3 } }
local filled_cube

function on_step(dt, t)
    local f = seiche.frame()
    if f == 1 then
        filled_cube = seiche.particle_count()
        seiche.check(filled_cube == 125, "the 0.2 m cube holds 5^3 = 125 particles: " .. filled_cube)
        local m = crate:mass()
        print(string.format("crate: mass %.4f kg (400 x 0.008 = 3.2), centre (%.4f, %.4f, %.4f)", m, crate:position().x,
                            crate:position().y, crate:position().z))
        seiche.check(math.abs(m - 3.2) < 0.01 * 3.2, "density x the hull's volume")
        local p = crate:position()
        seiche.check(math.abs(p.x - 0.3) < 1e-3 and math.abs(p.y - 0.15) < 0.01 and math.abs(p.z - 0.3) < 1e-3,
                     "the body sits at the hull's centre of mass, 0.1 m above the base it was placed by")
        -- The cup's solid (walls and bottom) filled: about its volume over the spacing cubed.
        seiche.fill { mesh = "assets/cup.obj", position = { 1.0, 0.55, 0.3 } }
    elseif f == 2 then
        local n = seiche.particle_count() - filled_cube
        local solid = math.pi * (0.1 ^ 2 - 0.07 ^ 2) * 0.09 + math.pi * 0.1 ^ 2 * 0.03 -- walls above the bottom, bottom
        print(string.format("cup filled with %d particles; solid volume / spacing^3 = %.1f", n, solid / 0.04 ^ 3))
        seiche.check(n > 0.6 * solid / 0.04 ^ 3 and n < 1.4 * solid / 0.04 ^ 3, "about the solid's volume")
    elseif f == 90 then
        local b = ball:position()
        print(string.format("ball in the cup at (%.4f, %.4f, %.4f): on the inner bottom at y = 0.03 + r = 0.06", b.x, b.y, b.z))
        seiche.check(math.abs(b.y - 0.06) < 0.01 and math.abs(b.x - 0.8) < 0.07 and math.abs(b.z - 0.3) < 0.07,
                     "the static cup's triangles hold the ball inside, on its bottom")
        seiche.check(math.abs(crate:position().y - 0.1) < 0.01, "the crate rests on the floor")
    end
end
