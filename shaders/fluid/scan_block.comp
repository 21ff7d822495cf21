#version 430
// Stage grid scan, part 1: exclusive prefix sum inside blocks of PBF_SCAN_BLOCK elements;
// each block's total goes to sums[block]. Each of the PBF_SCAN_WG threads sums
// PBF_SCAN_PER_THREAD consecutive elements on its own, the thread totals are scanned in
// shared memory (log2(PBF_SCAN_WG) barriers: barriers are what costs on CPU drivers),
// then each thread writes its run.
#include "pbf_shared.h"
layout(local_size_x = PBF_SCAN_WG) in;
layout(std430, binding = PBF_B_SCAN_DATA) buffer Data { uint data[]; };
layout(std430, binding = PBF_B_SCAN_SUMS) buffer Sums { uint sums[]; };
uniform uint scan_n;

shared uint part[PBF_SCAN_WG];

void main()
{
    uint t = gl_LocalInvocationID.x;
    uint base = gl_WorkGroupID.x * uint(PBF_SCAN_BLOCK) + t * uint(PBF_SCAN_PER_THREAD);
    uint v[PBF_SCAN_PER_THREAD];
    uint total = 0u;
    for (uint k = 0u; k < uint(PBF_SCAN_PER_THREAD); k++) {
        uint a = base + k;
        v[k] = a < scan_n ? data[a] : 0u;
        total += v[k];
    }
    part[t] = total;
    // Inclusive Hillis-Steele scan of the thread totals.
    for (uint d = 1u; d < uint(PBF_SCAN_WG); d <<= 1) {
        barrier();
        uint add = t >= d ? part[t - d] : 0u;
        barrier();
        part[t] += add;
    }
    barrier();
    uint run = part[t] - total; // exclusive prefix of this thread's run
    if (t == uint(PBF_SCAN_WG) - 1u) sums[gl_WorkGroupID.x] = part[t];
    for (uint k = 0u; k < uint(PBF_SCAN_PER_THREAD); k++) {
        uint a = base + k;
        if (a < scan_n) data[a] = run;
        run += v[k];
    }
}
