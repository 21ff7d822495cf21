-- An overflow drain (a sink in the wall) holds the water level: with a jet pouring
-- 200 particles/s into the tank, the particle count stays put once the water reaches
-- the drain (from t = 2.5 s to t = 4.5 s the jet adds 400; the count moves by less than
-- 30) and the surface stays at the drain's height.
-- frames: 272
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 2, substeps = 2 },
    capacity = 4000,
    container = { min = { 0, 0, 0 }, max = { 0.6, 0.5, 0.4 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.6, 0.12, 0.4 } } -- 15 x 3 x 10 = 450
local jet = seiche.emitter { position = { 0.15, 0.4, 0.2 }, direction = { 0, -1, 0 }, speed = 1.0, rate = 200,
                             radius = 0.06 }
local drain = seiche.sink { min = { 0.54, 0.16, 0.0 }, max = { 0.6, 0.24, 0.4 } }
local n1

function on_start()
    seiche.check(drain:is_valid(), "the sink exists")
    local b = drain:get()
    seiche.check(math.abs(b.min.y - 0.16) < 1e-6 and math.abs(b.max[2] - 0.24) < 1e-6, "sink:get returns its box")
end

function on_step(dt, t)
    local f = seiche.frame()
    if f == 150 then n1 = seiche.stats().particles end
    if f == 270 then
        local n2 = seiche.stats().particles
        seiche.check(math.abs(n2 - n1) < 30, string.format("count went from %d to %d while the jet added 400", n1, n2))
        local h = seiche.surface_height(0.3, 0.2, 0.1)
        seiche.check(h and h > 0.16 and h < 0.27, "surface at " .. tostring(h) .. " m, the drain is at 0.16-0.24 m")
        drain:remove()
        seiche.check(not drain:is_valid(), "a removed sink is no longer valid")
    end
end
