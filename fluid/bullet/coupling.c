// Bullet bodies as two-way coupled fluid boundaries. See coupling.h for the API and
// docs/coupling.md for the model.
//
// The loop, per cpl_step(dt) with n fluid substeps of h = dt / n:
//   forces <- fluid step (current - force_latency), read back (fenced)
//   pbf_world_step_with(fluid, dt, hook):
//     hook before substep k: apply forces to dynamic two-way bodies; phys_world_step(h);
//                            collider pose <- body pose (the old one becomes previous)
//     fluid substep k: sweeps every collider from its previous to its new pose
// Bullet adds gravity at the start of its step and clears applied forces at the end, so
// a force applied in the hook acts for exactly that substep.
#include "fluid/bullet/coupling.h"
#include "fluid/bullet/coupling_mesh.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "shaders/fluid/pbf_shared.h"

// The fluid's collider limit: at most this many bodies, and at most this many colliders
// in all (a compound takes one per part).
#define CPL_MAX_BODIES PBF_MAX_COLLIDERS
// Steps of each body's acceleration kept for the added mass (more than the largest
// force_latency, 7).
#define CPL_ACCEL_RING 8

typedef struct body_entry {
    bool used;
    phys_body_id body;
    phys_body_type type;
    bool two_way;
    bool measured;              // the fluid accumulates its force (two-way, kinematic, or asked)
    pbf_collider_id collider;  // the first of collider_count (one per part of a compound)
    uint32_t collider_count;
    pbf_collider_id *colliders; // collider_count; for a compound, in the order of its children
    float (*local)[7];          // compound children: position xyz, rotation xyzw in the body frame
    cpl_body_stats stats;
    float force[3], torque[3]; // applied in each substep of the current step (smoothed)
    float damping[3];          // N: the lag damping applied with it this step (not smoothed)
    float accel[3];            // m/s^2: its acceleration in the steps the force was measured in (smoothed as the force)
    float lagged[3];           // m/s^2: that acceleration as the added mass takes it (at most g)
    float added;               // kg: the added mass the force is applied with (cpl_def.added_mass), 0 none
    float share;               // the share of full submersion's lift it is taken for (slowly followed)
    float step_accel[CPL_ACCEL_RING][3]; // m/s^2: its acceleration in coupling step k, at k % CPL_ACCEL_RING
    float mass, volume;        // kg, m^3 (dynamic bodies; for the impulse limit)
    int stopping;              // steps left since the water last stopped its motion (limit_impulse)
    float placed;              // s: held while being set down in water (placing)
    float v0[3];               // velocity it was made with, m/s
    float fall[3], gained[3];  // what gravity did to it before its first measurement: m, m/s
    float after[6];            // its position and velocity at the end of the last such step
    uint64_t full_step;        // the fluid step its boundary first had full strength (0: not yet)
    float hold_sum[6];         // placing: force xyz, torque xyz summed over the held steps measured at full strength
    int hold_n;                // how many
    bool in_water;             // being set down in water (placing holds it)
    bool has_force;            // let go: the measured force applies (placing is over)
} body_entry;

struct cpl_coupling {
    cpl_def def; // as created (checked by cpl_def_check); cpl_get_def gives it back
    uint64_t fluid_serial; // pbf_world_serial of def.fluid: a fluid world destroyed first is not touched
    char error[512];
    body_entry bodies[CPL_MAX_BODIES];
    pbf_collider_id single[CPL_MAX_BODIES]; // the collider of single-shape body i
    uint64_t steps;
    cpl_result hook_error;
};

static void drop(cpl_coupling *c, body_entry *e);
static void set_strength(cpl_coupling *c, body_entry *e, float strength);

