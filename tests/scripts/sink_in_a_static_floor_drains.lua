-- A drain set into a static floor: the sink's box reaches into a static slab and holds
-- its centre there, so the slab does not shield the water above it from the sink (a body
-- that holds a sink's centre does not block that sink); the pool drains through it.
-- frames: 120
seiche.scene { capacity = 8000, container = { min = { 0, 0, 0 }, max = { 0.4, 0.3, 0.2 } } }
seiche.body { shape = "box", size = { 0.4, 0.05, 0.2 }, position = { 0.2, 0.025, 0.1 }, kind = "static" }
seiche.block { min = { 0, 0.0625, 0 }, max = { 0.4, 0.15, 0.2 } }
-- The start count is the CPU's (seiche.particle_count, exact once the block is placed):
-- seiche.stats() is one or two steps behind, and on a GPU that runs ahead of the CPU its
-- first record need not be step 0's.
local start
function on_start()
    start = seiche.particle_count()
    seiche.sink { min = { 0.15, 0, 0.05 }, max = { 0.25, 0.07, 0.15 } } -- centre y 0.035: inside the slab
end
function on_step(dt, t)
    local s = seiche.stats()
    if seiche.frame() == 120 then
        print(string.format("drain: %d -> %d particles", start, s.particles))
        seiche.check(s.particles < 0.7 * start, string.format("the drain took %d of %d particles", start - s.particles, start))
    end
end
