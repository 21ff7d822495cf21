-- A misspelt field is an error that lists the known ones, not a silent no-op.
-- expect-exit: 2
-- expect-stderr: unknown_field.lua:4: seiche.scene: unknown field "contaner"
seiche.scene {
    contaner = { min = { 0, 0, 0 }, max = { 1, 1, 1 } },
}