static cpl_result fail(cpl_coupling *c, cpl_result r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

static cpl_result fail(cpl_coupling *c, cpl_result r, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(c->error, sizeof c->error, fmt, ap);
    va_end(ap);
    if (c->def.log) c->def.log(c->def.log_user, c->error);
    return r;
}

static void note(cpl_coupling *c, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void note(cpl_coupling *c, const char *fmt, ...)
{
    if (!c->def.log) return;
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    c->def.log(c->def.log_user, msg);
}

cpl_body_def cpl_default_body_def(void)
{
    cpl_body_def d;
    memset(&d, 0, sizeof d);
    d.two_way = true;
    return d;
}

cpl_coupling *cpl_create(const cpl_def *def, char *err, size_t err_size)
{
    char scratch[8];
    if (!err || !err_size) {
        err = scratch;
        err_size = sizeof scratch;
    }
    err[0] = 0;
    if (!def) {
        snprintf(err, err_size, "cpl_create: def must not be NULL");
        return NULL;
    }
    if (!def->phys) {
        snprintf(err, err_size, "cpl_def.phys must not be NULL");
        return NULL;
    }
    if (!def->fluid) {
        snprintf(err, err_size, "cpl_def.fluid must not be NULL");
        return NULL;
    }
    if (cpl_def_check(def, err, err_size) != CPL_OK) return NULL;
    cpl_coupling *c = calloc(1, sizeof *c);
    if (!c) {
        snprintf(err, err_size, "cpl_create: out of memory");
        return NULL;
    }
    c->def = *def;
    c->fluid_serial = pbf_world_serial(def->fluid);
    return c;
}

// True (with the error set) when the fluid world was destroyed before the coupling.
static bool fluid_gone(cpl_coupling *c, const char *fn)
{
    if (pbf_world_alive(c->def.fluid, c->fluid_serial)) return false;
    fail(c, CPL_ERR_FLUID, "%s: the fluid world (cpl_def.fluid) was destroyed before the coupling: destroy the "
         "coupling first", fn);
    return true;
}

cpl_result cpl_get_def(const cpl_coupling *c, cpl_def *out)
{
    if (!c) return CPL_ERR_INVALID_ARG;
    if (!out) return fail((cpl_coupling *)c, CPL_ERR_INVALID_ARG, "cpl_get_def: out must not be NULL");
    *out = c->def;
    return CPL_OK;
}

void cpl_destroy(cpl_coupling *c)
{
    if (!c) return;
    // The colliders go with the fluid world when it went first.
    if (pbf_world_alive(c->def.fluid, c->fluid_serial))
        for (int i = 0; i < CPL_MAX_BODIES; i++)
            if (c->bodies[i].used) drop(c, &c->bodies[i]);
    free(c);
}

const char *cpl_last_error(const cpl_coupling *c) { return c ? c->error : "cpl: coupling is NULL"; }

static bool same_body(phys_body_id a, phys_body_id b)
{
    return a.index1 == b.index1 && a.world0 == b.world0 && a.generation == b.generation;
}

static body_entry *find(const cpl_coupling *c, phys_body_id body)
{
    for (int i = 0; i < CPL_MAX_BODIES; i++)
        if (c->bodies[i].used && same_body(c->bodies[i].body, body)) return (body_entry *)&c->bodies[i];
    return NULL;
}

static body_entry *find_live(cpl_coupling *c, phys_body_id body, const char *fn)
{
    if (!phys_body_is_valid(c->def.phys, body)) {
        fail(c, CPL_ERR_STALE_ID, "%s: body (index1 %u, generation %u) is null or was destroyed: attempt to use a "
             "destroyed body", fn, body.index1, body.generation);
        return NULL;
    }
    body_entry *e = find(c, body);
    if (!e) fail(c, CPL_ERR_STALE_ID, "%s: body (index1 %u, generation %u) is not coupled", fn, body.index1, body.generation);
    return e;
}

// ---- bodies --------------------------------------------------------------------------------

static cpl_result collider_from_shape(cpl_coupling *c, const phys_shape_desc *s, pbf_collider_def *d,
                                      float **planes, float **grid_values)
{
    *planes = NULL;
    *grid_values = NULL;
    switch (s->type) {
    case PHYS_SHAPE_PLANE:
        d->type = PBF_SHAPE_PLANE;
        d->size[0] = s->plane.normal.x;
        d->size[1] = s->plane.normal.y;
        d->size[2] = s->plane.normal.z;
        d->size[3] = s->plane.offset;
        return CPL_OK;
    case PHYS_SHAPE_BOX:
        d->type = PBF_SHAPE_BOX;
        d->size[0] = s->box.half_extents.x;
        d->size[1] = s->box.half_extents.y;
        d->size[2] = s->box.half_extents.z;
        return CPL_OK;
    case PHYS_SHAPE_SPHERE:
        d->type = PBF_SHAPE_SPHERE;
        d->size[0] = s->sphere.radius;
        return CPL_OK;
    case PHYS_SHAPE_CAPSULE:
        d->type = PBF_SHAPE_CAPSULE;
        d->size[0] = s->capsule.radius;
        d->size[1] = s->capsule.half_height;
        return CPL_OK;
    case PHYS_SHAPE_CYLINDER:
        d->type = PBF_SHAPE_CYLINDER;
        d->size[0] = s->cylinder.radius;
        d->size[1] = s->cylinder.half_height;
        return CPL_OK;
    case PHYS_SHAPE_CONVEX_HULL: {
        const phys_hull_desc *h = &s->hull;
        if (h->plane_count < 4 || h->plane_count > PBF_MAX_HULL_PLANES)
            return fail(c, CPL_ERR_INVALID_ARG, "cpl_add_body: the body's convex hull has %u faces; at most %d "
                        "supported (simplify the hull)", h->plane_count, PBF_MAX_HULL_PLANES);
        float *p = malloc((size_t)h->plane_count * 4 * sizeof *p);
        if (!p) return fail(c, CPL_ERR_OUT_OF_MEMORY, "cpl_add_body: out of memory");
        for (uint32_t k = 0; k < h->plane_count; k++) {
            p[4 * k] = h->planes[k].normal.x;
            p[4 * k + 1] = h->planes[k].normal.y;
            p[4 * k + 2] = h->planes[k].normal.z;
            p[4 * k + 3] = h->planes[k].offset;
        }
        float r = 0.0f;
        for (uint32_t k = 0; k < h->point_count; k++) {
            phys_vec3 q = h->points[k];
            float l = sqrtf(q.x * q.x + q.y * q.y + q.z * q.z);
            if (l > r) r = l;
        }
        d->type = PBF_SHAPE_CONVEX_HULL;
        d->planes = p;
        d->plane_count = h->plane_count;
        d->size[0] = r;
        *planes = p;
        return CPL_OK;
    }
    case PHYS_SHAPE_TRIANGLE_MESH: {
        float h = pbf_world_params(c->def.fluid)->kernel_radius, cell = c->def.mesh_cell;
        cpl_mesh_bake bake;
        if (!cpl_bake_mesh(&s->mesh, h, &cell, &bake))
            return fail(c, CPL_ERR_OUT_OF_MEMORY, "cpl_add_body: out of memory baking a triangle mesh");
        if (cell != c->def.mesh_cell)
            note(c, "cpl_add_body: triangle mesh of %.3g m baked at %.3g m spacing instead of cpl_def.mesh_cell %.3g m "
                 "(at most 128 samples per axis)", (double)bake.extent, (double)cell, (double)c->def.mesh_cell);
        d->grid = bake.grid;
        *grid_values = bake.values;
        d->type = PBF_SHAPE_SDF;
        return CPL_OK;
    }
    case PHYS_SHAPE_COMPOUND:
        break; // one collider per child: cpl_add_body
    }
    return fail(c, CPL_ERR_INVALID_ARG, "cpl_add_body: unknown shape type %d", (int)s->type);
}

// Hamilton product and rotation of a vector by a unit quaternion (x, y, z, w).
static void qmul(const float a[4], const float b[4], float o[4])
{
    o[0] = a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1];
    o[1] = a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0];
    o[2] = a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3];
    o[3] = a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2];
}

static void qrot(const float q[4], const float v[3], float o[3])
{
    // v + w t + u x t with t = 2 u x v, u = q.xyz
    float t[3] = { 2.0f * (q[1] * v[2] - q[2] * v[1]), 2.0f * (q[2] * v[0] - q[0] * v[2]),
                   2.0f * (q[0] * v[1] - q[1] * v[0]) };
    o[0] = v[0] + q[3] * t[0] + (q[1] * t[2] - q[2] * t[1]);
    o[1] = v[1] + q[3] * t[1] + (q[2] * t[0] - q[0] * t[2]);
    o[2] = v[2] + q[3] * t[2] + (q[0] * t[1] - q[1] * t[0]);
}

