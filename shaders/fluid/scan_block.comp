#version 430
// Stage grid scan, part 1: exclusive prefix sum inside blocks of PBF_SCAN_BLOCK
// elements (two per thread); each block's total goes to sums[block].
#include "pbf_shared.h"
layout(local_size_x = PBF_SCAN_WG) in;
layout(std430, binding = PBF_B_SCAN_DATA) buffer Data { uint data[]; };
layout(std430, binding = PBF_B_SCAN_SUMS) buffer Sums { uint sums[]; };
uniform uint scan_n;

shared uint tmp[PBF_SCAN_BLOCK];

void main()
{
    uint t = gl_LocalInvocationID.x;
    uint base = gl_WorkGroupID.x * PBF_SCAN_BLOCK;
    uint a = base + 2u * t, b = a + 1u;
    tmp[2u * t] = a < scan_n ? data[a] : 0u;
    tmp[2u * t + 1u] = b < scan_n ? data[b] : 0u;
    // Up-sweep (reduce).
    uint offset = 1u;
    for (uint d = PBF_SCAN_BLOCK >> 1; d > 0u; d >>= 1) {
        barrier();
        if (t < d) {
            uint ai = offset * (2u * t + 1u) - 1u;
            uint bi = offset * (2u * t + 2u) - 1u;
            tmp[bi] += tmp[ai];
        }
        offset <<= 1;
    }
    barrier();
    if (t == 0u) {
        sums[gl_WorkGroupID.x] = tmp[PBF_SCAN_BLOCK - 1];
        tmp[PBF_SCAN_BLOCK - 1] = 0u;
    }
    // Down-sweep.
    for (uint d = 1u; d < PBF_SCAN_BLOCK; d <<= 1) {
        offset >>= 1;
        barrier();
        if (t < d) {
            uint ai = offset * (2u * t + 1u) - 1u;
            uint bi = offset * (2u * t + 2u) - 1u;
            uint x = tmp[ai];
            tmp[ai] = tmp[bi];
            tmp[bi] += x;
        }
    }
    barrier();
    if (a < scan_n) data[a] = tmp[2u * t];
    if (b < scan_n) data[b] = tmp[2u * t + 1u];
}
