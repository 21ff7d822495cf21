-- A tank of water left alone comes to rest (issue 12, item 2): a 0.3 m cube of water at
-- the defaults, rms particle speed under 5 mm/s after 5 s (2.4 mm/s measured), and the
-- water has not drifted (centre of mass within 1 mm of where it settled at 2 s). Before
-- the density and its gradient came from one kernel and sor was 0.6, a tank like this kept
-- 85 mm/s for ever; at sor 1 it still boils (docs/solver.md, "Departures").
-- frames: 300
local L = 0.3
seiche.scene { capacity = 4000, container = { min = { 0, 0, 0 }, max = { L, 0.45, L } } }
seiche.block { min = { 0, 0, 0 }, max = { L, L, L } }
local settled_y
local function rms()
    local d = seiche.particle_data { fields = { "velocity" }, flat = true }
    local v2 = 0
    for i = 1, 3 * d.count do v2 = v2 + d.velocity[i] ^ 2 end
    return math.sqrt(v2 / d.count)
end
function on_step(dt, t)
    local f = seiche.frame()
    local s = seiche.stats()
    seiche.check(s.nan == 0 and s.outside == 0, "NaN or particles outside")
    if f == 120 then settled_y = s.center_of_mass.y end
    if f == 300 then
        local v = rms()
        print(string.format("tank_comes_to_rest: rms speed %.2f mm/s after %.1f s, centre of mass moved %.2f mm since 2 s",
                            1000 * v, t, 1000 * (s.center_of_mass.y - settled_y)))
        seiche.check(v < 0.005, string.format("rms speed %.1f mm/s after 5 s, want under 5", 1000 * v))
        seiche.check(math.abs(s.center_of_mass.y - settled_y) < 0.001, "the water's centre of mass still moves")
    end
end
