-- What the world checks (points inside the domain) is refused at the call once the world
-- exists, naming the Lua call, its field and a 1-based index, never the C API's names or
-- 0-based indices; counts and indices the API returns are Lua integers.
-- frames: 3
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08 },
    capacity = 2000,
    container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } },
}
seiche.block { min = { 0, 0, 0 }, max = { 0.2, 0.1, 0.2 } }

local function refused(want, f, ...)
    local ok, err = pcall(f, ...)
    seiche.check(not ok, want .. ": accepted")
    seiche.check(not ok and err:find(want, 1, true) ~= nil, "\n  want: " .. want .. "\n  got:  " .. tostring(err))
    seiche.check(not ok and not err:find("pbf_", 1, true), "a C name in: " .. tostring(err))
end

function on_start()
    -- The domain: the container, with half its height again above it for splashes.
    refused("seiche.particles: field 'positions'[2].x must be in [0, 0.4] m, inside the domain (got 9)",
            seiche.particles, { positions = { { 0.1, 0.1, 0.1 }, { 9, 9, 9 } } })
    refused("seiche.block: field 'max'.x must be in [0, 0.4] m, inside the domain (got 5)",
            seiche.block, { min = { 0, 0, 0 }, max = { 5, 0.1, 0.1 } })
    refused("seiche.block: field 'min'.y must be in [0, 0.6] m, inside the domain (got -1)",
            seiche.block, { min = { 0, -1, 0 }, max = { 0.1, 0.1, 0.1 } })
    refused("seiche.emitter: field 'position'.y must be in [0, 0.6] m, inside the domain (got 2)",
            seiche.emitter, { position = { 0.2, 2, 0.2 } })
    local e = seiche.emitter { position = { 0.2, 0.3, 0.2 }, rate = 10 }
    refused("emitter:set: field 'position'.z must be in [0, 0.4] m, inside the domain (got -1)",
            e.set, e, { position = { 0.2, 0.3, -1 } })
    refused("seiche.emitter: field 'rate' must be a number in [0, ", seiche.emitter, { position = { 0.2, 0.3, 0.2 }, rate = 1e9 })
    refused("(got 1000000000)", seiche.emitter, { position = { 0.2, 0.3, 0.2 }, rate = 1e9 })
    e:remove()
end

function on_step(dt, t)
    if seiche.frame() < 2 then return end
    local st = seiche.stats()
    for _, k in ipairs { "particles", "capacity", "step", "nan", "outside", "overflow", "substeps" } do
        seiche.check(math.type(st[k]) == "integer", "stats()." .. k .. " is " .. tostring(st[k]))
    end
    seiche.check(st.particles > 0, "the block is in the world")
    local r = seiche.region_stats({ 0, 0, 0 }, { 0.4, 0.6, 0.4 })
    seiche.check(math.type(r.particles) == "integer", "region_stats().particles is " .. tostring(r.particles))
    seiche.check(math.type(seiche.particle_data { fields = { "density" }, flat = true }.count) == "integer", "count")
    seiche.quit()
end
