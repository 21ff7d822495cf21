-- Usage: build/bin/seiche --headless --frames 21 --set fluid.particle_radius=R [--set fluid.wall_friction=0.005]
--        tools/dam_break_front.lua
-- (docs/validation.md, "Dam-break front").
-- Dam-break surge front: a column a wide and 2a high collapses along x; prints Z = front/a
-- against T = t sqrt(2 g / a) every frame. The front is the largest x among particles near
-- the floor (y < a / 4), ignoring the farthest 0.2 % as spray. Each line also gives Martin
-- & Moyce's front at that T (1952, their Table 2, a = 2.25 in, n^2 = 2: the first block of
-- docs/data/martin_moyce_1952.txt, where its source is named), interpolated linearly, and
-- the difference. A script that runs this one (dofile) may set the globals `front_radius`
-- (m) and `front_friction` first; the worst difference over Martin & Moyce's points up to
-- T = 3 is kept in the global `dam_break_front` {worst = fraction, at = T, last_T = T}.
local a = 0.2
dam_break_front = { worst = 0, at = 0, last_T = 0 }
local mm_T = { 0.41, 0.84, 1.19, 1.43, 1.63, 1.83, 1.98, 2.20, 2.32, 2.51, 2.65, 2.83, 2.98, 3.11, 3.33 }
local mm_Z = { 1.11, 1.22, 1.44, 1.67, 1.89, 2.11, 2.33, 2.56, 2.78, 3.00, 3.22, 3.44, 3.67, 3.89, 4.11 }
local function martin_moyce(T)
    if T < mm_T[1] or T > mm_T[#mm_T] then return nil end
    for i = 2, #mm_T do
        if T <= mm_T[i] then
            local f = (T - mm_T[i - 1]) / (mm_T[i] - mm_T[i - 1])
            return mm_Z[i - 1] + f * (mm_Z[i] - mm_Z[i - 1])
        end
    end
end
local fluid = {}
if front_radius then fluid.particle_radius, fluid.kernel_radius = front_radius, 4 * front_radius end
if front_friction then fluid.wall_friction = front_friction end
seiche.scene { capacity = 60000, container = { min = { 0, 0, 0 }, max = { 1.2, 0.5, 0.06 } }, fluid = fluid }
seiche.block { min = { 0, 0, 0 }, max = { a, 2 * a, 0.06 } }
function on_step(dt, t)
    local d = seiche.particle_data { fields = { "position" }, flat = true, min = { -1, -1, -1 }, max = { 2, a / 4, 1 } }
    local xs = {}
    for i = 1, d.count do xs[i] = d.position[3 * i - 2] end
    table.sort(xs)
    local k = math.max(1, math.floor(#xs * 0.998))
    local front = xs[k] + seiche.param("particle_radius")
    local T, Z = t * math.sqrt(2 * 9.81 / a), front / a
    local mm = martin_moyce(T)
    dam_break_front.last_T = T
    if mm and T >= 0.5 and T <= 3 and math.abs(Z / mm - 1) > math.abs(dam_break_front.worst) then
        dam_break_front.worst, dam_break_front.at = Z / mm - 1, T
    end
    if mm then
        print(string.format("T %.3f Z %.3f  Martin & Moyce %.3f (%+.1f %%)", T, Z, mm, 100 * (Z / mm - 1)))
    else
        print(string.format("T %.3f Z %.3f", T, Z))
    end
end
