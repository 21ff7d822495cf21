-- A trapdoor on a hinge (seiche.joint{kind = "hinge", limits = ...}): a 40 cm flap hinged at
-- its left edge along z falls under gravity, turning clockwise seen from +z (its angle goes
-- negative), and stops at its lower limit of -1 rad: it hangs there, the hinge's pivot holds
-- its edge, and the angle the joint reports matches the flap's own rotation.
-- frames: 150
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 1, substeps = 4 },
    capacity = 100,
    domain = { min = { 0, 0, 0 }, max = { 1, 1, 1 } },
}
local PIVOT = { 0.3, 0.6, 0.5 }
local flap = seiche.body { shape = "box", size = { 0.4, 0.02, 0.3 }, position = { 0.5, 0.6, 0.5 }, density = 600 }
local hinge = seiche.joint { kind = "hinge", a = flap, pivot = PIVOT, axis = { 0, 0, 1 }, limits = { -1.0, 0.2 } }
seiche.check(tostring(hinge) == "joint #2 (hinge, not yet in the world)", tostring(hinge))
seiche.check(hinge:angle() == 0, "a joint not in the world yet measures 0")
local lowest = 0

function on_step(dt, t)
    local a = hinge:angle()
    lowest = math.min(lowest, a)
    -- The flap's rotation about z, from its quaternion (it turns about z only).
    local q = flap:rotation()
    local turn = 2 * math.atan(q.z, q.w)
    seiche.check(math.abs(turn - a) < 0.01, string.format("t %.2f: joint angle %.4f, flap turned %.4f", t, a, turn))
    if seiche.frame() == 150 then
        local p, w = flap:position(), flap:angular_velocity()
        -- The flap's centre lies 0.2 m from the pivot along the flap: at (cos a, sin a) * 0.2.
        local want = { PIVOT[1] + 0.2 * math.cos(a), PIVOT[2] + 0.2 * math.sin(a) }
        print(string.format("trapdoor: angle %.4f rad (limit -1), lowest %.4f, centre (%.4f, %.4f) want (%.4f, %.4f), w.z %.2g",
                            a, lowest, p.x, p.y, want[1], want[2], w.z))
        seiche.check(math.abs(a + 1.0) < 0.02, "the flap should rest at its limit of -1 rad: " .. a)
        seiche.check(lowest > -1.1, "the limit stops the swing: lowest angle " .. lowest)
        seiche.check(math.abs(w.z) < 0.05, "at rest on its limit: w.z = " .. w.z)
        seiche.check(math.abs(p.x - want[1]) < 0.005 and math.abs(p.y - want[2]) < 0.005 and math.abs(p.z - 0.5) < 0.005,
                     "the hinge holds the flap's edge at the pivot")
        local f, torque = hinge:force()
        -- Held at rest: the hinge carries the flap's weight, m g up.
        local m = flap:mass()
        print(string.format("trapdoor: hinge force (%.2f, %.2f, %.2f) N, weight %.2f N", f.x, f.y, f.z, m * 9.81))
        seiche.check(math.abs(f.y - m * 9.81) < 0.03 * m * 9.81 and math.abs(f.x) < 0.05 * m * 9.81,
                     "nothing else touches it: the hinge and its limit carry its weight")
    end
end
