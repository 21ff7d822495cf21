-- A plate on an axle (it turns about z only; the axle takes the force) under a jet falling on
-- one arm: the angular momentum it gains, I w, is the angular impulse the water gives it, the
-- integral of body:fluid_torque() (the torque is applied a step late, so I w trails it a little
-- at first). Until 0.19.4 the coupling's impulse limit, meant for a light body's plunge, cut the
-- torque with the linear force that the axle carries: the plate got 30 % of it.
-- frames: 13
seiche.scene { name = "jet_turns_a_plate_on_an_axle", capacity = 8000,
    container = { min = { 0, 0, 0 }, max = { 0.6, 0.6, 0.3 } } }
local plate = seiche.body { shape = "box", size = { 0.3, 0.02, 0.1 }, position = { 0.3, 0.3, 0.15 },
    density = 1000, axle = "z" }
seiche.emitter { position = { 0.4, 0.45, 0.15 }, direction = { 0, -1, 0 }, speed = 3, radius = 0.03 }
local m = 0.3 * 0.02 * 0.1 * 1000
local inertia = m * (0.3 ^ 2 + 0.02 ^ 2) / 12
local impulse = 0

function on_step(dt, t)
    local _, torque = plate:fluid_force()
    impulse = impulse + torque.z * dt
    if seiche.frame() == 13 then
        local gained = inertia * plate:angular_velocity().z
        seiche.check(impulse < -0.02, string.format("the jet gave only %.4f N m s about the axle", impulse))
        local ratio = gained / impulse
        print(string.format("at %.3f s: I w %.5f N m s of the water's %.5f (%.3f)", t, gained, impulse, ratio))
        seiche.check(ratio > 0.8 and ratio < 1.25,
            string.format("the plate gained %.5f N m s of angular momentum for the water's %.5f (ratio %.3f)", gained, impulse, ratio))
    end
end
