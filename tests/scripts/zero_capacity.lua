-- A capacity of zero particles is refused: exit status 2 with the allowed range.
-- expect-exit: 2
-- expect-stderr: zero_capacity.lua:5: seiche.scene: field 'capacity' must be a whole number in [1, 67108864] particles (got 0)
-- frames: 2
seiche.scene { capacity = 0, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
