-- A space press pauses the scene; headless, --frames still ends the run.
-- frames: 20
seiche.scene { capacity = 10 }
function on_step()
    if seiche.frame() == 3 then seiche.inject_key("space", "press") end
end
