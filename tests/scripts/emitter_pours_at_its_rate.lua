-- An emitter pours at its documented rate: between t = 0.5 s and t = 1.5 s a jet of
-- 200 particles/s adds 200 particles (within one nozzle layer), every one of them lands
-- in the basin, and once switched off it adds none.
-- frames: 120
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 2, substeps = 2 },
    capacity = 2000,
    container = { min = { 0, 0, 0 }, max = { 0.6, 0.5, 0.6 } },
}
local rate = 200
local jet = seiche.emitter { position = { 0.3, 0.4, 0.3 }, direction = { 0, -1, 0 }, speed = 1.0, rate = rate,
                             radius = 0.06 }
local at_half, at_off

function on_start()
    -- 9 nozzle points (4 cm lattice on a 6 cm disc) at 1 m/s: 225 particles/s at most.
    seiche.check(math.abs(seiche.max_emitter_rate(1.0, 0.06) - 225) < 1e-3, "max rate " .. seiche.max_emitter_rate(1.0, 0.06))
    seiche.check(jet:get().rate == rate and jet:get().enabled, "emitter:get returns the def")
end

function on_step(dt, t)
    local f = seiche.frame()
    if f == 30 then at_half = seiche.particle_count() end
    if f == 90 then
        local added = seiche.particle_count() - at_half
        seiche.check(math.abs(added - rate) <= 9, string.format("1 s at %d/s added %d particles", rate, added))
        local inside = seiche.particles_in({ 0, 0, 0 }, { 0.6, 0.5, 0.6 })
        seiche.check(inside == seiche.particle_count(), string.format("%d of %d particles in the basin", inside,
                                                                      seiche.particle_count()))
        jet:set_enabled(false)
    end
    if f == 92 then at_off = seiche.particle_count() end
    if f == 120 then
        seiche.check(seiche.particle_count() == at_off, "a disabled emitter added particles")
        seiche.check(seiche.stats().nan == 0, "NaN particles")
    end
end
