-- Showcase: a river in a channel, from two coloured springs upstream (a red one and a blue
-- one: seiche.emitter{colour = ...}) to an overflow drain downstream (a sink that holds the
-- level), through a lock gate on a hinge, past a water wheel, with a boat and crates to
-- throw at it. The HUD (seiche.text) keeps the score: a crate that hits the boat scores 1.
-- The river's first stretch starts green (seiche.colour), and the colours stay with the
-- water as it flows and mixes.
--
--   build/bin/seiche scripts/scenes/showcase.lua
--   build/bin/seiche --headless --frames 240 --screenshot showcase.png scripts/scenes/showcase.lua
--
-- Mouse: left button on a crate (or the boat) grabs it; drag and let go to throw it.
-- Keys: g opens / closes the lock gate (its motor turns it to the limit); b drops a new
-- crate (box); e turns the springs on and off. The HUD sits right of the panel (F1 hides it).

seiche.scene {
    name = "showcase",
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 2, substeps = 2 },
    capacity = 12000,
    container = { min = { 0, 0, 0 }, max = { 2.4, 0.9, 0.6 } },
    camera = { eye = { 1.2, 1.35, 2.2 }, target = { 1.2, 0.1, 0.3 }, fov = 50 },
}

-- The river bed: 12 cm of water along the channel, the first stretch green.
seiche.block { min = { 0, 0, 0 }, max = { 2.4, 0.12, 0.6 } }
seiche.colour { min = { 0, 0, 0 }, max = { 0.8, 0.12, 0.6 }, colour = { 0.1, 0.8, 0.3 } }
-- The overflow at the downstream end: a slot from 14 cm up holds the level.
seiche.sink { min = { 2.32, 0.14, 0 }, max = { 2.4, 0.4, 0.6 } }

-- The springs: a red and a blue jet aimed downstream.
local springs = {
    seiche.emitter { position = { 0.08, 0.3, 0.18 }, direction = { 1, -0.3, 0 }, speed = 1.2, radius = 0.05,
                     colour = { 0.95, 0.12, 0.1 } },
    seiche.emitter { position = { 0.08, 0.3, 0.42 }, direction = { 1, -0.3, 0 }, speed = 1.2, radius = 0.05,
                     colour = { 0.1, 0.3, 0.95 } },
}

-- The lock gate: a board on a vertical hinge at the near wall, across half the channel when
-- shut (along z), turned flat against the wall (along x) when open. Its motor drives it.
local GATE_X = 0.95
local gate = seiche.body { shape = "box", size = { 0.03, 0.3, 0.28 }, position = { GATE_X, 0.16, 0.16 }, density = 600,
                           color = { 0.45, 0.32, 0.2 } }
local hinge = seiche.joint { kind = "hinge", a = gate, pivot = { GATE_X, 0.16, 0.015 }, axis = { 0, 1, 0 },
                             limits = { -math.pi / 2, 0 }, motor = { speed = 0, max_torque = 20 } }
local gate_open = false
local function set_gate(open)
    gate_open = open
    hinge:set_motor { speed = open and -1.5 or 1.5, max_torque = 20 }
end

-- The water wheel: a hub and six paddles on a hinge along z, dipping into the river.
local AXLE = { 1.75, 0.26, 0.3 }
local parts = { { shape = "cylinder", radius = 0.04, height = 0.4, rotation = { axis = { 1, 0, 0 }, angle = math.pi / 2 } } }
for k = 0, 5 do
    local a = k * math.pi / 3
    parts[#parts + 1] = { shape = "box", size = { 0.16, 0.02, 0.36 }, position = { 0.11 * math.cos(a), 0.11 * math.sin(a), 0 },
                          rotation = { axis = { 0, 0, 1 }, angle = a } }
end
local wheel = seiche.body { shape = "compound", parts = parts, position = AXLE, density = 500, angular_damping = 0.2,
                            color = { 0.62, 0.42, 0.24 } }
