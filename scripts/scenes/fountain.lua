-- Fountain: a jet from a nozzle on a column in a basin, and an overflow drain (a sink)
-- in one wall that holds the water level: once the pool reaches the drain, what the
-- nozzle pours the drain takes away.
--
--   build/bin/seiche scripts/scenes/fountain.lua
--   build/bin/seiche --headless --frames 300 --screenshot fountain.png scripts/scenes/fountain.lua
--
-- Keys: e turns the jet on and off; up / down change its speed (and height);
--       left / right change the rate (at most what the nozzle can pour at that speed).

seiche.scene {
    name = "fountain",
    fluid = {
        particle_radius = 0.0125,   -- m: 2.5 cm between particles
        kernel_radius = 0.05,
        iterations = 2,
        substeps = 4,
    },
    capacity = 24000,
    container = { min = { 0, 0, 0 }, max = { 1.0, 0.8, 1.0 } },
    camera = { eye = { 0.5, 1.0, 2.1 }, target = { 0.5, 0.3, 0.5 }, fov = 50 },
    look = { water = { low = { 0.05, 0.25, 0.55 }, high = { 0.9, 0.97, 1.0 } } },
}

-- A pool 10 cm deep: 40 x 4 x 40 = 6400 particles.
seiche.block { min = { 0, 0, 0 }, max = { 1.0, 0.1, 1.0 } }

-- The overflow: a slot in the +x wall from 14 cm up. Water that reaches it leaves.
local drain = seiche.sink { min = { 0.94, 0.14, 0.3 }, max = { 1.0, 0.24, 0.7 } }

-- A stone column in the middle of the pool (static bodies push the water, never move)...
seiche.body { shape = "cylinder", kind = "static", radius = 0.07, height = 0.16, position = { 0.5, 0.08, 0.5 },
              color = { 0.62, 0.60, 0.56 } }

-- ...with the nozzle on top: 6 cm across, straight up.
local jet = { position = { 0.5, 0.17, 0.5 }, direction = { 0, 1, 0 }, speed = 3.0, radius = 0.03, rate = 400 }
local nozzle = seiche.emitter(jet)

local function clamp_rate()
    local most = seiche.max_emitter_rate(jet.speed, jet.radius)
    if jet.rate > most then jet.rate = most end
end

function on_key(key, action)
    if action == "release" then return end
    if key == "e" and action == "press" then
        jet.enabled = not nozzle:get().enabled
        nozzle:set_enabled(jet.enabled)
        return
    elseif key == "up" then
        jet.speed = math.min(jet.speed + 0.25, 6.0)
    elseif key == "down" then
        jet.speed = math.max(jet.speed - 0.25, 0.5)
    elseif key == "right" then
        jet.rate = jet.rate + 50
    elseif key == "left" then
        jet.rate = math.max(jet.rate - 50, 0)
    else
        return
    end
    clamp_rate()
    nozzle:set { speed = jet.speed, rate = jet.rate }
    print(string.format("fountain: speed %.2f m/s, rate %.0f particles/s", jet.speed, jet.rate))
end

function on_step(dt, t)
    seiche.check(seiche.stats().nan == 0, "no particle may become NaN")
end
