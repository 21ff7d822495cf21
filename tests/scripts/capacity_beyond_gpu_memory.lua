-- A capacity whose particle buffers cannot fit in GPU memory (2^26 particles with 512
-- neighbours each: over 100 GiB) is refused before anything is allocated: exit status 2,
-- at the line of seiche.scene.
-- expect-exit: 2
-- expect-stderr: capacity_beyond_gpu_memory.lua:8: seiche.scene:
-- expect-stderr: 67108864
-- frames: 2
seiche.scene {
    fluid = { particle_radius = 0.01, kernel_radius = 0.095 },
    capacity = 67108864,
    container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } },
}
