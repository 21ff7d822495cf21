-- on_contact(a, b, impulse, point, normal): a 2 kg crate dropped 0.4 m onto a static slab
-- hits it once, with the impulse of the hit (its change of momentum in that frame less
-- gravity's, m (dv + g dt)), at its bottom face, the normal pointing from the crate down into
-- the slab; lying there after it calls nothing more. A bouncy ball on the slab hits it once
-- per bounce, each weaker than the last. A crate landing on the container's floor reports
-- b = nil. A pebble whose hit is below the threshold is not reported.
-- frames: 150
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 1, substeps = 4 },
    capacity = 100,
    container = { min = { 0, 0, 0 }, max = { 1.2, 0.8, 1.0 } },
}
seiche.check(seiche.contact_threshold() == 0.2, "the default threshold is 0.2 N s")
seiche.set_contact_threshold(0.5)
seiche.check(seiche.contact_threshold() == 0.5, "set_contact_threshold sets it")
local slab = seiche.body { shape = "box", kind = "static", size = { 0.6, 0.1, 0.6 }, position = { 0.5, 0.05, 0.5 },
                           restitution = 1 }
local crate = seiche.body { shape = "box", size = { 0.2, 0.2, 0.2 }, position = { 0.35, 0.6, 0.5 }, density = 250 }
local ball = seiche.body { shape = "sphere", radius = 0.05, position = { 0.7, 0.6, 0.5 }, density = 1000, restitution = 0.7 }
local other = seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, position = { 1.05, 0.4, 0.5 }, density = 1000 }
local pebble = seiche.body { shape = "sphere", radius = 0.02, position = { 0.5, 0.2, 0.8 }, density = 1000 }

local hits = { crate = {}, ball = {}, other = {}, pebble = {} }
local names = { [crate] = "crate", [ball] = "ball", [other] = "other", [pebble] = "pebble" }
local v_prev = {}

function on_contact(a, b, impulse, point, normal)
    local name = names[a]
    seiche.check(name ~= nil, "a is the script's body: " .. tostring(a))
    local list = hits[name]
    local v = a:velocity()
    list[#list + 1] = { t = seiche.time(), b = b, impulse = impulse, point = point, normal = normal,
                        m_dv = a:mass() * (v.y - v_prev[a].y + 9.81 * seiche.dt()), v_before = v_prev[a].y }
end

function on_step(dt, t)
    for body in pairs(names) do v_prev[body] = body:velocity() end
    if seiche.frame() < 150 then return end
    -- The crate: one hit on the slab.
    for i, x in ipairs(hits.crate) do print(string.format("crate hit %d at %.3f s: %.4f N s, m dv %.4f, b %s", i, x.t, x.impulse, x.m_dv, tostring(x.b))) end
    seiche.check(#hits.crate == 1, "the crate hits once, then lies still: " .. #hits.crate .. " calls")
    local h = hits.crate[1]
    print(string.format("crate: impulse %.4f N s, m (dv + g dt) %.4f, m |v| %.4f (v %.3f m/s), point (%.3f, %.3f, %.3f), normal (%.2f, %.2f, %.2f)",
                        h.impulse, h.m_dv, crate:mass() * math.abs(h.v_before), h.v_before, h.point.x, h.point.y, h.point.z,
                        h.normal.x, h.normal.y, h.normal.z))
    seiche.check(h.b == slab, "the crate hit the slab")
    seiche.check(math.abs(h.impulse - h.m_dv) < 0.02 * h.m_dv, "the impulse is the crate's change of momentum")
    seiche.check(math.abs(h.impulse - crate:mass() * math.abs(h.v_before)) < 0.25 * h.impulse, "about m v")
    seiche.check(math.abs(h.point.y - 0.1) < 0.01 and math.abs(h.point.x - 0.35) < 0.02, "at the crate's bottom face")
    seiche.check(h.normal.y < -0.99, "from the crate (a) into the slab (b)")
    -- The ball: a hit per bounce, each weaker.
    print(string.format("ball: %d hits, impulses %s", #hits.ball, table.concat((function()
        local t = {} for i, x in ipairs(hits.ball) do t[i] = string.format("%.3f", x.impulse) end return t end)(), ", ")))
    seiche.check(#hits.ball >= 3, "the ball bounces: " .. #hits.ball .. " hits")
    for i = 2, #hits.ball do
        seiche.check(hits.ball[i].impulse < hits.ball[i - 1].impulse and hits.ball[i].t > hits.ball[i - 1].t + 0.05,
                     "each bounce is later and weaker")
    end
    -- The other crate landed on the container's floor.
    seiche.check(#hits.other == 1 and hits.other[1].b == nil, "the container's floor is b = nil")
    seiche.check(#hits.pebble == 0, "the pebble's hit is below the threshold")
end
