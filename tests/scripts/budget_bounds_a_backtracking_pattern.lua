-- A backtracking pattern runs for hours inside one string.find call, where the VM's
-- count hook never fires; the sandbox's matcher counts its steps and stops at the budget.
-- expect-exit: 2
-- expect-stderr: budget_bounds_a_backtracking_pattern.lua:9: on_step ran longer than its budget of 0.3 s
-- frames: 5
-- budget: 0.3
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
function on_step(dt, t)
    while true do pcall(string.find, string.rep("a", 40), string.rep("a*", 40) .. "b") end
end
