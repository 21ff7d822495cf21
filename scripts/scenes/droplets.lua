-- Droplets: balls of water in weightlessness, held together by surface tension (docs/solver.md,
-- "Surface tension"). Two balls meet off-centre, merge and turn; throw more at them, or
-- switch gravity on and let the lot fall into a puddle.
--
--   build/bin/seiche scripts/scenes/droplets.lua
--
-- Keys:  b throw a ball at the middle from a random side    g gravity on / off
--        t surface tension 20 N/m / off (without it a thrown ball sprays apart)
--        r reset    space pause
-- The tension takes its substeps: 5 of a 1/60 s frame at 20 N/m (the explicit pull needs
-- them; far fewer blow a drop up); 5 N/m takes the default 4 and rounds a drop less.

local SIGMA = 20 -- N/m; water's own is 0.072: drops of a few particles' radius need far more
local R = 0.15  -- m: a ball's radius, 6 spacings (about 900 particles)

seiche.scene {
    name = "droplets",
    fluid = {
        particle_radius = 0.0125,
        kernel_radius = 0.05,
        iterations = 2,
        substeps = 4,
        surface_tension = SIGMA,
        vorticity = 0, -- nothing to confine in a droplet; its turning is kept as it is
    },
    gravity = { 0, 0, 0 },
    capacity = 8000,
    container = { min = { 0, 0, 0 }, max = { 2.0, 1.4, 1.4 } },
    camera = { eye = { 1.0, 1.2, 3.4 }, target = { 1.0, 0.7, 0.7 }, fov = 50 },
}

local MIDDLE = { 1.0, 0.7, 0.7 }

-- Two balls that meet a third of a radius off-centre: they merge and the merged drop turns.
seiche.sphere { center = { 0.45, 0.75, 0.7 }, radius = R, velocity = { 0.5, 0, 0 } }
seiche.sphere { center = { 1.55, 0.65, 0.7 }, radius = R, velocity = { -0.5, 0, 0 } }

math.randomseed(3) -- the same throws every run
local message, message_until = nil, 0

local function say(text, t)
    message, message_until = text, t + 2
end

-- A ball from a random point on a sphere about the middle, thrown at the middle at 1 m/s.
local balls, MOST = 2, 8 -- a ball is 925 particles; the capacity holds 8
local function throw(t)
    if balls >= MOST then
        say("full: r resets", t)
        return
    end
    balls = balls + 1
    local a = 2 * math.pi * math.random()
    local c = { MIDDLE[1] + 0.7 * math.cos(a), MIDDLE[2] + 0.3 * (2 * math.random() - 1), MIDDLE[3] + 0.45 * math.sin(a) }
    local d = { MIDDLE[1] - c[1], MIDDLE[2] - c[2], MIDDLE[3] - c[3] }
    local len = math.sqrt(d[1] * d[1] + d[2] * d[2] + d[3] * d[3])
    seiche.sphere { center = c, radius = R, velocity = { d[1] / len, d[2] / len, d[3] / len } }
end

local now = 0

function on_key(key, action)
    if action ~= "press" then return end
    if key == "b" then
        throw(now)
    elseif key == "g" then
        local falling = seiche.gravity().y ~= 0
        seiche.set_gravity(falling and { 0, 0, 0 } or { 0, -9.81, 0 })
        say(falling and "weightless" or "gravity on", now)
    elseif key == "t" then
        local on = seiche.param("surface_tension") > 0
        seiche.set_param("surface_tension", on and 0 or SIGMA)
        say(on and "surface tension off" or string.format("surface tension %g N/m", SIGMA), now)
    end
end

-- Half a second in, a third ball is thrown, as b would (in a window too; headless, a test
-- run, it is the only one).
seiche.after(0.5, function(t) throw(t) end)

function on_step(dt, t)
    now = t
    local st = seiche.stats()
    seiche.check(st.nan == 0, "no particle may become NaN")
    seiche.text(20, 20, string.format("%d particles, surface tension %g N/m, %d substeps", st.particles,
                                      seiche.param("surface_tension"), st.substeps))
    seiche.text(20, 50, "b throw a ball   g gravity   t tension")
    if message and t < message_until then seiche.text(20, 80, message, { colour = { 1, 0.85, 0.2 } }) end
end
