-- An edit that only the world can check (a fluid ball bigger than the domain) is refused
-- when it is applied, and the message points at the line that asked for it.
-- expect-exit: 2
-- expect-stderr: edit_refused_by_the_world.lua:8: seiche.sphere: the sphere's x range [-0.3, 0.5] must lie inside the domain [0, 0.4]
-- frames: 5
seiche.scene { capacity = 1000, container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } } }
function on_start()
    seiche.sphere { center = { 0.1, 0.2, 0.2 }, radius = 0.4 }
end
