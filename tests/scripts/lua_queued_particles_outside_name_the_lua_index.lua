-- Particles the main chunk queues are checked against the domain when they are applied (the
-- domain is known once the world is built): the error still names the script's line, the Lua
-- call and the point by its 1-based index, not "pbf_world_add_particles: positions[1]".
-- expect-exit: 2
-- expect-stderr: lua_queued_particles_outside_name_the_lua_index.lua:13: seiche.particles: field 'positions'[2].x must be in [0, 0.4] m, inside the domain (got 9)
-- frames: 2
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08 },
    capacity = 2000,
    container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.2, 0.1, 0.2 } }
seiche.particles { positions = { { 0.1, 0.1, 0.1 }, { 9, 9, 9 } } }
