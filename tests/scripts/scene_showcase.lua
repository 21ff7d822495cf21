-- scripts/scenes/showcase.lua as it ships: the coloured springs keep pouring while the
-- sink holds the level, the boat floats, the wheel turns in the stream, the g key swings
-- the lock gate open to its limit, and the HUD's score counts a crate landing on the boat.
-- frames: 150
-- trusted: runs the shipped scripts/scenes/showcase.lua as it is (dofile), then adds checks
local here = debug.getinfo(1, "S").source:match("^@(.*)/[^/]*$") or "."
dofile(here .. "/../../scripts/scenes/showcase.lua")

local scene_step = on_step
local start_count
local wheel_turned = 0

function on_step(dt, t)
    scene_step(dt, t)
    local f = seiche.frame()
    if f == 1 then start_count = seiche.particle_count() end
    wheel_turned = math.max(wheel_turned, math.abs(showcase.axle:angle()))
    if f == 20 then
        seiche.check(math.abs(showcase.gate:angle()) < 0.15, "the gate starts shut: " .. showcase.gate:angle())
        seiche.inject_key("g", "press")
    elseif f == 150 then
        local n = seiche.particle_count()
        seiche.check(n > start_count, "the springs pour: " .. start_count .. " -> " .. n .. " particles")
        seiche.check(n < 11000, "the sink keeps the river below the capacity: " .. n)
        seiche.check(showcase.gate:angle() < -1.2, "g opened the gate towards -pi/2: " .. showcase.gate:angle())
        local y = showcase.boat:position().y
        seiche.check(y > 0.1 and y < 0.3, "the boat floats at the surface: y = " .. y)
        seiche.check(wheel_turned > 0.05, "the wheel turned: " .. wheel_turned .. " rad at most")
        seiche.check(showcase.score >= 1, "the crate dropped on the boat scores: " .. showcase.score)
        print(string.format("showcase: %d -> %d particles, gate %.2f rad, boat y %.3f m, wheel %.2f rad, score %d", start_count, n,
                            showcase.gate:angle(), y, wheel_turned, showcase.score))
        for _, s in ipairs(showcase.springs) do
            local c = s:get().colour
            seiche.check(type(c) == "table", "the springs pour coloured water")
        end
    end
end
