#version 430
// Stage grid count, first part: zeroes the bucket counters (cell_start, P.grid_dims.w + 2
// entries) and scatter cursors (cell_fill, P.grid_dims.w + 1) for this substep. A pass over
// the buckets, which are a few per particle: no clear of anything the size of the world.
#define USE_CELL_START
#define WRITE_CELL_START
#define USE_CELL_FILL
#define WRITE_CELL_FILL
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    uint buckets = P.grid_dims.w;
    if (i < buckets + 2u) cell_start[i] = 0u;
    if (i < buckets + 1u) cell_fill[i] = 0u;
}
