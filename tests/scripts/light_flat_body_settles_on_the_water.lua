-- A light, flat body comes to rest on the water (docs/coupling.md, "Lag damping"): an
-- upright cylinder of 250 kg/m^3, 0.14 m across and 7 cm tall (a draft of 1.75 cm, under a
-- particle spacing), made at its draft and free to move only vertically. Its heave
-- frequency, sqrt(g / draft) = 24 rad/s, meets the force's lag (one step and the
-- smoothing's: 42 ms), which turns the restoring force into negative damping. Measured
-- (llvmpipe), the fastest vertical speed over the last second: 1.1 cm/s with the default
-- lag_damping 1.5, 5.1 cm/s with it off (the body still heaves; in the wider tank of
-- tools/drafts.lua it was thrown clear of the water every half second). Bound: 2 cm/s.
-- frames: 240
seiche.scene { capacity = 10000, container = { min = { 0, 0, 0 }, max = { 0.3, 0.6, 0.3 } } }
seiche.block { min = { 0, 0, 0 }, max = { 0.3, 0.2, 0.3 } }
local body, fastest
function on_step(dt, t)
    if not body and t >= 1 then
        local level = seiche.surface_height(0.03, 0.03, 0.03, "mean")
        body = seiche.body { shape = "cylinder", radius = 0.07, height = 0.07, density = 250,
                             position = { 0.15, level - 0.25 * 0.07 + 0.035, 0.15 },
                             linear_factor = { 0, 1, 0 }, angular_factor = { 0, 0, 0 } }
        return
    end
    if not body or t < 3.0 then return end
    fastest = math.max(fastest or 0, math.abs(body:velocity().y))
    if seiche.frame() == 239 then
        print(string.format("light cylinder: fastest vertical speed over the last second %.4f m/s", fastest))
        seiche.check(fastest < 0.02, string.format("the light cylinder still moves at %.3f m/s", fastest))
    end
end
