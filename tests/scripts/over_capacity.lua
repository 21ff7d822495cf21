-- A block larger than the particle capacity is rejected at the line that asked for it.
-- expect-exit: 2
-- expect-stderr: over_capacity.lua:11: seiche.block:
-- expect-stderr: capacity 100
-- frames: 2
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08 },
    capacity = 100,
    container = { min = { 0, 0, 0 }, max = { 1, 1, 1 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } }   -- 1000 particles