// World pose of collider k of a body at (pos, rot): the body pose times the child's pose.
static void collider_pose(const body_entry *e, uint32_t k, const float pos[3], const float rot[4], float out_pos[3],
                          float out_rot[4])
{
    if (!e->local) {
        memcpy(out_pos, pos, 3 * sizeof(float));
        memcpy(out_rot, rot, 4 * sizeof(float));
        return;
    }
    float r[3];
    qrot(rot, e->local[k], r);
    for (int i = 0; i < 3; i++) out_pos[i] = pos[i] + r[i];
    qmul(rot, e->local[k] + 3, out_rot);
}

static cpl_result sync_pose(cpl_coupling *c, body_entry *e)
{
    phys_vec3 p, v = { 0, 0, 0 }, w = { 0, 0, 0 };
    phys_quat q;
    if (phys_body_get_pose(c->def.phys, e->body, &p, &q) != PHYS_OK)
        return fail(c, CPL_ERR_PHYS, "cpl_step: %s", phys_world_last_error(c->def.phys));
    if (e->type != PHYS_BODY_STATIC) {
        phys_body_get_linear_velocity(c->def.phys, e->body, &v);
        phys_body_get_angular_velocity(c->def.phys, e->body, &w);
    }
    float pos[3] = { p.x, p.y, p.z }, rot[4] = { q.x, q.y, q.z, q.w };
    float lin[3] = { v.x, v.y, v.z }, ang[3] = { w.x, w.y, w.z };
    for (uint32_t k = 0; k < e->collider_count; k++) {
        // Every collider of a body takes its torque about the body's centre of mass (its
        // origin), so a compound's children's torques add up to the body's.
        float cp[3], cr[4];
        collider_pose(e, k, pos, rot, cp, cr);
        if (pbf_world_set_collider_pose(c->def.fluid, e->colliders[k], cp, cr, lin, ang, pos) != PBF_OK)
            return fail(c, CPL_ERR_FLUID, "cpl_step: %s", pbf_world_last_error(c->def.fluid));
    }
    return CPL_OK;
}

static uint32_t colliders_in_use(const cpl_coupling *c)
{
    uint32_t n = 0;
    for (int i = 0; i < CPL_MAX_BODIES; i++)
        if (c->bodies[i].used) n += c->bodies[i].collider_count;
    return n;
}

// Adds the collider of one shape (a body's, or a compound child's) at the given pose.
static cpl_result add_collider(cpl_coupling *c, const phys_shape_desc *shape, const float pos[3], const float rot[4],
                               bool measured, bool blocks_sinks, pbf_collider_id *out)
{
    pbf_collider_def d = pbf_default_collider_def();
    float *planes = NULL, *grid = NULL;
    cpl_result r = collider_from_shape(c, shape, &d, &planes, &grid);
    if (r != CPL_OK) return r;
    memcpy(d.position, pos, sizeof d.position);
    memcpy(d.rotation, rot, sizeof d.rotation);
    d.two_way = measured; // the fluid layer's flag: accumulate the force (the coupling applies it or not)
    d.blocks_sinks = blocks_sinks;
    pbf_result pr = pbf_world_add_collider(c->def.fluid, &d, out);
    free(planes);
    free(grid);
    if (pr != PBF_OK)
        return fail(c, pr == PBF_ERR_CAPACITY ? CPL_ERR_CAPACITY : CPL_ERR_FLUID, "cpl_add_body: %s",
                    pbf_world_last_error(c->def.fluid));
    return CPL_OK;
}

cpl_result cpl_add_body(cpl_coupling *c, phys_body_id body, const cpl_body_def *def)
{
    if (!c) return CPL_ERR_INVALID_ARG;
    if (fluid_gone(c, "cpl_add_body")) return CPL_ERR_FLUID;
    if (!phys_body_is_valid(c->def.phys, body))
        return fail(c, CPL_ERR_STALE_ID, "cpl_add_body: body (index1 %u, generation %u) is null or was destroyed: "
                    "attempt to use a destroyed body", body.index1, body.generation);
    if (find(c, body))
        return fail(c, CPL_ERR_STALE_ID, "cpl_add_body: body (index1 %u, generation %u) is already coupled", body.index1,
                    body.generation);
    cpl_body_def bd = def ? *def : cpl_default_body_def();
    body_entry *e = NULL;
    for (int i = 0; i < CPL_MAX_BODIES && !e; i++)
        if (!c->bodies[i].used) e = &c->bodies[i];
    if (!e) return fail(c, CPL_ERR_CAPACITY, "cpl_add_body: all %d coupled bodies in use", CPL_MAX_BODIES);
    phys_body_type type;
    phys_shape_desc shape;
    phys_vec3 p;
    phys_quat q;
    if (phys_body_get_type(c->def.phys, body, &type) != PHYS_OK || phys_body_get_shape(c->def.phys, body, &shape) != PHYS_OK ||
        phys_body_get_pose(c->def.phys, body, &p, &q) != PHYS_OK)
        return fail(c, CPL_ERR_PHYS, "cpl_add_body: %s", phys_world_last_error(c->def.phys));
    bool two_way = type == PHYS_BODY_DYNAMIC && bd.two_way;
    bool measured = two_way || type == PHYS_BODY_KINEMATIC || bd.measure_force;
    float pos[3] = { p.x, p.y, p.z }, rot[4] = { q.x, q.y, q.z, q.w };
    uint32_t count = shape.type == PHYS_SHAPE_COMPOUND ? shape.compound.child_count : 1;
    uint32_t in_use = colliders_in_use(c);
    if (in_use + count > PBF_MAX_COLLIDERS) {
        if (shape.type == PHYS_SHAPE_COMPOUND)
            return fail(c, CPL_ERR_CAPACITY, "cpl_add_body: the body is a compound of %u parts, which needs %u fluid "
                        "colliders (one per part), but only %u of the fluid's %d are free (use fewer parts)",
                        count, count, PBF_MAX_COLLIDERS - in_use, PBF_MAX_COLLIDERS);
        return fail(c, CPL_ERR_CAPACITY, "cpl_add_body: all %d fluid colliders are in use", PBF_MAX_COLLIDERS);
    }
    memset(e, 0, sizeof *e);
    e->body = body;
    e->type = type;
    e->two_way = two_way;
    e->measured = measured;
    if (shape.type == PHYS_SHAPE_COMPOUND) {
        e->colliders = calloc(count, sizeof *e->colliders);
        e->local = calloc(count, sizeof *e->local);
        if (!e->colliders || !e->local) {
            free(e->colliders);
            free(e->local);
            e->colliders = NULL;
            e->local = NULL;
            return fail(c, CPL_ERR_OUT_OF_MEMORY, "cpl_add_body: out of memory");
        }
        for (uint32_t k = 0; k < count; k++) {
            const phys_compound_child *ch = &shape.compound.children[k];
            float l[7] = { ch->position.x, ch->position.y, ch->position.z, ch->rotation.x, ch->rotation.y,
                           ch->rotation.z, ch->rotation.w };
            memcpy(e->local[k], l, sizeof l);
        }
    } else {
        e->colliders = &c->single[e - c->bodies];
    }
    // In use from here on, so that drop() removes what was made when a later part fails.
    e->used = true;
    for (uint32_t k = 0; k < count; k++) {
        const phys_shape_desc *part = shape.type == PHYS_SHAPE_COMPOUND ? &shape.compound.children[k].desc : &shape;
        float cp[3], cr[4];
        collider_pose(e, k, pos, rot, cp, cr);
        cpl_result r = add_collider(c, part, cp, cr, measured, type == PHYS_BODY_STATIC, &e->colliders[k]);
        if (r != CPL_OK) {
            drop(c, e);
            return r;
        }
        e->collider_count = k + 1;
    }
    if (type == PHYS_BODY_DYNAMIC && phys_body_set_sleep_enabled(c->def.phys, body, false) != PHYS_OK) {
        drop(c, e);
        return fail(c, CPL_ERR_PHYS, "cpl_add_body: %s", phys_world_last_error(c->def.phys));
    }
    e->collider = e->colliders[0];
    e->stats.two_way = two_way;
    e->stats.measured = measured;
    if (two_way) {
        set_strength(c, e, 0.0f); // placed: its share grows in (cpl_step)
        phys_vec3 v0 = { 0.0f, 0.0f, 0.0f };
        phys_body_get_linear_velocity(c->def.phys, body, &v0);
        e->v0[0] = v0.x, e->v0[1] = v0.y, e->v0[2] = v0.z;
    }
    e->stats.collider = e->collider;
    e->volume = shape.volume;
    phys_mass_data md;
    if (type == PHYS_BODY_DYNAMIC && phys_body_get_mass_data(c->def.phys, body, &md) == PHYS_OK) e->mass = md.mass;

    return sync_pose(c, e);
}

