// Colliders: rigid shapes as fluid boundaries (the generic interface a physics engine's
// bodies plug into; see fluid/bullet/coupling.c for Bullet). The GPU side, and the
// boundary model, are in shaders/fluid/colliders.glsl; docs/coupling.md explains both.
//
// Poses. pbf_world_set_collider_pose keeps the pose the collider had as its previous one.
// A pose set between steps spans the whole step: the shader interpolates it substep by
// substep. A pose set from the substep hook spans that substep only; after it has been
// uploaded the CPU copy's previous pose catches up, so a collider that is not moved again
// stands still in the next substep instead of sweeping the same path twice.
//
// Forces. The collide pass adds fixed-point force and torque per collider (each collider
// with its own scale, from its size) into the accumulators; the end of a step copies them
// into the step's ring slot, and they are read once that step's fence has signalled:
// from pbf_world_poll_stats, or here, without consuming the statistics, when a host asks
// for forces (pbf_world_collider_force / _report).
#include "fluid/pbf_internal.h"
#include "fluid/pbf_uniforms.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI_F 3.14159265f

pbf_collider_def pbf_default_collider_def(void)
{
    pbf_collider_def d;
    memset(&d, 0, sizeof d);
    d.type = PBF_SHAPE_BOX;
    d.size[0] = d.size[1] = d.size[2] = 0.1f;
    d.rotation[3] = 1.0f;
    d.two_way = true;
    return d;
}

static collider_slot *get_slot(pbf_world *w, pbf_collider_id id, const char *fn)
{
    if (id.index1 == 0 || id.index1 > PBF_MAX_COLLIDERS) {
        pbf_fail(w, PBF_ERR_STALE_ID, "%s: collider id is null or out of range (index1 %u)", fn, id.index1);
        return NULL;
    }
    collider_slot *s = &w->slots[id.index1 - 1];
    if (!s->used || s->generation != id.generation) {
        pbf_fail(w, PBF_ERR_STALE_ID, "%s: collider id is stale (index %u, generation %u): attempt to use a removed collider",
                 fn, id.index1 - 1, id.generation);
        return NULL;
    }
    return s;
}

bool pbf_collider_is_valid(const pbf_world *w, pbf_collider_id id)
{
    if (!w) return false;
    if (id.index1 == 0 || id.index1 > PBF_MAX_COLLIDERS) return false;
    const collider_slot *s = &w->slots[id.index1 - 1];
    return s->used && s->generation == id.generation;
}

static bool finite_n(const float *v, int n)
{
    for (int k = 0; k < n; k++)
        if (!isfinite(v[k])) return false;
    return true;
}

static float len3(const float *v) { return sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }


static pbf_result check_hull(pbf_world *w, const pbf_collider_def *d)
{
    if (!d->planes)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.planes must not be NULL for a convex hull");
    if (d->plane_count < 4 || d->plane_count > PBF_MAX_HULL_PLANES)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.plane_count must be in [4, %d] (got %u)",
                        PBF_MAX_HULL_PLANES, d->plane_count);
    for (uint32_t k = 0; k < d->plane_count; k++) {
        const float *p = d->planes + 4 * k;
        if (!finite_n(p, 4) || fabsf(len3(p) - 1.0f) > 1e-3f)
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.planes[%u] must be finite with a unit normal "
                            "(got normal (%g, %g, %g), length %g, offset %g)", k, (double)p[0], (double)p[1],
                            (double)p[2], (double)len3(p), (double)p[3]);
    }
    if (!(d->size[0] > 0.0f))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size[0] (the hull's bounding radius about its origin) "
                        "must be > 0 m (got %g)", (double)d->size[0]);
    return PBF_OK;
}

