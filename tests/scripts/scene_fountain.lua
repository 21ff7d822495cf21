-- scripts/scenes/fountain.lua as it ships: the jet stands above the pool, the pool keeps
-- its water (the drain is above it), and the e key turns the jet off: half a second
-- later no water is left in the air.
-- frames: 80
-- trusted: runs the shipped scripts/scenes/fountain.lua as it is (dofile), then adds checks
local here = debug.getinfo(1, "S").source:match("^@(.*)/[^/]*$") or "."
dofile(here .. "/../../scripts/scenes/fountain.lua")

local scene_step = on_step
local in_air = function() return seiche.particles_in({ 0.3, 0.45, 0.3 }, { 0.7, 0.8, 0.7 }) end

function on_step(dt, t)
    scene_step(dt, t)
    local f = seiche.frame()
    if f == 45 then
        seiche.check(in_air() > 20, "the jet should stand above 0.45 m, " .. in_air() .. " particles there")
        seiche.check(seiche.particle_count() > 6400, "the pool lost water: " .. seiche.particle_count())
        seiche.inject_key("e", "press")
    elseif f == 80 then
        seiche.check(in_air() == 0, in_air() .. " particles still in the air after the jet was turned off")
    end
end
