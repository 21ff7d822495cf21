-- The particles' mass and spacing come from particle_radius: changing it while the world
-- holds water is refused where it is applied, and the message points at the line that
-- asked for it (it used to be taken, leaving the water at an eighth of its density).
-- expect-exit: 2
-- expect-stderr: new_particle_radius_refused_with_water.lua:13: seiche.set_param:
-- expect-stderr: particle_radius 0.01 differs from the world's 0.02 while it holds 125 particles
-- frames: 5
seiche.scene { capacity = 2000, container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } }, fluid = { particle_radius = 0.02 } }
seiche.block { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } }
function on_step()
    seiche.set_param("iterations", 3) -- other parameters change with water as before
    if seiche.frame() == 2 then
        seiche.set_param("particle_radius", 0.01)
    end
end
