-- A mesh file of 300 bytes that declares two billion vertices (assets/hostile_ply_declares_billions.ply,
-- a copy of tests/fixtures/'s). assimp reserves room for all of them: before 0.20.1 the importer
-- took 3.7 GB within 30 s and went on until the call's budget ran out. Its process may now take
-- 4096 MiB at most: the call fails at once with a message naming the limit, and a script that
-- catches it goes on (the scene runs, with the body it made instead).
-- frames: 3
-- unsanitized: AddressSanitizer reports the importer's failed allocation instead of throwing it
local ok, err = pcall(seiche.body, { mesh = "assets/hostile_ply_declares_billions.ply", kind = "static" })
seiche.check(not ok, "a file that declares two billion vertices was read")
print(err)
seiche.check(tostring(err):find("the importer ran out of its memory (4096 MiB", 1, true) ~= nil,
             "the refusal does not name the importer's memory limit: " .. tostring(err))
seiche.scene { name = "mesh_file_that_declares_billions_is_refused", capacity = 1000 }
seiche.block { min = { 0.4, 0, 0.4 }, max = { 0.6, 0.1, 0.6 } }
seiche.body { shape = "box", size = { 0.1, 0.1, 0.1 }, kind = "static", position = { 0.2, 0.05, 0.2 } }
