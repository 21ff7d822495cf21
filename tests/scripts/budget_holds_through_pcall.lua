-- A loop around pcall cannot swallow the budget: once over, every instruction raises the
-- budget error again (in every coroutine) until the runner's own call returns; xpcall's
-- handler runs after the stack unwound, with the budget still on.
-- expect-exit: 2
-- expect-stderr: budget_holds_through_pcall.lua:13: on_step ran longer than its budget of 0.3 s (an endless loop?)
-- frames: 5
-- budget: 0.3
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }

local spin = coroutine.wrap(function()
    while true do
        pcall(function()
            while true do end
        end)
        xpcall(function() while true do end end, function() while true do end end)
        coroutine.yield()
    end
end)

function on_step(dt, t)
    while true do
        pcall(spin)
        pcall(pcall, pcall, spin)
    end
end
