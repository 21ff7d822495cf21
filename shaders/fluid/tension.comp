#version 430
// Stage tension (surface_tension > 0), after the neighbour search: each particle's cohesion
// acceleration at the predicted positions, a_i = sum_j tension_pair (pbf_kernels.h), into
// tension[i] (for inspection), and x* += dt^2 a_i into pred_out (lambda kept in w), so that
// the solve of this substep answers the pull and the velocity (x - x0) / dt carries it.
// The pull is taken where the constraint pushes, at x*: taken at the substep's start x0 and
// pushed back at x*, whose pair directions the substep's motion has turned, the two did not
// cancel along the motion, and a droplet spun up and buzzed (docs/solver.md, "Surface
// tension"). Densities from the volumes in vel.w (the last substep's).
#define USE_PRED
#define USE_PRED_OUT
#define WRITE_PRED_OUT
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
    vec4 pi = pred[i];
    vec3 xi = pi.xyz;
    float rho_i = P.mass / max(vel[i].w, 1e-12);
    vec3 a = vec3(0.0);
    uint nn = nb_len(i);
    for (uint q = 0u; q < nn; q++) {
        uint j = nb_at(i, q);
        a += tension_pair(xi - pred[j].xyz, rho_i, P.mass / max(vel[j].w, 1e-12));
    }
    tension[i] = vec4(a, 0.0);
    pred_out[i] = vec4(xi + (P.dt * P.dt) * a, pi.w);
}
