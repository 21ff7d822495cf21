-- A droplet swings about round with Rayleigh's period (issue 12, item 6; docs/solver.md,
-- "Surface tension"): a ball of water 8 spacings in radius in zero gravity, given the flow
-- of its l = 2 mode, v = A (x, -y/2, -z/2) with A = 0.5 /s, at 20 N/m with the kernel
-- three spacings wide (kernel_radius 6 r, the surface-tension parameter set). Its anisotropy
-- (x'x' - (y'y' + z'z')/2) / r'r' over the particles must cross zero at least three times, and
-- the period from those crossings must be within 10 % of Rayleigh's,
-- 2 pi / sqrt(8 sigma / (rho R^3)), R from the particles' volume. With the default kernel (two
-- spacings, --set fluid.kernel_radius=0.025) the droplet rounds part way and stops at an
-- anisotropy of about 0.06: the packing's yield, and this test fails.
-- Measured (llvmpipe, 0.16.1, 2109 particles): crossings at 0.689, 1.363, 2.066 s, a period of
-- 1.376 s against Rayleigh's 1.393 s (-1.2 %), swinging about 0.000 (a fit over 4 s: 1.34 s).
-- frames: 140
local r = seiche.param("particle_radius")
local s = 2 * r
local N, A, sigma = 8, 0.5, 20
local R0 = N * s
local L = 6 * R0
local c = L / 2
seiche.scene { name = "droplet", capacity = 4000, gravity = { 0, 0, 0 },
               domain = { min = { 0, 0, 0 }, max = { L, L, L } },
               fluid = { kernel_radius = 6 * r, surface_tension = sigma, viscosity = 0, vorticity = 0,
                         iterations = 4 } }
local pts, vel = {}, {}
for i = -N, N do
    for j = -N, N do
        for k = -N, N do
            local x, y, z = i * s, j * s, k * s
            if x * x + y * y + z * z <= R0 * R0 then
                pts[#pts + 1] = { c + x, c + y, c + z }
                vel[#vel + 1] = { A * x, -A * y / 2, -A * z / 2 }
            end
        end
    end
end
seiche.particles { positions = pts, velocities = vel }
sigma = seiche.param("surface_tension") -- what --set gave, if it did
local R = (3 * #pts / (4 * math.pi)) ^ (1 / 3) * s
local rayleigh = 2 * math.pi / math.sqrt(8 * sigma / (seiche.param("rest_density") * R ^ 3))

local function anisotropy()
    local d = seiche.particle_data { fields = { "position" }, flat = true }
    local n, p = d.count, d.position
    local cx, cy, cz = 0, 0, 0
    for q = 0, n - 1 do cx, cy, cz = cx + p[3 * q + 1], cy + p[3 * q + 2], cz + p[3 * q + 3] end
    cx, cy, cz = cx / n, cy / n, cz / n
    local xx, yy, zz = 0, 0, 0
    for q = 0, n - 1 do
        local x, y, z = p[3 * q + 1] - cx, p[3 * q + 2] - cy, p[3 * q + 3] - cz
        xx, yy, zz = xx + x * x, yy + y * y, zz + z * z
    end
    return (xx - (yy + zz) / 2) / (xx + yy + zz)
end

local last, last_t, crossings, peak, done = nil, nil, {}, 0, false
function on_step(dt, t)
    local a = anisotropy()
    peak = math.max(peak, math.abs(a))
    if last and (last > 0) ~= (a > 0) then
        crossings[#crossings + 1] = last_t + (t - last_t) * last / (last - a) -- linear in between
    end
    last, last_t = a, t
    if done or t < 2.3 then return end
    done = true
    local times = {}
    for _, x in ipairs(crossings) do times[#times + 1] = string.format("%.3f", x) end
    print(string.format("droplet: %d particles, R %.3f m, %g N/m, Rayleigh's l = 2 period %.3f s; largest anisotropy %.3f, now %+.4f",
                        #pts, R, sigma, rayleigh, peak, a))
    print("zero crossings at " .. (#times > 0 and table.concat(times, ", ") or "none") .. " s")
    seiche.check(#crossings >= 3, string.format(
        "the droplet does not swing about round: %d zero crossings of its anisotropy in %.2f s (now %+.4f)",
        #crossings, t, a))
    local period = 2 * (crossings[#crossings] - crossings[1]) / (#crossings - 1)
    print(string.format("period %.3f s, %+.1f %% of Rayleigh's", period, 100 * (period / rayleigh - 1)))
    seiche.check(math.abs(period / rayleigh - 1) <= 0.10, string.format(
        "period %.3f s against Rayleigh's %.3f s (bound 10 %%)", period, rayleigh))
end
