-- A carriage on a slider (seiche.joint{kind = "slider", motor = ...}) along x, tied to the
-- world: its motor drives it at 0.5 m/s with at most 40 N; the slider holds it up against
-- gravity and keeps it from turning. Halfway the motor is set to -0.3 m/s, and then turned off
-- (set_motor(false)): it coasts at the speed it had. The joint's position() follows the
-- carriage's displacement along the axis.
-- frames: 150
seiche.scene {
    fluid = { particle_radius = 0.02, kernel_radius = 0.08, iterations = 1, substeps = 4 },
    capacity = 100,
    domain = { min = { 0, 0, 0 }, max = { 1, 1, 1 } },
}
local cart = seiche.body { shape = "box", size = { 0.2, 0.1, 0.1 }, position = { 0.5, 0.5, 0.5 }, density = 1000 }
local rail = seiche.joint { kind = "slider", a = cart, axis = { 1, 0, 0 }, motor = { speed = 0.5, max_force = 40 } }
seiche.check(rail:get().anchor.x == 0.5, "the anchor defaults to the body's centre")
local x_at = {}

function on_step(dt, t)
    local f, p, v = seiche.frame(), cart:position(), cart:velocity()
    x_at[f] = p.x
    seiche.check(math.abs(rail:position() - (p.x - 0.5)) < 1e-3,
                 string.format("frame %d: position() %.4f, moved %.4f", f, rail:position(), p.x - 0.5))
    seiche.check(math.abs(p.y - 0.5) < 2e-3 and math.abs(p.z - 0.5) < 1e-3, string.format("off the rail: y %.4f", p.y))
    if f == 60 then
        local speed = (x_at[60] - x_at[40]) / (20 * dt)
        print(string.format("slider: %.4f m/s by position after 1 s (motor 0.5), v.x %.4f", speed, v.x))
        seiche.check(math.abs(speed - 0.5) < 0.01 and math.abs(v.x - 0.5) < 0.01, "the motor should hold 0.5 m/s")
        rail:set_motor { speed = -0.3, max_force = 40 }
        seiche.check(math.abs(rail:get().motor.speed + 0.3) < 1e-6, "get() shows the new motor")
    elseif f == 100 then
        local speed = (x_at[100] - x_at[90]) / (10 * dt)
        print(string.format("slider: %.4f m/s after the change to -0.3", speed))
        seiche.check(math.abs(speed + 0.3) < 0.01, "the motor should hold -0.3 m/s")
        rail:set_motor(false)
        seiche.check(rail:get().motor == nil, "no motor in get() once it is off")
    elseif f == 140 then
        local speed = (x_at[140] - x_at[120]) / (20 * dt)
        print(string.format("slider: coasting at %.4f m/s", speed))
        seiche.check(math.abs(speed + 0.3) < 0.01, "without its motor it keeps its speed (no friction on the rail)")
    end
end
