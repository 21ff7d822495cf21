#version 430
// Stage tension (surface_tension > 0): each particle's cohesion acceleration at the substep's
// end, a_i = sum_j tension_pair (pbf_kernels.h), into tension[i]; the next predict adds
// dt a_i to the velocity with gravity, so that the solve that follows answers it in the same
// substep (applied to the velocity here, the pull of every surface particle would show in
// its velocity though the constraint holds it still). Densities from the volumes in vel.w.
#define USE_POS
#define USE_VEL
#define USE_NB
#define USE_TENSION
#define WRITE_TENSION
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 xi = pos[i].xyz;
    float rho_i = P.mass / max(vel[i].w, 1e-12);
    vec3 a = vec3(0.0);
    uint nn = nb_len(i);
    for (uint q = 0u; q < nn; q++) {
        uint j = nb_at(i, q);
        a += tension_pair(xi - pos[j].xyz, rho_i, P.mass / max(vel[j].w, 1e-12));
    }
    tension[i] = vec4(a, 0.0);
}
