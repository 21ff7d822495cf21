-- A bad fluid parameter names the field, the value and the allowed range: exit status 2.
-- expect-exit: 2
-- expect-stderr: bad_fluid_parameter.lua:5:
-- expect-stderr: seiche.scene: fluid: field 'particle_radius' must be in (0.0005, 1] m (got -0.01)
seiche.scene {
    fluid = { particle_radius = -0.01 },
    container = { min = { 0, 0, 0 }, max = { 1, 1, 1 } },
}
