-- Every bad argument is refused with a message that names the function, the field or
-- argument, the value given and what is allowed, at the caller's file:line; NaN and
-- infinities are refused like any out-of-range number. (pcall keeps the run going.)
-- frames: 1
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08 },
    capacity = 500,
    container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } },
}

local cases = {
    -- { code, text the message must contain }
    { "seiche.block('x')", "seiche.block: argument #1 must be a table" },
    { "seiche.block{min = {0, 0, 0}, max = {0/0, 1, 1}}", "seiche.block: field 'max'.x must be a number in [-100000, 100000] m (got nan)" },
    { "seiche.block{min = {0, 0, 0}, max = {1, math.huge, 1}}", "field 'max'.y must be a number in [-100000, 100000] m (got inf)" },
    { "seiche.block{min = {0, 0, 0}, max = {1, 1}}", "field 'max' must be a table of 3 numbers {x, y, z} (got a table of 2)" },
    { "seiche.block{min = {0, 0, 0}, max = {1, 0, 1}}", "seiche.block: max.y must be greater than min.y (got min 0, max 0)" },
    { "seiche.block{min = {0, 0, 0}, max = {1, 1, 1}, speed = 2}", "seiche.block: unknown field \"speed\" (known: min, max, velocity)" },
    { "seiche.sphere{center = {0.2, 0.2, 0.2}, radius = -0.1}", "seiche.sphere: field 'radius' must be a number in (0, 1000] m (got -0.1)" },
    { "seiche.sphere{center = 'middle', radius = 0.1}", "seiche.sphere: field 'center' must be a table of 3 numbers {x, y, z} in m (got \"middle\")" },
    { "seiche.particles{positions = {}}", "seiche.particles: field 'positions' must hold 1 to 500 points (got 0)" },
    { "seiche.particles{positions = {{0, 0, 0}, {1, 'a', 0}}}", "field 'positions'[2].y must be a number" },
    { "seiche.emitter{position = {0.2, 0.3, 0.2}, rate = -5}", "seiche.emitter: field 'rate' must be a number in [0, " },
    { "seiche.emitter{position = {0.2, 0.3, 0.2}, rate = 1e6}", "is the most a nozzle of radius 0.05 m pours at speed 1 m/s" },
    { "seiche.emitter{position = {0.2, 0.3, 0.2}, speed = -1}", "seiche.emitter: field 'speed' must be a number in (0, 100] m/s (got -1)" },
    { "seiche.emitter{position = {0.2, 0.3, 0.2}, radius = 0.001}", "field 'radius' must be a number in [0.02, 10] m (the particle radius at least) (got 0.001)" },
    { "seiche.emitter{position = {0.2, 0.3, 0.2}, direction = {0, 0, 0}}", "seiche.emitter: field 'direction' must not be zero" },
    { "seiche.emitter{rate = 10}", "seiche.emitter: field 'position' is required" },
    { "seiche.sink{min = {0, 0, 0}, max = {-1, 1, 1}}", "seiche.sink: max.x must be greater than min.x" },
    { "seiche.body{shape = 'cube'}", "seiche.body: field 'shape' must be one of \"box\", \"sphere\", \"capsule\", \"cylinder\", \"plane\", \"hull\", \"mesh\", \"compound\" (got \"cube\")" },
    { "seiche.body{shape = 'box', size = {0.1, -0.1, 0.1}}", "seiche.body: field 'size'.y must be a number in (0, 1000] m (got -0.1)" },
    { "seiche.body{shape = 'box'}", "seiche.body: field 'size' is required for a box" },
    { "seiche.body{shape = 'sphere', radius = 0.1, size = {1, 1, 1}}", "field 'size' does not apply to shape \"sphere\" (it takes 'radius')" },
    { "seiche.body{shape = 'capsule', radius = 0.1, height = 0.1}", "must exceed 2 radius = 0.2 m (got 0.1)" },
    { "seiche.body{shape = 'plane'}", nil }, -- a static plane is fine
    { "seiche.body{shape = 'plane', kind = 'dynamic'}", "shape \"plane\" has no volume and must be kind \"static\" or \"kinematic\"" },
    { "seiche.body{shape = 'sphere', radius = 0.1, kind = 'static', density = 500}", "apply to dynamic bodies only" },
    { "seiche.body{shape = 'sphere', radius = 0.1, density = -1}", "field 'density' must be a number in (0, 1000000] kg/m^3 (got -1)" },
    { "seiche.body{shape = 'sphere', radius = 0.1, rotation = {0, 0, 0, 2}}", "field 'rotation' must be a unit quaternion {x, y, z, w} (length 1; got length 2)" },
    { "seiche.body{shape = 'sphere', radius = 0.1, velocity = {0/0, 0, 0}}", "field 'velocity'.x must be a number in [-10000, 10000] m/s (got nan)" },
    { "seiche.body{shape = 'box', size = {0.1, 0.1, 0.1}, mass = 1e8}", "seiche.body: field 'mass' must be a number in [1e-06, 1000000] kg (got 100000000)" },
    { "seiche.body{shape = 'box', size = {1.1, 1, 1}, density = 1e6}", "gives mass 1.1e+06 kg, outside [1e-06, 1e+06] kg (Bullet lets heavier bodies fall through static ones, and keeps 1/mass in a float)" },
    { "seiche.body{shape = 'hull', points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}}", "field 'points' must hold 4 to 65536 points (got 3)" },
    { "seiche.body{shape = 'mesh', vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, indices = {1, 2, 4}}", "field 'indices'[3] must be a whole number in [1, 3] (a vertex number) (got 4)" },
    { "seiche.after(-1, print)", "seiche.after: argument #1 'delay' must be a number in [0, 1000000000] s (got -1)" },
    { "seiche.every(0, print)", "seiche.every: argument #1 'period' must be a number in (0, 1000000000] s (got 0)" },
    { "seiche.after(1, 'later')", "seiche.after: argument #2 'callback' must be a function or a table with a __call metamethod (got \"later\")" },
    { "seiche.set_param('iterations', 2.5)", "seiche.set_param: argument #2 'value' (iterations) must be a whole number in [1, 100] (got 2.5)" },
    { "seiche.set_param('speed', 1)", "seiche.set_param: argument #1 'name' must be a fluid parameter name" },
    { "seiche.set_param('viscosity', 0/0)", "(got nan)" },
    { "seiche.set_gravity({0, -1e9, 0})", "seiche.set_gravity: argument #1 'gravity'.y must be a number in [-1000, 1000] m/s^2 (got -1000000000)" },
    { "seiche.set_camera{fov = 200}", "seiche.set_camera: field 'fov' must be a number in [1, 170] degrees (got 200)" },
    { "seiche.set_look{sky = {2, 0, 0}}", "seiche.set_look: field 'sky'.x must be a number in [0, 1] (got 2)" },
    { "seiche.key_down('hyper')", "seiche.key_down: argument #1 'key' must be a key name" },
    { "seiche.inject_key('a', 'hold')", "seiche.inject_key: argument #2 'action' must be \"press\", \"release\" or \"repeat\" (got \"hold\")" },
    { "seiche.inject_mouse(9, 'press')", "seiche.inject_mouse: argument #1 'button' must be a whole number in [1, 8]" },
    { "seiche.surface_height('a', 0)", "seiche.surface_height: argument #1 'x' must be a number" },
    { "seiche.ray_cast({0, 0, 0}, {0, 0, 0})", "seiche.ray_cast: arguments 'from' and 'to' must differ" },
    { "seiche.scene{}", "seiche.scene: the scene is described once, in the script's main chunk" },
    -- A __len that answers a fraction or a string names the field, not only Lua's own words.
    { "seiche.particles{positions = setmetatable({}, {__len = function() return 1.5 end})}", "seiche.particles: field 'positions': its length (from __len) must be a whole number (got 1.5)" },
    { "seiche.body{shape = 'box', size = setmetatable({}, {__len = function() return 'x' end, __index = function() return 0.1 end})}", "seiche.body: field 'size': its length (from __len) must be a whole number (got \"x\")" },
}

