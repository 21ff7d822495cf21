-- Usage: build/bin/seiche --headless --frames 360 tools/drafts.lua [--set fluid.particle_radius=R]
-- (docs/validation.md, "Bodies").
-- Floating bodies against Archimedes: a box, a sphere, an upright cylinder and a hull (an
-- octagonal prism) at density ratios 0.25, 0.5 and 0.75, twelve bodies in one tank 0.2 m
-- deep, each in its own 0.3 m cell. They are made at Archimedes' draft once the water has
-- settled (t = 1 s) and may only move vertically (linear_factor {0, 1, 0}, no rotation), so
-- the draft is read without tipping or drifting into a neighbour. From t = 3 s to the end
-- the script averages each body's draft, as a fraction of its height, below the mean water
-- surface (surface_height "mean" at the four corners of its cell, where no body is), and
-- prints it against Archimedes' fraction. A script that runs this one (dofile) may set the
-- global `drafts_radius` (m) first and reads the results from the global `drafts` once the
-- analysis ran (t >= 5.9 s, hence --frames 360).
local r0 = drafts_radius or seiche.param("particle_radius")
local cell, H = 0.3, 0.2 -- m
local ratios = { 0.25, 0.5, 0.75 }
local rho_w = seiche.param("rest_density")

-- Each shape: Lua body fields, its height, and its submerged fraction (of the height) at a
-- density ratio q.
local octagon = {}
for k = 0, 7 do
    local a = (k + 0.5) * math.pi / 4
    for _, y in ipairs { -0.04, 0.04 } do octagon[#octagon + 1] = { 0.065 * math.cos(a), y, 0.065 * math.sin(a) } end
end
local function sphere_fraction(q)
    -- submerged cap of depth x*2R holds q of the volume: x^2 (3 - 2x) = q, bisection
    local lo, hi = 0, 1
    for _ = 1, 60 do
        local x = 0.5 * (lo + hi)
        if x * x * (3 - 2 * x) < q then lo = x else hi = x end
    end
    return 0.5 * (lo + hi)
end
local shapes = {
    { name = "box", fields = { shape = "box", size = { 0.12, 0.08, 0.12 } }, height = 0.08, fraction = function(q) return q end },
    { name = "sphere", fields = { shape = "sphere", radius = 0.05 }, height = 0.1, fraction = sphere_fraction },
    { name = "cylinder", fields = { shape = "cylinder", radius = 0.07, height = 0.07 }, height = 0.07,
      fraction = function(q) return q end },
    { name = "hull", fields = { shape = "hull", points = octagon }, height = 0.08, fraction = function(q) return q end },
}

local nx, nz = #shapes, #ratios
local W, D = nx * cell, nz * cell
seiche.scene { capacity = 400000, container = { min = { 0, 0, 0 }, max = { W, 0.6, D } },
               fluid = { particle_radius = r0, kernel_radius = 4 * r0 } }
seiche.block { min = { 0, 0, 0 }, max = { W, H, D } }

local bodies = {} -- { body, shape, ratio, cx, cz, sum, n }
local made = false
local function corners_level(cx, cz)
    local sum, n = 0, 0
    for _, dx in ipairs { -0.5, 0.5 } do
        for _, dz in ipairs { -0.5, 0.5 } do
            local x = math.min(math.max(cx + dx * cell, 0.03), W - 0.03)
            local z = math.min(math.max(cz + dz * cell, 0.03), D - 0.03)
            local h = seiche.surface_height(x, z, 0.03, "mean")
            if h then sum, n = sum + h, n + 1 end
        end
    end
    return n > 0 and sum / n or nil
end

drafts = nil
function on_step(dt, t)
    if not made and t >= 1.0 then
        made = true
        for i, sh in ipairs(shapes) do
            for j, q in ipairs(ratios) do
                local cx, cz = (i - 0.5) * cell, (j - 0.5) * cell
                local level = corners_level(cx, cz) or H
                local f = { kind = "dynamic", density = q * rho_w, linear_factor = { 0, 1, 0 },
                            angular_factor = { 0, 0, 0 } }
                for k, v in pairs(sh.fields) do f[k] = v end
                local expect = sh.fraction(q)
                f.position = { cx, level - expect * sh.height + 0.5 * sh.height, cz }
                bodies[#bodies + 1] = { body = seiche.body(f), shape = sh, ratio = q, expect = expect, cx = cx, cz = cz,
                                        sum = 0, n = 0 }
            end
        end
        return
    end
    if not made or drafts or t < 3.0 then return end
    for _, b in ipairs(bodies) do
        local level = corners_level(b.cx, b.cz)
        if level then
            local bottom = b.body:position().y - 0.5 * b.shape.height
            b.sum, b.n = b.sum + (level - bottom) / b.shape.height, b.n + 1
        end
    end
    if t < 5.9 then return end
    drafts = {}
    print(string.format("particle radius %.4f m; draft below the mean surface, fraction of the height, t 3-5.9 s", r0))
    for _, b in ipairs(bodies) do
        local got = b.sum / math.max(b.n, 1)
        drafts[#drafts + 1] = { shape = b.shape.name, ratio = b.ratio, draft = got, archimedes = b.expect }
        print(string.format("%-9s ratio %.2f: %.3f (Archimedes %.3f, %+.3f)", b.shape.name, b.ratio, got, b.expect,
                            got - b.expect))
    end
end
