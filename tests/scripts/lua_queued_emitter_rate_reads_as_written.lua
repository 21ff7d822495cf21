-- An emitter rate the main chunk gives is checked against the nozzle when the world is built:
-- the number reads as the script wrote it, in the same format as the check at the call
-- ("got 1000000000", not "got 1e+09").
-- expect-exit: 2
-- expect-stderr: lua_queued_emitter_rate_reads_as_written.lua:13: seiche.emitter: field 'rate' must be a number in [0,
-- expect-stderr: particles/s (got 1000000000); 
-- frames: 2
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08 },
    capacity = 2000,
    container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } },
}
seiche.emitter { position = { 0.2, 0.3, 0.2 }, rate = 1e9 }
