-- A negative size is refused with the field, the value and the rule: exit status 2.
-- expect-exit: 2
-- expect-stderr: negative_size.lua:6: seiche.body: field 'size'.x must be a number in (0, 1000] m (got -0.2)
-- frames: 2
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.4, 0.4, 0.4 } } }
seiche.body { shape = "box", size = { -0.2, 0.1, 0.1 }, position = { 0.2, 0.2, 0.2 } }
