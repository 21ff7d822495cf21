#version 430
// Stage grid sort: one thread per cell sorts its slots by the particles' previous slot,
// so the new order is a stable counting sort and runs are bit-identical.
#define USE_CELL_START
#define USE_SORTED
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint c = gl_GlobalInvocationID.x;
    if (c > P.grid_dims.w) return; // the real cells and the removed cell
    uint b = cell_start[c], e = cell_start[c + 1u];
    for (uint k = b + 1u; k < e; k++) {
        uint v = sorted_slot[k];
        uint m = k;
        while (m > b && sorted_slot[m - 1u] > v) {
            sorted_slot[m] = sorted_slot[m - 1u];
            m--;
        }
        sorted_slot[m] = v;
    }
}
