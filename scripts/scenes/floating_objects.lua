-- Floating objects: one body of every shape the Bullet wrapper offers, dropped into a
-- tank of water. Lighter than water (rho < 1000 kg/m^3) floats with the fraction
-- rho / 1000 below the surface; heavier sinks. The bodies are two-way coupled: the water
-- lifts them and they push it aside.
--
--   build/bin/seiche scripts/scenes/floating_objects.lua
--   build/bin/seiche --headless --frames 240 --screenshot floating.png scripts/scenes/floating_objects.lua
--
-- Keys: r drops everything again (reset), space pauses.

seiche.scene {
    name = "floating_objects",
    fluid = {
        particle_radius = 0.015,    -- m: 3 cm between particles
        kernel_radius = 0.06,       -- m: twice the spacing
        iterations = 2,
        substeps = 4,
    },
    capacity = 16000,
    container = { min = { 0, 0, 0 }, max = { 1.2, 0.9, 0.8 } },
    camera = { eye = { 0.6, 1.05, 1.95 }, target = { 0.6, 0.25, 0.4 }, fov = 50 },
    look = { sky = { 0.58, 0.72, 0.88 }, water = { low = { 0.02, 0.16, 0.45 }, mid = { 0.08, 0.45, 0.75 } } },
}

-- 1.2 m x 0.33 m x 0.8 m of water: 40 x 11 x 26 = 11440 particles.
seiche.block { min = { 0, 0, 0 }, max = { 1.2, 0.33, 0.8 } }

local y = 0.45 -- drop height, m: 12 cm above the water
seiche.body { shape = "box", size = { 0.16, 0.08, 0.12 }, position = { 0.18, y, 0.22 }, density = 500,
              color = { 0.78, 0.56, 0.30 } }                                        -- pine plank
seiche.body { shape = "sphere", radius = 0.06, position = { 0.45, y, 0.55 }, density = 250,
              color = { 0.92, 0.86, 0.40 } }                                        -- cork ball
seiche.body { shape = "capsule", radius = 0.04, height = 0.22, position = { 0.75, y, 0.25 }, density = 700,
              rotation = { axis = { 0, 0, 1 }, angle = math.pi / 2 }, color = { 0.36, 0.62, 0.34 } }
seiche.body { shape = "cylinder", radius = 0.06, height = 0.1, position = { 1.0, y, 0.55 }, density = 400,
              color = { 0.80, 0.30, 0.28 } }                                        -- buoy
seiche.body { shape = "hull", density = 600, position = { 0.6, y, 0.4 }, color = { 0.55, 0.45, 0.72 },
              points = { { -0.05, -0.035, -0.04 }, { 0.05, -0.035, -0.04 }, { -0.05, -0.035, 0.04 },
                         { 0.05, -0.035, 0.04 }, { -0.08, 0.035, -0.06 }, { 0.08, 0.035, -0.06 },
                         { -0.08, 0.035, 0.06 }, { 0.08, 0.035, 0.06 } } }            -- punt (a tapered hull)
seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, position = { 1.0, y + 0.05, 0.2 }, density = 2500,
              color = { 0.45, 0.45, 0.48 } }                                        -- stone: sinks

function on_step(dt, t)
    seiche.check(seiche.stats().nan == 0, "no particle may become NaN")
end
