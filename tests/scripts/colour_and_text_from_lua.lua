-- seiche.colour tints the water in a box and emitters pour tinted water (emitter:get shows
-- the colour, emitter:set changes or clears it); seiche.text is accepted and checked headless
-- (no UI to draw it): every bad argument names the function, field, value and what is
-- allowed. (That the tint follows the particles on the GPU: tests/test_tint.c.)
-- frames: 20
seiche.scene {
    name = "colour and text",
    fluid = { particle_radius = 0.03, kernel_radius = 0.12, iterations = 2, substeps = 1 },
    capacity = 6000,
    container = { min = { -1, 0, -0.3 }, max = { 1, 1.5, 0.3 } },
}
seiche.block { min = { -1, 0, -0.3 }, max = { -0.5, 0.5, 0.3 } }
seiche.block { min = { 0.5, 0, -0.3 }, max = { 1, 0.5, 0.3 } }
seiche.colour { min = { -1, 0, -0.3 }, max = { -0.5, 0.5, 0.3 }, colour = { 1, 0, 0 } }
seiche.colour { min = { 0.5, 0, -0.3 }, max = { 1, 0.5, 0.3 }, colour = { 0, 0.2, 1 } }
local e = seiche.emitter { position = { 0, 1.2, 0 }, direction = { 0, -1, 0 }, speed = 1, radius = 0.08,
                           colour = { 0, 1, 0 } }
local c = e:get().colour
seiche.check(type(c) == "table" and c[1] == 0 and c[2] == 1 and c[3] == 0, "emitter:get().colour is {0, 1, 0}")

local function refused(pattern, f, ...)
    local ok, err = pcall(f, ...)
    seiche.check(not ok and string.find(tostring(err), pattern, 1, true) ~= nil,
                 "expected an error with '" .. pattern .. "', got " .. tostring(err))
end

refused("seiche.colour: field 'colour' must be a colour {r, g, b} with each in [0, 1], or false for none (got true)",
        seiche.colour, { min = { 0, 0, 0 }, max = { 1, 1, 1 }, colour = true })
refused("seiche.colour: field 'colour' is required", seiche.colour, { min = { 0, 0, 0 }, max = { 1, 1, 1 } })
refused("seiche.colour: field 'colour'", seiche.colour, { min = { 0, 0, 0 }, max = { 1, 1, 1 }, colour = { 2, 0, 0 } })
refused("seiche.colour: max.x must be greater than min.x", seiche.colour,
        { min = { 1, 0, 0 }, max = { 0, 1, 1 }, colour = { 1, 0, 0 } })
refused("seiche.colour: give 'colour' or 'color' (two spellings of one field), not both", seiche.colour,
        { min = { 0, 0, 0 }, max = { 1, 1, 1 }, color = { 1, 0, 0 }, colour = { 1, 0, 0 } })
refused("seiche.emitter: field 'colour'", seiche.emitter, { position = { 0, 1, 0 }, colour = "red" })
refused("seiche.text: call it from a callback", seiche.text, 10, 10, "too early")

function on_step(dt, t)
    local f = seiche.frame()
    seiche.text(10, 10, "frame " .. f)
    seiche.text(10, 40, "score: 12", { size = 32, colour = { 1, 0.8, 0.1 } })
    seiche.text(10, 80, "half", { colour = { 1, 1, 1, 0.5 } })
    seiche.text(0, 0, 42) -- a number is text too
    refused("seiche.text: argument #1 'x' must be", seiche.text, -1, 10, "left of the window")
    refused("seiche.text: argument #2 'y' must be", seiche.text, 10, 1e9, "far below")
    refused("seiche.text: argument #3 'text' must be a string (got no value)", seiche.text, 10, 10)
    refused("seiche.text: argument #3 'text' must be at most 256 bytes (got 300 bytes)", seiche.text, 10, 10,
            string.rep("x", 300))
    refused("seiche.text: field 'size' must be", seiche.text, 10, 10, "tiny", { size = 1 })
    refused('seiche.text: unknown field "font"', seiche.text, 10, 10, "x", { font = "mono" })
    refused("seiche.text: field 'colour'", seiche.text, 10, 10, "x", { colour = { 1, 2, 0 } })
    if f == 5 then
        -- A frame's calls are capped (the HUD is cleared every frame, so this is per frame).
        local ok, err = pcall(function() for i = 1, 300 do seiche.text(1, 1, "x") end end)
        seiche.check(not ok and string.find(err, "seiche.text: at most 256 texts in one frame", 1, true) ~= nil,
                     "the per-frame cap: " .. tostring(err))
    end
    if f == 10 then
        e:set { colour = false }
        seiche.check(e:get().colour == false, "emitter:set{colour = false} clears the tint")
        e:set { colour = { 0.5, 0.5, 0.5 } }
        seiche.check(e:get().colour[1] == 0.5, "emitter:set{colour = ...} sets it")
        seiche.colour { min = { -1, 0, -0.3 }, max = { 1, 1.5, 0.3 }, colour = false }
    end
end
