-- An infinite number is refused: exit status 2, file:line, the field and what is allowed.
-- expect-exit: 2
-- expect-stderr: infinite_argument.lua:7: seiche.sphere: field 'radius' must be a number in (0, 1000] m (got inf)
-- frames: 2
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
function on_start()
    seiche.sphere { center = { 0.1, 0.1, 0.1 }, radius = math.huge }
end
