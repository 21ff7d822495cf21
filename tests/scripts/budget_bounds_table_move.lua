-- C library calls that loop as often as an argument says are counted against the budget
-- (table.move of 1e15 elements is one call; before, it never ended). string.rep of an
-- empty string 1e15 times is done at once: there is nothing to repeat.
-- expect-exit: 2
-- expect-stderr: budget_bounds_table_move.lua:11: on_step ran longer than its budget of 0.3 s
-- frames: 5
-- budget: 0.3
seiche.scene { capacity = 100, container = { min = { 0, 0, 0 }, max = { 0.2, 0.2, 0.2 } } }
function on_step(dt, t)
    seiche.check(string.rep("", 1e15) == "", "string.rep of nothing is empty")
    table.move({}, 1, 1e15, 1)
end
