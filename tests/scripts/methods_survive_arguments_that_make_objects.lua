-- A method's argument may be a table whose metamethods run Lua, and that Lua may make objects
-- (here 100 timers on each read, so the object table grows and moves). Until 0.19.4 nine methods
-- kept a pointer into that table across their argument reads and then read or wrote freed memory
-- (an outside review under ASan: body:teleport, move_to, velocity_at, grab, set_colour, grab:move,
-- emitter:set, joint:set_motor, joint:set_limits). Each must now take its arguments and land them on
-- the object. (tests/fuzz/regressions/fuzz_lua_script/method_used_its_object_* replay these
-- under AddressSanitizer.)
-- frames: 2
seiche.scene { name = "methods_survive_arguments_that_make_objects", capacity = 1000,
    container = { min = { 0, 0, 0 }, max = { 1, 1, 1 } } }
local function grow() for _ = 1, 100 do seiche.after(100, function() end) end end
local function evil(vals)
    return setmetatable({}, { __len = function() return #vals end,
        __index = function(_, k) grow() return vals[k] end })
end

local box = seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, position = { 0.5, 0.5, 0.5 } }
local paddle = seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, position = { 0.3, 0.5, 0.5 }, kind = "kinematic" }
local door = seiche.body { shape = "box", size = { 0.3, 0.2, 0.02 }, position = { 0.5, 0.2, 0.2 } }
local hinge = seiche.joint { kind = "hinge", a = door, pivot = { 0.35, 0.2, 0.2 }, axis = { 0, 1, 0 } }
local jet = seiche.emitter { position = { 0.5, 0.8, 0.5 }, direction = { 0, -1, 0 }, speed = 1, rate = 10, radius = 0.03 }

box:teleport(evil { 0.6, 0.4, 0.5 })
paddle:move_to(evil { 0.3, 0.6, 0.5 })
box:set_colour(evil { 1, 0, 0 })
jet:set(evil { speed = 2 })
hinge:set_motor(evil { speed = 1.5, max_torque = 3 })
hinge:set_limits(evil { -0.5, 0.5 })
local v = box:velocity_at(evil { 0.6, 0.5, 0.5 })
seiche.check(v.x == 0 and v.y == 0 and v.z == 0, "a body at rest moves at its points")

seiche.check(jet:get().speed == 2, "emitter:set's speed did not land on the emitter: " .. tostring(jet:get().speed))
local j = hinge:get()
seiche.check(j.motor and j.motor.speed == 1.5 and j.motor.max_torque == 3, "joint:set_motor did not land on the joint")
seiche.check(j.limits and j.limits[1] == -0.5 and j.limits[2] == 0.5, "joint:set_limits did not land on the joint")

local grab
function on_start()
    local p = box:position()
    seiche.check(math.abs(p.x - 0.6) < 1e-6 and math.abs(p.y - 0.4) < 1e-6, "teleport did not land: " .. p.x .. ", " .. p.y)
    grab = box:grab(evil { 0.6, 0.45, 0.5 })
    grab:move(evil { 0.6, 0.5, 0.5 })
    local q = grab:pivot()
    seiche.check(q.y == 0.5, "grab:move did not land on the grab")
end
