-- Using a destroyed body is an error at the line that uses it: exit status 2.
-- expect-exit: 2
-- expect-stderr: destroyed_body.lua:11: body:velocity: attempt to use a destroyed body
-- frames: 5
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } } }
local crate = seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, position = { 0.2, 0.3, 0.2 } }
function on_step(dt, t)
    if seiche.frame() == 2 then
        crate:destroy()
    elseif seiche.frame() == 3 then
        local v = crate:velocity()
    end
end
