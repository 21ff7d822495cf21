#version 430
// Stage delta: the position correction from the fluid and the container,
//   dp_i = relax * ( (m/rho0) sum_j (lambda_i + lambda_j + s_corr) grad W_ij
//                    + lambda_i grad V_walls )
// then collisions with the container (a particle radius from every wall) and the domain
// clamp. Bodies come after, in collide.comp (only when there are any).
#define USE_PRED
#define USE_PRED_OUT
#define WRITE_PRED_OUT
#define USE_NB
#define USE_LEVEL
#include "common.glsl"
layout(local_size_x = PBF_WG) in;
uniform float relax; // this iteration's relaxation factor (pbf_relaxation)
uniform bool apply_level; // in the iteration after the coarse level's solve (pbf_level_iteration)

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 xi = pred[i].xyz;
    float li = pred[i].w; // lambda, written by the density pass
    vec3 dp = vec3(0.0);
    uint nn = nb_len(i);
    vec3 twice;
    uint mask = mirror_mask(xi, twice);
    if (mask != 0u) { // next to a wall: the neighbours' images too, and i's own
        for (uint q = 0u; q < nn; q++) {
            vec4 pj = pred[nb_at(i, q)];
            dp += mirrored_correction(xi, pj.xyz, li + pj.w, mask, twice);
        }
        dp += self_image_correction(xi, li, mask, twice);
    }
    if (P.scorr_k > 0.0) {
        for (uint q = 0u; q < nn; q++) {
            uint j = nb_at(i, q);
            vec4 pj = pred[j];
            vec3 r = xi - pj.xyz;
            dp += (li + pj.w + scorr_of(r)) * grad_spiky(r);
        }
    } else {
        // Four neighbours per trip (loads first; the sum still in list order): two were
        // about 10 % faster than one on llvmpipe, four 5 % faster than two on an NVIDIA
        // H100 (docs/performance.md, "Kernel changes").
        uint q = 0u;
        for (; q + 3u < nn; q += 4u) {
            uint ja = nb_at(i, q), jb = nb_at(i, q + 1u), jc = nb_at(i, q + 2u), jd = nb_at(i, q + 3u);
            vec4 pa = pred[ja], pb = pred[jb], pc = pred[jc], pd = pred[jd];
            vec3 ga = grad_spiky(xi - pa.xyz);
            vec3 gb = grad_spiky(xi - pb.xyz);
            vec3 gc = grad_spiky(xi - pc.xyz);
            vec3 gd = grad_spiky(xi - pd.xyz);
            dp += (li + pa.w) * ga;
            dp += (li + pb.w) * gb;
            dp += (li + pc.w) * gc;
            dp += (li + pd.w) * gd;
        }
        for (; q < nn; q++) { // the last 0-3
            vec4 pj = pred[nb_at(i, q)];
            dp += (li + pj.w) * grad_spiky(xi - pj.xyz);
        }
    }
    dp *= P.mass_density * P.inv_rest_density;
    vec3 x = xi + relax * dp;
    if (apply_level) x += level_correction(xi);
    // Collisions: keep a particle radius away from every boundary.
    for (uint p = 0u; p < P.plane_count; p++) {
        vec3 n;
        float d = plane_distance(p, x, n);
        if (d < P.radius) x += (P.radius - d) * n;
    }
    x = clamp(x, P.domain_min.xyz + P.radius, P.domain_max.xyz - P.radius);
    pred_out[i] = vec4(x, 0.0);
}