static void drop(cpl_coupling *c, body_entry *e)
{
    for (uint32_t k = 0; k < e->collider_count; k++)
        if (pbf_collider_is_valid(c->def.fluid, e->colliders[k])) pbf_world_remove_collider(c->def.fluid, e->colliders[k]);
    if (e->local) {
        free(e->colliders);
        free(e->local);
    }
    e->colliders = NULL;
    e->local = NULL;
    e->collider_count = 0;
    e->used = false;
}

cpl_result cpl_remove_body(cpl_coupling *c, phys_body_id body)
{
    if (!c) return CPL_ERR_INVALID_ARG;
    if (fluid_gone(c, "cpl_remove_body")) return CPL_ERR_FLUID;
    body_entry *e = find(c, body);
    if (!e)
        return fail(c, CPL_ERR_STALE_ID, "cpl_remove_body: body (index1 %u, generation %u) is not coupled", body.index1,
                    body.generation);
    drop(c, e);
    return CPL_OK;
}

bool cpl_has_body(const cpl_coupling *c, phys_body_id body) { return c && find(c, body) != NULL; }

cpl_result cpl_body_collider(cpl_coupling *c, phys_body_id body, pbf_collider_id *out)
{
    if (!c) return CPL_ERR_INVALID_ARG;
    if (!out) return fail(c, CPL_ERR_INVALID_ARG, "cpl_body_collider: out must not be NULL");
    body_entry *e = find_live(c, body, "cpl_body_collider");
    if (!e) return CPL_ERR_STALE_ID;
    *out = e->collider;
    return CPL_OK;
}

cpl_result cpl_teleport_body(cpl_coupling *c, phys_body_id body, phys_vec3 position, phys_quat orientation)
{
    if (!c) return CPL_ERR_INVALID_ARG;
    if (fluid_gone(c, "cpl_teleport_body")) return CPL_ERR_FLUID;
    const float v[7] = { position.x, position.y, position.z, orientation.x, orientation.y, orientation.z, orientation.w };
    static const char *const names[7] = { "position.x", "position.y", "position.z", "orientation.x",
                                          "orientation.y", "orientation.z", "orientation.w" };
    for (int k = 0; k < 7; k++)
        if (!isfinite(v[k]))
            return fail(c, CPL_ERR_INVALID_ARG, "cpl_teleport_body: %s must be finite (got %g)", names[k], (double)v[k]);
    body_entry *e = find_live(c, body, "cpl_teleport_body");
    if (!e) return CPL_ERR_STALE_ID;
    if (phys_body_set_pose(c->def.phys, body, position, orientation) != PHYS_OK)
        return fail(c, CPL_ERR_INVALID_ARG, "cpl_teleport_body: %s", phys_world_last_error(c->def.phys));
    // Set twice: the previous pose equals the new one, so nothing is swept.
    cpl_result r = sync_pose(c, e);
    return r == CPL_OK ? sync_pose(c, e) : r;
}

// ---- the step ------------------------------------------------------------------------------

