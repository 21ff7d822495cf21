-- --frames ends the run whatever the script does with the loop: a reset asked for from
-- on_step restarts the frame number (and the script, which asks again), yet the runner
-- stops after the frames asked for.
-- frames: 20
seiche.scene { capacity = 10 }
function on_step()
    if seiche.frame() == 3 then seiche.inject_key("r", "press") end
end
