-- Timers run on simulated time: seiche.after(0.5) fires once, in the step that reaches
-- t = 0.5 s (frame 30 at 60 frames/s); seiche.every(0.25) fires 4 times a second, and
-- a period shorter than the frame step fires as often as it is due; a cancelled timer
-- never fires; a timer made inside a timer callback works.
-- frames: 70
seiche.scene { capacity = 10, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }

local once_at, once_frame, ticks, fast, cancelled_fired, nested_at = nil, nil, 0, 0, false, nil

function on_start()
    seiche.after(0.5, function(t)
        once_at, once_frame = t, seiche.frame()
        seiche.after(0.25, function(t2) nested_at = t2 end)
    end)
    seiche.every(0.25, function() ticks = ticks + 1 end)
    seiche.every(0.005, function() fast = fast + 1 end) -- 200 per second, more than one per frame
    local never = seiche.after(0.3, function() cancelled_fired = true end)
    seiche.check(never:is_valid() and never:remaining() > 0.29, "a new timer is valid")
    never:cancel()
    seiche.check(not never:is_valid(), "a cancelled timer is not valid")
    local ok, err = pcall(never.cancel, never)
    seiche.check(not ok and err:find("attempt to use a destroyed timer", 1, true), "cancelling twice: " .. tostring(err))
end

function on_step(dt, t)
    if seiche.frame() == 61 then -- t = 1.0167 s; on_step runs before the timers of its step
        seiche.check(once_frame == 30 and math.abs(once_at - 0.5) < 1e-9,
                     string.format("after(0.5) fired at frame %s, t = %s", tostring(once_frame), tostring(once_at)))
        seiche.check(ticks == 4, "every(0.25) fired " .. ticks .. " times in 1 s")
        seiche.check(fast == 200, "every(0.005) fired " .. fast .. " times in 1 s")
        seiche.check(not cancelled_fired, "a cancelled timer fired")
        seiche.check(nested_at and math.abs(nested_at - 0.75) < 1e-9, "nested after fired at " .. tostring(nested_at))
        seiche.quit()
    end
end
