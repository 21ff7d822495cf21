#version 430
// Stage reorder: gathers particle data into cell order (the *_out buffers), so that
// neighbour reads hit memory that is close together.
#define USE_POS
#define USE_VEL
#define USE_PRED
#define USE_ID
#define USE_POS_OUT
#define WRITE_POS_OUT
#define USE_VEL_OUT
#define WRITE_VEL_OUT
#define USE_PRED_OUT
#define WRITE_PRED_OUT
#define USE_ID_OUT
#define WRITE_ID_OUT
#define USE_ORDER
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    uint j = order[i];
    pos_out[i] = pos[j];
    vel_out[i] = vel[j];
    pred_out[i] = pred[j];
    pid_out[i] = pid[j];
}
