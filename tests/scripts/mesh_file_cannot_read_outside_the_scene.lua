-- A glTF file inside the scene's folder names its buffer by a path that leaves it
-- (assets/buffer_outside_the_scene.gltf: "../../fixtures/tetrahedron_buffer.bin"). Until 0.19.4 the
-- importer opened it with its own file access, so a sandboxed scene could read any file the
-- runner could (an outside review read a tetrahedron's volume out of a file beside the scene's
-- folder). The importer now reads only regular files inside the scene's folder: the call fails,
-- naming the file it refused.
-- frames: 1
-- expect-exit: 2
-- expect-stderr: mesh_file_cannot_read_outside_the_scene.lua:13: seiche.body: mesh file
-- expect-stderr: buffer_outside_the_scene.gltf' could not be read: it refers to
-- expect-stderr: fixtures/tetrahedron_buffer.bin', which is not a regular file inside
seiche.scene { name = "mesh_file_cannot_read_outside_the_scene", capacity = 100 }
seiche.body { mesh = "assets/buffer_outside_the_scene.gltf", kind = "static", position = { 0.5, 0.5, 0.5 } }
