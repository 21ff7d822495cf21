-- scripts/scenes/prefilled_drop.lua as it ships: the block held 0.45 m above the pool
-- falls into it (after 0.6 s all but a few splashes are below 0.65 m), no particle is lost and
-- the pool's density stays within 10 % of rest.
-- frames: 36
-- trusted: runs the shipped scripts/scenes/prefilled_drop.lua as it is (dofile), then adds checks
local here = debug.getinfo(1, "S").source:match("^@(.*)/[^/]*$") or "."
dofile(here .. "/../../scripts/scenes/prefilled_drop.lua")

local scene_step = on_step
local n0

function on_step(dt, t)
    scene_step(dt, t)
    local f = seiche.frame()
    if f == 1 then
        n0 = seiche.particle_count()
        seiche.check(seiche.particles_in({ 0, 0.7, 0 }, { 1, 1, 0.6 }) > 1000, "the block starts above the pool")
    elseif f == 36 then
        seiche.check(seiche.particle_count() == n0, "particles were lost")
        local up = seiche.particles_in({ 0, 0.65, 0 }, { 1, 1.8, 0.6 })
        seiche.check(up < 50, "the block has not fallen: " .. up .. " of its 1728 particles above 0.65 m")
        local s = seiche.stats()
        seiche.check(s.rho_max < 1.1 * s.rho0, string.format("rho_max %.0f", s.rho_max))
    end
end
