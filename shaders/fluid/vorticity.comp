#version 430
// Stage vorticity: omega_i, the curl of the velocity's first-order corrected gradient
// (corrected_curl, pbf_kernels.h), from the sums B = sum_j V_j (v_j - v_i) (x) grad_i W_ij
// and A = sum_j V_j (x_j - x_i) (x) grad_i W_ij, V_j = m / rho_j.
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
    vec3 bx = vec3(0.0), by = vec3(0.0), bz = vec3(0.0), ad = vec3(0.0), ao = vec3(0.0);
    uint nn = nb_len(i);
    for (uint q = 0u; q < nn; q++) {
        uint j = nb_at(i, q);
        vec4 vj = vel[j]; // w: volume m / rho_j (velocity pass)
        vec3 dx = pos[j].xyz - xi;
        vec3 g = vj.w * grad_spiky(-dx);
        vec3 dv = vj.xyz - vi;
        bx += dv.x * g;
        by += dv.y * g;
        bz += dv.z * g;
        ad += dx * g;
        ao += vec3(dx.x * g.y, dx.x * g.z, dx.y * g.z);
    }
    vec3 w = corrected_curl(bx, by, bz, ad, ao);
    omega[i] = vec4(w, length(w));
}
