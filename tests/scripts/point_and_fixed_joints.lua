-- A pendulum: a ball on a point joint 30 cm from a world pivot swings with its length kept; a
-- box welded to the ball (a fixed joint, b = ball) keeps its place and turn relative to it.
-- Removing the point joint lets the pair fall; destroying the ball takes the weld with it:
-- its handle goes stale, and is_valid says so.
-- frames: 100
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 1, substeps = 4 },
    capacity = 100,
    domain = { min = { 0, 0, 0 }, max = { 1, 1, 1 } },
}
local PIVOT = { 0.5, 0.8, 0.5 }
local ball = seiche.body { shape = "sphere", radius = 0.05, position = { 0.8, 0.8, 0.5 }, density = 1000 }
local box = seiche.body { shape = "box", size = { 0.06, 0.06, 0.06 }, position = { 0.8, 0.72, 0.5 }, density = 500 }
local swing = seiche.joint { kind = "point", a = ball, pivot = PIVOT }
local weld = seiche.joint { kind = "fixed", a = box, b = ball }
local a, b = weld:bodies()
seiche.check(a == box and b == ball, "bodies() gives a and b")
seiche.check(select(2, swing:bodies()) == nil, "a joint to the world has no body b")
local lowest_x = 1

local function sub(p, q) return { p.x - q.x, p.y - q.y, p.z - q.z } end

function on_step(dt, t)
    local f = seiche.frame()
    local pb = f <= 80 and ball:position()
    if f < 60 then
        local d = sub(pb, { x = PIVOT[1], y = PIVOT[2], z = PIVOT[3] })
        local len = math.sqrt(d[1] ^ 2 + d[2] ^ 2 + d[3] ^ 2)
        seiche.check(math.abs(len - 0.3) < 0.005, string.format("frame %d: pendulum length %.4f", f, len))
        lowest_x = math.min(lowest_x, pb.x)
        -- The box stays 8 cm below the ball in the ball's own frame.
        local q = ball:rotation()
        local off = sub(box:position(), pb)
        -- rotate off by the inverse of q: v' = v + 2w(u x v) + 2u x (u x v) with u = -q.xyz
        local u = { -q.x, -q.y, -q.z }
        local c1 = { u[2] * off[3] - u[3] * off[2], u[3] * off[1] - u[1] * off[3], u[1] * off[2] - u[2] * off[1] }
        local c2 = { u[2] * c1[3] - u[3] * c1[2], u[3] * c1[1] - u[1] * c1[3], u[1] * c1[2] - u[2] * c1[1] }
        local local_off = { off[1] + 2 * q.w * c1[1] + 2 * c2[1], off[2] + 2 * q.w * c1[2] + 2 * c2[2], off[3] + 2 * q.w * c1[3] + 2 * c2[3] }
        seiche.check(math.abs(local_off[1]) < 0.004 and math.abs(local_off[2] + 0.08) < 0.004 and math.abs(local_off[3]) < 0.004,
                     string.format("frame %d: the weld moved the box to (%.4f, %.4f, %.4f) in the ball's frame", f,
                                   local_off[1], local_off[2], local_off[3]))
    elseif f == 60 then
        print(string.format("pendulum: swung to x = %.3f (pivot 0.5)", lowest_x))
        seiche.check(lowest_x < 0.45, "the pendulum should swing past the pivot")
        swing:remove()
        seiche.check(not swing:is_valid(), "a removed joint's handle is stale")
    elseif f == 80 then
        local d = sub(pb, { x = PIVOT[1], y = PIVOT[2], z = PIVOT[3] })
        seiche.check(math.sqrt(d[1] ^ 2 + d[2] ^ 2 + d[3] ^ 2) > 0.35, "free of the pivot, the ball falls away")
        ball:destroy()
        seiche.check(not weld:is_valid(), "destroying a body releases its joints")
        local ok, err = pcall(weld.angle, weld)
        seiche.check(not ok and err:find("joint:angle: attempt to use a destroyed joint", 1, true), tostring(err))
        seiche.check(tostring(weld):find("destroyed"), tostring(weld))
    elseif f == 90 then
        seiche.check(box:velocity().y < -1, "the box falls on alone")
    end
end
