-- Without gravity a block of water at 1 m/s hits a ball of the water's density at rest, in a
-- closed box, over the 0.5 s before the spreading water reaches the far wall: the water's momentum
-- goes into the ball, and water and ball together keep the block's momentum, at the coupling's
-- defaults. Before 0.20.0 the impulse limit was a bound made of g alone (for a light body's plunge),
-- so in zero gravity it let the water stop a body but not push it: the ball stayed at rest and
-- 0.7 kg m/s went missing (an outside review), unless the scene set impulse_limit 0. The bound now
-- lets the water bring a body up to the water's own speed (docs/coupling.md).
-- frames: 30
seiche.scene { name = "water_pushes_a_body_without_gravity", gravity = { 0, 0, 0 }, capacity = 4000,
    container = { min = { 0, 0, 0 }, max = { 1.0, 0.5, 0.5 }, closed_top = true } }
seiche.block { min = { 0.05, 0.1, 0.1 }, max = { 0.3, 0.4, 0.4 }, velocity = { 1, 0, 0 } }
local ball = seiche.body { shape = "sphere", radius = 0.05, position = { 0.45, 0.25, 0.25 }, density = 1000 }
local start

function on_step(dt, t)
    local s = seiche.stats()
    local m, v = ball:mass(), ball:velocity()
    local total = s.momentum.x + m * v.x
    if not start then start = total end
    seiche.check(math.abs(total - start) < 0.01 * start,
        string.format("at %.2f s water and ball hold %.4f kg m/s, not the %.4f they began with", t, total, start))
    -- While the block hits it, the water pushing the ball moves at the block's speed or a little
    -- less, faster than the ball (body:fluid_velocity), and its pushes add up to the force or more.
    if seiche.frame() == 9 then
        local w, push = ball:fluid_velocity()
        local f = ball:fluid_force()
        seiche.check(w.x > 0.5 and w.x < 1.1 and w.x > v.x and push >= 0.999 * math.abs(f.x),
            string.format("the water pushing the ball: %.3f m/s (ball %.3f), pushes %.3f N, force %.3f N", w.x, v.x, push, f.x))
    end
    if seiche.frame() == 30 then
        seiche.check(v.x > 0.3, string.format("the water pushed the ball to only %.3f m/s", v.x))
        print(string.format("ball %.3f m/s after %.2f s; water and ball %.4f kg m/s of %.4f", v.x, t, total, start))
    end
end
