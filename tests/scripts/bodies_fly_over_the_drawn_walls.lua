-- The container's walls stop bodies only as high as they are drawn (container.max.y): a
-- ball thrown over the +x wall lands outside, one thrown into it below the top bounces back.
-- frames: 60
seiche.scene {
    capacity = 10,
    container = { min = { 0, 0, 0 }, max = { 1, 0.3, 1 } },
    domain = { min = { -2, 0, -2 }, max = { 3, 3, 3 } },
}
local over = seiche.body { shape = "sphere", radius = 0.05, density = 500, position = { 0.8, 0.5, 0.3 },
                           velocity = { 2, 2, 0 } }
local into = seiche.body { shape = "sphere", radius = 0.05, density = 500, position = { 0.8, 0.1, 0.7 },
                           velocity = { 3, 0, 0 } }

function on_step()
    if seiche.frame() == 60 then
        local a, b = over:position(), into:position()
        seiche.check(a.x > 1.05, string.format("the ball thrown above the 0.3 m wall should be past it: x = %.3f", a.x))
        seiche.check(b.x < 1.0, string.format("the ball thrown into the wall should stay inside: x = %.3f", b.x))
    end
end
