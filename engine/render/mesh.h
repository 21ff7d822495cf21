// GPU meshes for the renderer: indexed triangles with a position and a normal per vertex
// (VAO + VBO + EBO), made from primitive shapes or from arbitrary triangles.
//
// Meshes live in an eng_mesh_store and are named by eng_mesh_id values that carry a
// generation: a destroyed mesh's id stops being valid (eng_mesh_is_valid) instead of
// pointing at a reused slot. Scene nodes hold mesh ids; the renderer resolves them.
//
// Shapes are centred on the origin, Y up, lengths in metres. Round shapes are tessellated
// with eng_mesh_store_def.segments around their axis.
#ifndef ENG_MESH_H
#define ENG_MESH_H

#include <stdbool.h>
#include <stdint.h>

#include "engine/core/log.h"

/// A mesh in a store. All zero is the null id.
typedef struct eng_mesh_id {
    uint32_t index1;     ///< slot + 1; 0 = null
    uint32_t generation; ///< slot generation when created
} eng_mesh_id;

/// The null mesh id (all zero).
#define ENG_NULL_MESH ((eng_mesh_id){ 0, 0 })

typedef struct eng_mesh_store eng_mesh_store;

typedef struct eng_mesh_store_def {
    int segments;      ///< subdivisions around the axis of spheres, capsules, cylinders: 6..256
    int max_meshes;    ///< store capacity: 1..65536
    eng_logger logger; ///< input errors go here
} eng_mesh_store_def;

eng_mesh_store_def eng_default_mesh_store_def(void);

/// Creates an empty store (no GL calls yet). NULL with a logged message on a bad def.
eng_mesh_store *eng_mesh_store_create(const eng_mesh_store_def *def);
/// Destroys the store and every mesh in it; the GL context must be current.
void eng_mesh_store_destroy(eng_mesh_store *store);

/// The GL objects of one mesh, for drawing: glBindVertexArray(vao) then
/// glDrawElements(GL_TRIANGLES, index_count, GL_UNSIGNED_INT, 0).
/// Attribute 0 = position (vec3, m), attribute 1 = normal (vec3, unit).
typedef struct eng_mesh_gpu {
    unsigned vao, vbo, ebo;
    int vertex_count;
    int index_count;
    float bounds_min[3], bounds_max[3]; ///< axis-aligned bounds in m
} eng_mesh_gpu;

/// A plane in XZ facing +Y, `size_x` by `size_z` m (each > 0).
eng_mesh_id eng_mesh_create_plane(eng_mesh_store *store, float size_x, float size_z);
/// A box with half extents in m (each > 0), flat-shaded faces.
eng_mesh_id eng_mesh_create_box(eng_mesh_store *store, const float half_extents[3]);
/// A UV sphere of `radius` m (> 0).
eng_mesh_id eng_mesh_create_sphere(eng_mesh_store *store, float radius);
/// A capsule along Y: a cylinder of `radius` m from -half_height to +half_height, capped
/// by hemispheres (total height 2 half_height + 2 radius). radius > 0, half_height >= 0.
eng_mesh_id eng_mesh_create_capsule(eng_mesh_store *store, float radius, float half_height);
/// A closed cylinder along Y from -half_height to +half_height. radius, half_height > 0.
eng_mesh_id eng_mesh_create_cylinder(eng_mesh_store *store, float radius, float half_height);
/// A mesh from triangles: `vertex_count` positions (xyz in m, 3 floats each) and
/// `index_count` indices (a multiple of 3, each < vertex_count). Normals are flat, from
/// each triangle's winding (counter-clockwise seen from outside), so convex hulls and
/// triangle meshes from the physics side render with hard edges.
eng_mesh_id eng_mesh_create_triangles(eng_mesh_store *store, const float *positions, int vertex_count,
                                      const uint32_t *indices, int index_count);

void eng_mesh_destroy(eng_mesh_store *store, eng_mesh_id id);
bool eng_mesh_is_valid(const eng_mesh_store *store, eng_mesh_id id);
/// The GL objects of a valid mesh, NULL for a null or stale id.
const eng_mesh_gpu *eng_mesh_get_gpu(const eng_mesh_store *store, eng_mesh_id id);
/// Live meshes in the store.
int eng_mesh_store_count(const eng_mesh_store *store);

#endif
