#version 430
// Stage predict: gravity (and the surface tension of the last substep's tension pass, whose
// buffer holds zeros for new particles), damping and the speed clamp on v; x* = x + dt v.
#define USE_POS
#define USE_VEL
#define WRITE_VEL
#define USE_PRED
#define WRITE_PRED
#define USE_TENSION
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 a = P.gravity.xyz;
    if (P.surface_tension > 0.0) a += tension[i].xyz;
    vec3 v = vel[i].xyz + P.dt * a;
    v *= 1.0 / (1.0 + P.damping * P.dt);
    float s = length(v);
    if (s > P.max_speed) v *= P.max_speed / s;
    vel[i].xyz = v;
    pred[i] = vec4(pos[i].xyz + P.dt * v, 0.0);
}
