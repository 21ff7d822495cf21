-- A sink leaves the water a static body holds: a basin (a static floor plate and two
-- static walls) full of water inside the sink's box keeps it, while water beside the
-- basin, in the same box, drains. Static bodies block sinks (pbf_collider_def.blocks_sinks):
-- a particle is shielded when it is inside one or the straight path to the sink's centre
-- meets one.
-- frames: 60
seiche.scene { capacity = 12000, container = { min = { 0, 0, 0 }, max = { 0.6, 0.4, 0.3 } } }
seiche.body { shape = "box", size = { 0.2, 0.02, 0.3 }, position = { 0.15, 0.11, 0.15 }, kind = "static" }
seiche.body { shape = "box", size = { 0.02, 0.2, 0.3 }, position = { 0.06, 0.2, 0.15 }, kind = "static" }
seiche.body { shape = "box", size = { 0.02, 0.2, 0.3 }, position = { 0.24, 0.2, 0.15 }, kind = "static" }
seiche.block { min = { 0.075, 0.125, 0 }, max = { 0.225, 0.2, 0.3 } }
seiche.block { min = { 0.35, 0, 0 }, max = { 0.55, 0.1, 0.3 } }
local basin_min, basin_max = { 0.07, 0.12, 0 }, { 0.23, 0.3, 0.3 }
local outside_min, outside_max = { 0.26, 0, 0 }, { 0.6, 0.4, 0.3 }
local in_basin
function on_start()
    seiche.sink { min = { 0, 0, 0 }, max = { 0.6, 0.18, 0.3 } } -- its centre (0.3, 0.09) is below and beside the basin
end
function on_step(dt, t)
    local f = seiche.frame()
    if f == 2 then
        in_basin = seiche.particles_in(basin_min, basin_max)
        seiche.check(in_basin > 150, "the basin holds water: " .. in_basin)
    elseif f == 60 then
        local kept = seiche.particles_in(basin_min, basin_max)
        local beside = seiche.particles_in(outside_min, outside_max)
        print(string.format("basin %d -> %d particles, beside it %d left", in_basin, kept, beside))
        seiche.check(kept >= 0.97 * in_basin, string.format("the basin kept %d of %d particles", kept, in_basin))
        seiche.check(beside == 0, string.format("%d particles beside the basin were not drained", beside))
    end
end
