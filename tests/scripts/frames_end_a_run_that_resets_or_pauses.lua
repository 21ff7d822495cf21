-- --frames ends the run whatever the script does with the loop: a reset asked for every
-- frame from on_step restarts the frame number, a space press pauses a headless run;
-- neither keeps the runner going past the frames asked for.
-- frames: 20
seiche.scene { capacity = 10 }
local n = 0
function on_step()
    n = n + 1
    if seiche.frame() == 3 then seiche.inject_key("r", "press") end
    if n == 8 then seiche.inject_key("space", "press") end
end
