-- on_splash(body, speed, volume): a box dropped into a pool splashes when it reaches the water,
-- with its downward speed then (sqrt(2 g h) for the height it fell) and its volume; a box
-- dropped beside the pool, on the dry floor behind a wall, never splashes; a box that floats
-- in the water from the start, pushed down at 1 m/s, does not splash either.
-- frames: 90
seiche.scene {
    fluid = { particle_radius = 0.015, kernel_radius = 0.06, iterations = 2, substeps = 4 },
    capacity = 3000,
    container = { min = { 0, 0, 0 }, max = { 1.0, 0.6, 0.4 } },
}
seiche.check(seiche.splash_threshold() == 0.5, "the default splash threshold is 0.5 m/s")
seiche.block { min = { 0, 0, 0 }, max = { 0.48, 0.15, 0.4 } }
seiche.body { shape = "box", kind = "static", size = { 0.04, 0.3, 0.4 }, position = { 0.5, 0.15, 0.2 } }
local START = 0.45
local dropped = seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, position = { 0.25, START, 0.2 }, density = 500 }
local dry = seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, position = { 0.75, START, 0.2 }, density = 500 }
local floater = seiche.body { shape = "box", size = { 0.08, 0.06, 0.08 }, position = { 0.1, 0.14, 0.3 }, density = 400,
                              velocity = { 0, -1, 0 } }
local splashes = {}
local surface

function on_splash(body, speed, volume)
    splashes[#splashes + 1] = { body = body, speed = speed, volume = volume, t = seiche.time(), y = body:position().y }
end

function on_step(dt, t)
    if seiche.frame() == 1 then surface = seiche.surface_height(0.3, 0.1, 0.05) end
    if seiche.frame() < 90 then return end
    for _, s in ipairs(splashes) do
        print(string.format("splash: %s at %.3f s, %.3f m/s, volume %.5f m^3, centre at y %.3f", tostring(s.body), s.t,
                            s.speed, s.volume, s.y))
    end
    seiche.check(#splashes >= 1 and splashes[1].body == dropped, "the dropped box splashes first")
    -- It fell from START (its bottom START - 0.05) to the water's surface.
    local want = math.sqrt(2 * 9.81 * (START - 0.05 - surface))
    local s = splashes[1]
    print(string.format("surface at %.3f m: sqrt(2 g h) = %.3f m/s", surface, want))
    seiche.check(s.speed > 0.9 * want and s.speed < 1.05 * want, "the splash's speed is the speed it hit the water at")
    seiche.check(math.abs(s.volume - 0.001) < 1e-6, "the volume is the box's: " .. s.volume)
    for i = 2, #splashes do
        seiche.check(splashes[i].body == dropped and splashes[i].speed < s.speed,
                     "only the dropped box splashes again (bobbing back in), more slowly")
    end
    for _, x in ipairs(splashes) do
        seiche.check(x.body ~= dry, "the box that never touched water splashed")
        seiche.check(x.body ~= floater, "the box that floats from the start splashed")
    end
    seiche.check(dry:position().y < 0.06, "the dry box lies on the floor")
end
