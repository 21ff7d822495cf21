-- Usage: build/bin/seiche --headless --frames 150 tools/heavy_sphere.lua [--set ...]
-- (docs/validation.md, "Bodies").
-- A heavy sphere's first sinking acceleration against potential flow,
-- a = (rho_b - rho_w) g / (rho_b + rho_w / 2). Spheres of 0.05 m radius at 1050, 1500 and
-- 2000 kg/m^3, each in its own 0.3 m cell of one tank 0.4 m deep, are made at mid-depth once
-- the water has settled (t = 1 s) and may only move vertically. A sphere made in water is
-- placed (held while the water makes room, docs/coupling.md "Placing"); the script times
-- each from its release (the first step it moves) and fits drop = a t^2 / 2 by least
-- squares over the first 0.05, 0.1 and 0.2 s. A script that runs this one (dofile) may set
-- the global `heavy_densities` first and reads the fits from the global `heavy_sphere`; it sets
-- `heavy_sphere_keep_running` to check them itself in the same step (the tool then does not quit).
local densities = heavy_densities or { 1050, 1500, 2000 }
local R, cell, H, depth = 0.05, 0.3, 0.4, 0.2
seiche.scene { capacity = 20000, container = { min = { 0, 0, 0 }, max = { cell * #densities, 0.6, cell } } }
seiche.block { min = { 0, 0, 0 }, max = { cell * #densities, H, cell } }
local rho_w = seiche.param("rest_density")
local g = -seiche.gravity().y
local bodies, made, track, released = {}, nil, {}, {}
heavy_sphere = nil

local function fit(tr, window)
    local sn, sd = 0, 0
    for _, p in ipairs(tr) do
        if p[1] <= window + 1e-6 then sn, sd = sn + p[2] * p[1] * p[1], sd + p[1] ^ 4 end
    end
    return 2 * sn / sd
end

function on_step(dt, t)
    if not made then
        if t < 1.0 then return end
        for i, d in ipairs(densities) do
            bodies[i] = seiche.body { shape = "sphere", radius = R, position = { cell * (i - 0.5), depth, cell / 2 },
                                      density = d, linear_factor = { 0, 1, 0 }, angular_factor = { 0, 0, 0 } }
            track[i] = {}
        end
        made = t
        return
    end
    local done = true
    for i, b in ipairs(bodies) do
        local y = b:position().y
        -- Released: moving after the placing (the first step's fall is undone by it).
        if not released[i] and t > made + 0.05 and math.abs(y - depth) > 1e-5 then
            released[i] = t - dt
            track[i][1] = { 0, 0 }
        end
        if released[i] then
            local s = t - released[i]
            if s <= 0.2 + 1e-6 then track[i][#track[i] + 1] = { s, depth - y } else track[i].done = true end
        end
        done = done and track[i].done
    end
    if done or t > made + 1.5 then
        heavy_sphere = {}
        for i, d in ipairs(densities) do
            local want = (d - rho_w) * g / (d + 0.5 * rho_w)
            local r = { density = d, potential_flow = want, released = released[i] and released[i] - made }
            local parts = {}
            for _, w in ipairs { 0.05, 0.1, 0.2 } do
                local a = released[i] and fit(track[i], w) or 0
                r[w] = a
                parts[#parts + 1] = string.format("%.2f s: %.3f (%+.0f %%)", w, a, 100 * (a / want - 1))
            end
            heavy_sphere[i] = r
            print(string.format("sphere %d kg/m^3: potential flow %.3f m/s^2; released %.3f s after it was made; "
                .. "a over %s", d, want, r.released or -1, table.concat(parts, ", ")))
        end
        if not heavy_sphere_keep_running then seiche.quit() end
    end
end
