-- F5 reloads the script (headless too, through an injected key): the file runs again in
-- a fresh Lua state, the world is rebuilt, on_start runs and then on_reload; the clock
-- starts again from zero. (The key is injected from on_step: asked for while the scene
-- loads, a reload is an error, reset_asked_while_loading.lua.)
-- frames: 20
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
seiche.block { min = { 0, 0, 0 }, max = { 0.1, 0.1, 0.1 } }

local started = false

function on_start()
    started = true
end

function on_reload()
    seiche.check(started, "on_start runs before on_reload")
    seiche.check(seiche.frame() == 0 and seiche.time() == 0, "a reloaded scene starts at frame 0")
    seiche.check(seiche.particle_count() > 0, "the reloaded world has its block")
    seiche.quit()
end

function on_step(dt, t)
    if seiche.frame() == 1 then seiche.inject_key("f5", "press") end
    seiche.check(seiche.frame() < 5, "F5 did not reload the script")
end
