-- Sandbox: a pool to play in. Drop boxes, balls, capsules, cylinders and rocks (convex
-- hulls) where the mouse points, grab them with the left mouse button and drag them
-- through the water, pour more water, clear the pool.
--
--   build/bin/seiche scripts/scenes/sandbox.lua
--
-- Mouse: left button on a body grabs it (drag it around; release lets go, throwing it with
--        the drag's speed); left button elsewhere orbits the camera, the wheel zooms.
-- Keys:  1 box   2 ball   3 capsule   4 cylinder   5 rock   6 boat (assets/boat.obj)
--        (dropped above the pointer)
--        w pour water on / off    x remove every body    r reset    space pause

seiche.scene {
    name = "sandbox",
    fluid = {
        particle_radius = 0.015,
        kernel_radius = 0.06,
        iterations = 2,
        substeps = 4,
    },
    capacity = 24000,
    container = { min = { 0, 0, 0 }, max = { 1.5, 0.8, 1.0 } },
    camera = { eye = { 0.75, 1.3, 2.2 }, target = { 0.75, 0.15, 0.5 }, fov = 50 },
}

-- A pool 18 cm deep: 50 x 6 x 33 = 9900 particles.
seiche.block { min = { 0, 0, 0 }, max = { 1.5, 0.18, 1.0 } }

-- A tap in a corner, off until w is pressed.
local tap = seiche.emitter { position = { 0.15, 0.7, 0.15 }, direction = { 0.3, -1, 0.3 }, speed = 1.5, radius = 0.05,
                             rate = 300, enabled = false }

math.randomseed(7)      -- the same "random" bodies every run (reproducible runs)
local MAX_BODIES = 40  -- the fluid couples at most 64 bodies; keep room
local dropped = {}     -- bodies in the order they were dropped
local grab, grab_distance

local shapes = {
    ["1"] = function(p) return { shape = "box", size = { 0.1, 0.07, 0.12 }, density = 300 + 900 * math.random() } end,
    ["2"] = function(p) return { shape = "sphere", radius = 0.05, density = 200 + 1000 * math.random() } end,
    ["3"] = function(p) return { shape = "capsule", radius = 0.035, height = 0.18, density = 600 } end,
    ["4"] = function(p) return { shape = "cylinder", radius = 0.05, height = 0.08, density = 450 } end,
    ["5"] = function(p)
        local pts = {}
        for i = 1, 12 do
            local a, b = 2 * math.pi * math.random(), math.acos(2 * math.random() - 1)
            local r = 0.04 + 0.025 * math.random()
            pts[i] = { r * math.sin(b) * math.cos(a), 0.8 * r * math.cos(b), r * math.sin(b) * math.sin(a) }
        end
        return { shape = "hull", points = pts, density = 2200 }
    end,
    -- A boat from a mesh file: its convex hull, light enough to float high.
    ["6"] = function(p) return { mesh = "assets/boat.obj", density = 300 } end,
}

-- Where the mouse points: the first thing the ray hits (a body or the container), else nil.
local function pointed(x, y)
    local origin, dir = seiche.screen_ray(x, y)
    local far = { origin.x + 20 * dir.x, origin.y + 20 * dir.y, origin.z + 20 * dir.z }
    return seiche.ray_cast(origin, far), origin, dir
end

-- Drops a body of the key's kind above `at` ({x, y, z}), or above where the mouse points.
local function drop(key, at)
    if not at then
        local hit = pointed(seiche.mouse_position())
        at = hit and hit.point or { x = 0.75, y = 0, z = 0.5 }
    end
    local def = shapes[key]()
    def.position = { math.min(math.max(at.x, 0.15), 1.35), 0.4, math.min(math.max(at.z, 0.15), 0.85) }
    def.rotation = { axis = { math.random() - 0.5, 1, math.random() - 0.5 }, angle = math.pi * math.random() }
    dropped[#dropped + 1] = seiche.body(def)
    if #dropped > MAX_BODIES then
        table.remove(dropped, 1):destroy()
    end
end

function on_key(key, action)
    if action ~= "press" then return end
    if shapes[key] then
        drop(key)
    elseif key == "w" then
        tap:set_enabled(not tap:get().enabled)
    elseif key == "x" then
        if grab then grab:release(); grab = nil end
        for _, b in ipairs(dropped) do b:destroy() end
        dropped = {}
    end
end

function on_mouse(button, action, x, y)
    if button ~= 1 then return false end
    if action == "press" then
        local hit, origin = pointed(x, y)
        if hit and hit.body and hit.body:kind() == "dynamic" then
            grab = hit.body:grab(hit.point)
            local d = { hit.point.x - origin.x, hit.point.y - origin.y, hit.point.z - origin.z }
            grab_distance = math.sqrt(d[1] ^ 2 + d[2] ^ 2 + d[3] ^ 2)
            return true -- ours: the camera leaves this drag alone
        end
    elseif action == "release" and grab then
        if grab:is_valid() then grab:release() end -- thrown with the pointer's last 0.1 s of motion
        grab = nil
    end
    return false
end

function on_mouse_move(x, y, dx, dy)
    if not (grab and grab:is_valid()) then return end
    local origin, dir = seiche.screen_ray(x, y)
    local p = { origin.x + grab_distance * dir.x, origin.y + grab_distance * dir.y, origin.z + grab_distance * dir.z }
    p[2] = math.max(p[2], 0.02) -- not through the floor
    grab:move(p)
end

function on_start()
    -- A few bodies to begin with.
    drop("1", { x = 0.45, y = 0, z = 0.5 })
    drop("2", { x = 0.75, y = 0, z = 0.4 })
    drop("4", { x = 1.05, y = 0, z = 0.6 })
end

function on_step(dt, t)
    seiche.check(seiche.stats().nan == 0, "no particle may become NaN")
end
