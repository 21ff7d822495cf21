#version 430
// Stage delta: the position correction
//   dp_i = omega * ( (m/rho0) sum_j (lambda_i + lambda_j + s_corr) grad W_ij
//                    - lambda_i sum_b G(d_b) n_b )
// then collisions: a particle closer than its radius to a boundary is moved out along the
// normal. Boundary moves of two-way colliders become reaction forces (fixed point).
#define USE_PRED
#define USE_PRED_OUT
#define USE_NB
#define USE_LAMBDA
#define USE_COLLIDERS
#define USE_FORCES
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

void add_force(uint b, vec3 f, vec3 at)
{
    if ((colliders[b].info.y & 1u) == 0u) return;
    vec3 t = cross(at - colliders[b].center_of_mass.xyz, f);
    int base = int(b) * 8;
    atomicAdd(forces[base + 0], int(round(f.x * PBF_FORCE_SCALE)));
    atomicAdd(forces[base + 1], int(round(f.y * PBF_FORCE_SCALE)));
    atomicAdd(forces[base + 2], int(round(f.z * PBF_FORCE_SCALE)));
    atomicAdd(forces[base + 4], int(round(t.x * PBF_FORCE_SCALE)));
    atomicAdd(forces[base + 5], int(round(t.y * PBF_FORCE_SCALE)));
    atomicAdd(forces[base + 6], int(round(t.z * PBF_FORCE_SCALE)));
}

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= P.count) return;
    vec3 xi = pred[i].xyz;
    float li = lambda_rho[i].x;
    vec3 dp = vec3(0.0);
    uint nn = nb_len(i);
    if (P.scorr_k > 0.0) {
        for (uint q = 0u; q < nn; q++) {
            uint j = nb_at(i, q);
            vec3 r = xi - pred[j].xyz;
            float s = -P.scorr_k * pow(w_poly6(dot(r, r)) * P.scorr_inv_wdq, P.scorr_n);
            dp += (li + lambda_rho[j].x + s) * grad_spiky(r);
        }
    } else {
        for (uint q = 0u; q < nn; q++) {
            uint j = nb_at(i, q);
            dp += (li + lambda_rho[j].x) * grad_spiky(xi - pred[j].xyz);
        }
    }
    dp *= P.mass_density * P.inv_rest_density;
    for (uint p = 0u; p < P.plane_count; p++) {
        vec3 n;
        float d = plane_distance(p, xi, n);
        if (d < P.h) dp -= li * boundary_gradient(d) * n;
    }
    float to_force = -P.mass * P.inv_dt * P.inv_dt;
    for (uint b = 0u; b < P.collider_count; b++) {
        if (distance(xi, colliders[b].position.xyz) > colliders[b].position.w + P.h) continue;
        vec3 n;
        float d = collider_sdf(colliders[b], colliders[b].position.xyz, colliders[b].rotation, xi, n);
        if (d < P.h) {
            vec3 bdp = -li * boundary_gradient(d) * n;
            dp += bdp;
            add_force(b, to_force * P.omega * bdp, xi - d * n);
        }
    }
    vec3 x = xi + P.omega * dp;
    // Collisions: keep a particle radius away from every boundary.
    for (uint p = 0u; p < P.plane_count; p++) {
        vec3 n;
        float d = plane_distance(p, x, n);
        if (d < P.radius) x += (P.radius - d) * n;
    }
    for (uint b = 0u; b < P.collider_count; b++) {
        if (distance(x, colliders[b].position.xyz) > colliders[b].position.w + P.radius) continue;
        vec3 n;
        float d = collider_sdf(colliders[b], colliders[b].position.xyz, colliders[b].rotation, x, n);
        if (d < P.radius) {
            vec3 push = (P.radius - d) * n;
            x += push;
            add_force(b, to_force * push, x - P.radius * n);
        }
    }
    x = clamp(x, P.domain_min.xyz + P.radius, P.domain_max.xyz - P.radius);
    pred_out[i] = vec4(x, 0.0);
}