static pbf_result check_grid(pbf_world *w, const pbf_sdf_grid *g)
{
    if (!g->values) return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.values must not be NULL");
    for (int k = 0; k < 3; k++)
        if (g->dims[k] < 2 || g->dims[k] > 1023)
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.dims[%d] must be in [2, 1023] (got %u)", k,
                            g->dims[k]);
    if (!isfinite(g->cell) || !(g->cell > 0.0f))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.cell must be > 0 m and finite (got %g)",
                        (double)g->cell);
    if (!finite_n(g->origin, 3))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.origin must be finite");
    size_t n = (size_t)g->dims[0] * g->dims[1] * g->dims[2];
    for (size_t i = 0; i < n; i++)
        if (!isfinite(g->values[i]))
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.values[%zu] must be finite", i);
    return PBF_OK;
}

// Fixed-point units per newton for a collider of bounding radius r: the accumulators
// (2^31 units, summed over a step's substeps) then hold about 1000 times the weight of the
// fluid the bounding sphere could displace, at a resolution of a millionth of it.
static float force_scale(const pbf_world *w, float r)
{
    if (!(r < 1e29f)) return (float)PBF_FORCE_SCALE;
    const float *g = w->params.gravity;
    float gm = len3(g);
    if (gm < 9.81f) gm = 9.81f;
    double weight = (double)w->params.rest_density * (4.0 / 3.0) * PI_F * (double)r * r * r * gm;
    double range = 1000.0 * weight * (double)w->step_substeps;
    double s = 2147483647.0 / range;
    if (s > 1048576.0) s = 1048576.0;
    if (s < 1e-3) s = 1e-3;
    return (float)s;
}

