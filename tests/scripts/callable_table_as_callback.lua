-- A callback may be any callable: a table with a __call metamethod is called (with itself
-- first, as Lua calls it). Before, it was silently never called.
-- frames: 4
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local calls = 0
on_step = setmetatable({ name = "stepper" }, {
    __call = function(self, dt, t)
        seiche.check(self.name == "stepper" and dt > 0 and t > 0, "called as self, dt, t")
        calls = calls + 1
        if seiche.frame() == 4 then seiche.check(calls == 4, "on_step called every step: " .. calls) end
    end,
})
