-- scripts/scenes/dam_break.lua as it ships: released at t = 0, the water front reaches
-- the far wall (1.6 m away) within 0.5 s; no particle leaves the domain or turns NaN.
-- frames: 30
-- trusted: runs the shipped scripts/scenes/dam_break.lua as it is (dofile), then adds checks
local here = debug.getinfo(1, "S").source:match("^@(.*)/[^/]*$") or "."
dofile(here .. "/../../scripts/scenes/dam_break.lua")

local scene_step = on_step

function on_step(dt, t)
    scene_step(dt, t)
    local s = seiche.stats()
    seiche.check(s.outside == 0, s.outside .. " particles outside the domain")
    if seiche.frame() == 30 then
        local far = seiche.particles_in({ 1.4, 0, 0 }, { 1.6, 1.0, 0.6 })
        seiche.check(far > 100, "the front has not reached the far wall: " .. far .. " particles there")
    end
end
