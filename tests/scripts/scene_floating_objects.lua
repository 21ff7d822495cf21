-- scripts/scenes/floating_objects.lua as it ships: one body of every shape goes into the
-- water; after 0.6 s the cork ball (250 kg/m^3) rides at the surface while the stone
-- (2500 kg/m^3) is already well below it, and every body is still in the tank.
-- frames: 36
-- trusted: runs the shipped scripts/scenes/floating_objects.lua as it is (dofile), then adds checks
local here = debug.getinfo(1, "S").source:match("^@(.*)/[^/]*$") or "."
dofile(here .. "/../../scripts/scenes/floating_objects.lua")

local scene_step = on_step

function on_step(dt, t)
    scene_step(dt, t)
    if seiche.frame() == 36 then
        local shapes = {}
        for _, b in ipairs(seiche.bodies()) do
            shapes[b:shape()] = b
            local p = b:position()
            seiche.check(p.x > 0 and p.x < 1.2 and p.y > 0 and p.y < 0.9 and p.z > 0 and p.z < 0.8,
                         string.format("%s left the tank: %.2f %.2f %.2f", tostring(b), p.x, p.y, p.z))
        end
        for _, name in ipairs({ "box", "sphere", "capsule", "cylinder", "hull" }) do
            seiche.check(shapes[name], "no " .. name .. " in the scene")
        end
        local bodies = seiche.bodies()
        local cork, stone = bodies[2], bodies[6]
        seiche.check(cork:shape() == "sphere" and stone:shape() == "box", "body order changed")
        seiche.check(cork:position().y > 0.3, "the cork ball should float at the surface (0.33 m): y = " .. cork:position().y)
        seiche.check(stone:position().y < 0.25, "the stone should sink: y = " .. stone:position().y)
    end
end
