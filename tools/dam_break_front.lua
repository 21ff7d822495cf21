-- Usage: build/bin/seiche --headless --frames 21 --set fluid.particle_radius=R tools/dam_break_front.lua
-- (docs/validation.md, "Dam-break front").
-- Dam-break surge front: a column a wide and 2a high collapses along x; prints Z = front/a
-- against T = t sqrt(2 g / a) every frame. The front is the largest x among particles near
-- the floor (y < a / 4), ignoring the farthest 0.2 % as spray.
local a = 0.2
seiche.scene { capacity = 60000, container = { min = { 0, 0, 0 }, max = { 1.2, 0.5, 0.06 } } }
seiche.block { min = { 0, 0, 0 }, max = { a, 2 * a, 0.06 } }
function on_step(dt, t)
    local d = seiche.particle_data { fields = { "position" }, flat = true, min = { -1, -1, -1 }, max = { 2, a / 4, 1 } }
    local xs = {}
    for i = 1, d.count do xs[i] = d.position[3 * i - 2] end
    table.sort(xs)
    local k = math.max(1, math.floor(#xs * 0.998))
    local front = xs[k] + seiche.param("particle_radius")
    print(string.format("T %.3f Z %.3f", t * math.sqrt(2 * 9.81 / a), front / a))
end
