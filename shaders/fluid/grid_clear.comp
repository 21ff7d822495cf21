#version 430
// Stage grid count, first part: zeroes the bucket counters (cell_start, P.grid_dims.w + 2
// entries) and scatter cursors (cell_fill, P.grid_dims.w + 1) for this substep. A pass over
// the buckets, which are a few per particle: no clear of anything the size of the world.
// Each thread strides over the buckets, so the dispatch may have fewer groups than
// buckets / PBF_WG (GL promises only 65535 groups: 8.4M buckets, 2.1M particles).
#define USE_CELL_START
#define WRITE_CELL_START
#define USE_CELL_FILL
#define WRITE_CELL_FILL
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint buckets = P.grid_dims.w;
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < buckets + 2u; i += stride) {
        cell_start[i] = 0u;
        if (i < buckets + 1u) cell_fill[i] = 0u;
    }
}
