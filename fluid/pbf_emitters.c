// Particles added from the CPU (blocks, point lists, and emitters, which pour them from a
// nozzle), generated on the CPU and appended on the GPU, and sinks (boxes that remove
// particles, applied on the GPU in the grid pass).
#include "fluid/pbf_internal.h"
#include "fluid/pbf_uniforms.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

// ---- blocks and point lists ---------------------------------------------------------------

pbf_block_def pbf_default_block_def(void)
{
    pbf_block_def b;
    memset(&b, 0, sizeof b);
    b.max[0] = b.max[1] = b.max[2] = 0.1f;
    return b;
}

pbf_result pbf_world_add_particles(pbf_world *w, const float *positions, const float *velocities, uint32_t n)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (pbf_refused_in_step(w, "pbf_world_add_particles", "")) return PBF_ERR_INVALID_ARG;
    if (pbf_without_context(w, "pbf_world_add_particles")) return PBF_ERR_GL;
    if (!positions && n > 0) return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_add_particles: positions must not be NULL");
    if (n > w->capacity - w->count && !(pbf_count_settle(w) && n <= w->capacity - w->count))
        return pbf_fail(w, PBF_ERR_CAPACITY, "pbf_world_add_particles: %u particles do not fit: %u of capacity %u in use",
                    n, w->count, w->capacity);
    char err[256];
    if (!pbf_points_check("pbf_world_add_particles", positions, velocities, n, w->domain_min, w->domain_max, err, sizeof err))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "%s", err);
    float *p4 = malloc((size_t)n * 16 + 16), *v4 = malloc((size_t)n * 16 + 16);
    if (!p4 || !v4) {
        free(p4);
        free(v4);
        return pbf_fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_world_add_particles: out of memory");
    }
    for (uint32_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            p4[4 * i + k] = positions[3 * i + k];
            v4[4 * i + k] = velocities ? velocities[3 * i + k] : 0.0f;
        }
        p4[4 * i + 3] = pbf_colour_of(w, positions[3 * i + 1]);
        v4[4 * i + 3] = 0.0f;
    }
    pbf_result r = pbf_append(w, p4, v4, n);
    free(p4);
    free(v4);
    return r;
}

pbf_result pbf_world_add_block(pbf_world *w, const pbf_block_def *b, uint32_t *added)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!b) return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_add_block: block must not be NULL");
    if (pbf_refused_in_step(w, "pbf_world_add_block", "")) return PBF_ERR_INVALID_ARG;
    if (pbf_without_context(w, "pbf_world_add_block")) return PBF_ERR_GL;
    if (added) *added = 0;
    float s = w->k.spacing;
    uint32_t n[3];
    char err[256];
    uint64_t total;
    pbf_result fit = pbf_block_lattice(b, s, w->domain_min, w->domain_max, w->count, w->capacity, n, &total, err, sizeof err);
    if (fit == PBF_ERR_CAPACITY && pbf_count_settle(w)) // the count was an upper bound: try the exact one
        fit = pbf_block_lattice(b, s, w->domain_min, w->domain_max, w->count, w->capacity, n, &total, err, sizeof err);
    if (fit != PBF_OK) return pbf_fail(w, fit, "%s", err);
    float *p4 = malloc((size_t)total * 16), *v4 = malloc((size_t)total * 16);
    if (!p4 || !v4) {
        free(p4);
        free(v4);
        return pbf_fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_world_add_block: out of memory");
    }
    size_t i = 0;
    for (uint32_t z = 0; z < n[2]; z++)
        for (uint32_t y = 0; y < n[1]; y++)
            for (uint32_t x = 0; x < n[0]; x++, i++) {
                float *p = p4 + 4 * i, *v = v4 + 4 * i;
                pbf_block_point(b, s, x, y, z, p);
                p[3] = pbf_colour_of(w, p[1]);
                v[0] = b->velocity[0];
                v[1] = b->velocity[1];
                v[2] = b->velocity[2];
                v[3] = 0.0f;
            }
    pbf_result r = pbf_append(w, p4, v4, (uint32_t)total);
    free(p4);
    free(v4);
    if (r == PBF_OK && added) *added = (uint32_t)total;
    return r;
}

// ---- emitters ------------------------------------------------------------------------------