// The force and torque of the step, on a body integrated with its added mass m_a (added_mass):
// (m + m_a) a = m g + F + H + m_a a_lag, H the force the host holds on the body
// (phys_body_set_held_force, which Bullet applies whole), that is the force
// m (F + m_a (a_lag - g)) / (m + m_a) - m_a H / (m + m_a) on the body of mass m that Bullet
// integrates under m g + H. (Without the last term a steady push held a floating box down as if it
// were 1 + m_a / m times as strong: 2 N sank it as 4 N would.)
static void apply_fluid(cpl_coupling *c, body_entry *e)
{
    phys_vec3 f = { e->force[0] + e->damping[0], e->force[1] + e->damping[1], e->force[2] + e->damping[2] };
    if (e->added > 0.0f && e->mass > 0.0f) {
        phys_vec3 g = phys_world_get_gravity(c->def.phys), held = { 0.0f, 0.0f, 0.0f };
        if (phys_body_get_held_force(c->def.phys, e->body, &held, NULL) != PHYS_OK) held = (phys_vec3){ 0.0f, 0.0f, 0.0f };
        float k = e->mass / (e->mass + e->added);
        f.x = k * (f.x + e->added * (e->lagged[0] - g.x)) - (1.0f - k) * held.x;
        f.y = k * (f.y + e->added * (e->lagged[1] - g.y)) - (1.0f - k) * held.y;
        f.z = k * (f.z + e->added * (e->lagged[2] - g.z)) - (1.0f - k) * held.z;
    }
    phys_body_apply_force(c->def.phys, e->body, f, true);
    phys_body_apply_torque(c->def.phys, e->body, (phys_vec3){ e->torque[0], e->torque[1], e->torque[2] }, true);
}

// m/s: a body moving into the water's force faster than this is being stopped by it.
#define CPL_STOPPING_SPEED 0.01f

// The fluid may stop the body's motion against the force, bring it up to the speed of the
// water that pushes it along the force (`water`: the push-weighted mean velocity the step's
// report measured), and push it with at most impulse_limit times the acceleration of full
// submersion plus g/4, for one step. The bound keeps the late force of a plunge from throwing
// a light body back out (along gravity, and across it: a thin plate thrown face on through
// water at 10 m/s was thrown back to the wall by a bound on the lift alone): the water a
// plunging body pushes moves with it, so its speed adds nothing then (the share-weighted mean
// of all the water near a thin plate, tried first, took in the water flowing back round its
// rim and threw it back). The smoothed state keeps the bounded force, so its tail does not
// carry the excess either. The torque is left alone: a body on an axle or a hinge takes the
// force on its bearing and turns under the torque (scaled with the force, a plate on an axle
// under a jet received 32 % of the water's angular impulse). Before 0.20.0 the bound knew no
// water speed, so in zero gravity the water could stop a body but not push it
// (docs/coupling.md, "Latency and lockstep").
static void limit_impulse(cpl_coupling *c, body_entry *e, const float water[3], float dt)
{
    if (c->def.impulse_limit <= 0.0f || e->type != PHYS_BODY_DYNAMIC || !(e->mass > 0.0f) || !(e->volume > 0.0f)) return;
    float f = sqrtf(e->force[0] * e->force[0] + e->force[1] * e->force[1] + e->force[2] * e->force[2]);
    if (!(f > 0.0f)) return;
    phys_vec3 v, g = phys_world_get_gravity(c->def.phys);
    if (phys_body_get_linear_velocity(c->def.phys, e->body, &v) != PHYS_OK) return;
    float against = -(v.x * e->force[0] + v.y * e->force[1] + v.z * e->force[2]) / f; // m/s into the force
    float behind = ((water[0] - v.x) * e->force[0] + (water[1] - v.y) * e->force[1] + (water[2] - v.z) * e->force[2]) /
                   f; // m/s the water is faster than the body along the force
    // While (and a little after) the water stops a body's motion into it, the water pressed
    // ahead of it springs back (PBF's water is slightly compressible: a plate at 10 m/s left
    // it coming back at 3 m/s): that is no stream to be carried by, so its speed counts only
    // once the water has not opposed the body for the force's latency and smoothing and a
    // step more.
    if (against > CPL_STOPPING_SPEED) e->stopping = c->def.force_latency + 2 + (int)ceilf(c->def.force_smoothing /
                                                                                        (1.0f - c->def.force_smoothing));
    else if (e->stopping > 0) e->stopping--;
    if (e->stopping == 0 && behind > against) against = behind;
    float gmag = sqrtf(g.x * g.x + g.y * g.y + g.z * g.z);
    float rho_fluid = pbf_world_params(c->def.fluid)->rest_density;
    // Plus a quarter of g: the bound then sits above the lift that holds a neutral body, so
    // the noise of that lift is not cut on one side only (it made such a body sink).
    float accel = c->def.impulse_limit * gmag * (rho_fluid / (e->mass / e->volume) + 0.25f);
    float dv_max = (against > 0.0f ? against : 0.0f) + accel * dt;
    float dv = f * dt / e->mass;
    if (dv <= dv_max) return;
    float s = dv_max / dv;
    for (int k = 0; k < 3; k++) e->force[k] *= s;
    e->stats.limited_steps++;
}

// The fluid's force on a floating body is a restoring force measured tau late, which acts
// like the spring plus a damping of -k tau (k the heave stiffness): energy flows in at the
// body's heave frequency, and a light flat body bounces for ever (docs/coupling.md). This
// adds lag_damping k tau of damping along gravity, k = rho g V / H (H: the body's height
// along gravity), while the body floats: weighted by how far the lift of the step's measured
// force `measured` (N) is from none and from full submersion's.
static void lag_damping(cpl_coupling *c, body_entry *e, const float measured[3], float dt)
{
    e->damping[0] = e->damping[1] = e->damping[2] = 0.0f;
    if (c->def.lag_damping <= 0.0f || e->type != PHYS_BODY_DYNAMIC || !(e->mass > 0.0f) || !(e->volume > 0.0f)) return;
    phys_vec3 v, g = phys_world_get_gravity(c->def.phys);
    float gmag = sqrtf(g.x * g.x + g.y * g.y + g.z * g.z);
    if (!(gmag > 0.0f) || phys_body_get_linear_velocity(c->def.phys, e->body, &v) != PHYS_OK) return;
    float rho = pbf_world_params(c->def.fluid)->rest_density;
    float up = -(measured[0] * g.x + measured[1] * g.y + measured[2] * g.z) / gmag; // N
    float f = up / (rho * gmag * e->volume); // share of full submersion's lift
    float w = fminf(fmaxf(fminf(f, 1.0f - f) / 0.1f, 0.0f), 1.0f);
    if (!(w > 0.0f)) return;
    float keep = c->def.force_smoothing;
    // The force applied in a step is the mean over a step measured force_latency steps
    // earlier (centred half a step before that step's end), smoothed: keep / (1 - keep)
    // steps more on average.
    float tau = ((float)c->def.force_latency + 0.5f + keep / (1.0f - keep)) * dt;
    // The waterplane area: the volume over the height along gravity (exact for an upright
    // box or cylinder, 2/3 of a ball's middle section), V^(2/3) if Bullet has no extent.
    float area = powf(e->volume, 2.0f / 3.0f);
    phys_vec3 ext;
    if (phys_body_get_extent(c->def.phys, e->body, &ext) == PHYS_OK) {
        float height = (fabsf(g.x) * ext.x + fabsf(g.y) * ext.y + fabsf(g.z) * ext.z) / gmag;
        if (height > 0.0f) area = e->volume / height;
    }
    float k = rho * gmag * area;
    float damp = fminf(c->def.lag_damping * w * k * tau, e->mass / dt); // N s/m, at most a stop in one step
    float along = (v.x * g.x + v.y * g.y + v.z * g.z) / gmag;          // m/s along gravity
    e->damping[0] = -damp * along * g.x / gmag;
    e->damping[1] = -damp * along * g.y / gmag;
    e->damping[2] = -damp * along * g.z / gmag;
}

