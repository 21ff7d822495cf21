#version 430
// Stage tension: cohesion and curvature (Akinci et al. 2013; pbf_kernels.h, tension_pair)
// as a velocity change, v += dt * -gamma sum_j K_ij (V0 C(r) r/|r| + n_i - n_j). Reads the
// normals of the pass before; densities from the volumes in vel.w. Writes vel_out.
#define USE_POS
#define USE_VEL
#define USE_VEL_OUT
#define WRITE_VEL_OUT
#define USE_NB
#define USE_NORMAL
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 xi = pos[i].xyz;
    vec4 vi = vel[i];
    vec3 ni = normal[i].xyz;
    float rho_i = P.mass / max(vi.w, 1e-12);
    vec3 a = vec3(0.0);
    uint nn = nb_len(i);
    for (uint q = 0u; q < nn; q++) {
        uint j = nb_at(i, q);
        float rho_j = P.mass / max(vel[j].w, 1e-12);
        a += tension_pair(xi - pos[j].xyz, rho_i, rho_j, ni, normal[j].xyz);
    }
    vel_out[i] = vec4(vi.xyz - P.dt * P.surface_tension * a, vi.w);
}
