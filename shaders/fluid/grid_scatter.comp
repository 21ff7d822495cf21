#version 430
// Stage grid scatter: each particle takes a slot in its cell's range. The order inside a
// cell depends on thread timing here; grid_sort makes it deterministic.
#define USE_CELL
#define USE_CELL_START
#define USE_CELL_FILL
#define WRITE_CELL_FILL
#define USE_SORTED
#define WRITE_SORTED
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    uint c = cell_of[i];
    uint slot = cell_start[c] + atomicAdd(cell_fill[c], 1u);
    sorted_slot[slot] = i;
}
