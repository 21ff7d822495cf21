#version 430
// Stage velocity: v = (x* - x) / dt, clamped to the maximum speed; x = x*.
#define USE_POS
#define USE_VEL
#define USE_PRED
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 x = pred[i].xyz;
    vec3 v = (x - pos[i].xyz) * P.inv_dt;
    float s = length(v);
    if (s > P.max_speed) v *= P.max_speed / s;
    vel[i] = vec4(v, vel[i].w);
    pos[i].xyz = x;
}
