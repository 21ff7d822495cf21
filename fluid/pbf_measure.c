// Measurements of the particles for tests, tools and scripts: the fields of the particles in
// a box (positions, velocities, densities) and what they add up to. Slow paths: they download
// the particle state (pbf_read_sorted); the per-step statistics stay on the GPU (metrics.comp).
#include "fluid/pbf_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static bool inside(const float *x, const float *mn, const float *mx)
{
    if (!mn) return true;
    return x[0] >= mn[0] && x[0] <= mx[0] && x[1] >= mn[1] && x[1] <= mx[1] && x[2] >= mn[2] && x[2] <= mx[2];
}

static bool box_ok(const float *mn, const float *mx)
{
    if (!mn != !mx) return false;
    if (!mn) return true;
    for (int k = 0; k < 3; k++)
        if (!isfinite(mn[k]) || !isfinite(mx[k]) || mn[k] > mx[k]) return false;
    return true;
}

pbf_result pbf_world_read_fields(pbf_world *w, const float box_min[3], const float box_max[3], float *positions,
                                 float *velocities, float *densities, uint32_t max, uint32_t *count)
{
    if (count) *count = 0;
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!box_ok(box_min, box_max))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_read_fields: the box needs both corners, finite, "
                                                "with min <= max on every axis");
    uint32_t n = w->count;
    if (n == 0) return PBF_OK;
    float *p = malloc((size_t)n * 16), *v = malloc((size_t)n * 16), *vol = malloc((size_t)n * 4);
    if (!p || !v || !vol) {
        free(p);
        free(v);
        free(vol);
        return pbf_fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_world_read_fields: no memory for %u particles", n);
    }
    n = pbf_read_sorted(w, p, v, vol, NULL, n);
    uint32_t m = 0;
    for (uint32_t i = 0; i < n; i++) {
        if (!inside(p + 4 * i, box_min, box_max)) continue;
        if (m < max) {
            if (positions) memcpy(positions + 3 * (size_t)m, p + 4 * i, 12);
            if (velocities) memcpy(velocities + 3 * (size_t)m, v + 4 * i, 12);
            if (densities) densities[m] = vol[i] > 0.0f ? w->k.mass / vol[i] : 0.0f;
        }
        m++;
    }
    free(p);
    free(v);
    free(vol);
    if (count) *count = m;
    return PBF_OK;
}

pbf_result pbf_region_stats_of(const float *positions, const float *velocities, const float *densities, uint32_t count,
                               float particle_mass, const float box_min[3], const float box_max[3],
                               pbf_region_stats *out)
{
    if (!out) return PBF_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    if ((!positions && count > 0) || !box_ok(box_min, box_max) || !(particle_mass >= 0.0f)) return PBF_ERR_INVALID_ARG;
    double m = particle_mass, rho_sum = 0.0;
    for (uint32_t i = 0; i < count; i++) {
        const float *x = positions + 3 * (size_t)i;
        if (!inside(x, box_min, box_max)) continue;
        out->particles++;
        for (int k = 0; k < 3; k++) out->center_of_mass[k] += x[k];
        if (velocities) {
            const float *u = velocities + 3 * (size_t)i;
            double u2 = 0.0;
            for (int k = 0; k < 3; k++) {
                out->velocity[k] += u[k];
                u2 += (double)u[k] * u[k];
            }
            out->kinetic_energy += 0.5 * m * u2;
            if (sqrt(u2) > out->speed_max) out->speed_max = sqrt(u2);
        }
        if (densities && densities[i] > 0.0f) {
            out->with_density++;
            rho_sum += densities[i];
            if (densities[i] > out->density_max) out->density_max = densities[i];
        }
    }
    out->mass = m * out->particles;
    if (out->particles > 0)
        for (int k = 0; k < 3; k++) {
            out->center_of_mass[k] /= out->particles;
            out->momentum[k] = m * out->velocity[k];
            out->velocity[k] /= out->particles;
        }
    out->density_avg = out->with_density > 0 ? rho_sum / out->with_density : 0.0;
    return PBF_OK;
}

pbf_result pbf_world_region_stats(pbf_world *w, const float box_min[3], const float box_max[3], pbf_region_stats *out)
{
    if (out) memset(out, 0, sizeof *out);
    if (!w || !out) return PBF_ERR_INVALID_ARG;
    uint32_t n = w->count, got = 0;
    float *f = malloc((size_t)(n ? n : 1) * 7 * sizeof(float));
    if (!f) return pbf_fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_world_region_stats: no memory for %u particles", n);
    pbf_result r = pbf_world_read_fields(w, box_min, box_max, f, f + 3 * (size_t)n, f + 6 * (size_t)n, n, &got);
    if (r == PBF_OK) {
        if (got > n) got = n;
        r = pbf_region_stats_of(f, f + 3 * (size_t)n, f + 6 * (size_t)n, got, w->k.mass, NULL, NULL, out);
    }
    free(f);
    return r;
}
