-- What a sandboxed script gets (docs/lua-api.md, "What a script can and cannot do"): the
-- base library without dofile and loadfile; string, table, math, utf8, coroutine; os.clock,
-- os.time, os.date, os.difftime; seiche.version, the fluid module's version.
-- frames: 1
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
for _, name in ipairs { "assert", "error", "ipairs", "load", "next", "pairs", "pcall", "print", "rawget",
                        "require", "select", "setmetatable", "tonumber", "tostring", "type", "xpcall" } do
    seiche.check(type(_G[name]) == "function", name .. " is there")
end
for _, lib in ipairs { "string", "table", "math", "utf8", "coroutine" } do
    seiche.check(type(_G[lib]) == "table", lib .. " is there")
end
seiche.check(type(os.clock()) == "number" and type(os.time()) == "number" and #os.date("%Y") == 4, "os.clock, time, date")
for _, left_out in ipairs { "dofile", "loadfile" } do
    seiche.check(not pcall(_G[left_out], "x"), left_out .. " is refused")
end
for _, field in ipairs { "io.open", "os.execute", "os.getenv", "os.exit", "package.loadlib", "debug.getinfo" } do
    local lib, name = field:match("(%a+)%.(%a+)")
    local ok, err = pcall(function() return _G[lib][name] end)
    seiche.check(not ok and err:find(field .. " is not available in a scene script", 1, true), field .. " is refused: " .. tostring(err))
end
seiche.check(type(seiche.version) == "string" and seiche.version:match("^%d+%.%d+%.%d+$"), "seiche.version: " .. tostring(seiche.version))
local f = load("return 1 + 1")
seiche.check(f and f() == 2, "load of source text works")
