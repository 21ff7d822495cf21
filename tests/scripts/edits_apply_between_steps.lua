-- World edits made in a callback are queued and applied before the next step: a block,
-- a body, an emitter and a parameter change made in on_step are not in the world during
-- that call (queries still show the old state) and are there in the next one.
-- frames: 8
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08 },
    capacity = 1000,
    container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } },
}
local n0, body, e

function on_step(dt, t)
    local f = seiche.frame()
    if f == 2 then
        n0 = seiche.particle_count()
        seiche.check(n0 == 0, "the scene starts empty")
        seiche.block { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } -- 5 x 5 x 5
        seiche.check(seiche.particle_count() == 0, "a block appeared inside the callback that made it")
        body = seiche.body { shape = "sphere", radius = 0.05, position = { 0.3, 0.3, 0.3 } }
        seiche.check(tostring(body):find("not yet in the world", 1, true), tostring(body))
        seiche.check(#seiche.bodies() == 1 and seiche.bodies()[1] == body, "seiche.bodies() lists the new body")
        seiche.check(body:position().y == 0.3 or math.abs(body:position().y - 0.3) < 1e-6, "a pending body reports its def")
        e = seiche.emitter { position = { 0.2, 0.35, 0.2 }, rate = 0 }
        seiche.set_param("viscosity", 0.05)
        seiche.check(math.abs(seiche.param("viscosity") - 0.05) < 1e-6, "param reads the queued value")
    elseif f == 3 then
        seiche.check(seiche.particle_count() == 125, "the block holds 125 particles, got " .. seiche.particle_count())
        seiche.check(not tostring(body):find("not yet", 1, true), tostring(body))
        seiche.check(body:position().y < 0.3, "the body fell during the step")
        seiche.check(math.abs(seiche.params().viscosity - 0.05) < 1e-6, "the parameter changed")
        body:destroy()
        seiche.check(not body:is_valid(), "a destroyed body is not valid")
        seiche.check(#seiche.bodies() == 0, "seiche.bodies() after destroy")
        local ok, err = pcall(body.position, body)
        seiche.check(not ok and err:find("body:position: attempt to use a destroyed body", 1, true), tostring(err))
        e:remove()
        ok, err = pcall(e.set, e, { rate = 1 })
        seiche.check(not ok and err:find("attempt to use a destroyed emitter", 1, true), tostring(err))
        seiche.quit()
    end
end
