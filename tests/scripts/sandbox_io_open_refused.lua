-- The sandbox has no io library: a script cannot read (or write) files.
-- expect-exit: 2
-- expect-stderr: sandbox_io_open_refused.lua:6: io.open is not available in a scene script
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local f = io.open("/etc/passwd")
