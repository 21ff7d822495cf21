#version 430
// Stage grid count: the bucket of each predicted position's cell, and particles per bucket
// (common.glsl bucket_of). grid_clear zeroed cell_start before this pass. A particle inside
// a sink goes to the extra bucket P.grid_dims.w ("removed"), which sorts after every real
// bucket; the count pass then drops it from the live range. Colliders that block sinks
// (static bodies) shield what is inside them or behind them as seen from the sink's centre.
#define USE_PRED
#define USE_CELL
#define WRITE_CELL
#define USE_CELL_START
#define WRITE_CELL_START
#define USE_COLLIDERS
#include "common.glsl"
#include "colliders.glsl"
layout(local_size_x = PBF_WG) in;

// True when a sink-blocking collider lies between x and the centre c of a sink: x is
// inside it, or the straight path from x to c meets it (within a quarter particle radius).
// A collider that holds c itself (a drain set into a floor) does not block.
bool sink_shielded(vec3 x, vec3 c)
{
    for (uint b = 0u; b < P.collider_count; b++) {
        if ((colliders[b].info.y & PBF_COLLIDER_BLOCKS_SINKS) == 0u) continue;
        vec3 p1;
        vec4 q1;
        collider_end_pose(b, p1, q1);
        vec3 a = quat_rotate_inv(q1, x - p1), e = quat_rotate_inv(q1, c - p1), n;
        if (shape_distance(b, e, n) < 0.0) continue;
        float da = shape_distance(b, a, n);
        if (da < 0.0) return true;
        vec3 hit;
        if (sweep_hit(b, a, e, da, 0.25 * P.radius, hit)) return true;
    }
    return false;
}

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 x = pred[i].xyz;
    uint c = bucket_of(cell_coord(x));
    for (uint k = 0u; k < P.sink_count; k++)
        if (all(greaterThanEqual(x, P.sink_min[k].xyz)) && all(lessThanEqual(x, P.sink_max[k].xyz)) &&
            !sink_shielded(x, 0.5 * (P.sink_min[k].xyz + P.sink_max[k].xyz)))
            c = P.grid_dims.w;
    cell_of[i] = c;
    atomicAdd(cell_start[c], 1u);
}
