-- The sandbox has no package library: no C library can be loaded.
-- expect-exit: 2
-- expect-stderr: sandbox_package_loadlib_refused.lua:6: package.loadlib is not available in a scene script
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local system = package.loadlib("libc.so.6", "system")
