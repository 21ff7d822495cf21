-- Headless, a space press does not pause (nothing could resume the run): it is ignored with
-- one warning, the steps go on, and --frames, counting steps, ends the run after its 20.
-- (Before 0.19.3 it paused, the remaining frames spun through unstepped and a check due
-- later never ran.)
-- expect-stderr: a pause (the space key, from seiche.inject_key) is ignored headless
-- frames: 20
seiche.scene { capacity = 10 }
local presses = 0
function on_key(key, action)
    if key == "space" and action == "press" then presses = presses + 1 end
end
function on_step()
    if seiche.frame() == 3 then seiche.inject_key("space", "press") end
    if seiche.frame() == 19 then
        seiche.check(presses == 1, "the press reached on_key once (got " .. presses .. ")")
        seiche.check(math.abs(seiche.time() - 19 / 60) < 1e-6, "19 steps simulated before the last (time " .. seiche.time() .. ")")
    end
end
