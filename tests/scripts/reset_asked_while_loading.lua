-- A reset (or reload) asked for while the scene loads would load it again, and again, every
-- frame: the frame counter would restart for ever and --frames never end the run. It is
-- an error at its line.
-- expect-exit: 2
-- expect-stderr: reset_asked_while_loading.lua:10: seiche.inject_key: a reset ("r") cannot be asked for while the scene loads
-- frames: 10
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }

function on_start()
    seiche.inject_key("r")
end
