#version 430
// Stage level, a sweep: the cells of one colour of a red-black ordering take their relaxed
// p (pbf_kernels.h level_relaxed), so none reads a cell this pass writes; the threads
// stride over the cells.
#define USE_LEVEL
#define WRITE_LEVEL
#include "common.glsl"
layout(local_size_x = PBF_WG) in;
uniform uint parity; // this pass's cells: those whose x + y + z has this parity

void main()
{
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint id = gl_GlobalInvocationID.x; id < P.level_dims.w; id += stride)
        if (level_parity(id) == parity) level[id].p = level_relaxed(id);
}
