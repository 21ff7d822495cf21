-- A bad field of seiche.render names the field, the value and what is allowed, at the
-- caller's line: exit status 2.
-- expect-exit: 2
-- expect-stderr: render_bad_look.lua:11:
-- expect-stderr: seiche.render: field 'density_range'[2] must be greater than density_range[1] (got {1.1, 0.9})
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08 },
    capacity = 100,
    container = { min = { 0, 0, 0 }, max = { 0.5, 0.5, 0.5 } },
}
seiche.render { density_range = { 1.1, 0.9 } }
