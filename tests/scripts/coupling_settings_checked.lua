-- seiche.coupling{...}: the coupling's settings from the scene, each checked with the
-- field, the value and the range; set in the main chunk, read anywhere.
-- frames: 2
seiche.scene { fluid = { particle_radius = 0.02 }, capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.5, 0.5, 0.5 } } }
local d = seiche.coupling()
seiche.check(d.force_latency == 1 and math.abs(d.force_smoothing - 0.5) < 1e-6 and d.impulse_limit == 1,
             "defaults: latency 1, smoothing 0.5, impulse limit 1")
local function refused(t, pattern)
    local ok, err = pcall(seiche.coupling, t)
    seiche.check(not ok and err:find(pattern, 1, true) and err:find("coupling_settings_checked.lua:", 1, true),
                 "refused with '" .. pattern .. "': " .. tostring(err))
end
refused({ force_latency = 9 }, "field 'force_latency' must be a whole number in [1, 7]")
refused({ force_latency = 1.5 }, "whole number")
refused({ force_smoothing = 0.99 }, "field 'force_smoothing'")
refused({ impulse_limit = -1 }, "field 'impulse_limit'")
refused({ mesh_cell = 0 }, "field 'mesh_cell' must be a number in (0, 1] m (got 0)")
refused({ mesh_cel = 0.1 }, "unknown field \"mesh_cel\"")
refused({ mesh_cell = 1e-89 }, "1e-89 is 0 as a float")
refused({ force_latency = "2" }, "force_latency")
seiche.coupling { force_latency = 2, impulse_limit = 0 }
function on_start()
    local c = seiche.coupling()
    seiche.check(c.force_latency == 2 and c.impulse_limit == 0 and math.abs(c.force_smoothing - 0.5) < 1e-6,
                 "the live coupling has the scene's settings")
    local ok, err = pcall(seiche.coupling, { force_latency = 1 })
    seiche.check(not ok and err:find("set it in the main chunk", 1, true), "after the world exists: " .. tostring(err))
end