local axle = seiche.joint { kind = "hinge", a = wheel, pivot = AXLE, axis = { 0, 0, 1 } }

-- The boat, and crates to throw at it.
local boat = seiche.body { shape = "box", size = { 0.3, 0.08, 0.16 }, position = { 1.3, 0.16, 0.4 }, density = 250,
                           color = { 0.85, 0.85, 0.8 } }
local crates = {}
local MAX_CRATES = 8
local function drop_crate(x, z)
    crates[#crates + 1] = seiche.body { shape = "box", size = { 0.07, 0.07, 0.07 }, density = 500,
                                        position = { x or 0.3 + 0.5 * math.random(), 0.45, z or 0.15 + 0.3 * math.random() },
                                        color = { 0.75, 0.55, 0.25 } }
    if #crates > MAX_CRATES then table.remove(crates, 1):destroy() end
end

-- What the checks of tests/scripts/scene_showcase.lua read.
showcase = { score = 0, gate = hinge, axle = axle, boat = boat, crates = crates, springs = springs }

local function is_crate(b)
    for _, c in ipairs(crates) do
        if c == b then return true end
    end
    return false
end

function on_contact(a, b, impulse)
    if b and ((a == boat and is_crate(b)) or (b == boat and is_crate(a))) then showcase.score = showcase.score + 1 end
end

-- Grabbing and throwing (as scripts/scenes/sandbox.lua).
local grab, grab_distance
local function pointed(x, y)
    local origin, dir = seiche.screen_ray(x, y)
    local far = { origin.x + 20 * dir.x, origin.y + 20 * dir.y, origin.z + 20 * dir.z }
    return seiche.ray_cast(origin, far), origin
end

function on_mouse(button, action, x, y)
    if button ~= 1 then return false end
    if action == "press" then
        local hit, origin = pointed(x, y)
        if hit and hit.body and hit.body ~= gate and hit.body ~= wheel and hit.body:kind() == "dynamic" then
            grab = hit.body:grab(hit.point)
            local d = { hit.point.x - origin.x, hit.point.y - origin.y, hit.point.z - origin.z }
            grab_distance = math.sqrt(d[1] ^ 2 + d[2] ^ 2 + d[3] ^ 2)
            return true
        end
    elseif action == "release" and grab then
        if grab:is_valid() then grab:release() end -- thrown with the pointer's last motion
        grab = nil
    end
    return false
end

function on_mouse_move(x, y, dx, dy)
    if not (grab and grab:is_valid()) then return end
    local origin, dir = seiche.screen_ray(x, y)
    local p = { origin.x + grab_distance * dir.x, origin.y + grab_distance * dir.y, origin.z + grab_distance * dir.z }
    p[2] = math.max(p[2], 0.05)
    grab:move(p)
end

function on_key(key, action)
    if action ~= "press" then return end
    if key == "g" then
        set_gate(not gate_open)
    elseif key == "b" then
        drop_crate()
    elseif key == "e" then
        local on = not springs[1]:get().enabled
        for _, s in ipairs(springs) do s:set_enabled(on) end
    end
end

function on_start()
    set_gate(false)
    drop_crate(0.5, 0.3)
    drop_crate(0.7, 0.2)
    drop_crate(1.3, 0.42) -- lands on the boat: the first point
end

function on_step(dt, t)
    seiche.check(seiche.stats().nan == 0, "no particle may become NaN")
    local x = 520 -- right of the parameter panel
    seiche.text(x, 14, string.format("score %d", showcase.score), { size = 30, colour = { 1, 0.85, 0.2 } })
    seiche.text(x, 50, string.format("time %5.1f s   water %d   wheel %4.1f rad/s", t, seiche.particle_count(),
                                     wheel:angular_velocity().z))
    seiche.text(x, 72, string.format("gate %s (g)   new crate (b)   springs (e)   throw crates onto the boat",
                                     gate_open and "open" or "shut"), { size = 16, colour = { 0.1, 0.1, 0.2, 0.9 } })
end