pbf_result pbf_world_add_collider(pbf_world *w, const pbf_collider_def *d, pbf_collider_id *out)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!d) return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_add_collider: def must not be NULL");
    // Without the id the collider could never be moved or removed: its slot would be lost.
    if (!out) return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_add_collider: out must not be NULL");
    *out = (pbf_collider_id){ 0, 0 };
    if ((unsigned)d->type > PBF_SHAPE_SDF)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.type must be a pbf_collider_type 0..6 (got %d)", (int)d->type);
    if (!finite_n(d->size, 4))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size must be finite");
    if (!finite_n(d->position, 3))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.position must be finite");
    if (!finite_n(d->rotation, 4))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.rotation must be finite");
    int need = d->type == PBF_SHAPE_BOX ? 3 : d->type == PBF_SHAPE_SPHERE ? 1
             : (d->type == PBF_SHAPE_CAPSULE || d->type == PBF_SHAPE_CYLINDER) ? 2 : 0;
    for (int k = 0; k < need; k++)
        if (!(d->size[k] > 0.0f))
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size[%d] must be > 0 m (got %g)", k, (double)d->size[k]);
    float qn = sqrtf(d->rotation[0] * d->rotation[0] + d->rotation[1] * d->rotation[1] +
                     d->rotation[2] * d->rotation[2] + d->rotation[3] * d->rotation[3]);
    if (fabsf(qn - 1.0f) > 1e-3f)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.rotation must be a unit quaternion (got length %g)", (double)qn);
    if (d->type == PBF_SHAPE_PLANE && !(len3(d->size) > 0.0f))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size xyz (plane normal) must be non-zero");
    pbf_result r = PBF_OK;
    if (d->type == PBF_SHAPE_CONVEX_HULL) r = check_hull(w, d);
    if (d->type == PBF_SHAPE_SDF) r = check_grid(w, &d->grid);
    if (r != PBF_OK) return r;

    int free_slot = -1;
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++)
        if (!w->slots[i].used) {
            free_slot = i;
            break;
        }
    if (free_slot < 0) return pbf_fail(w, PBF_ERR_CAPACITY, "pbf_world_add_collider: all %d colliders in use", PBF_MAX_COLLIDERS);
    collider_slot *s = &w->slots[free_slot];
    float *data = NULL;
    uint32_t data_count = pbf_collider_data_count(d);
    if (data_count) {
        data = malloc((size_t)data_count * sizeof *data);
        if (!data) return pbf_fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_world_add_collider: out of memory");
        pbf_collider_data_fill(d, data);
        w->collider_data_dirty = true;
    }
    uint16_t generation = (uint16_t)(s->generation + 1);
    memset(s, 0, sizeof *s);
    s->used = true;
    s->generation = generation;
    s->data = data;
    s->data_count = data_count;
    s->added_step = w->step_index;
    pbf_gpu_collider *g = &s->gpu;
    g->position = (pbf_float4){ d->position[0], d->position[1], d->position[2], 0.0f };
    g->rotation = (pbf_float4){ d->rotation[0] / qn, d->rotation[1] / qn, d->rotation[2] / qn, d->rotation[3] / qn };
    g->prev_rotation = g->rotation;
    if (d->type == PBF_SHAPE_PLANE) {
        float nl = len3(d->size);
        g->params = (pbf_float4){ d->size[0] / nl, d->size[1] / nl, d->size[2] / nl, d->size[3] };
    } else if (d->type == PBF_SHAPE_SDF) {
        g->params = (pbf_float4){ d->grid.origin[0], d->grid.origin[1], d->grid.origin[2], d->grid.cell };
    } else {
        g->params = (pbf_float4){ d->size[0], d->size[1], d->size[2], d->size[3] };
    }
    static const uint32_t gpu_type[] = { PBF_COLLIDER_PLANE, PBF_COLLIDER_BOX, PBF_COLLIDER_SPHERE,
                                         PBF_COLLIDER_CAPSULE, PBF_COLLIDER_CYLINDER, PBF_COLLIDER_HULL,
                                         PBF_COLLIDER_GRID };
    uint32_t packed = 0;
    if (d->type == PBF_SHAPE_CONVEX_HULL) packed = d->plane_count;
    if (d->type == PBF_SHAPE_SDF) packed = d->grid.dims[0] | d->grid.dims[1] << 10 | d->grid.dims[2] << 20;
    uint32_t flags = (d->two_way ? PBF_COLLIDER_TWO_WAY : 0u) | (d->blocks_sinks ? PBF_COLLIDER_BLOCKS_SINKS : 0u);
    g->info = (pbf_uint4){ gpu_type[d->type], flags, 0u, packed };
    g->position.w = pbf_collider_bounding_radius(d);
    g->prev_position = g->position;
    g->center_of_mass = g->position;
    g->center_of_mass.w = force_scale(w, g->position.w);
    g->linear_velocity.w = 1.0f;
    g->angular_velocity.w = 1.0f;
    memset(w->force[free_slot], 0, sizeof w->force[free_slot]);
    w->force_step[free_slot] = w->step_index; // results of earlier steps are not its own
    w->colliders_dirty = true;
    if (out) *out = (pbf_collider_id){ (uint16_t)(free_slot + 1), s->generation };
    return PBF_OK;
}

pbf_result pbf_world_remove_collider(pbf_world *w, pbf_collider_id id)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    collider_slot *s = get_slot(w, id, "pbf_world_remove_collider");
    if (!s) return PBF_ERR_STALE_ID;
    s->used = false;
    if (s->data) w->collider_data_dirty = true;
    free(s->data);
    s->data = NULL;
    s->data_count = 0;
    w->colliders_dirty = true;
    return PBF_OK;
}