// The added mass (cpl_def.added_mass, docs/coupling.md "Added mass"): the body's acceleration
// in the step its force was measured in, `back` steps ago, smoothed with the force's `keep`,
// and m_a = C_a rho V times the share of full submersion's lift in the smoothed force.
#define CPL_ADDED_MASS_TIME 0.5f // s

static void added_mass(cpl_coupling *c, body_entry *e, int back, float keep, float dt)
{
    e->added = 0.0f;
    if (c->def.added_mass <= 0.0f || e->type != PHYS_BODY_DYNAMIC || !(e->mass > 0.0f) || !(e->volume > 0.0f)) return;
    const float zero[3] = { 0.0f, 0.0f, 0.0f };
    const float *a = c->steps >= (uint64_t)back ? e->step_accel[(c->steps - (uint64_t)back) % CPL_ACCEL_RING] : zero;
    for (int k = 0; k < 3; k++) e->accel[k] = keep * e->accel[k] + (1.0f - keep) * a[k];
    phys_vec3 g = phys_world_get_gravity(c->def.phys);
    float gmag = sqrtf(g.x * g.x + g.y * g.y + g.z * g.z);
    if (!(gmag > 0.0f)) return;
    // At most g: the correction is for what gravity and buoyancy start (a release); an impact's
    // or a contact's jolt, which the water answers with a slam rather than its inertia alone,
    // would come back a step later as a kick.
    float amag = sqrtf(e->accel[0] * e->accel[0] + e->accel[1] * e->accel[1] + e->accel[2] * e->accel[2]);
    float clamp = amag > gmag ? gmag / amag : 1.0f;
    float rho = pbf_world_params(c->def.fluid)->rest_density;
    float up = -(e->force[0] * g.x + e->force[1] * g.y + e->force[2] * g.z) / gmag;
    float share = fminf(fmaxf(up / (rho * gmag * e->volume), 0.0f), 1.0f);
    // The share changes with the body's heave, in step with its acceleration: taken as it is,
    // m_a a_lag would not average out over a bob and lifted floating bodies (a sphere of half
    // the water's density rode 0.026 of its height higher). So it follows the share over
    // CPL_ADDED_MASS_TIME, from its first measurement.
    float follow = e->has_force ? fminf(dt / CPL_ADDED_MASS_TIME, 1.0f) : 1.0f;
    e->share += follow * (share - e->share);
    e->added = c->def.added_mass * rho * e->volume * e->share;
    for (int k = 0; k < 3; k++) e->lagged[k] = clamp * e->accel[k];
}

// A body's force is measured force_latency steps late, and water within a spacing of a new
// body's surface, given the body's full boundary share at once, is thrown off it with a
// force many times its weight (a light box made at its draft was thrown 8 cm up, and a
// body made in water fell freely until its lift came: docs/coupling.md, "Placing"). So a
// new two-way body is *placed*:
// - it starts with no boundary share (pbf_world_set_collider_strength 0) and moves under
//   gravity alone until its first measurement (what a body in the air does anyway);
// - if that step found no water at it (made in the air), or it moves faster than
//   CPL_PLACE_SPEED (thrown in), it gets its full share and the measured force from then on;
// - otherwise it was set down in water: what gravity did to it in those steps is undone
//   (a teleport by the host in between is kept) and it is held there against gravity, its
//   velocity kept and the water's force not applied, while its share grows
//   from 0 to 1 over CPL_PLACE_TIME so that the water makes room for it gently; it is let
//   go with the force measured at the full share once CPL_PLACE_HOLD has passed and no
//   water is left inside it (at the latest after CPL_PLACE_MAX).
#define CPL_PLACE_TIME 0.1f  // s
#define CPL_PLACE_HOLD 0.3f  // s
#define CPL_PLACE_MAX 0.5f   // s
#define CPL_PLACE_SPEED 0.5f // m/s

static void set_strength(cpl_coupling *c, body_entry *e, float strength)
{
    for (uint32_t k = 0; k < e->collider_count; k++) pbf_world_set_collider_strength(c->def.fluid, e->colliders[k], strength);
}

static void set_force(body_entry *e, float x, float y, float z)
{
    e->force[0] = x, e->force[1] = y, e->force[2] = z;
    e->torque[0] = e->torque[1] = e->torque[2] = 0.0f;
    e->damping[0] = e->damping[1] = e->damping[2] = 0.0f;
}

// The body's position and velocity (and rotation, q may be NULL), false if Bullet has none.
static bool body_state(cpl_coupling *c, const body_entry *e, phys_vec3 *p, phys_quat *q, phys_vec3 *v)
{
    return phys_body_get_pose(c->def.phys, e->body, p, q) == PHYS_OK &&
           phys_body_get_linear_velocity(c->def.phys, e->body, v) == PHYS_OK;
}

// body_state, and what gravity did to the body before its first measurement (fall, gained)
// is forgotten where the host has moved it or set it going since the end of the last such
// step (`after`).
static bool unmeasured_state(cpl_coupling *c, body_entry *e, phys_vec3 *p, phys_quat *q, phys_vec3 *v)
{
    if (!body_state(c, e, p, q, v)) return false;
    if (p->x != e->after[0] || p->y != e->after[1] || p->z != e->after[2]) e->fall[0] = e->fall[1] = e->fall[2] = 0.0f;
    if (v->x != e->after[3] || v->y != e->after[4] || v->z != e->after[5])
        e->gained[0] = e->gained[1] = e->gained[2] = 0.0f;
    return true;
}

