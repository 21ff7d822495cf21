-- Placing (docs/coupling.md) holds a body made in water while the water makes room for it,
-- but only a body set down there: one made in the water moving faster than 0.5 m/s (thrown
-- in) is not held, and one made at rest in the water stays where it was made for the hold
-- (0.3 s) and then floats up or sinks. A body set down and then teleported by the script
-- before its first measurement is held where the script put it.
-- frames: 90
seiche.scene { capacity = 5000, container = { min = { 0, 0, 0 }, max = { 0.6, 0.5, 0.3 } } }
seiche.block { min = { 0, 0, 0 }, max = { 0.6, 0.2, 0.3 } }
local thrown, set, moved, made, f0
function on_step(dt, t)
    if not made then
        if t < 0.5 then return end
        thrown = seiche.body { shape = "box", size = { 0.08, 0.08, 0.08 }, position = { 0.15, 0.18, 0.15 },
                               density = 500, velocity = { 0, -2, 0 } }
        set = seiche.body { shape = "box", size = { 0.08, 0.08, 0.08 }, position = { 0.45, 0.18, 0.15 }, density = 300 }
        moved = seiche.body { shape = "box", size = { 0.06, 0.06, 0.06 }, position = { 0.3, 0.1, 0.15 }, density = 800 }
        made, f0 = t, seiche.frame()
        return
    end
    local s, k = t - made, seiche.frame() - f0
    if k == 1 then moved:teleport({ 0.3, 0.12, 0.15 }) end
    if k == 3 then
        local y = thrown:position().y
        print(string.format("thrown: %.4f m below where it was made after %.3f s", 0.18 - y, s))
        seiche.check(0.18 - y > 0.03, string.format("the thrown box moved only %.4f m in %.3f s", 0.18 - y, s))
    end
    if k == 12 then
        local p = set:position()
        print(string.format("set down: %.5f m from where it was made after %.3f s", p.y - 0.18, s))
        seiche.check(math.abs(p.y - 0.18) < 0.001 and math.abs(p.x - 0.45) < 0.001,
                     string.format("the box set down moved to (%.4f, %.4f) during the hold", p.x, p.y))
        local q = moved:position()
        print(string.format("teleported: %.5f m from where the script put it after %.3f s", q.y - 0.12, s))
        seiche.check(math.abs(q.y - 0.12) < 0.001, string.format("the teleported box was held at y %.4f, not 0.12", q.y))
    end
    if k == 45 then
        local y = set:position().y
        print(string.format("set down: %.4f m above where it was made after %.3f s", y - 0.18, s))
        seiche.check(y - 0.18 > 0.005, "the light box set down did not float up once let go")
        seiche.quit()
    end
end
