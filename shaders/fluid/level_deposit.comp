#version 430
// Stage level, first pass: each particle adds its trilinear weights over the eight nearest
// coarse cells' centres, and those weights times its compression rho / rho0 - 1 (from the
// density pass just before), in fixed point: integer atomics, so the sums do not depend on
// the order in which the particles add them (pbf_kernels.h level_corner).
#define USE_PRED
#define USE_LAMBDA
#define USE_LEVEL
#define WRITE_LEVEL
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 x = pred[i].xyz;
    float e;
    if (!level_excess(lambda_rho[i].y, e)) return; // not finite: the metrics report it
    for (int k = 0; k < 8; k++) {
        uint cell;
        float wgt = level_corner(x, k, cell);
        atomicAdd(level[cell].weight, level_fixed(wgt));
        atomicAdd(level[cell].excess, level_fixed(wgt * e));
    }
}