-- In on_start the world exists, so the emitter's rate bound is known.
function on_start()
    for i, c in ipairs(cases) do
        local chunk = assert(load(c[1], "=case" .. i))
        local ok, err = pcall(chunk)
        if c[2] == nil then
            seiche.check(ok, c[1] .. " should be accepted, got: " .. tostring(err))
        else
            seiche.check(not ok, c[1] .. " should be refused")
            seiche.check(err:find("case" .. i .. ":1: ", 1, true) == 1, "no file:line in: " .. err)
            seiche.check(err:find(c[2], 1, true), "\n  " .. c[1] .. "\n  want: " .. c[2] .. "\n  got:  " .. err)
        end
    end
    -- Methods: the handle, then the arguments.
    local b = seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, position = { 0.2, 0.3, 0.2 } }
    local method_cases = {
        { function() b.position() end, "body:position: 'self' must be a body (got no value); call methods with a colon" },
        { function() b:apply_force({ 1, 0 }) end, "body:apply_force: argument #1 'force' must be a table of 3 numbers {x, y, z} (got a table of 2)" },
        { function() b:apply_impulse({ 0, 0, 1 }, { 0 / 0, 0, 0 }) end, "body:apply_impulse: argument #2 'point'.x must be a number in [-100000, 100000] m (got nan)" },
        { function() b:move_to({ 0, 0, 0 }) end, "body:move_to: the body is dynamic: move_to drives kinematic bodies" },
        { function() b:set_color({ 1, 1, 2 }) end, "body:set_color: argument #1 'color'.z must be a number in [0, 1] (got 2)" },
        { function() b:grab({ 0, 0, 0 }, -1) end, "body:grab: argument #2 'max_force' must be a number in (0, 1000000000] N (got -1)" },
        { function() b.destroy = 1 end, "'destroy' is a method and cannot be assigned" },
    }
    for i, c in ipairs(method_cases) do
        local ok, err = pcall(c[1])
        seiche.check(not ok and err:find(c[2], 1, true), "method case " .. i .. ":\n  want: " .. c[2] .. "\n  got:  " .. tostring(err))
    end
    b.label = "crate" -- scripts may keep their own fields on handles
    seiche.check(b.label == "crate", "a handle keeps the script's fields")
    seiche.quit()
end
