-- A trusted script's finaliser that calls a body's method runs when a reload (or reset)
-- throws the old Lua state away: the API refuses it, the new scene runs on, no crash.
-- trusted: __gc is only allowed with --trusted
-- frames: 20
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } } }
local crate = seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, position = { 0.2, 0.2, 0.2 }, density = 500 }
keep = setmetatable({}, { __gc = function() crate:apply_impulse({ 0, 1, 0 }); crate:destroy() end })

function on_reload()
    seiche.check(crate:is_valid(), "the reloaded scene has its own crate")
    seiche.quit()
end

function on_step(dt, t)
    if seiche.frame() == 2 then seiche.inject_key("f5", "press") end
    seiche.check(seiche.frame() < 10, "F5 did not reload the script")
end
