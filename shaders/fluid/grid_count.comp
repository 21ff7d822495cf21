#version 430
// Stage grid count: the bucket of each predicted position's cell, and particles per bucket
// (common.glsl bucket_of). grid_clear zeroed cell_start before this pass. A particle inside
// a sink goes to the extra bucket P.grid_dims.w ("removed"), which sorts after every real
// bucket; the count pass then drops it from the live range.
#define USE_PRED
#define USE_CELL
#define WRITE_CELL
#define USE_CELL_START
#define WRITE_CELL_START
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 x = pred[i].xyz;
    uint c = bucket_of(cell_coord(x));
    for (uint k = 0u; k < P.sink_count; k++)
        if (all(greaterThanEqual(x, P.sink_min[k].xyz)) && all(lessThanEqual(x, P.sink_max[k].xyz)))
            c = P.grid_dims.w;
    cell_of[i] = c;
    atomicAdd(cell_start[c], 1u);
}
