-- A splat seiche.render does not know is refused naming the field, the value and the two
-- it knows, at the caller's line: exit status 2.
-- expect-exit: 2
-- expect-stderr: render_bad_splat.lua:11:
-- expect-stderr: seiche.render: field 'splat' must be one of "raster", "compute" (got "vulkan")
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08 },
    capacity = 100,
    container = { min = { 0, 0, 0 }, max = { 0.5, 0.5, 0.5 } },
}
seiche.render { splat = "vulkan" }
