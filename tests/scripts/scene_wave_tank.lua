-- scripts/scenes/wave_tank.lua as it ships: the paddle follows x = 0.06 + 0.05 sin(2 pi
-- 0.7 t) exactly, and the water in front of it rises and falls with it.
-- frames: 36
-- trusted: runs the shipped scripts/scenes/wave_tank.lua as it is (dofile), then adds checks
local here = debug.getinfo(1, "S").source:match("^@(.*)/[^/]*$") or "."
dofile(here .. "/../../scripts/scenes/wave_tank.lua")

local scene_step = on_step
local paddle
local low, high = math.huge, -math.huge

local scene_start = on_start
function on_start()
    scene_start()
    paddle = seiche.bodies()[1]
end

function on_step(dt, t)
    scene_step(dt, t)
    local f = seiche.frame()
    seiche.check(paddle:kind() == "kinematic", "the first body is the paddle")
    local want = 0.06 + 0.05 * math.sin(2 * math.pi * 0.7 * t)
    seiche.check(math.abs(paddle:position().x - want) < 1e-3,
                 string.format("paddle at %.4f m at t = %.3f s, want %.4f", paddle:position().x, t, want))
    if f % 6 == 0 then
        local h = seiche.surface_height(0.3, 0.21, 0.08)
        low, high = math.min(low, h), math.max(high, h)
    end
    if f == 36 then
        seiche.check(high - low > 0.01, string.format("the water by the paddle only moved %.3f m", high - low))
    end
end
