-- With the world running, every seiche function and every method, given junk for every
-- argument (a function, NaN, a table of NaNs, a huge number), either ignores its
-- arguments or refuses with a message that starts with its own name; nothing crashes and
-- the world carries on.
-- frames: 3
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08 },
    capacity = 500,
    container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } }

local junk = {
    { print, print, print, print },
    { 0 / 0, 0 / 0, 0 / 0, 0 / 0 },
    { { 0 / 0, 0, 0 }, { 0, math.huge, 0 }, { 0, 0, -math.huge }, { 1, 2 } },
    { 1e300, -1e300, "1", true },
    { {}, {}, {}, {} },
}
local skip = { quit = true, check = true }
local refused = 0

local function try(name, f, ...)
    local ok, err = pcall(f, ...)
    if not ok then
        refused = refused + 1
        seiche.check(type(err) == "string" and err:find(name .. ": ", 1, true),
                     name .. " refused junk without naming itself: " .. tostring(err))
    end
end

-- Each maker returns a fresh handle and a function that removes what it made.
local makers = {
    emitter = function()
        local e = seiche.emitter { position = { 0.2, 0.3, 0.2 }, rate = 10 }
        return e, function() if e:is_valid() then e:remove() end end
    end,
    sink = function()
        local s = seiche.sink { min = { 0, 0, 0 }, max = { 0.1, 0.1, 0.1 } }
        return s, function() if s:is_valid() then s:remove() end end
    end,
    body = function()
        local b = seiche.body { shape = "sphere", radius = 0.03, position = { 0.3, 0.3, 0.3 } }
        return b, function() if b:is_valid() then b:destroy() end end
    end,
    timer = function()
        local t = seiche.after(100, print)
        return t, function() if t:is_valid() then t:cancel() end end
    end,
    grab = function()
        local b = seiche.body { shape = "sphere", radius = 0.03, position = { 0.3, 0.3, 0.1 } }
        return b:grab({ 0.3, 0.3, 0.1 }), function() b:destroy() end
    end,
}
local methods = { "set", "set_enabled", "get", "remove", "is_valid", "position", "rotation", "velocity",
                  "angular_velocity", "velocity_at", "mass", "kind", "shape", "fluid_force", "apply_force",
                  "apply_torque", "apply_impulse", "apply_angular_impulse", "set_velocity", "set_angular_velocity",
                  "move_to", "teleport", "set_color", "set_visible", "grab", "destroy", "cancel", "remaining", "move",
                  "release", "body", "pivot" }

function on_start()
    for name, f in pairs(seiche) do
        if type(f) == "function" and not skip[name] then
            for _, args in ipairs(junk) do try("seiche." .. name, f, table.unpack(args)) end
        end
    end
    for kind, make in pairs(makers) do
        for _, m in ipairs(methods) do
            local probe, clean = make()
            local has = type(probe[m]) == "function"
            clean()
            if has then
                for _, args in ipairs(junk) do
                    local h, done = make()
                    try(kind .. ":" .. m, h[m], h, table.unpack(args))
                    done()
                end
            end
        end
    end
    seiche.check(refused > 100, "only " .. refused .. " calls refused junk")
end

function on_step(dt, t)
    seiche.check(seiche.stats().nan == 0, "the world broke")
end
