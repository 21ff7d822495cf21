#version 430
// Stage grid scan, part 2: adds each block's scanned offset to its elements.
#include "pbf_shared.h"
layout(local_size_x = PBF_SCAN_WG) in;
layout(std430, binding = PBF_B_SCAN_DATA) buffer Data { uint data[]; };
layout(std430, binding = PBF_B_SCAN_SUMS) buffer Sums { uint sums[]; };
uniform uint scan_n;

void main()
{
    uint block = gl_WorkGroupID.x;
    uint base = block * PBF_SCAN_BLOCK;
    uint a = base + 2u * gl_LocalInvocationID.x;
    uint add = sums[block];
    if (a < scan_n) data[a] += add;
    if (a + 1u < scan_n) data[a + 1u] += add;
}