pbf_result pbf_world_set_collider_pose(pbf_world *w, pbf_collider_id id, const float position[3],
                                       const float rotation[4], const float linear_velocity[3],
                                       const float angular_velocity[3], const float center_of_mass[3])
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!position || !rotation)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_collider_pose: %s must not be NULL",
                        !position ? "position" : "rotation");
    collider_slot *s = get_slot(w, id, "pbf_world_set_collider_pose");
    if (!s) return PBF_ERR_STALE_ID;
    if (!position || !rotation)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_collider_pose: position and rotation must not be NULL");
    if (!finite_n(position, 3))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_collider_pose: position must be finite (got %g, %g, %g)",
                        (double)position[0], (double)position[1], (double)position[2]);
    if (!finite_n(rotation, 4))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_collider_pose: rotation must be finite");
    if (linear_velocity && !finite_n(linear_velocity, 3))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_collider_pose: linear_velocity must be finite");
    if (angular_velocity && !finite_n(angular_velocity, 3))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_collider_pose: angular_velocity must be finite");
    if (center_of_mass && !finite_n(center_of_mass, 3))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_collider_pose: center_of_mass must be finite");
    float qn = sqrtf(rotation[0] * rotation[0] + rotation[1] * rotation[1] + rotation[2] * rotation[2] +
                     rotation[3] * rotation[3]);
    if (fabsf(qn - 1.0f) > 1e-3f)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_collider_pose: rotation must be a unit quaternion "
                        "(got length %g)", (double)qn);
    pbf_gpu_collider *g = &s->gpu;
    g->prev_position = g->position;
    g->prev_rotation = g->rotation;
    g->position = (pbf_float4){ position[0], position[1], position[2], g->position.w };
    g->rotation = (pbf_float4){ rotation[0] / qn, rotation[1] / qn, rotation[2] / qn, rotation[3] / qn };
    if (linear_velocity)
        g->linear_velocity = (pbf_float4){ linear_velocity[0], linear_velocity[1], linear_velocity[2], g->linear_velocity.w };
    if (angular_velocity)
        g->angular_velocity = (pbf_float4){ angular_velocity[0], angular_velocity[1], angular_velocity[2],
                                            g->angular_velocity.w };
    const float *c = center_of_mass ? center_of_mass : position;
    g->center_of_mass = (pbf_float4){ c[0], c[1], c[2], g->center_of_mass.w };
    w->colliders_dirty = true;
    return PBF_OK;
}

pbf_result pbf_world_set_collider_strength(pbf_world *w, pbf_collider_id id, float strength)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    collider_slot *s = get_slot(w, id, "pbf_world_set_collider_strength");
    if (!s) return PBF_ERR_STALE_ID;
    if (!(strength >= 0.0f && strength <= 1.0f))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_collider_strength: strength must be in [0, 1] (got %g)",
                        (double)strength);
    if (s->gpu.angular_velocity.w != strength) w->colliders_dirty = true;
    s->gpu.angular_velocity.w = strength;
    return PBF_OK;
}

// ---- upload -------------------------------------------------------------------------------

static void rebuild_data(pbf_world *w)
{
    size_t total = 0;
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++)
        if (w->slots[i].used) total += w->slots[i].data_count;
    GLsizeiptr bytes = (GLsizeiptr)(total ? total : 4) * 4;
    bool fresh = !w->collider_data;
    if (fresh) glGenBuffers(1, &w->collider_data);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->collider_data);
    if (fresh) glObjectLabel(GL_BUFFER, w->collider_data, -1, "pbf.collider_data");
    if (bytes > w->collider_data_size || bytes < w->collider_data_size / 4) {
        glBufferData(GL_SHADER_STORAGE_BUFFER, bytes, NULL, GL_STATIC_DRAW);
        w->collider_data_size = bytes;
    }
    uint32_t offset = 0;
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++) {
        collider_slot *s = &w->slots[i];
        if (!s->used || !s->data_count) continue;
        glBufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)offset * 4, (GLsizeiptr)s->data_count * 4, s->data);
        s->gpu.info.z = offset;
        offset += s->data_count;
    }
    w->collider_data_dirty = false;
}

void pbf_colliders_bind(pbf_world *w)
{
    if (!w->collider_data || w->collider_data_dirty) rebuild_data(w);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_COLLIDER_DATA, w->collider_data);
}

static bool moved(const pbf_gpu_collider *g)
{
    return memcmp(&g->prev_position, &g->position, sizeof g->position) != 0 ||
           memcmp(&g->prev_rotation, &g->rotation, sizeof g->rotation) != 0;
}

