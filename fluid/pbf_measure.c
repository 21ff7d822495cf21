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
    if (pbf_without_context(w, "pbf_world_read_fields")) return PBF_ERR_GL;
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
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!out) return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_region_stats: out must not be NULL");
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

// ---- downloads of the whole state (tests, tools; pbf_download) ---------------------------

typedef struct id_index {
    uint32_t id, slot;
} id_index;

static int cmp_id(const void *a, const void *b)
{
    uint32_t x = ((const id_index *)a)->id, y = ((const id_index *)b)->id;
    return x < y ? -1 : x > y;
}

static uint32_t gpu_count(pbf_world *w)
{
    pbf_gpu_state st;
    if (!pbf_download(w, w->state, 0, sizeof st, &st)) return 0;
    return st.count;
}

uint32_t pbf_read_sorted(pbf_world *w, float *positions, float *velocities, float *volumes, uint32_t *ids,
                         uint32_t max)
{
    uint32_t n = gpu_count(w), m = 0;
    if (n == 0) return 0;
    float *p = malloc((size_t)n * 16), *v = malloc((size_t)n * 16);
    uint32_t *id = malloc((size_t)n * 4);
    id_index *order = malloc((size_t)n * sizeof *order);
    if (!p || !v || !id || !order || !pbf_download(w, w->pos[w->cur_pos], 0, (GLsizeiptr)n * 16, p) ||
        !pbf_download(w, w->vel[w->cur_vel], 0, (GLsizeiptr)n * 16, v) ||
        !pbf_download(w, w->ids[w->cur_ids], 0, (GLsizeiptr)n * 4, id))
        goto done;
    for (uint32_t i = 0; i < n; i++) order[i] = (id_index){ id[i], i };
    qsort(order, n, sizeof *order, cmp_id);
    m = n < max ? n : max;
    for (uint32_t i = 0; i < m; i++) {
        uint32_t s = order[i].slot;
        if (positions) memcpy(positions + 4 * i, p + 4 * s, 16);
        if (velocities) {
            memcpy(velocities + 4 * i, v + 4 * s, 12);
            velocities[4 * i + 3] = 0.0f; // w is the solver's scratch (particle volume)
        }
        if (volumes) volumes[i] = v[4 * s + 3];
        if (ids) ids[i] = order[i].id;
    }
done:
    free(p);
    free(v);
    free(id);
    free(order);
    return m;
}

uint32_t pbf_world_read_particles(pbf_world *w, float *positions, float *velocities, uint32_t *ids, uint32_t max)
{
    if (!w || pbf_without_context(w, "pbf_world_read_particles")) return 0;
    return pbf_read_sorted(w, positions, velocities, NULL, ids, max);
}

uint64_t pbf_world_state_hash(pbf_world *w)
{
    if (!w || pbf_without_context(w, "pbf_world_state_hash")) return 0;
    uint32_t n = gpu_count(w);
    float *p = malloc((size_t)n * 16 + 16), *v = malloc((size_t)n * 16 + 16);
    uint64_t h = 1469598103934665603ull;
    if (p && v) {
        pbf_world_read_particles(w, p, v, NULL, n);
        const unsigned char *bytes[2] = { (const unsigned char *)p, (const unsigned char *)v };
        for (int b = 0; b < 2; b++)
            for (size_t i = 0; i < (size_t)n * 16; i++) {
                h ^= bytes[b][i];
                h *= 1099511628211ull;
            }
    }
    free(p);
    free(v);
    return h;
}
