-- A neutrally buoyant body (1000 kg/m^3) made in water at rest hovers at the coupling's
-- defaults: it is placed (held 0.3 s while the water its volume held is pushed out,
-- docs/coupling.md) and is 0.7 mm from where it was made after 0.5 s (7 mm before
-- placing); it then drifts less than 1 cm in 3.5 s (+1.1 mm measured; -2.1 mm before
-- placing, -3.4 mm with the impulse limit off). Before the limit had its quarter-g headroom (docs/coupling.md) it cut
-- the upper half of the lift's noise around full-submersion buoyancy: the body dropped
-- 1.8 cm in the transient here and, in a deeper tank, sank about 7 mm more over 4 s
-- (docs/validation.md, "Bodies").
-- frames: 300
seiche.scene { capacity = 8000, container = { min = { 0, 0, 0 }, max = { 0.3, 0.45, 0.3 } } }
seiche.block { min = { 0, 0, 0 }, max = { 0.3, 0.3, 0.3 } }
local box, y0, made
function on_step(dt, t)
    if not box and t >= 1.0 then
        box = seiche.body { shape = "box", size = { 0.075, 0.075, 0.075 }, position = { 0.15, 0.15, 0.15 },
                            density = 1000 }
        made = t
        return
    end
    if not box then return end
    local y = box:position().y
    if not y0 and t >= made + 0.5 then y0 = y end
    if seiche.frame() == 300 then
        local drift = y - y0
        print(string.format("neutral box: drift %.4f m in %.2f s (start at %.4f m)", drift, t - made - 0.5, y0))
        seiche.check(math.abs(drift) < 0.01, string.format("a neutral box drifted %.4f m", drift))
        seiche.check(math.abs(y0 - 0.15) < 0.005, string.format("the creation transient took it to %.4f m", y0))
    end
end