// span_step: poses were set between steps and span all substeps of the coming step.
static void upload(pbf_world *w, bool span_step)
{
    pbf_colliders_bind(w);
    pbf_gpu_collider tmp[PBF_MAX_COLLIDERS];
    uint32_t n = 0;
    bool again = false;
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++) {
        collider_slot *s = &w->slots[i];
        s->gpu_index = -1;
        if (!s->used) continue;
        s->gpu_index = (int)n;
        bool m = moved(&s->gpu);
        s->gpu.linear_velocity.w = span_step && m ? (float)w->step_substeps : 1.0f;
        tmp[n++] = s->gpu;
        if (!span_step && m) {
            // Swept in this substep; it stands still from here unless moved again.
            s->gpu.prev_position = s->gpu.position;
            s->gpu.prev_rotation = s->gpu.rotation;
            again = true;
        }
    }
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->colliders);
    if (n) glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)n * (GLsizeiptr)sizeof(pbf_gpu_collider), tmp);
    w->gpu_colliders = n;
    w->colliders_dirty = again;
}

void pbf_colliders_upload(pbf_world *w) { upload(w, false); }

void pbf_colliders_begin_step(pbf_world *w, stats_slot *slot)
{
    // Force scales follow the parameters (substeps, rest density, gravity).
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++) {
        collider_slot *s = &w->slots[i];
        if (!s->used) continue;
        float fs = force_scale(w, s->gpu.position.w);
        if (fs != s->gpu.center_of_mass.w) {
            s->gpu.center_of_mass.w = fs;
            w->colliders_dirty = true;
        }
    }
    upload(w, true);
    int ring_slot = (int)(slot - w->ring);
    slot->colliders = (int)w->gpu_colliders;
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++) slot->collider_slot_of[i] = -1;
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++) {
        collider_slot *s = &w->slots[i];
        if (!s->used || s->gpu_index < 0) continue;
        slot->collider_slot_of[s->gpu_index] = i;
        s->step_scale[ring_slot] = s->gpu.center_of_mass.w;
    }
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->forces);
    glClearBufferSubData(GL_SHADER_STORAGE_BUFFER, GL_R32I, 0, PBF_FORCES_BYTES, GL_RED_INTEGER, GL_INT, NULL);
}

// Copies this step's force accumulators into the ring slot read back later, and makes the
// pose given for this step the previous pose of the next.
void pbf_colliders_end_step(pbf_world *w)
{
    int slot_index = w->ring_head;
    // The collide passes wrote the accumulators with atomics: a copy reads them as a
    // buffer update, which needs its own barrier bit.
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_COPY_READ_BUFFER, w->forces);
    glBindBuffer(GL_COPY_WRITE_BUFFER, w->forces_ring);
    glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0,
                        (GLintptr)slot_index * PBF_FORCES_BYTES, PBF_FORCES_BYTES);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++) {
        collider_slot *s = &w->slots[i];
        if (!s->used) continue;
        if (moved(&s->gpu)) w->colliders_dirty = true;
        s->gpu.prev_position = s->gpu.position;
        s->gpu.prev_rotation = s->gpu.rotation;
    }
}

// ---- forces read back ------------------------------------------------------------------------

