#version 430
// Stage velocity: v = (x* - x) / dt, clamped to the maximum speed; x = x*.
#define USE_POS
#define WRITE_POS
#define USE_VEL
#define WRITE_VEL
#define USE_PRED
#define USE_LAMBDA
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
    if (P.wall_friction > 0.0) v = wall_friction_of(x, v);
    // w: the particle's volume m / rho (m^3) from the last density pass, so the
    // vorticity and viscosity passes read a neighbour's velocity and volume in one load.
    vel[i] = vec4(v, P.mass / max(lambda_rho[i].y, 1e-6 * P.rest_density));
    pos[i].xyz = x;
}
