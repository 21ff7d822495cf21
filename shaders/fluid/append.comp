#version 430
// Appends the staged particles (emitters, blocks, points) after the live ones, as far as
// the capacity allows; the count pass (mode 1) then takes them in.
#define USE_POS
#define WRITE_POS
#define USE_VEL
#define WRITE_VEL
#define USE_PRED
#define WRITE_PRED
#define USE_ID
#define WRITE_ID
#define USE_TENSION
#define WRITE_TENSION
#include "common.glsl"
layout(local_size_x = PBF_WG) in;
layout(std430, binding = PBF_B_STAGE_POS) readonly buffer StagePos { vec4 stage_pos[]; };
layout(std430, binding = PBF_B_STAGE_VEL) readonly buffer StageVel { vec4 stage_vel[]; };
layout(std430, binding = PBF_B_STAGE_ID) readonly buffer StageId { uint stage_id[]; };

void main()
{
    uint k = gl_GlobalInvocationID.x;
    if (k >= P.append_count) return;
    uint slot = state.count + k;
    if (slot >= P.capacity) return;
    pos[slot] = stage_pos[k];
    pred[slot] = vec4(stage_pos[k].xyz, 0.0);
    vel[slot] = stage_vel[k];
    pid[slot] = stage_id[k];
    tension[slot] = vec4(0.0); // no pull before its first tension pass
}
