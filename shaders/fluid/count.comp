#version 430
// The live particle count, on the GPU (one thread):
//   mode 0, after the grid was built: particles that entered a sink were sorted into the
//     removed cell after all real cells, so the live count is that cell's start;
//   mode 1, after an append: the appended particles that fitted the capacity are added.
// Then the indirect dispatch size of the particle passes and the draw command follow.
#define USE_CELL_START
#define WRITE_STATE
#include "common.glsl"
layout(local_size_x = 1) in;
layout(std430, binding = PBF_B_DRAW) buffer Draw { uint draw_cmd[4]; };

void main()
{
    uint n = state.count;
    if (P.count_mode == 0u) {
        uint alive = cell_start[P.grid_dims.w];
        state.removed += n - alive;
        n = alive;
    } else {
        uint room = P.capacity - n;
        uint add = min(P.append_count, room);
        state.dropped += P.append_count - add;
        n += add;
    }
    state.count = n;
    state.groups_x = (n + uint(PBF_WG) - 1u) / uint(PBF_WG);
    state.groups_y = 1u;
    state.groups_z = 1u;
    draw_cmd[0] = 4u;
    draw_cmd[1] = n;
    draw_cmd[2] = 0u;
    draw_cmd[3] = 0u;
}
