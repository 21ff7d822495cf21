-- The dam-break surge front (tools/dam_break_front.lua: a column a = 0.2 m wide and 2a
-- high, 5 mm particles) at the defaults (the walls' skin friction C_f = 0.02) stays within
-- 10 % of Martin & Moyce's front (1952, Table 2) for 0.5 <= T <= 3: worst +7.9 % measured
-- (at T = 1.16; +8.9 % at C_f = 0.01). With frictionless walls (fluid.wall_friction=0) it
-- leads by 10.4 % at T = 1.3 and by 8.9 % at T = 3, and fails. docs/validation.md,
-- "Dam-break front", has three spacings.
-- frames: 20
-- trusted: runs tools/dam_break_front.lua (dofile)
local here = debug.getinfo(1, "S").source:match("^@(.*)/[^/]*$") or "."
front_radius = 0.005
dofile(here .. "/../../tools/dam_break_front.lua")
local tool_step = on_step
function on_step(dt, t)
    tool_step(dt, t)
    if seiche.frame() == 19 then
        local d = dam_break_front
        print(string.format("dam_break_front: worst %+.1f %% at T = %.2f (up to T = %.2f)", 100 * d.worst, d.at, d.last_T))
        seiche.check(d.last_T > 3.0, "the run did not reach T = 3")
        seiche.check(math.abs(d.worst) < 0.10, string.format("the front is %+.1f %% off Martin & Moyce at T = %.2f",
                                                             100 * d.worst, d.at))
    end
end
