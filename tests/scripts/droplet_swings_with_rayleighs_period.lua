-- A droplet at rest, set swinging, swings about round near Rayleigh's period (issue 12, item 6;
-- docs/solver.md, "Surface tension"): a ball of water 8 spacings in radius in zero gravity at
-- 20 N/m with the kernel three spacings wide (kernel_radius 6 r), 4 iterations and the
-- substeps the step takes by itself. A ball made as a lattice heats itself: its staircase
-- surface relaxes and about 5 % of its surface energy (sigma 4 pi R^2, 10 J) turns into particle
-- jitter, ten times the mode's energy, which a droplet without viscosity keeps for seconds. So
-- the ball first comes to rest under a velocity damping (1 s at 20 /s), and then, at the
-- positions it settled into, is given the flow of its l = 2 mode, v = A (x, -y/2, -z/2) with
-- A = 0.5 /s. Checked: before the flow the droplet is quiet (kinetic energy under a tenth of the
-- flow's); after it, its anisotropy (x'x' - (y'y' + z'z')/2) / r'r' crosses zero at least three
-- times in 3.2 s and the period from those crossings is within 10 % of Rayleigh's,
-- 2 pi / sqrt(8 sigma / (rho R^3)), R from the particles' volume. This holds at the default
-- substeps; the period still depends on the solve (about right at 4 x 2 to 8 x 2, 12 % slow at
-- 16 x 2, 24-32 % slow at 16 x 4 and 32 x 4) and a droplet at half the spacing swings heavily damped
-- (docs/solver.md, "A wide kernel and its relaxation"), so item 6 is not met by this alone.
-- It fails with the default kernel (--set fluid.kernel_radius=0.05: the packing's yield holds
-- the droplet stretched), before 0.18.0, whose relaxation factors let the wide kernel's top
-- modes grow (the droplet boiled at these substeps), and before 0.19.0, whose k came from a
-- continuum's cut rather than the lattice's with Akinci's K_ij (a tension of about 1.3 sigma:
-- -13.9 %).
-- Measured (llvmpipe, 0.19.0, 2109 particles, 4 substeps): 0.0018 J at rest against the flow's
-- 0.047 J; from +0.098 to -0.067, crossings at 0.689, 1.333, 2.022, 2.684 s, a period of 1.330 s
-- against Rayleigh's 1.393 s (-4.5 %).
-- frames: 260
local r = seiche.param("particle_radius")
local s = 2 * r
local N, A, sigma = 8, 0.5, 20
local SETTLE, DAMPING, WATCH = 60, 20, 3.2 -- frames at rest, its damping (1/s), seconds watched
local R0 = N * s
local L = 6 * R0
local c = L / 2
seiche.scene { name = "droplet", capacity = 4000, gravity = { 0, 0, 0 },
               domain = { min = { 0, 0, 0 }, max = { L, L, L } },
               fluid = { particle_radius = r, kernel_radius = 6 * r, surface_tension = sigma, viscosity = 0, vorticity = 0,
                         iterations = 4, damping = DAMPING } }