pbf_emitter_def pbf_default_emitter_def(void)
{
    pbf_emitter_def d;
    memset(&d, 0, sizeof d);
    d.direction[1] = -1.0f;
    d.speed = 1.0f;
    d.rate = 0.0f; // the most depends on the world's spacing: pbf_emitter_max_rate
    d.radius = 0.05f;
    d.enabled = true;
    return d;
}

// A disc of PBF_MAX_EMITTER_POINTS points has a radius of sqrt(points / pi) = 578 spacings.
#define DISC_MAX_CELLS 600.0

// Lattice points of spacing s on a disc of radius R (the centre always included).
static int disc_points(float s, float radius, float *out)
{
    int n = (int)floorf(radius / s);
    int count = 0;
    for (int j = -n; j <= n; j++)
        for (int i = -n; i <= n; i++) {
            float u = (float)i * s, v = (float)j * s;
            if (u * u + v * v <= radius * radius + 1e-9f) {
                if (out) {
                    out[2 * count] = u;
                    out[2 * count + 1] = v;
                }
                count++;
            }
        }
    return count;
}

float pbf_emitter_max_rate(const pbf_world *w, float speed, float radius)
{
    if (!w || !(speed > 0.0f) || !(radius > 0.0f) || !isfinite(speed) || !isfinite(radius)) return 0.0f;
    float s = w->k.spacing;
    // Count the lattice points where that is cheap; a disc wider than any emitter the checks
    // accept (PBF_MAX_EMITTER_POINTS) is estimated by its area instead.
    double cells = (double)radius / (double)s;
    if (cells > DISC_MAX_CELLS) return (float)((double)speed * 3.14159265358979 * cells * cells / (double)s);
    return speed * (float)disc_points(s, radius, NULL) / s;
}

static pbf_result check_emitter(pbf_world *w, const pbf_emitter_def *d, float dir[3])
{
    static const char *const axis = "xyz";
    for (int k = 0; k < 3; k++) {
        if (!isfinite(d->position[k]) || d->position[k] < w->domain_min[k] || d->position[k] > w->domain_max[k])
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_emitter_def.position.%c must be inside the domain [%g, %g] (got %g)",
                            axis[k], (double)w->domain_min[k], (double)w->domain_max[k], (double)d->position[k]);
        if (!isfinite(d->direction[k]))
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_emitter_def.direction.%c must be finite (got %g)", axis[k],
                            (double)d->direction[k]);
    }
    float len = sqrtf(d->direction[0] * d->direction[0] + d->direction[1] * d->direction[1] +
                      d->direction[2] * d->direction[2]);
    if (!(len > 1e-6f))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_emitter_def.direction must have a length over 1e-6 (got (%g, %g, %g))",
                        (double)d->direction[0], (double)d->direction[1], (double)d->direction[2]);
    for (int k = 0; k < 3; k++) dir[k] = d->direction[k] / len;
    if (!(isfinite(d->speed) && d->speed > 0.0f && d->speed <= 100.0f))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_emitter_def.speed must be in (0, 100] m/s (got %g)", (double)d->speed);
    float r = w->params.particle_radius;
    if (!(isfinite(d->radius) && d->radius >= r && d->radius <= 10.0f))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_emitter_def.radius must be in [%g, 10] m (the particle radius at "
                        "least; got %g)", (double)r, (double)d->radius);
    // One layer of the nozzle is generated at once: keep it to PBF_MAX_EMITTER_POINTS.
    double cells = (double)d->radius / (double)w->k.spacing;
    int points = cells > DISC_MAX_CELLS ? PBF_MAX_EMITTER_POINTS + 1 : disc_points(w->k.spacing, d->radius, NULL);
    if (points > PBF_MAX_EMITTER_POINTS)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_emitter_def.radius %g m holds more than %d particles per layer at "
                        "spacing %g m; at most %d allowed (a smaller radius, or larger particles)", (double)d->radius,
                        PBF_MAX_EMITTER_POINTS, (double)w->k.spacing, PBF_MAX_EMITTER_POINTS);
    float max_rate = pbf_emitter_max_rate(w, d->speed, d->radius);
    if (!(isfinite(d->rate) && d->rate >= 0.0f && d->rate <= max_rate * 1.0001f))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_emitter_def.rate must be in [0, %g] particles/s for speed %g m/s "
                        "and radius %g m (got %g; raise speed or radius for more)", (double)max_rate, (double)d->speed,
                        (double)d->radius, (double)d->rate);
    // Layers leave one spacing apart at the jet's speed: a particle the solver slows to
    // max_speed would be caught up by the next layers (the water piled to ten times rho0).
    if (d->speed > w->params.max_speed)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_emitter_def.speed %g m/s is over the solver's max_speed %g m/s: "
                        "the solver would slow the jet and its layers pile up (a slower jet, or raise max_speed)",
                        (double)d->speed, (double)w->params.max_speed);
    // The disc across the jet: where it passes a wall its points would be moved onto the
    // wall, on top of each other. A particle radius over is allowed (a nozzle in a wall).
    for (int k = 0; k < 3; k++) {
        float across = d->radius * sqrtf(fmaxf(0.0f, 1.0f - dir[k] * dir[k]));
        float lo = d->position[k] - across, hi = d->position[k] + across;
        if (lo < w->domain_min[k] - r || hi > w->domain_max[k] + r)
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_emitter_def.radius %g m: the nozzle's disc around position.%c = %g "
                            "spans %c in [%g, %g], which must lie inside the domain [%g, %g] (a smaller radius, or the "
                            "nozzle moved in)", (double)d->radius, axis[k], (double)d->position[k], axis[k], (double)lo,
                            (double)hi, (double)w->domain_min[k], (double)w->domain_max[k]);
    }
    return PBF_OK;
}

