-- Surface tension holds water together (docs/solver.md, "Surface tension"): a ball of water
-- 6 spacings in radius in zero gravity, thrown apart from its centre at 0.3 m/s at its
-- surface, keeps its particles within its radius plus two spacings at 20 N/m, where
-- without tension (--set fluid.surface_tension=0) they scatter, and it comes to rest: its
-- kinetic energy averaged over 4-5 s is under half that over 1.5-2.5 s. Measured
-- (llvmpipe, 0.12.1): 925 of 925 particles held after 5 s at 20 N/m, 81 without after 1 s;
-- kinetic energy 0.004 J over 1.5-2.5 s, 0.001 J over 4-5 s at the 6 substeps the tension took
-- (0.19.0, whose k from sigma is the lattice's: the same figures at its 5)
-- (0.12.0, whose pull was taken at the substep's start, at its 16: 0.074 and 0.052 J, a buzzing
-- surface and a slow spin-up).
-- tests/test_tension.c does the first second through the C API.
-- frames: 300
local s = 2 * seiche.param("particle_radius")
local R, L = 6 * s, 1.2
local c = L / 2
seiche.scene { name = "thrown ball", capacity = 4000, gravity = { 0, 0, 0 },
               domain = { min = { 0, 0, 0 }, max = { L, L, L } },
               fluid = { surface_tension = 20, viscosity = 0, vorticity = 0, iterations = 4 } }
local pts, vel = {}, {}
for i = -6, 6 do
    for j = -6, 6 do
        for k = -6, 6 do
            local x, y, z = i * s, j * s, k * s
            if x * x + y * y + z * z <= R * R then
                pts[#pts + 1] = { c + x, c + y, c + z }
                vel[#vel + 1] = { 0.3 * x / R, 0.3 * y / R, 0.3 * z / R }
            end
        end
    end
end
seiche.particles { positions = pts, velocities = vel }
local done = false
local early, early_n, late, late_n = 0, 0, 0, 0 -- kinetic energy summed over 1.5-2.5 s and 4-5 s
function on_step(dt, t)
    local e = seiche.stats().kinetic_energy
    if t >= 1.5 and t <= 2.5 then early, early_n = early + e, early_n + 1 end
    if t >= 4.0 then late, late_n = late + e, late_n + 1 end
    if done or t < 4.99 then return end
    done = true
    local d = seiche.particle_data { fields = { "position" }, flat = true }
    local n, p = d.count, d.position
    local cx, cy, cz = 0, 0, 0
    for q = 0, n - 1 do cx, cy, cz = cx + p[3 * q + 1], cy + p[3 * q + 2], cz + p[3 * q + 3] end
    cx, cy, cz = cx / n, cy / n, cz / n
    local radius = (3 * n / (4 * math.pi)) ^ (1 / 3) * s -- of the particles' volume
    local held = 0
    for q = 0, n - 1 do
        local x, y, z = p[3 * q + 1] - cx, p[3 * q + 2] - cy, p[3 * q + 3] - cz
        if math.sqrt(x * x + y * y + z * z) <= radius + 2 * s then held = held + 1 end
    end
    print(string.format("surface_tension %g N/m: %d of %d particles within R + 2 spacings after %.2f s",
                        seiche.param("surface_tension"), held, n, t))
    early, late = early / early_n, late / late_n
    print(string.format("kinetic energy %.3f J over 1.5-2.5 s, %.3f J over 4-5 s", early, late))
    seiche.check(held >= 0.95 * n, string.format("only %d of %d particles held together", held, n))
    seiche.check(late < 0.5 * early, string.format("the ball does not settle: %.3f J over 1.5-2.5 s, %.3f J over 4-5 s",
                                                   early, late))
end
