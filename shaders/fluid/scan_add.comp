#version 430
// Stage grid scan, part 2: adds each block's scanned offset to its elements, consecutive
// threads on consecutive elements (coalesced on a GPU).
#include "pbf_shared.h"
layout(local_size_x = PBF_SCAN_WG) in;
layout(std430, binding = PBF_B_SCAN_DATA) buffer Data { uint data[]; };
layout(std430, binding = PBF_B_SCAN_SUMS) readonly buffer Sums { uint sums[]; };
uniform uint scan_n;

void main()
{
    uint block = gl_WorkGroupID.x;
    uint add = sums[block];
    uint base = block * uint(PBF_SCAN_BLOCK) + gl_LocalInvocationID.x;
    for (uint k = 0u; k < uint(PBF_SCAN_PER_THREAD); k++) {
        uint a = base + k * uint(PBF_SCAN_WG);
        if (a < scan_n) data[a] += add;
    }
}
