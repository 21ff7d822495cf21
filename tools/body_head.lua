-- Usage: build/bin/seiche --headless --frames 360 tools/body_head.lua [--set fluid.particle_radius=R]
-- (docs/validation.md, "Bodies").
-- What the water's boundary passes on to a body that does not move: four static boxes
-- (0.1 m cubes, `measure_force`), each in its own 0.3 m cell of one tank 0.25 m deep, made
-- at t = 1 s once the water has settled, three standing in the surface about 2, 4 and 6 cm
-- deep and one submerged at mid-depth. From t = 2.5 s to the end the script averages each
-- box's vertical fluid force and the mean water surface at its cell's corners
-- (surface_height "mean", where no box is), and prints the force against Archimedes':
-- rho g A times the draft below that surface for the three in the surface, rho g V for the
-- submerged one. "head" is the force's excess as a height of water (mm): a floating box of
-- the same size rides that much higher than Archimedes says against the visible surface.
-- With no motion, no lag and no coupling dynamics in it, this is the water's part of a
-- floating body's draft (tools/drafts.lua measures the whole).
local r0 = seiche.param("particle_radius")
local rho_w, g = seiche.param("rest_density"), 9.81
local cell, H, a = 0.3, 0.25, 0.1 -- m
local drafts = { 0.02, 0.04, 0.06 }
local W, D = (#drafts + 1) * cell, cell
seiche.scene { capacity = 400000, container = { min = { 0, 0, 0 }, max = { W, 0.6, D } },
               fluid = { particle_radius = r0, kernel_radius = 4 * r0 } }
seiche.block { min = { 0, 0, 0 }, max = { W, H, D } }

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

local boxes, done = nil, false
function on_step(dt, t)
    if not boxes then
        if t < 1.0 then return end
        boxes = {}
        for i = 1, #drafts + 1 do
            local cx, cz = (i - 0.5) * cell, 0.5 * cell
            local bottom = i <= #drafts and corners_level(cx, cz) - drafts[i] or 0.5 * H - 0.5 * a
            boxes[i] = { cx = cx, cz = cz, bottom = bottom, submerged = i > #drafts, force = 0, level = 0, n = 0,
                         body = seiche.body { kind = "static", measure_force = true, shape = "box",
                                              size = { a, a, a }, position = { cx, bottom + 0.5 * a, cz } } }
        end
        return
    end
    if t < 2.5 then return end
    for _, b in ipairs(boxes) do
        local level = corners_level(b.cx, b.cz)
        if level then
            b.force, b.level, b.n = b.force + b.body:fluid_force().y, b.level + level, b.n + 1
        end
    end
    if t >= 5.9 and not done then
        done = true
        print(string.format("static 0.1 m boxes, particle radius %.4f m; force against Archimedes", r0))
        for _, b in ipairs(boxes) do
            local f, level = b.force / b.n, b.level / b.n
            local draft = b.submerged and a or level - b.bottom
            local archimedes = rho_w * g * a * a * draft
            print(string.format("%s draft %.4f m: %.3f N for %.3f N (%+.2f %%), head %+.1f mm",
                b.submerged and "submerged" or "surface  ", draft, f, archimedes, 100 * (f / archimedes - 1),
                1000 * (f - archimedes) / (rho_w * g * a * a)))
        end
    end
end
