// A static or kinematic triangle mesh as the fluid sees it: a signed distance grid, baked
// once when the body joins the coupling (coupling.c). Internal to the coupling.
#ifndef SEICHE_FLUID_BULLET_COUPLING_MESH_H
#define SEICHE_FLUID_BULLET_COUPLING_MESH_H

#include <stdbool.h>
#include <stdint.h>

#include "fluid/bullet/phys.h"
#include "fluid/pbf.h"

typedef struct cpl_mesh_bake {
    pbf_sdf_grid grid;  // its values are `values`
    float *values;      // malloc'd: the caller frees it once the collider has copied it
    float extent;       // m, the grid's largest side
    bool closed;        // every edge shared by two triangles: solid inside
    uint64_t triangle_tests; // closest-point tests the bake took (tests: far fewer than samples x triangles)
} cpl_mesh_bake;

// Bakes the mesh's signed distance, positive on the front side of the nearest triangle (the
// side its counter-clockwise winding faces), at *cell (made coarser, and written back, where
// the mesh needs more than 128 samples along an axis), with room for a kernel of radius h
// around it. A closed mesh is solid inside; an open one (a sheet, a terrain, a cup) is a shell
// h thick behind its triangles, so water on its back side stays there instead of being taken
// for water inside a solid and thrown out through the front. Exact (the same value as testing
// every triangle) within the band the fluid reads, h + 2 cells of the mesh (2 h + 2 cells
// for an open one, whose shell lies within it); beyond it the chamfer distance from the band,
// on the right side, never shorter than the true distance and at most 13 % longer. The
// nearest triangle comes from a hierarchy of boxes over the triangles, so the cost grows
// with the samples times the log of the triangles, not with their product. False when out of
// memory.
bool cpl_bake_mesh(const phys_triangle_mesh *mesh, float h, float *cell, cpl_mesh_bake *out);

#endif
