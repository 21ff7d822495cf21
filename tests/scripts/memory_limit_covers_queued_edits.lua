-- Queued edits count against the script's memory limit: a million blocks queued in one
-- frame stop at the limit with a message naming it (before, the C-side queue grew without
-- one: 4M queued calls took 1.2 GB).
-- expect-exit: 2
-- expect-stderr: memory_limit_covers_queued_edits.lua:12: seiche.block: this would take the script past its memory limit of 512 MiB
-- The time budget is far beyond what reaching the limit takes, so the memory limit is what
-- stops it even under AddressSanitizer on a loaded machine.
-- frames: 1
-- budget: 120
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
for i = 1, 1e7 do
    seiche.block { min = { 0, 0, 0 }, max = { 0.1, 0.1, 0.1 } }
end
