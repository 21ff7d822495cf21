#version 430
// Stage predict: gravity, damping and the speed clamp on v; x* = x + dt v. (Surface tension
// moves x* after the neighbour search: tension.comp.)
#define USE_POS
#define USE_VEL
#define WRITE_VEL
#define USE_PRED
#define WRITE_PRED
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 a = P.gravity.xyz;
    vec3 v = vel[i].xyz + P.dt * a;
    v *= 1.0 / (1.0 + P.damping * P.dt);
    float s = length(v);
    if (s > P.max_speed) v *= P.max_speed / s;
    vel[i].xyz = v;
    pred[i] = vec4(pos[i].xyz + P.dt * v, 0.0);
}
