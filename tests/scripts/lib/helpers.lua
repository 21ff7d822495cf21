-- A module for require_loads_from_the_scene_folder.lua (not a test itself: tests/run.sh runs
-- tests/scripts/*.lua only).
local M = {}
function M.double(x) return 2 * x end
return M
