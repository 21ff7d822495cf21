-- A floating box (0.1 x 0.08 x 0.1 m, 500 kg/m^3, moving up and down only) is pushed down by a
-- steady 2 N from 1.5 s on (body:apply_force every step). Archimedes: the water's force on it rises
-- by 2 N, and it sinks 2 / (rho g A) = 20.4 mm deeper into the water. Until 0.19.4 apply_force was
-- an impulse at each frame's start, and the coupling's heave damping read that jerk as motion
-- (the force rose by 1.68 N at 1/60 s, by 0.75 N at 1/30 s); held through the substeps, the
-- push then counted 1 + m_a / m times over (4 N) until the added-mass integration took it in.
-- frames: 180
seiche.scene { name = "a_steady_push_sinks_a_floating_box", capacity = 4000,
    container = { min = { 0, 0, 0 }, max = { 0.3, 0.4, 0.3 } } }
seiche.block { min = { 0, 0, 0 }, max = { 0.3, 0.2, 0.3 } }
local box = seiche.body { shape = "box", size = { 0.1, 0.08, 0.1 }, position = { 0.15, 0.2, 0.15 }, density = 500,
    linear_factor = { 0, 1, 0 }, angular_factor = { 0, 0, 0 } }
local push, area = 2.0, 0.1 * 0.1
local before, after = { n = 0, y = 0, f = 0, l = 0 }, { n = 0, y = 0, f = 0, l = 0 }

local function add(acc)
    acc.n = acc.n + 1
    acc.y = acc.y + box:position().y
    acc.f = acc.f + box:fluid_force().y
    acc.l = acc.l + seiche.surface_height(0.03, 0.03, 0.03, "mean")
end

function on_step(dt, t)
    if t >= 1.5 then box:apply_force({ 0, -push, 0 }) end
    if t > 1.0 and t <= 1.5 then add(before) end
    if t > 2.5 then add(after) end
    if seiche.frame() == 180 then
        local rise = after.f / after.n - before.f / before.n
        local sank = (before.y / before.n - after.y / after.n) + (after.l / after.n - before.l / before.n)
        local want = push / (1000 * 9.81 * area)
        print(string.format("the water's force rose %.3f N for a push of %.3f N; the box sank %.2f mm into the water (%.2f mm expected)",
            rise, push, 1000 * sank, 1000 * want))
        seiche.check(math.abs(rise - push) < 0.05 * push,
            string.format("the water's force on the box rose by %.3f N under a steady push of %.3f N", rise, push))
        seiche.check(math.abs(sank - want) < 0.15 * want,
            string.format("the box sank %.2f mm into the water under %.1f N, not the %.2f mm Archimedes says", 1000 * sank, push, 1000 * want))
    end
end