static void set_emitter(pbf_world *w, emitter_slot *e, const pbf_emitter_def *d, const float dir[3])
{
    bool reshape = !e->disc || e->def.radius != d->radius;
    e->def = *d;
    memcpy(e->dir, dir, sizeof e->dir);
    // An orthonormal basis of the nozzle plane.
    float a[3] = { 1, 0, 0 };
    if (fabsf(dir[0]) > 0.9f) {
        a[0] = 0;
        a[1] = 1;
    }
    float u[3] = { dir[1] * a[2] - dir[2] * a[1], dir[2] * a[0] - dir[0] * a[2], dir[0] * a[1] - dir[1] * a[0] };
    float ul = sqrtf(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (int k = 0; k < 3; k++) e->basis_u[k] = u[k] / ul;
    e->basis_v[0] = dir[1] * e->basis_u[2] - dir[2] * e->basis_u[1];
    e->basis_v[1] = dir[2] * e->basis_u[0] - dir[0] * e->basis_u[2];
    e->basis_v[2] = dir[0] * e->basis_u[1] - dir[1] * e->basis_u[0];
    if (reshape) {
        free(e->disc);
        e->disc_count = disc_points(w->k.spacing, d->radius, NULL);
        e->disc = malloc((size_t)e->disc_count * 2 * sizeof(float));
        if (e->disc) disc_points(w->k.spacing, d->radius, e->disc);
        e->cursor = 0;
    }
    if (!d->enabled) e->credit = 0.0;
}

static emitter_slot *get_emitter(pbf_world *w, pbf_emitter_id id, const char *fn)
{
    if (id.index1 == 0 || id.index1 > PBF_MAX_EMITTERS || !w->emitters[id.index1 - 1].used ||
        w->emitters[id.index1 - 1].generation != id.generation) {
        pbf_fail(w, PBF_ERR_STALE_ID, "%s: emitter id is null or stale (index1 %u, generation %u): attempt to use a "
                 "removed emitter", fn, id.index1, id.generation);
        return NULL;
    }
    return &w->emitters[id.index1 - 1];
}

bool pbf_emitter_is_valid(const pbf_world *w, pbf_emitter_id id)
{
    if (!w) return false;
    return id.index1 > 0 && id.index1 <= PBF_MAX_EMITTERS && w->emitters[id.index1 - 1].used &&
           w->emitters[id.index1 - 1].generation == id.generation;
}

pbf_result pbf_world_add_emitter(pbf_world *w, const pbf_emitter_def *d, pbf_emitter_id *out)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!d || !out)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_add_emitter: %s must not be NULL", !d ? "def" : "out");
    if (out) *out = (pbf_emitter_id){ 0, 0 };
    float dir[3];
    pbf_result r = check_emitter(w, d, dir);
    if (r != PBF_OK) return r;
    for (int i = 0; i < PBF_MAX_EMITTERS; i++) {
        emitter_slot *e = &w->emitters[i];
        if (e->used) continue;
        uint16_t gen = (uint16_t)(e->generation + 1);
        memset(e, 0, sizeof *e);
        e->used = true;
        e->generation = gen;
        set_emitter(w, e, d, dir);
        if (!e->disc) {
            e->used = false;
            return pbf_fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_world_add_emitter: out of memory");
        }
        if (out) *out = (pbf_emitter_id){ (uint16_t)(i + 1), gen };
        return PBF_OK;
    }
    return pbf_fail(w, PBF_ERR_CAPACITY, "pbf_world_add_emitter: all %d emitters in use", PBF_MAX_EMITTERS);
}

