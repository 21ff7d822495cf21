-- Throwing with the mouse (as scripts/scenes/sandbox.lua drags bodies): a press on a box grabs
-- it, the pointer drags it up and then sideways at a steady 12 pixels a frame, and the release
-- leaves the box with the pivot's velocity over the last 0.1 s, so it flies on; a second drag
-- that stops for a quarter of a second before the release drops the box with no throw; a
-- release(false) leaves the body its own velocity; a flick faster than 20 m/s is thrown at 20.
-- frames: 140
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 1, substeps = 4 },
    capacity = 100,
    container = { min = { 0, 0, 0 }, max = { 3, 1.5, 1 } },
    camera = { eye = { 1.5, 0.6, 3.0 }, target = { 1.5, 0.6, 0.5 }, fov = 50 },
}
local box = seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, position = { 0.8, 0.05, 0.5 }, density = 500 }
local ball = seiche.body { shape = "sphere", radius = 0.05, position = { 2.4, 0.05, 0.5 }, density = 500 }
local grab, grab_distance
local pivots = {}  -- t -> pivot, while dragging

function on_mouse(button, action, x, y)
    if button ~= 1 then return false end
    if action == "press" then
        local origin, dir = seiche.screen_ray(x, y)
        local hit = seiche.ray_cast(origin, { origin.x + 10 * dir.x, origin.y + 10 * dir.y, origin.z + 10 * dir.z })
        seiche.check(hit and hit.body == box, "the press is on the box")
        grab = hit.body:grab(hit.point)
        grab_distance = math.sqrt((hit.point.x - origin.x) ^ 2 + (hit.point.y - origin.y) ^ 2 + (hit.point.z - origin.z) ^ 2)
        return true
    elseif grab then
        grab:release()
        grab = nil
    end
    return false
end

function on_mouse_move(x, y)
    if not grab then return end
    local origin, dir = seiche.screen_ray(x, y)
    local p = { origin.x + grab_distance * dir.x, origin.y + grab_distance * dir.y, origin.z + grab_distance * dir.z }
    grab:move(p)
    pivots[#pivots + 1] = { t = seiche.time(), x = p[1], y = p[2], z = p[3] }
end

local px, py  -- the pointer
local throw_v, released_at, after_throw, dropped_v, fallen_v

function on_step(dt, t)
    local f = seiche.frame()
    if f == 5 then
        px, py = seiche.screen_point(box:position())
        seiche.inject_mouse(1, "press", px, py)
    elseif f > 5 and f <= 20 then      -- lift it: 6 pixels a frame up
        py = py - 6
        seiche.inject_motion(px, py)
    elseif f > 20 and f <= 40 then     -- then sideways, 12 pixels a frame
        px = px + 12
        seiche.inject_motion(px, py)
    elseif f == 41 then
        seiche.inject_mouse(1, "release", px, py)
    elseif f == 42 then
        -- The pivot's steady velocity over the sideways part of the drag.
        local a, b = pivots[#pivots - 10], pivots[#pivots]
        throw_v = { (b.x - a.x) / (b.t - a.t), (b.y - a.y) / (b.t - a.t), (b.z - a.z) / (b.t - a.t) }
        local v = box:velocity()
        print(string.format("throw: pivot %.3f %.3f %.3f m/s, box after the release %.3f %.3f %.3f m/s",
                            throw_v[1], throw_v[2], throw_v[3], v.x, v.y, v.z))
        seiche.check(throw_v[1] > 1.0, "the drag moves the pivot sideways at over 1 m/s")
        seiche.check(math.abs(v.x - throw_v[1]) < 0.05 * throw_v[1] and math.abs(v.z - throw_v[3]) < 0.05 * throw_v[1],
                     "the box leaves with the pivot's velocity")
        -- gravity's one step since the release: v.y = throw_v.y - g dt
        seiche.check(math.abs(v.y - (throw_v[2] - 9.81 * dt)) < 0.05 * throw_v[1], "and its vertical velocity")
        released_at = box:position()
    elseif f == 50 then
        local p = box:position()
        seiche.check(p.x - released_at.x > 0.8 * throw_v[1] * 8 * dt, "it flies on sideways")
        seiche.check(grab == nil, "released")
    elseif f == 70 then
        -- The ball: grabbed with grab:move alone, dragged, held still, released: no throw.
        grab = ball:grab(ball:position())
    elseif f > 70 and f <= 85 then
        local p = ball:position()
        grab:move({ 2.4 - 0.05 * (f - 70), 0.6, 0.5 })   -- 3 m/s towards -x, then held
    elseif f > 85 and f < 100 then
        grab:move({ 2.4 - 0.05 * 15, 0.6, 0.5 })
    elseif f == 100 then
        dropped_v = ball:velocity()
        grab:release()
        grab = nil
    elseif f == 101 then
        local v = ball:velocity()
        print(string.format("held still, then released: %.3f %.3f %.3f m/s (before %.3f %.3f %.3f)", v.x, v.y, v.z,
                            dropped_v.x, dropped_v.y, dropped_v.z))
        seiche.check(math.abs(v.x) < 0.02 and math.abs(v.z) < 0.02 and math.abs(v.y + 9.81 * dt) < 0.02,
                     "a pivot held still for longer than the window throws nothing")
        -- release(false): the body keeps its own velocity.
        grab = ball:grab(ball:position())
    elseif f > 101 and f <= 110 then
        grab:move({ 1.65 + 0.05 * (f - 101), 0.6, 0.5 })
    elseif f == 111 then
        fallen_v = ball:velocity()
        grab:release(false)
        grab = nil
    elseif f == 112 then
        local v = ball:velocity()
        seiche.check(math.abs(v.x - fallen_v.x) < 0.02 and math.abs(v.y - (fallen_v.y - 9.81 * dt)) < 0.02,
                     string.format("release(false) keeps the body's velocity: %.3f, %.3f before, %.3f, %.3f after",
                                   fallen_v.x, fallen_v.y, v.x, v.y))
        seiche.check(math.abs(v.x - 3) > 0.1, "the pivot's 3 m/s was not given (the spring lags): " .. v.x)
        -- A flick: 1 m a frame (60 m/s) is thrown at 20 m/s.
        grab = box:grab(box:position())
    elseif f > 112 and f <= 118 then
        local p = grab:pivot()
        grab:move({ p.x, p.y + 1.0, p.z })
    elseif f == 119 then
        grab:release()
        grab = nil
    elseif f == 120 then
        local v = box:velocity()
        local speed = math.sqrt(v.x ^ 2 + (v.y + 9.81 * dt) ^ 2 + v.z ^ 2)
        print(string.format("flick: thrown at %.2f m/s", speed))
        seiche.check(math.abs(speed - 20) < 0.01, "a throw is at most 20 m/s")
    end
end