// True while the body is being placed (this step's force is set here). `back`: the
// report's age in steps (the step about to run is rep->step + back).
static bool placing(cpl_coupling *c, body_entry *e, const pbf_collider_report *rep, int back, float dt)
{
    if (!rep->existed) {
        set_force(e, 0.0f, 0.0f, 0.0f);
        return true;
    }
    if (!e->in_water) {
        bool dry = rep->contacts == 0 && rep->pushed_out == 0;
        float speed2 = e->v0[0] * e->v0[0] + e->v0[1] * e->v0[1] + e->v0[2] * e->v0[2];
        if (dry || speed2 > CPL_PLACE_SPEED * CPL_PLACE_SPEED) {
            set_strength(c, e, 1.0f);
            return false;
        }
        e->in_water = true;
        // Set down in water: undo what gravity did in the unmeasured steps (a teleport by
        // the host in between is kept).
        phys_vec3 p, v;
        phys_quat q;
        if (unmeasured_state(c, e, &p, &q, &v)) {
            if (e->fall[0] != 0.0f || e->fall[1] != 0.0f || e->fall[2] != 0.0f)
                phys_body_set_pose(c->def.phys, e->body, (phys_vec3){ p.x - e->fall[0], p.y - e->fall[1], p.z - e->fall[2] }, q);
            if (e->gained[0] != 0.0f || e->gained[1] != 0.0f || e->gained[2] != 0.0f)
                phys_body_set_linear_velocity(c->def.phys, e->body,
                                              (phys_vec3){ v.x - e->gained[0], v.y - e->gained[1], v.z - e->gained[2] });
        }
    }
    e->placed += dt;
    float strength = fminf(e->placed / CPL_PLACE_TIME, 1.0f);
    if (strength >= 1.0f && e->full_step == 0) e->full_step = rep->step + (uint64_t)back;
    set_strength(c, e, strength);
    bool full = e->full_step != 0 && rep->step >= e->full_step;
    if (full) {
        for (int k = 0; k < 3; k++) e->hold_sum[k] += rep->force[k], e->hold_sum[3 + k] += rep->torque[k];
        e->hold_n++;
    }
    bool done = full && e->placed >= CPL_PLACE_HOLD && rep->pushed_out == 0;
    if (done || e->placed >= CPL_PLACE_MAX) {
        // Let go: the smoothing starts from the mean over the hold at full strength (water
        // that has just made room still moves, and one measurement of it is far off).
        for (int k = 0; k < 3 && e->hold_n > 0; k++) {
            e->force[k] = e->hold_sum[k] / (float)e->hold_n;
            e->torque[k] = e->hold_sum[3 + k] / (float)e->hold_n;
        }
        set_strength(c, e, 1.0f);
        return false;
    }
    phys_vec3 g = phys_world_get_gravity(c->def.phys);
    set_force(e, -e->mass * g.x, -e->mass * g.y, -e->mass * g.z); // held: gravity cancelled
    return true;
}

static void hook(void *user, pbf_world *fluid, int substep, float dt)
{
    (void)fluid;
    (void)substep;
    cpl_coupling *c = user;
    if (c->hook_error != CPL_OK) return;
    for (int i = 0; i < CPL_MAX_BODIES; i++) {
        body_entry *e = &c->bodies[i];
        if (e->used && e->two_way) apply_fluid(c, e);
    }
    if (phys_world_step(c->def.phys, dt) != PHYS_OK) {
        c->hook_error = fail(c, CPL_ERR_PHYS, "cpl_step: %s", phys_world_last_error(c->def.phys));
        return;
    }
    for (int i = 0; i < CPL_MAX_BODIES; i++) {
        body_entry *e = &c->bodies[i];
        if (!e->used || e->type == PHYS_BODY_STATIC) continue;
        cpl_result r = sync_pose(c, e);
        if (r != CPL_OK) {
            c->hook_error = r;
            return;
        }
    }
}

