#version 430
// Stage tension, first part: the surface normal of each particle,
// n_i = -h sum_j V_j grad_i W_ij (pbf_kernels.h, tension_normal_of), with the neighbours'
// volumes V_j = m / rho_j in vel[j].w (velocity pass). Runs only with surface_tension > 0.
#define USE_POS
#define USE_VEL
#define USE_NB
#define USE_NORMAL
#define WRITE_NORMAL
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 xi = pos[i].xyz;
    vec3 n = vec3(0.0);
    uint nn = nb_len(i);
    for (uint q = 0u; q < nn; q++) {
        uint j = nb_at(i, q);
        n += tension_normal_of(xi - pos[j].xyz, vel[j].w);
    }
    normal[i] = vec4(n, 0.0);
}
