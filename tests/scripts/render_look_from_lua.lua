-- seiche.render{...} changes the renderer's look of the water from a script: the fields it
-- names change, the others stay, and the renderer has the new look on the next frame
-- (seiche.render() reads it back). --render picks the starting mode.
-- frames: 3
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 1, substeps = 1 },
    capacity = 1000,
    container = { min = { 0, 0, 0 }, max = { 0.5, 0.5, 0.5 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } }

local before = seiche.render()
seiche.check(before.mode == "surface", "the default look is the surface (got " .. tostring(before.mode) .. ")")
seiche.check(before.splat == "compute", "the default splat is compute (got " .. tostring(before.splat) .. ")")
local asked = seiche.render { mode = "speed", speed_max = 3, absorption = { 1, 0.5, 0.25 }, splat = "raster" }
seiche.check(asked.mode == "speed" and asked.speed_max == 3, "the call returns the look it asked for")
seiche.check(asked.smoothing == before.smoothing, "fields not named stay as they were")

function on_step(dt, t)
    local now = seiche.render()
    if seiche.frame() == 2 then
        seiche.check(now.mode == "speed", "the renderer took the mode (got " .. now.mode .. ")")
        seiche.check(now.absorption.y == 0.5, "the renderer took the absorption")
        seiche.check(now.splat == "raster", "the renderer took the splat (got " .. tostring(now.splat) .. ")")
        seiche.check(now.view == "shaded" and now.shadows == true, "the rest is the default")
        seiche.render { mode = "density", density_range = { 0.95, 1.05 }, splat = "compute" }
    elseif seiche.frame() == 3 then
        seiche.check(now.mode == "density" and math.abs(now.density_range[2] - 1.05) < 1e-6 and now.splat == "compute",
                     "a second call applies")
    end
end
