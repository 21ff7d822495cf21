-- Mill wheel: an overshot water wheel. A flume pours water onto the paddles on its right;
-- the water's weight and push turn the wheel clockwise (seen from the camera) on its fixed
-- axle, and the water falls on into a basin whose overflow drain keeps the level.
--
-- The wheel is one rigid body of a non-convex shape: a compound of a hub and eight paddles
-- (seiche.body{shape = "compound", parts = ...}), on a hinge joint along z through its centre
-- (seiche.joint{kind = "hinge"}): the axle's bearing, which holds the wheel up and lets it turn
-- about z only. The load of the millstones is the hinge's motor used as a brake (speed 0, at
-- most 0.05 N m) and the wheel's angular damping.
--
--   build/bin/seiche scripts/scenes/mill_wheel.lua
--   build/bin/seiche --headless --frames 240 --screenshot mill_wheel.png scripts/scenes/mill_wheel.lua
--
-- Keys: e turns the flume on and off; up / down change the flow.

seiche.scene {
    name = "mill_wheel",
    fluid = {
        particle_radius = 0.015,    -- m: 3 cm between particles
        kernel_radius = 0.06,
        iterations = 2,
        substeps = 4,
    },
    capacity = 16000,
    container = { min = { 0, 0, 0 }, max = { 1.2, 1.0, 0.6 } },
    camera = { eye = { 0.6, 0.65, 1.85 }, target = { 0.6, 0.4, 0.3 }, fov = 50 },
    look = { water = { low = { 0.04, 0.20, 0.45 }, mid = { 0.10, 0.45, 0.72 } } },
}

-- The basin: 12 cm of water, 40 x 4 x 20 = 3200 particles.
seiche.block { min = { 0, 0, 0 }, max = { 1.2, 0.12, 0.6 } }
-- The overflow: a slot in the -x wall from 15 cm up holds the level.
seiche.sink { min = { 0.0, 0.15, 0.0 }, max = { 0.06, 0.3, 0.6 } }

-- The wheel: a hub (a cylinder turned onto z) and eight paddles radiating from it, 44 cm
-- across, 30 cm wide, of oak (700 kg/m^3).
local AXLE = { 0.55, 0.42, 0.3 }
local PADDLES = 8
local parts = { { shape = "cylinder", radius = 0.05, height = 0.34, rotation = { axis = { 1, 0, 0 }, angle = math.pi / 2 } } }
for k = 0, PADDLES - 1 do
    local a = k * 2 * math.pi / PADDLES
    parts[#parts + 1] = { shape = "box", size = { 0.17, 0.025, 0.3 },
                          position = { 0.135 * math.cos(a), 0.135 * math.sin(a), 0 },
                          rotation = { axis = { 0, 0, 1 }, angle = a } }
end
local wheel = seiche.body { shape = "compound", parts = parts, position = AXLE, density = 700,
                            angular_damping = 0.3, color = { 0.62, 0.42, 0.24 } }
seiche.joint { kind = "hinge", a = wheel, pivot = AXLE, axis = { 0, 0, 1 },
                            motor = { speed = 0, max_torque = 0.05 } }

-- The flume: a static trough from the right wall to above the paddles' right side, and the
-- water leaving its end (an emitter 8 cm across, aimed down and a little back to the left).
seiche.body { shape = "box", kind = "static", size = { 0.5, 0.02, 0.16 }, position = { 0.95, 0.8, 0.3 },
              rotation = { axis = { 0, 0, 1 }, angle = -0.12 }, color = { 0.50, 0.40, 0.30 } }
for _, z in ipairs({ 0.21, 0.39 }) do
    seiche.body { shape = "box", kind = "static", size = { 0.5, 0.08, 0.02 }, position = { 0.95, 0.84, z },
                  rotation = { axis = { 0, 0, 1 }, angle = -0.12 }, color = { 0.50, 0.40, 0.30 } }
end
-- Its rate, 80 % of what the nozzle can pour, is set once the world exists (on_start).
local flow = { position = { 0.70, 0.77, 0.3 }, direction = { -0.35, -1, 0 }, speed = 1.5, radius = 0.04, rate = 0 }
local flume = seiche.emitter(flow)

function on_start()
    flow.rate = 0.8 * seiche.max_emitter_rate(flow.speed, flow.radius)
    flume:set { rate = flow.rate }
end

function on_key(key, action)
    if action == "release" then return end
    if key == "e" and action == "press" then
        flume:set_enabled(not flume:get().enabled)
        return
    elseif key == "up" then
        flow.speed = math.min(flow.speed + 0.25, 4.0)
    elseif key == "down" then
        flow.speed = math.max(flow.speed - 0.25, 0.5)
    else
        return
    end
    flow.rate = 0.8 * seiche.max_emitter_rate(flow.speed, flow.radius)
    flume:set { speed = flow.speed, rate = flow.rate }
    print(string.format("mill_wheel: flow %.2f m/s, %.0f particles/s", flow.speed, flow.rate))
end

function on_step(dt, t)
    seiche.check(seiche.stats().nan == 0, "no particle may become NaN")
end
