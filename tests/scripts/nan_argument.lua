-- NaN is refused like any out-of-range number: exit status 2, file:line, the field.
-- expect-exit: 2
-- expect-stderr: nan_argument.lua:6: seiche.block: field 'min'.y must be a number in [-100000, 100000] m (got nan)
-- frames: 2
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
seiche.block { min = { 0, 0 / 0, 0 }, max = { 0.1, 0.1, 0.1 } }
