#version 430
// Stage level, second pass: each coarse cell's E from the deposit's sums (pbf_kernels.h
// level_compression), p from zero, and the sums zeroed for the next substep's deposit. The
// threads stride over the cells, as in grid_clear.
#define USE_LEVEL
#define WRITE_LEVEL
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint c = gl_GlobalInvocationID.x; c < P.level_dims.w; c += stride) {
        level[c].e = level_compression(level[c].weight, level[c].excess);
        level[c].p = 0.0;
        level[c].weight = 0;
        level[c].excess = 0;
    }
}
