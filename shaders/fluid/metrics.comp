#version 430
// Stage metrics, part 1: density of the final positions (fluid + boundary share, over the
// neighbour list of the last substep; the fluid's part summed by the viscosity pass when it
// ran, in lambda_rho[i].y, else here), then
// per-work-group sum and max, non-finite and out-of-domain counts, reduced in shared
// memory in a fixed order (deterministic); momentum, kinetic energy, the sum of positions
// (centre of mass) and the largest speed of the finite particles.
#define USE_POS
#define USE_VEL
#define USE_NB
#define USE_LAMBDA
#define USE_COLLIDERS
#include "common.glsl"
#include "colliders.glsl"
layout(local_size_x = PBF_WG) in;
layout(std430, binding = PBF_B_REDUCE) buffer Reduce { pbf_gpu_reduce partial[]; };

shared float s_sum[PBF_WG];
shared float s_err[PBF_WG];
shared float s_max[PBF_WG];
shared uint s_nan[PBF_WG];
shared uint s_out[PBF_WG];
shared uint s_ovf[PBF_WG];
shared vec4 s_mom[PBF_WG]; // xyz m v, w m |v|^2 / 2
shared vec4 s_pos[PBF_WG]; // xyz x, w |v| (max)

void main()
{
    uint i = gl_GlobalInvocationID.x;
    uint t = gl_LocalInvocationID.x;
    float rho = 0.0;
    uint bad = 0u, outside = 0u, overflow = 0u;
    vec4 mom = vec4(0.0), at = vec4(0.0);
    if (i < particle_count()) {
        vec3 xi = pos[i].xyz;
        vec3 vi = vel[i].xyz;
        if (any(isnan(xi)) || any(isinf(xi)) || any(isnan(vi)) || any(isinf(vi))) {
            bad = 1u;
        } else {
            if (P.viscosity > 0.0 || P.vorticity > 0.0) { // the viscosity pass ran (pbf_world.c)
                rho = lambda_rho[i].y;
            } else {
                float sum_w = w_spiky(0.0);
                uint nn = nb_len(i);
                for (uint q = 0u; q < nn; q++) sum_w += w_spiky(length(xi - pos[nb_at(i, q)].xyz));
                add_final_wall_images(i, xi, nn, sum_w);
                rho = P.mass_density * sum_w;
            }
            vec3 unused_grad = vec3(0.0);
            if (P.collider_count > 0u) colliders_density(xi, rho, unused_grad);
            if (nb_count[i] > P.max_neighbours) overflow = 1u;
            mom = vec4(P.mass * vi, 0.5 * P.mass * dot(vi, vi));
            at = vec4(xi, length(vi));
            if (any(lessThan(xi, P.domain_min.xyz)) || any(greaterThan(xi, P.domain_max.xyz))) outside = 1u;
        }
    }
    s_sum[t] = rho;
    s_err[t] = max(rho * P.inv_rest_density - 1.0, 0.0);
    s_max[t] = rho;
    s_nan[t] = bad;
    s_out[t] = outside;
    s_ovf[t] = overflow;
    s_mom[t] = mom;
    s_pos[t] = at;
    for (uint s = PBF_WG / 2u; s > 0u; s >>= 1) {
        barrier();
        if (t < s) {
            s_sum[t] += s_sum[t + s];
            s_err[t] += s_err[t + s];
            s_max[t] = max(s_max[t], s_max[t + s]);
            s_nan[t] += s_nan[t + s];
            s_out[t] += s_out[t + s];
            s_ovf[t] += s_ovf[t + s];
            s_mom[t] += s_mom[t + s];
            s_pos[t] = vec4(s_pos[t].xyz + s_pos[t + s].xyz, max(s_pos[t].w, s_pos[t + s].w));
        }
    }
    if (t == 0u) {
        partial[gl_WorkGroupID.x].density_sum = s_sum[0];
        partial[gl_WorkGroupID.x].error_sum = s_err[0];
        partial[gl_WorkGroupID.x].density_max = s_max[0];
        partial[gl_WorkGroupID.x].nan_count = s_nan[0];
        partial[gl_WorkGroupID.x].outside_count = s_out[0];
        partial[gl_WorkGroupID.x].overflow_count = s_ovf[0];
        partial[gl_WorkGroupID.x].kinetic_sum = s_mom[0].w;
        partial[gl_WorkGroupID.x].speed_max = s_pos[0].w;
        partial[gl_WorkGroupID.x].momentum_sum = vec4(s_mom[0].xyz, 0.0);
        partial[gl_WorkGroupID.x].position_sum = vec4(s_pos[0].xyz, 0.0);
    }
}
