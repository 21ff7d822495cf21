#version 430
// Stage grid scan, part 1: exclusive prefix sum inside blocks of PBF_SCAN_BLOCK elements;
// each block's total goes to sums[block]. The block is loaded into shared memory with
// consecutive threads on consecutive elements (coalesced on a GPU), each of the
// PBF_SCAN_WG threads then scans PBF_SCAN_PER_THREAD consecutive elements there on its own,
// the thread totals are scanned in shared memory (log2(PBF_SCAN_WG) barriers: barriers are
// what costs on CPU drivers), and the block goes back out coalesced. Shared memory is
// padded by a word every 32 so that the threads' runs fall in different banks.
#include "pbf_shared.h"
layout(local_size_x = PBF_SCAN_WG) in;
layout(std430, binding = PBF_B_SCAN_DATA) buffer Data { uint data[]; };
layout(std430, binding = PBF_B_SCAN_SUMS) buffer Sums { uint sums[]; };
uniform uint scan_n;

shared uint tile[PBF_SCAN_BLOCK + PBF_SCAN_BLOCK / 32];
shared uint part[PBF_SCAN_WG];

uint padded(uint i) { return i + (i >> 5); }

void main()
{
    uint t = gl_LocalInvocationID.x;
    uint block = gl_WorkGroupID.x * uint(PBF_SCAN_BLOCK);
    for (uint k = 0u; k < uint(PBF_SCAN_PER_THREAD); k++) {
        uint e = k * uint(PBF_SCAN_WG) + t, a = block + e;
        tile[padded(e)] = a < scan_n ? data[a] : 0u;
    }
    barrier();
    uint run0 = t * uint(PBF_SCAN_PER_THREAD);
    uint total = 0u;
    for (uint k = 0u; k < uint(PBF_SCAN_PER_THREAD); k++) { // exclusive, in place
        uint s = padded(run0 + k);
        uint v = tile[s];
        tile[s] = total;
        total += v;
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
    for (uint k = 0u; k < uint(PBF_SCAN_PER_THREAD); k++) tile[padded(run0 + k)] += run;
    barrier();
    for (uint k = 0u; k < uint(PBF_SCAN_PER_THREAD); k++) {
        uint e = k * uint(PBF_SCAN_WG) + t, a = block + e;
        if (a < scan_n) data[a] = tile[padded(e)];
    }
}
