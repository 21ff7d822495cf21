#version 430
// Stage collide (each iteration, only when there are colliders): the colliders' part of
// the position correction, -lambda_i sum_b G(d_b) n_b (with the reaction forces on
// two-way bodies), in the coarse level's iteration the bodies' reaction to its push (no
// motion), then the swept collisions against the bodies, on the positions the delta pass
// wrote. A pass of its own because the collider code, even when it is skipped, makes the
// delta pass twice as slow on CPU drivers.
#define USE_POS
#define USE_PRED
#define USE_PRED_OUT
#define WRITE_PRED_OUT
#define USE_COLLIDERS
#define USE_FORCES
#define WRITE_FORCES
#define USE_LEVEL
#include "common.glsl"
#include "colliders.glsl"
layout(local_size_x = PBF_WG) in;
uniform float relax; // this iteration's relaxation factor (pbf_relaxation)
uniform bool apply_level; // in the iteration after the coarse level's solve (pbf_level_iteration)

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec4 pi = pred[i];   // the iteration's start: position, and lambda in w
    vec3 bdp = vec3(0.0);
    colliders_delta(pi.xyz, pi.w, relax, apply_level ? -level_pressure(pi.xyz) : 0.0, collider_start(i), bdp);
    vec3 x = pred_out[i].xyz + relax * bdp;
    x = colliders_collide(i, x);
    for (uint p = 0u; p < P.plane_count; p++) {
        vec3 n;
        float d = plane_distance(p, x, n);
        if (d < P.radius) x += (P.radius - d) * n;
    }
    x = clamp(x, P.domain_min.xyz + P.radius, P.domain_max.xyz - P.radius);
    pred_out[i] = vec4(x, 0.0);
}
