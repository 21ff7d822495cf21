#version 430
// Stage metrics, part 2: one work group folds the partials (fixed order) into the
// frame's record in the metrics ring.
#include "common.glsl"
layout(local_size_x = PBF_WG) in;
layout(std430, binding = PBF_B_REDUCE) readonly buffer Reduce { pbf_gpu_reduce partial[]; };
layout(std430, binding = PBF_B_METRICS) buffer Metrics { pbf_gpu_metrics metrics[]; };
uniform uint frame;

shared float s_sum[PBF_WG];
shared float s_err[PBF_WG];
shared float s_max[PBF_WG];
shared uint s_nan[PBF_WG];
shared uint s_out[PBF_WG];
shared uint s_ovf[PBF_WG];
shared vec4 s_mom[PBF_WG]; // xyz momentum, w kinetic energy
shared vec4 s_pos[PBF_WG]; // xyz sum of positions, w largest speed

void main()
{
    uint t = gl_LocalInvocationID.x;
    float sum = 0.0, mx = 0.0, err = 0.0;
    uint bad = 0u, outside = 0u, overflow = 0u;
    vec4 mom = vec4(0.0), at = vec4(0.0);
    uint groups = state.groups_x;
    for (uint g = t; g < groups; g += PBF_WG) {
        sum += partial[g].density_sum;
        err += partial[g].error_sum;
        mx = max(mx, partial[g].density_max);
        bad += partial[g].nan_count;
        outside += partial[g].outside_count;
        overflow += partial[g].overflow_count;
        mom += vec4(partial[g].momentum_sum.xyz, partial[g].kinetic_sum);
        at = vec4(at.xyz + partial[g].position_sum.xyz, max(at.w, partial[g].speed_max));
    }
    s_sum[t] = sum;
    s_err[t] = err;
    s_max[t] = mx;
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
        uint n = particle_count();
        uint slot = P.metrics_slot;
        float good = float(n - s_nan[0] > 0u ? n - s_nan[0] : 1u);
        metrics[slot].density_avg = n > 0u ? s_sum[0] / good : 0.0;
        metrics[slot].error_avg = n > 0u ? s_err[0] / good : 0.0;
        metrics[slot].density_max = s_max[0];
        metrics[slot].nan_count = s_nan[0];
        metrics[slot].outside_count = s_out[0];
        metrics[slot].overflow_count = s_ovf[0];
        metrics[slot].count = n;
        metrics[slot].frame = frame;
        metrics[slot].momentum = s_mom[0];
        metrics[slot].center_of_mass = vec4(n > 0u ? s_pos[0].xyz / good : vec3(0.0), s_pos[0].w);
    }
}