local pts = {}
for i = -N, N do
    for j = -N, N do
        for k = -N, N do
            local x, y, z = i * s, j * s, k * s
            if x * x + y * y + z * z <= R0 * R0 then pts[#pts + 1] = { c + x, c + y, c + z } end
        end
    end
end
seiche.particles { positions = pts }
sigma = seiche.param("surface_tension") -- what --set gave, if it did
local rho = seiche.param("rest_density")
local R = (3 * #pts / (4 * math.pi)) ^ (1 / 3) * s
local rayleigh = 2 * math.pi / math.sqrt(8 * sigma / (rho * R ^ 3))

-- The particles' positions and their centre.
local function positions()
    local d = seiche.particle_data { fields = { "position" }, flat = true }
    local n, p = d.count, d.position
    local cx, cy, cz = 0, 0, 0
    for q = 0, n - 1 do cx, cy, cz = cx + p[3 * q + 1], cy + p[3 * q + 2], cz + p[3 * q + 3] end
    return n, p, cx / n, cy / n, cz / n
end

local function anisotropy()
    local n, p, cx, cy, cz = positions()
    local xx, yy, zz = 0, 0, 0
    for q = 0, n - 1 do
        local x, y, z = p[3 * q + 1] - cx, p[3 * q + 2] - cy, p[3 * q + 3] - cz
        xx, yy, zz = xx + x * x, yy + y * y, zz + z * z
    end
    return (xx - (yy + zz) / 2) / (xx + yy + zz)
end

local drain, settled, t0
local last, last_t, crossings, peak, trough, done = nil, nil, {}, 0, 0, false
function on_step(dt, t)
    local f = seiche.frame()
    if f == SETTLE then
        -- At rest: keep where the particles sit and drain them, to put them back moving.
        local n, p, cx, cy, cz = positions()
        local at, vel, flow = {}, {}, 0
        for q = 0, n - 1 do
            local x, y, z = p[3 * q + 1] - cx, p[3 * q + 2] - cy, p[3 * q + 3] - cz
            at[q + 1] = { p[3 * q + 1], p[3 * q + 2], p[3 * q + 3] }
            vel[q + 1] = { A * x, -A * y / 2, -A * z / 2 }
            flow = flow + 0.5 * rho * s ^ 3 * (x * x + y * y / 4 + z * z / 4) * A * A
        end
        local ke = seiche.stats().kinetic_energy
        print(string.format("droplet: %d particles, R %.3f m, %g N/m, Rayleigh's l = 2 period %.3f s; after %.2f s at rest "
                            .. "its kinetic energy is %.4f J, the l = 2 flow's %.4f J", n, R, sigma, rayleigh, t, ke, flow))
        seiche.check(n == #pts, string.format("the droplet lost particles while it settled: %d of %d", n, #pts))
        seiche.check(ke < 0.1 * flow, string.format(
            "the droplet is not quiet at rest: %.4f J of jitter against the flow's %.4f J (bound a tenth)", ke, flow))
        settled = { positions = at, velocities = vel }
        drain = seiche.sink { min = { 0, 0, 0 }, max = { L, L, L } }
        return
    elseif f == SETTLE + 1 then
        drain:remove()
        seiche.set_param("damping", 0)
        seiche.particles(settled)
        t0 = t
        return
    end
    if not t0 or f < SETTLE + 3 then return end -- the particles are back from the next step on
    local a = anisotropy()
    peak, trough = math.max(peak, a), math.min(trough, a)
    if last and (last > 0) ~= (a > 0) then
        crossings[#crossings + 1] = last_t + (t - last_t) * last / (last - a) -- linear in between
    end
    last, last_t = a, t
    if done or t - t0 < WATCH then return end
    done = true
    local times = {}
    for _, x in ipairs(crossings) do times[#times + 1] = string.format("%.3f", x - t0) end
    print(string.format("set swinging: anisotropy from %+.3f to %+.3f, now %+.4f; zero crossings at %s s", peak,
                        trough, a, #times > 0 and table.concat(times, ", ") or "none"))
    -- A swing about round goes nearly as far to the other side and keeps its time: a droplet
    -- held stretched by the packing's yield creeps about a small anisotropy and may cross zero
    -- now and then (the default kernel: from +0.044 to -0.018, crossings 0.45, 1.56 and 0.19 s
    -- apart; the wide kernel's 0.58-0.62 s apart, to -0.062 from +0.089).
    local mean, worst = #crossings > 1 and (crossings[#crossings] - crossings[1]) / (#crossings - 1) or 0, 0
    for q = 2, #crossings do worst = math.max(worst, math.abs((crossings[q] - crossings[q - 1]) / mean - 1)) end
    seiche.check(#crossings >= 3 and -trough >= 0.5 * peak and worst <= 0.25, string.format(
        "the droplet does not swing about round: %d zero crossings of its anisotropy in %.2f s, half periods within "
        .. "%.0f %% of their mean, from %+.3f to %+.3f (bound: three crossings, within 25 %%, and to the other side by "
        .. "half the first stretch), now %+.4f", #crossings, t - t0, 100 * worst, peak, trough, a))
    local period = 2 * mean -- a half period's mean
    print(string.format("period %.3f s, %+.1f %% of Rayleigh's", period, 100 * (period / rayleigh - 1)))
    seiche.check(math.abs(period / rayleigh - 1) <= 0.10, string.format(
        "period %.3f s against Rayleigh's %.3f s (bound 10 %%)", period, rayleigh))
end
