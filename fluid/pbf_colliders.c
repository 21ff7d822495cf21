// Colliders: rigid shapes as fluid boundaries (the generic interface a physics engine's
// bodies plug into; see fluid/bullet/coupling.c for Bullet). The GPU side is
// shaders/fluid/colliders.glsl.
#include "fluid/pbf_internal.h"

#include <math.h>
#include <string.h>

// ---- colliders --------------------------------------------------------------------------

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

static float bounding_radius(const pbf_collider_def *d)
{
    const float *z = d->size;
    switch (d->type) {
    case PBF_SHAPE_PLANE: return 1e30f;
    case PBF_SHAPE_BOX: return sqrtf(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    case PBF_SHAPE_SPHERE: return z[0];
    case PBF_SHAPE_CAPSULE: return z[0] + z[1];
    case PBF_SHAPE_CYLINDER: return sqrtf(z[0] * z[0] + z[1] * z[1]);
    }
    return 1e30f;
}

pbf_result pbf_world_add_collider(pbf_world *w, const pbf_collider_def *d, pbf_collider_id *out)
{
    if (out) *out = (pbf_collider_id){ 0, 0 };
    if ((unsigned)d->type > PBF_SHAPE_CYLINDER)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.type must be a pbf_collider_type 0..4 (got %d)", (int)d->type);
    if (!finite_n(d->size, 4) || !finite_n(d->position, 3) || !finite_n(d->rotation, 4))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size/position/rotation must be finite");
    int need = d->type == PBF_SHAPE_BOX ? 3 : d->type == PBF_SHAPE_SPHERE ? 1 : d->type == PBF_SHAPE_PLANE ? 0 : 2;
    for (int k = 0; k < need; k++)
        if (!(d->size[k] > 0.0f))
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size[%d] must be > 0 m (got %g)", k, (double)d->size[k]);
    float qn = sqrtf(d->rotation[0] * d->rotation[0] + d->rotation[1] * d->rotation[1] +
                     d->rotation[2] * d->rotation[2] + d->rotation[3] * d->rotation[3]);
    if (fabsf(qn - 1.0f) > 1e-3f)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.rotation must be a unit quaternion (got length %g)", (double)qn);
    int free_slot = -1;
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++)
        if (!w->slots[i].used) {
            free_slot = i;
            break;
        }
    if (free_slot < 0) return pbf_fail(w, PBF_ERR_CAPACITY, "pbf_world_add_collider: all %d colliders in use", PBF_MAX_COLLIDERS);
    collider_slot *s = &w->slots[free_slot];
    s->used = true;
    s->generation++;
    pbf_gpu_collider *g = &s->gpu;
    memset(g, 0, sizeof *g);
    g->position = (pbf_float4){ d->position[0], d->position[1], d->position[2], 0.0f };
    g->rotation = (pbf_float4){ d->rotation[0], d->rotation[1], d->rotation[2], d->rotation[3] };
    g->prev_position = g->position;
    g->prev_rotation = g->rotation;
    g->center_of_mass = g->position;
    if (d->type == PBF_SHAPE_PLANE) {
        float nl = sqrtf(d->size[0] * d->size[0] + d->size[1] * d->size[1] + d->size[2] * d->size[2]);
        if (!(nl > 0.0f)) {
            s->used = false;
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size xyz (plane normal) must be non-zero");
        }
        g->params = (pbf_float4){ d->size[0] / nl, d->size[1] / nl, d->size[2] / nl, d->size[3] };
    } else {
        g->params = (pbf_float4){ d->size[0], d->size[1], d->size[2], d->size[3] };
    }
    g->info = (pbf_uint4){ (uint32_t)d->type, d->two_way ? 1u : 0u, 0u, 0u };
    g->position.w = bounding_radius(d);
    memset(w->force[free_slot], 0, sizeof w->force[free_slot]);
    w->colliders_dirty = true;
    if (out) *out = (pbf_collider_id){ (uint16_t)(free_slot + 1), s->generation };
    return PBF_OK;
}

pbf_result pbf_world_remove_collider(pbf_world *w, pbf_collider_id id)
{
    collider_slot *s = get_slot(w, id, "pbf_world_remove_collider");
    if (!s) return PBF_ERR_STALE_ID;
    s->used = false;
    w->colliders_dirty = true;
    return PBF_OK;
}

