#version 430
// Stage vorticity: omega_i = curl v = sum_j (m / rho_j) grad_i W_ij x (v_j - v_i).
#define USE_POS
#define USE_VEL
#define USE_NB
#define USE_OMEGA
#define WRITE_OMEGA
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 xi = pos[i].xyz;
    vec3 vi = vel[i].xyz;
    vec3 w = vec3(0.0);
    uint nn = nb_len(i);
    for (uint q = 0u; q < nn; q++) {
        uint j = nb_at(i, q);
        vec4 vj = vel[j]; // w: volume m / rho_j (velocity pass)
        w += vj.w * cross(grad_spiky(xi - pos[j].xyz), vj.xyz - vi);
    }
    omega[i] = vec4(w, length(w));
}
