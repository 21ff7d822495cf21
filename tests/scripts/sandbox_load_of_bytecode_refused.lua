-- load reads Lua source text only: precompiled (binary) chunks, which corrupt ones crash
-- Lua with, are refused.
-- expect-exit: 2
-- expect-stderr: sandbox_load_of_bytecode_refused.lua:8: load: binary (precompiled) chunks are not allowed in a scene script
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
local bytecode = "\27Lua\84\0\25\147\13\10\26\10\4\8\8\120\86\0\0\0\0\0\0\0\0\0\0\0\40\119\64\1\255\255"
assert(load(bytecode, "=corrupt", "b"))
