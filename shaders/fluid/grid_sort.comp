#version 430
// Stage grid sort: the scatter put each cell's particles in its range in an order that
// depends on thread timing; here each particle takes the rank of its previous slot among
// its cell's, so the new order is a stable counting sort and runs are bit-identical. One
// thread per particle (cells hold a handful), so empty cells cost nothing; a cell of more
// than PBF_SORT_RANK_MAX keeps the scatter's order (pbf_shared.h).
#define USE_CELL
#define USE_CELL_START
#define USE_SORTED
#define USE_ORDER
#define WRITE_ORDER
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint k = gl_GlobalInvocationID.x;
    if (k >= particle_count()) return;
    uint me = sorted_slot[k];
    uint c = cell_of[me];
    uint b = cell_start[c], e = cell_start[c + 1u];
    if (e - b > uint(PBF_SORT_RANK_MAX)) { // a pile: the scatter's order (slot k is in [b, e))
        order[k] = me;
        return;
    }
    uint rank = 0u;
    for (uint m = b; m < e; m++) rank += sorted_slot[m] < me ? 1u : 0u;
    order[b + rank] = me;
}