// Reads the forces of a completed step (its fence has signalled: no stall). May be called
// more than once for the same step.
void pbf_colliders_read_forces(pbf_world *w, const stats_slot *r)
{
    int ring_slot = (int)(r - w->ring);
    if (r->colliders <= 0) return;
    int32_t f[PBF_MAX_COLLIDERS * PBF_FORCE_WORDS];
    glBindBuffer(GL_COPY_READ_BUFFER, w->forces_ring);
    glGetBufferSubData(GL_COPY_READ_BUFFER, (GLintptr)ring_slot * PBF_FORCES_BYTES,
                       (GLsizeiptr)r->colliders * PBF_COLLIDER_FORCE_BYTES, f);
    double per = 1.0 / (r->substeps > 0 ? r->substeps : 1);
    for (int g = 0; g < r->colliders; g++) {
        int sl = r->collider_slot_of[g];
        if (sl < 0) continue;
        collider_slot *s = &w->slots[sl];
        if (!s->used || r->step < s->added_step) continue; // removed since, or added after it

        double k = per / (double)s->step_scale[ring_slot];
        pbf_collider_report rep;
        memset(&rep, 0, sizeof rep);
        const int32_t *fg = f + g * PBF_FORCE_WORDS;
        for (int c = 0; c < 3; c++) {
            rep.force[c] = (float)(fg[c] * k);
            rep.torque[c] = (float)(fg[4 + c] * k);
        }
        rep.contacts = (uint32_t)fg[3];
        rep.pushed_out = (uint32_t)fg[7];
        pbf_water_of_sums(fg, s->step_scale[ring_slot], r->substeps, &rep);
        rep.step = r->step;
        rep.ready = true;
        rep.existed = true;
        s->hist[r->step % RING] = rep;
        if (w->force_step[sl] <= r->step + 1) {
            for (int c = 0; c < 3; c++) {
                w->force[sl][c] = rep.force[c];
                w->force[sl][3 + c] = rep.torque[c];
            }
            w->force_step[sl] = r->step + 1;
        }
    }
}

// Reads every step the GPU has finished (oldest first) without consuming its statistics;
// with `until_step` >= 0 waits for that step.
static void refresh(pbf_world *w, int64_t wait_step)
{
    for (int k = 0; k < RING; k++) {
        stats_slot *r = &w->ring[(w->ring_head + k) % RING];
        if (!r->pending || !r->fence) continue;
        bool wait = wait_step >= 0 && (int64_t)r->step <= wait_step;
        if (!pbf_step_done(w, r, wait)) break;
        pbf_colliders_read_forces(w, r);
    }
}

pbf_result pbf_world_collider_force(pbf_world *w, pbf_collider_id id, float force[3], float torque[3])
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!force && !torque)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_collider_force: force and torque must not both be NULL");
    collider_slot *s = get_slot(w, id, "pbf_world_collider_force");
    if (!s) return PBF_ERR_STALE_ID;
    refresh(w, -1);
    int i = (int)(s - w->slots);
    for (int k = 0; k < 3; k++) {
        if (force) force[k] = w->force[i][k];
        if (torque) torque[k] = w->force[i][3 + k];
    }
    return PBF_OK;
}

pbf_result pbf_world_collider_report(pbf_world *w, pbf_collider_id id, int steps_back, bool wait,
                                     pbf_collider_report *out)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!out) return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_collider_report: out must not be NULL");
    memset(out, 0, sizeof *out);
    collider_slot *s = get_slot(w, id, "pbf_world_collider_report");
    if (!s) return PBF_ERR_STALE_ID;
    if (steps_back < 1 || steps_back > RING - 1)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_collider_report: steps_back must be in [1, %d] (got %d)",
                        RING - 1, steps_back);
    if ((uint64_t)steps_back > w->step_index || w->step_index - (uint64_t)steps_back < s->added_step) {
        // No such step yet, or the collider did not exist then: no force.
        out->ready = true;
        out->step = w->step_index >= (uint64_t)steps_back ? w->step_index - (uint64_t)steps_back : 0;
        return PBF_OK;
    }
    uint64_t step = w->step_index - (uint64_t)steps_back;
    const pbf_collider_report *h = &s->hist[step % RING];
    if (!(h->ready && h->step == step)) refresh(w, wait ? (int64_t)step : -1);
    if (h->ready && h->step == step) {
        *out = *h;
    } else {
        out->step = step; // not finished yet (without `wait`): ready false, forces zero
        out->existed = true;
    }
    return PBF_OK;
}

void pbf_colliders_free(pbf_world *w)
{
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++) {
        free(w->slots[i].data);
        w->slots[i].data = NULL;
    }
    if (w->collider_data) glDeleteBuffers(1, &w->collider_data);
    w->collider_data = 0;
}
