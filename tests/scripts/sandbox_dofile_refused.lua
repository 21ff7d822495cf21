-- The sandbox has no dofile (nor loadfile): scripts run no file outside their folder.
-- expect-exit: 2
-- expect-stderr: sandbox_dofile_refused.lua:6: dofile is not available in a scene script
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
dofile("/etc/passwd")
