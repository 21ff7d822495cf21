-- A syntax error is reported with file:line and exit status 2.
-- expect-exit: 2
-- expect-stderr: syntax_error.lua:6:
seiche.scene { capacity = 100 }

local x = = 3
