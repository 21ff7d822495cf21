-- Usage: build/bin/seiche --headless --frames 17 --metrics OUT.csv tools/reference_dam_break.lua
--        [--set fluid.particle_radius=R --set fluid.kernel_radius=4R] [--set fluid.iterations=K ...]
-- (docs/performance.md, "Quality per millisecond": the defaults at a million particles).
-- The benchmark's reference dam break as a scene, so it runs with the library's defaults
-- as a game would (frame step 1/60 s, 2 iterations x 4 substeps, the time-step guard
-- adding substeps when the water is fast), where seiche-bench fixes iterations x substeps
-- per 4 ms step with the guard off: a 1 m cube of water at a corner of a 4 x 3 x 1.5 m
-- tank. Particle radius 5 mm by default: 100^3 = 1 000 000 particles (--set another; the
-- library's default radius, 0.0125, reads as "not set": give 0.01249 for that spacing,
-- 64 000 particles; the kernel radius follows, 4 radii). Every frame it prints the density error and the substeps of the latest measured
-- step, and the worst and mean so far (over the steps after 0.035 s).
local r = seiche.param("particle_radius")
if math.abs(r - 0.0125) < 1e-7 then r = 0.005 end -- a float: 0.0125 comes back as 0.012500000186...
local n = math.floor(1 / (2 * r) + 0.5)
seiche.scene {
    capacity = n * n * n,
    container = { min = { 0, 0, 0 }, max = { 4, 3, 1.5 } },
    fluid = { particle_radius = r, kernel_radius = 4 * r },
}
seiche.block { min = { 0, 0, 0 }, max = { 1, 1, 1 } }
local worst, sum, frames = 0, 0, 0
function on_step(dt, t)
    local s = seiche.stats()
    if s.step < 0 then return end
    local f = seiche.frame()
    local rho0 = s.rho0
    local err = s.rho_err_avg
    if s.time > 0.035 then -- the step measured (one or two behind), past the benchmark's warm-up
        worst = math.max(worst, s.rho_max / rho0 - 1)
        sum, frames = sum + err, frames + 1
    end
    local mean = frames > 0 and sum / frames or 0
    print(string.format("frame %d t %.3f s: %d particles, rho_max %+.2f %%, mean compression %.3f %%, %d substeps; "
                        .. "so far worst %+.2f %%, mean %.3f %%", f, t, s.particles, 100 * (s.rho_max / rho0 - 1),
                        100 * err, s.substeps, 100 * worst, 100 * mean))
    reference_dam_break = { worst = worst, mean = mean }
end

