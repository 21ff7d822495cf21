-- Usage: build/bin/seiche --headless --frames 480 --set fluid.particle_radius=0.005 tools/sloshing.lua
--        [--set fluid.NAME=V ...]
-- (docs/validation.md, "Rest" and "Waves").
-- The first sloshing mode of a tank 0.8 m long, water 0.2 m deep: the surface starts as
-- H + A cos(pi x / L) (columns one spacing wide) and is let go. Each frame the level is read
-- near both ends; at the end the script prints the period (from the zero crossings of the
-- difference) against linear theory, T = 2 pi / sqrt(g k tanh(k H)) with k = pi / L, and
-- the decay: the amplitude of each half-cycle and the damping ratio from their log decrement.
-- A script that runs this one (dofile) may set the global `sloshing_radius` (m) first, and
-- reads the figures from the global `sloshing` once it is filled in (at t = 7.9 s).
local r0 = sloshing_radius or seiche.param("particle_radius")
local s = 2 * r0
local L, W, H, A = 0.8, 4 * s, 0.2, 0.02 -- m: a slice four particles wide
seiche.scene { capacity = 100000, container = { min = { 0, 0, 0 }, max = { L, 0.5, W } },
               fluid = { particle_radius = r0, kernel_radius = 4 * r0 } }
local columns = math.floor(L / s + 0.5)
for c = 0, columns - 1 do
    local x0, x1 = c * L / columns, (c + 1) * L / columns
    local top = H + A * math.cos(math.pi * 0.5 * (x0 + x1) / L)
    seiche.block { min = { x0, 0, 0 }, max = { x1, top, W } }
end

local xa, xb = 0.125 * L, 0.875 * L
local until_t = 7.9 -- s: the analysis runs once here (hence --frames 480)
local times, diffs = {}, {}
local analyse -- defined below
function on_step(dt, t)
    if #times > 0 and times[#times] >= until_t then return end
    local r = 0.06 * L
    local a = seiche.surface_height(xa, W / 2, r, "level")
    local b = seiche.surface_height(xb, W / 2, r, "level")
    if a and b then
        times[#times + 1], diffs[#diffs + 1] = t, a - b
    end
    if t >= until_t then analyse() end
end

analyse = function()
    -- zero crossings of the difference, linearly interpolated; a crossing counts once the
    -- signal has gone past the band of +-`band` on the other side (noise at the surface
    -- makes it wobble about zero)
    local band = 0.1 * s
    local zeros, side, last = {}, diffs[1] > 0, nil
    for i = 2, #diffs do
        if (diffs[i - 1] > 0) ~= (diffs[i] > 0) then
            local f = diffs[i - 1] / (diffs[i - 1] - diffs[i])
            last = times[i - 1] + f * (times[i] - times[i - 1])
        end
        if last and math.abs(diffs[i]) > band and (diffs[i] > 0) ~= side then
            zeros[#zeros + 1], side, last = last, diffs[i] > 0, nil
        end
    end
    -- the largest |difference| between consecutive zero crossings (and before the first)
    local peaks, from = {}, 0
    for k = 1, #zeros + 1 do
        local to = zeros[k] or math.huge
        local m = 0
        for i = 1, #diffs do
            if times[i] >= from and times[i] < to then m = math.max(m, math.abs(diffs[i])) end
        end
        if to < math.huge then peaks[#peaks + 1] = m end
        from = to
    end
    local k = math.pi / L
    local g = -seiche.gravity()[2]
    local theory = 2 * math.pi / math.sqrt(g * k * math.tanh(k * H))
    -- The period from the crossings of the half-cycles still at least a fifth of the first
    -- amplitude: once the wave has decayed into the surface's noise (a few mm), a crossing
    -- can come early or late by a large share of a half-cycle (seen on an NVIDIA GPU: a last
    -- half-cycle of 1.8 mm ended 0.36 s after the one before, against 0.57 s for the others).
    local m = #zeros
    while m > 1 and peaks[m] < 0.2 * peaks[1] do m = m - 1 end
    local period = m >= 3 and 2 * (zeros[m] - zeros[1]) / (m - 1) or 0 / 0
    local amp = {}
    for i = 1, #peaks do amp[#amp + 1] = string.format("%.1f", 1000 * peaks[i]) end
    print(string.format("sloshing: period %.3f s over %d half-cycles (of %d: those under a fifth of the first " ..
                        "amplitude left out), linear theory %.3f s (%+.1f %%)", period, math.max(m - 1, 0),
                        math.max(#zeros - 1, 0), theory, 100 * (period / theory - 1)))
    print("sloshing: amplitude of each half-cycle (level difference, mm): " .. table.concat(amp, " "))
    local zeta = 0 / 0
    if #peaks >= 3 then
        -- log decrement per full cycle over the half-cycles after the first
        local n = #peaks - 2
        local delta = 2 * math.log(peaks[2] / peaks[#peaks]) / n
        zeta = delta / math.sqrt(4 * math.pi ^ 2 + delta ^ 2)
        print(string.format("sloshing: damping ratio %.4f (log decrement %.3f per cycle, amplitude halves in %.1f cycles)",
                            zeta, delta, delta > 0 and math.log(2) / delta or math.huge))
    end
    sloshing = { period = period, theory = theory, half_cycles = math.max(#zeros - 1, 0), damping_ratio = zeta }
end