pbf_result pbf_world_set_collider_pose(pbf_world *w, pbf_collider_id id, const float position[3],
                                       const float rotation[4], const float linear_velocity[3],
                                       const float angular_velocity[3], const float center_of_mass[3])
{
    collider_slot *s = get_slot(w, id, "pbf_world_set_collider_pose");
    if (!s) return PBF_ERR_STALE_ID;
    if (!finite_n(position, 3) || !finite_n(rotation, 4) || (linear_velocity && !finite_n(linear_velocity, 3)) ||
        (angular_velocity && !finite_n(angular_velocity, 3)) || (center_of_mass && !finite_n(center_of_mass, 3)))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_collider_pose: position, rotation and velocities must be finite");
    pbf_gpu_collider *g = &s->gpu;
    g->prev_position = g->position;
    g->prev_rotation = g->rotation;
    g->position = (pbf_float4){ position[0], position[1], position[2], g->position.w };
    g->rotation = (pbf_float4){ rotation[0], rotation[1], rotation[2], rotation[3] };
    if (linear_velocity) g->linear_velocity = (pbf_float4){ linear_velocity[0], linear_velocity[1], linear_velocity[2], 0 };
    if (angular_velocity) g->angular_velocity = (pbf_float4){ angular_velocity[0], angular_velocity[1], angular_velocity[2], 0 };
    g->center_of_mass = center_of_mass ? (pbf_float4){ center_of_mass[0], center_of_mass[1], center_of_mass[2], 0 } : g->position;
    w->colliders_dirty = true;
    return PBF_OK;
}

pbf_result pbf_world_collider_force(pbf_world *w, pbf_collider_id id, float force[3], float torque[3])
{
    collider_slot *s = get_slot(w, id, "pbf_world_collider_force");
    if (!s) return PBF_ERR_STALE_ID;
    int i = (int)(s - w->slots);
    for (int k = 0; k < 3; k++) {
        if (force) force[k] = w->force[i][k];
        if (torque) torque[k] = w->force[i][3 + k];
    }
    return PBF_OK;
}

void pbf_colliders_upload(pbf_world *w)
{
    pbf_gpu_collider tmp[PBF_MAX_COLLIDERS];
    uint32_t n = 0;
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++) {
        w->slots[i].gpu_index = -1;
        if (!w->slots[i].used) continue;
        w->slots[i].gpu_index = (int)n;
        tmp[n++] = w->slots[i].gpu;
    }
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->colliders);
    if (n) glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)n * (GLsizeiptr)sizeof(pbf_gpu_collider), tmp);
    w->gpu_colliders = n;
    w->colliders_dirty = false;
}


void pbf_colliders_begin_step(pbf_world *w, stats_slot *slot)
{
    if (w->colliders_dirty) pbf_colliders_upload(w);
    slot->colliders = (int)w->gpu_colliders;
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++) slot->collider_slot_of[i] = -1;
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++)
        if (w->slots[i].used && w->slots[i].gpu_index >= 0) slot->collider_slot_of[w->slots[i].gpu_index] = i;
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->forces);
    glClearBufferSubData(GL_SHADER_STORAGE_BUFFER, GL_R32I, 0, PBF_MAX_COLLIDERS * 8 * 4, GL_RED_INTEGER, GL_INT, NULL);
}

// Copies this step's force accumulators into the ring slot read back later, and makes the
// pose given for this step the previous pose of the next.
void pbf_colliders_end_step(pbf_world *w)
{
    int slot_index = w->ring_head;
    glBindBuffer(GL_COPY_READ_BUFFER, w->forces);
    glBindBuffer(GL_COPY_WRITE_BUFFER, w->forces);
    glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0,
                        (GLintptr)(1 + slot_index) * PBF_MAX_COLLIDERS * 8 * 4, PBF_MAX_COLLIDERS * 8 * 4);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++) {
        if (!w->slots[i].used) continue;
        w->slots[i].gpu.prev_position = w->slots[i].gpu.position;
        w->slots[i].gpu.prev_rotation = w->slots[i].gpu.rotation;
    }
}

// Reads the forces of a completed step (its fence has signalled: no stall).
void pbf_colliders_read_forces(pbf_world *w, const stats_slot *r)
{
    int slot = (int)(r - w->ring);
    if (r->colliders > 0) {
        int32_t f[PBF_MAX_COLLIDERS * 8];
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->forces);
        glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)(1 + slot) * PBF_MAX_COLLIDERS * 8 * 4,
                           (GLsizeiptr)r->colliders * 8 * 4, f);
        for (int g = 0; g < r->colliders; g++) {
            int sl = r->collider_slot_of[g];
            if (sl < 0 || w->force_step[sl] > r->step + 1) continue;
            for (int k = 0; k < 3; k++) {
                w->force[sl][k] = (float)(f[g * 8 + k] / PBF_FORCE_SCALE / r->substeps);
                w->force[sl][3 + k] = (float)(f[g * 8 + 4 + k] / PBF_FORCE_SCALE / r->substeps);
            }
            w->force_step[sl] = r->step + 1;
        }
    }
}
