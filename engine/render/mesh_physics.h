// Bullet shapes from a mesh (mesh_file.h), and through them the fluid's colliders.
//
// Dynamic bodies get the mesh's convex hull (Bullet simulates convex shapes well, and the
// fluid sees a hull as its face planes); static bodies get the triangles themselves (the
// fluid sees them through a signed distance grid). The fluid side needs nothing more from
// here: coupling a body (cpl_add_body, fluid/bullet/coupling.h) makes its collider from the
// shape, hull planes or a baked grid, so the same geometry stops bodies and water.
//
//     // a dynamic body from a mesh: its origin is the hull's centre of mass
//     eng_mesh_hull hull;
//     if (!eng_mesh_create_hull(phys, &mesh, ENG_MESH_HULL_DEFAULT_POINTS, &hull, err, sizeof err)) ...
//     eng_mesh_data_translate(&mesh, (float[3]){ -hull.centre_of_mass[0], -hull.centre_of_mass[1],
//                                                -hull.centre_of_mass[2] });  // draw it on the body
//     bd.shape = hull.shape;
//     bd.position = where the mesh's origin should be + rotation * centre_of_mass;
//
//     // a static body: the mesh frame is the body frame
//     phys_shape_id shape;
//     if (!eng_mesh_create_static_shape(phys, &mesh, &shape, err, sizeof err)) ...
//
// Costs and limits:
// - A hull is built from at most `max_points` of the mesh's vertices (the most extreme ones,
//   below), so it has at most 2 max_points - 4 faces: with ENG_MESH_HULL_MAX_POINTS that is
//   PBF_MAX_HULL_PLANES, the most the fluid's hull collider takes.
// - A static mesh coupled to the fluid is baked into a distance grid once (at most 128^3
//   samples at cpl_def.mesh_cell; the nearest triangle found through a hierarchy of boxes, so
//   the cost grows with the samples and only slowly with the triangles: docs/meshes.md), and
//   is one-sided: fluid belongs on the side its triangles face (outside, for a closed mesh as
//   loaded).
#ifndef ENG_MESH_PHYSICS_H
#define ENG_MESH_PHYSICS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "engine/render/mesh_file.h"
#include "fluid/bullet/phys.h"
#include "fluid/pbf.h"

/// The most points a hull from a mesh may have: its faces then fit the fluid's hull
/// collider (2 n - 4 <= PBF_MAX_HULL_PLANES). 130.
#define ENG_MESH_HULL_MAX_POINTS ((PBF_MAX_HULL_PLANES + 4) / 2)
/// The fewest (fewer cannot be trusted to span a volume).
#define ENG_MESH_HULL_MIN_POINTS 8
/// The default of scripts and tools.
#define ENG_MESH_HULL_DEFAULT_POINTS 64

/// Points for a convex hull of the mesh, at most `max_points` ([ENG_MESH_HULL_MIN_POINTS,
/// ENG_MESH_HULL_MAX_POINTS]), mesh frame, m: every vertex when there are no more than that;
/// else the vertices extreme along a fixed, evenly spread sequence of directions (the six
/// axes, then the eight corner and twelve edge diagonals of a cube, so the bounds are kept;
/// then a low-discrepancy spiral), added until max_points are found. The reduced hull lies
/// inside the mesh's hull: a finely divided sphere keeps 38 % of its volume at 8 points,
/// 88 % at 64, 94 % at 130 (tests/test_mesh_file.c). *out_points is malloc'd (free()); on failure NULL, with err
/// naming the mesh.
bool eng_mesh_hull_points(const eng_mesh_data *mesh, uint32_t max_points, phys_vec3 **out_points,
                          uint32_t *out_count, char *err, size_t err_size);

/// A convex hull shape made from a mesh.
typedef struct eng_mesh_hull {
    phys_shape_id shape;      ///< the hull, in its body's frame: the origin is its centre of mass
    /// m, mesh frame: the hull's centre of mass (of uniform density), where the body's origin
    /// lies in the mesh. Translate the mesh by minus this to draw it on the body.
    float centre_of_mass[3];
    float volume;             ///< m^3, the hull's (Bullet's exact hull volume)
    uint32_t point_count;     ///< corners of the hull
    uint32_t face_count;      ///< faces (at most PBF_MAX_HULL_PLANES)
} eng_mesh_hull;

/// Creates a convex hull shape for a dynamic body from the mesh (eng_mesh_hull_points with
/// `max_points`), moved so that its centre of mass is the shape's origin (phys.h: a body's
/// centre of mass is its origin). The mesh need not be closed. On failure returns false,
/// creates nothing and err names the mesh and the reason (Bullet's message included).
bool eng_mesh_create_hull(phys_world *world, const eng_mesh_data *mesh, uint32_t max_points, eng_mesh_hull *out,
                          char *err, size_t err_size);

/// Creates a triangle mesh shape of the mesh as it is (mesh frame = body frame), for a
/// static or kinematic body. Open meshes are allowed. On failure returns false, creates
/// nothing and err names the mesh and the reason.
bool eng_mesh_create_static_shape(phys_world *world, const eng_mesh_data *mesh, phys_shape_id *out, char *err,
                                  size_t err_size);

#endif
