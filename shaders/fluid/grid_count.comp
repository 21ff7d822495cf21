#version 430
// Stage grid count: the cell of each predicted position, and particles per cell.
// cell_start was cleared to zero before this pass.
#define USE_PRED
#define USE_CELL
#define USE_CELL_START
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= P.count) return;
    uint c = cell_index(cell_coord(pred[i].xyz));
    cell_of[i] = c;
    atomicAdd(cell_start[c], 1u);
}
