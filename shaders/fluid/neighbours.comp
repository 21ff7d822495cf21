#version 430
// Stage neighbours: once per substep, after the reorder, each particle lists the slots of
// the particles within h of its predicted position (the paper's "find neighbours"); the
// solver iterations and the velocity passes then walk the list instead of 27 cells.
// A particle with more neighbours than the list holds keeps the first max_neighbours found
// (in cell order) and is counted in the metrics (overflow); nothing is written out of bounds.
#define USE_PRED
#define USE_CELL_START
#define USE_NB
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 xi = pred[i].xyz;
    ivec3 c = cell_coord(xi);
    uint n = 0u;
    uint base = i * P.max_neighbours;
    float h2 = P.h * P.h;
    FOR_NEIGHBOURS(c, j) {
        vec3 r = xi - pred[j].xyz;
        if (dot(r, r) < h2 && j != i) {
            if (n < P.max_neighbours) nb_list[base + n] = j;
            n++;
        }
    }
    nb_count[i] = n;
}
