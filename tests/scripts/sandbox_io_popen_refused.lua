-- The sandbox has no io library: io.popen is refused at its line.
-- expect-exit: 2
-- expect-stderr: sandbox_io_popen_refused.lua:6: io.popen is not available in a scene script
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local p = io.popen("id")
