-- Wave tank: a kinematic paddle at one end of a long tank pushes the water back and forth
-- (x = x0 + A sin(2 pi f t)); the waves run down the tank and lift the floating blocks.
-- A wave gauge near the far end reports the surface height every two seconds.
--
--   build/bin/seiche scripts/scenes/wave_tank.lua
--   build/bin/seiche --headless --frames 300 --screenshot waves.png scripts/scenes/wave_tank.lua
--
-- Keys: up / down change the stroke A, left / right the frequency f.

seiche.scene {
    name = "wave_tank",
    fluid = {
        particle_radius = 0.015,    -- m: 3 cm between particles
        kernel_radius = 0.06,
        iterations = 2,
        substeps = 4,
    },
    capacity = 16000,
    container = { min = { 0, 0, 0 }, max = { 2.4, 0.7, 0.42 } },
    camera = { eye = { 1.2, 1.15, 2.3 }, target = { 1.2, 0.12, 0.2 }, fov = 50 },
    look = { water = { low = { 0.02, 0.20, 0.50 }, mid = { 0.10, 0.55, 0.80 }, high = { 0.85, 0.95, 1.0 } } },
}

-- Water 24 cm deep behind the paddle's rest position: 76 x 8 x 14 = 8512 particles.
seiche.block { min = { 0.12, 0, 0 }, max = { 2.4, 0.24, 0.42 } }

-- The paddle: a kinematic board across the tank, moved by script every step.
local paddle_x, stroke, frequency = 0.06, 0.05, 0.7 -- m, m, Hz
local paddle = seiche.body { shape = "box", kind = "kinematic", size = { 0.04, 0.5, 0.41 },
                             position = { paddle_x, 0.25, 0.21 }, color = { 0.85, 0.85, 0.80 } }

-- Floating blocks along the tank.
for i, x in ipairs({ 0.9, 1.4, 1.9 }) do
    seiche.body { shape = "box", size = { 0.12, 0.06, 0.12 }, position = { x, 0.3, 0.21 }, density = 450,
                  color = { 0.85 - 0.15 * i, 0.45, 0.20 + 0.15 * i } }
end

-- Each step the paddle is told where to be at the end of the next one.
local function drive(t, dt)
    paddle:move_to({ paddle_x + stroke * math.sin(2 * math.pi * frequency * (t + dt)), 0.25, 0.21 })
end

function on_start()
    drive(0, seiche.dt())
end

function on_step(dt, t)
    drive(t, dt)
    seiche.check(seiche.stats().nan == 0, "no particle may become NaN")
end

-- A gauge: the surface height 2 m from the paddle, every 2 s (a particle download: slow).
seiche.every(2.0, function(t)
    local h = seiche.surface_height(2.1, 0.21)
    print(string.format("wave_tank: t = %4.1f s, surface at x = 2.1 m: %s", t, h and string.format("%.3f m", h) or "dry"))
end)

function on_key(key, action)
    if action == "release" then return end
    if key == "up" then stroke = math.min(stroke + 0.01, 0.1)
    elseif key == "down" then stroke = math.max(stroke - 0.01, 0)
    elseif key == "right" then frequency = math.min(frequency + 0.1, 2.0)
    elseif key == "left" then frequency = math.max(frequency - 0.1, 0.1)
    else return end
    print(string.format("wave_tank: stroke %.2f m, frequency %.1f Hz", stroke, frequency))
end
