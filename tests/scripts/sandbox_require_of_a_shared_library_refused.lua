-- require loads Lua modules from the scene's own folder only: a path to a shared library
-- is not a module name, and no C loader exists.
-- expect-exit: 2
-- expect-stderr: sandbox_require_of_a_shared_library_refused.lua:7: require: bad module name '/usr/lib/x86_64-linux-gnu/liblua5.4.so'
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
require("/usr/lib/x86_64-linux-gnu/liblua5.4.so")