pbf_result pbf_world_set_emitter(pbf_world *w, pbf_emitter_id id, const pbf_emitter_def *d)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!d) return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_emitter: def must not be NULL");
    emitter_slot *e = get_emitter(w, id, "pbf_world_set_emitter");
    if (!e) return PBF_ERR_STALE_ID;
    float dir[3];
    pbf_result r = check_emitter(w, d, dir);
    if (r != PBF_OK) return r;
    set_emitter(w, e, d, dir);
    return e->disc ? PBF_OK : pbf_fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_world_set_emitter: out of memory");
}

pbf_result pbf_world_set_emitter_tint(pbf_world *w, pbf_emitter_id id, const float rgb[3])
{
    if (!w) return PBF_ERR_INVALID_ARG;
    emitter_slot *e = get_emitter(w, id, "pbf_world_set_emitter_tint");
    if (!e) return PBF_ERR_STALE_ID;
    if (rgb) {
        for (int c = 0; c < 3; c++)
            if (!(rgb[c] >= 0.0f && rgb[c] <= 1.0f))
                return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_emitter_tint: rgb[%d] must be in [0, 1] (got %g)",
                                c, (double)rgb[c]);
        e->tint = pbf_tint_encode(rgb);
    }
    e->tinted = rgb != NULL;
    return PBF_OK;
}

pbf_result pbf_world_remove_emitter(pbf_world *w, pbf_emitter_id id)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    emitter_slot *e = get_emitter(w, id, "pbf_world_remove_emitter");
    if (!e) return PBF_ERR_STALE_ID;
    free(e->disc);
    e->disc = NULL;
    e->used = false;
    return PBF_OK;
}

void pbf_emitters_free(pbf_world *w)
{
    for (int i = 0; i < PBF_MAX_EMITTERS; i++) {
        free(w->emitters[i].disc);
        w->emitters[i].disc = NULL;
    }
}

// Particles a layer gets from `credit` owed: its whole part, at most the disc's points
// (compared as a double: the credit of a long step can exceed an int).
static int layer_count(double credit, int disc_count)
{
    double k = floor(credit + 1e-9);
    return k > (double)disc_count ? disc_count : (int)k;
}