cpl_result cpl_step(cpl_coupling *c, float dt)
{
    if (!c) return CPL_ERR_INVALID_ARG;
    if (fluid_gone(c, "cpl_step")) return CPL_ERR_FLUID;
    const pbf_params *fp = pbf_world_params(c->def.fluid);
    int most = fp->max_substeps > fp->substeps ? fp->max_substeps : fp->substeps;
    float shortest = CPL_MIN_SUBSTEP_DT * (float)most;
    if (!(dt >= shortest && dt <= 1.0f))
        return fail(c, CPL_ERR_INVALID_ARG, "cpl_step: dt must be in [%g, 1] s (Bullet's shortest step, %g s, times the "
                    "%d substeps the fluid may take) (got %g)", (double)shortest, (double)CPL_MIN_SUBSTEP_DT, most, (double)dt);
    // Bodies destroyed behind the coupling's back are uncoupled.
    for (int i = 0; i < CPL_MAX_BODIES; i++) {
        body_entry *e = &c->bodies[i];
        if (e->used && !phys_body_is_valid(c->def.phys, e->body)) {
            note(c, "cpl_step: body (index1 %u, generation %u) was destroyed; uncoupled", e->body.index1,
                 e->body.generation);
            drop(c, e);
        }
    }
    // The fluid's forces of step (now - latency), waiting for them if the GPU is behind;
    // for bodies only measured, of a step earlier still when the latency is 1, which a GPU
    // has normally finished (no stall for a reading nobody applies).
    for (int i = 0; i < CPL_MAX_BODIES; i++) {
        body_entry *e = &c->bodies[i];
        if (!e->used || !e->measured) continue;
        int back = e->two_way || c->def.force_latency >= 2 ? c->def.force_latency : 2;
        // A compound's force and torque are the sums over its children (all torques are
        // about the body's centre of mass).
        pbf_collider_report rep;
        if (pbf_world_collider_report(c->def.fluid, e->colliders[0], back, true, &rep) != PBF_OK)
            return fail(c, CPL_ERR_FLUID, "cpl_step: %s", pbf_world_last_error(c->def.fluid));
        // The pushing water's velocity: the mean over the parts, by their pushes.
        float water[3];
        for (int i = 0; i < 3; i++) water[i] = rep.fluid_velocity[i] * rep.fluid_push;
        for (uint32_t k = 1; k < e->collider_count; k++) {
            pbf_collider_report part;
            if (pbf_world_collider_report(c->def.fluid, e->colliders[k], back, true, &part) != PBF_OK)
                return fail(c, CPL_ERR_FLUID, "cpl_step: %s", pbf_world_last_error(c->def.fluid));
            for (int i = 0; i < 3; i++) {
                rep.force[i] += part.force[i];
                rep.torque[i] += part.torque[i];
                water[i] += part.fluid_velocity[i] * part.fluid_push;
            }
            rep.fluid_push += part.fluid_push;
            rep.contacts += part.contacts;
            rep.pushed_out += part.pushed_out;
        }
        for (int i = 0; i < 3; i++) water[i] = rep.fluid_push > 0.0f ? water[i] / rep.fluid_push : 0.0f;
        for (int k = 0; k < 3; k++) {
            e->stats.force[k] = rep.force[k];
            e->stats.torque[k] = rep.torque[k];
            e->stats.fluid_velocity[k] = water[k];
        }
        e->stats.fluid_push = rep.fluid_push;
        e->stats.force_step = rep.step;
        e->stats.contacts = rep.contacts;
        e->stats.pushed_out = rep.pushed_out;
        if (!e->two_way) continue;
        if (!e->has_force && placing(c, e, &rep, back, dt)) continue;
        // Smoothed from step to step (exponential average; the force's mean is kept),
        // starting from the first measured force itself, or from the mean over its hold for
        // a body that was placed.
        float keep = e->has_force || e->hold_n > 0 ? c->def.force_smoothing : 0.0f;
        for (int k = 0; k < 3; k++) {
            e->force[k] = keep * e->force[k] + (1.0f - keep) * rep.force[k];
            e->torque[k] = keep * e->torque[k] + (1.0f - keep) * rep.torque[k];
        }
        limit_impulse(c, e, water, dt);
        lag_damping(c, e, rep.force, dt);
        added_mass(c, e, back, keep, dt);
        e->has_force = true;
    }
    // Bodies not yet measured: what gravity does to them in this step (placing undoes it
    // for a body found set down in water).
    phys_vec3 before_p[CPL_MAX_BODIES] = { { 0.0f, 0.0f, 0.0f } }, before_v[CPL_MAX_BODIES] = { { 0.0f, 0.0f, 0.0f } };
    for (int i = 0; i < CPL_MAX_BODIES; i++) {
        body_entry *e = &c->bodies[i];
        if (e->used && e->two_way && !e->has_force && !e->in_water) unmeasured_state(c, e, &before_p[i], NULL, &before_v[i]);
    }
    // Each dynamic body's velocity before the step, for its acceleration in it (the added mass).
    phys_vec3 start_v[CPL_MAX_BODIES] = { { 0.0f, 0.0f, 0.0f } };
    for (int i = 0; i < CPL_MAX_BODIES; i++) {
        body_entry *e = &c->bodies[i];
        if (!e->used || !e->two_way || e->type != PHYS_BODY_DYNAMIC) continue;
        if (phys_body_get_linear_velocity(c->def.phys, e->body, &start_v[i]) != PHYS_OK)
            start_v[i] = (phys_vec3){ 0.0f, 0.0f, 0.0f };
    }
    c->hook_error = CPL_OK;
    pbf_result r = pbf_world_step_with(c->def.fluid, dt, hook, c);
    if (c->hook_error != CPL_OK) return c->hook_error;
    for (int i = 0; i < CPL_MAX_BODIES; i++) {
        body_entry *e = &c->bodies[i];
        phys_vec3 v;
        if (!e->used || !e->two_way || e->type != PHYS_BODY_DYNAMIC) continue;
        float *a = e->step_accel[c->steps % CPL_ACCEL_RING];
        if (phys_body_get_linear_velocity(c->def.phys, e->body, &v) != PHYS_OK || !e->has_force) {
            a[0] = a[1] = a[2] = 0.0f; // not yet let go: held, or falling before its first measurement
            continue;
        }
        a[0] = (v.x - start_v[i].x) / dt, a[1] = (v.y - start_v[i].y) / dt, a[2] = (v.z - start_v[i].z) / dt;
    }
    for (int i = 0; i < CPL_MAX_BODIES; i++) {
        body_entry *e = &c->bodies[i];
        if (!e->used || !e->two_way || e->has_force || e->in_water) continue;
        phys_vec3 p, v;
        if (!body_state(c, e, &p, NULL, &v)) continue;
        e->fall[0] += p.x - before_p[i].x - before_v[i].x * dt;
        e->fall[1] += p.y - before_p[i].y - before_v[i].y * dt;
        e->fall[2] += p.z - before_p[i].z - before_v[i].z * dt;
        e->gained[0] += v.x - before_v[i].x, e->gained[1] += v.y - before_v[i].y, e->gained[2] += v.z - before_v[i].z;
        float after[6] = { p.x, p.y, p.z, v.x, v.y, v.z };
        memcpy(e->after, after, sizeof after);
    }
    if (r != PBF_OK) return fail(c, CPL_ERR_FLUID, "cpl_step: %s", pbf_world_last_error(c->def.fluid));
    c->steps++;
    return CPL_OK;
}

cpl_result cpl_body_get_stats(cpl_coupling *c, phys_body_id body, cpl_body_stats *out)
{
    if (!c) return CPL_ERR_INVALID_ARG;
    if (!out) return fail(c, CPL_ERR_INVALID_ARG, "cpl_body_get_stats: out must not be NULL");
    body_entry *e = find_live(c, body, "cpl_body_get_stats");
    if (!e) return CPL_ERR_STALE_ID;
    *out = e->stats;
    return CPL_OK;
}

uint32_t cpl_body_count(const cpl_coupling *c)
{
    uint32_t n = 0;
    if (c)
        for (int i = 0; i < CPL_MAX_BODIES; i++) n += c->bodies[i].used;
    return n;
}

uint64_t cpl_step_count(const cpl_coupling *c) { return c ? c->steps : 0; }