// Generates the particles every enabled emitter owes for a step of dt and appends them.
// Particles that would exceed the capacity are not generated (the emitter just stops).
pbf_result pbf_emitters_emit(pbf_world *w, float dt)
{
    uint32_t total = 0;
    for (int i = 0; i < PBF_MAX_EMITTERS; i++) {
        emitter_slot *e = &w->emitters[i];
        if (!e->used || !e->def.enabled || !e->disc_count) continue;
        float s = w->k.spacing;
        double travel = e->travel + (double)e->def.speed * dt;
        int layers = (int)floor(travel / s);
        double per_layer = (double)e->def.rate * s / e->def.speed;
        double credit = e->credit + per_layer * layers;
        int64_t owed = 0; // up to layers x disc points: more than an int holds
        for (int l = 0; l < layers; l++) {
            int k = layer_count(credit, e->disc_count);
            owed += k;
            credit -= k;
        }
        if (owed == 0) {
            e->travel = travel - s * layers;
            e->credit = credit;
            continue;
        }
        uint32_t room = w->capacity > w->count + total ? w->capacity - w->count - total : 0;
        int n = owed > (int64_t)room ? (int)room : (int)owed;
        float *p4 = malloc((size_t)n * 16 + 16), *v4 = malloc((size_t)n * 16 + 16);
        if (!p4 || !v4) {
            free(p4);
            free(v4);
            return pbf_fail(w, PBF_ERR_OUT_OF_MEMORY, "emitter: out of memory");
        }
        // Layer l (0 oldest) has moved travel - (l + 1) s past the nozzle.
        int made = 0;
        credit = e->credit;
        for (int l = 0; l < layers && made < n; l++) {
            credit += per_layer;
            int k = layer_count(credit, e->disc_count);
            credit -= k;
            double ahead = travel - (double)(l + 1) * s;
            for (int q = 0; q < k && made < n; q++) {
                // A stride coprime with the point count spreads partial layers over the disc.
                int idx = e->cursor;
                e->cursor = (e->cursor + 7) % e->disc_count;
                if (e->disc_count % 7 == 0) e->cursor = (e->cursor + 1) % e->disc_count;
                const float *d2 = e->disc + 2 * idx;
                float *p = p4 + 4 * made, *v = v4 + 4 * made;
                for (int c = 0; c < 3; c++) {
                    p[c] = e->def.position[c] + d2[0] * e->basis_u[c] + d2[1] * e->basis_v[c] +
                           (float)ahead * e->dir[c];
                    v[c] = e->def.speed * e->dir[c];
                }
                // Keep the particle inside the domain (a nozzle at a wall).
                for (int c = 0; c < 3; c++) {
                    float lo = w->domain_min[c] + w->params.particle_radius, hi = w->domain_max[c] - w->params.particle_radius;
                    p[c] = p[c] < lo ? lo : p[c] > hi ? hi : p[c];
                }
                p[3] = e->tinted ? e->tint : pbf_colour_of(w, p[1]);
                v[3] = 0.0f;
                made++;
            }
        }
        e->travel = travel - s * layers;
        e->credit = credit;
        pbf_result r = pbf_append(w, p4, v4, (uint32_t)made);
        free(p4);
        free(v4);
        if (r != PBF_OK) return r;
        total += (uint32_t)made;
    }
    return PBF_OK;
}

// ---- sinks -----------------------------------------------------------------------------

pbf_result pbf_world_add_sink(pbf_world *w, const float min[3], const float max[3], pbf_sink_id *out)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!min || !max)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_add_sink: %s must not be NULL", !min ? "min" : "max");
    static const char *const axis = "xyz";
    // Without the id the sink could never be removed: its slot would be lost.
    if (!out) return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_add_sink: out must not be NULL");
    *out = (pbf_sink_id){ 0, 0 };
    for (int k = 0; k < 3; k++)
        if (!isfinite(min[k]) || !isfinite(max[k]) || !(max[k] > min[k]))
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "sink max.%c must be finite and greater than min.%c (got min %g, max %g)",
                            axis[k], axis[k], (double)min[k], (double)max[k]);
    for (int i = 0; i < PBF_MAX_SINKS; i++) {
        sink_slot *s = &w->sinks[i];
        if (s->used) continue;
        s->used = true;
        s->generation++;
        memcpy(s->min, min, sizeof s->min);
        memcpy(s->max, max, sizeof s->max);
        if (out) *out = (pbf_sink_id){ (uint16_t)(i + 1), s->generation };
        return PBF_OK;
    }
    return pbf_fail(w, PBF_ERR_CAPACITY, "pbf_world_add_sink: all %d sinks in use", PBF_MAX_SINKS);
}

bool pbf_sink_is_valid(const pbf_world *w, pbf_sink_id id)
{
    if (!w) return false;
    return id.index1 > 0 && id.index1 <= PBF_MAX_SINKS && w->sinks[id.index1 - 1].used &&
           w->sinks[id.index1 - 1].generation == id.generation;
}

pbf_result pbf_world_remove_sink(pbf_world *w, pbf_sink_id id)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!pbf_sink_is_valid(w, id))
        return pbf_fail(w, PBF_ERR_STALE_ID, "pbf_world_remove_sink: sink id is null or stale (index1 %u, generation %u)",
                        id.index1, id.generation);
    w->sinks[id.index1 - 1].used = false;
    return PBF_OK;
}
