// CPU reference, colliders: the host side of pbf_colliders.c (checks, poses, force scales,
// reports) and colliders.glsl's passes around the shared geometry (pbf_shapes.h).
#include "fluid/pbf_cpu_internal.h"
#include "fluid/pbf_uniforms.h"
#include "shaders/fluid/pbf_shapes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// ---- colliders (colliders.glsl) ---------------------------------------------------------
// The geometry (shapes, poses, boundary share, swept hit) is shaders/fluid/pbf_shapes.h,
// shared with the shaders; these wrappers name a collider as colliders.glsl's do.

static float shape_distance(const pbf_cpu_world *w, const pbf_gpu_collider *c, pbf_vec3 l, pbf_vec3 *ln)
{
    return shape_distance_of(w->collider_data, *c, l, ln);
}

static void collider_poses(const pbf_gpu_params *P, const pbf_gpu_collider *c, pbf_vec3 *p0, pbf_float4 *q0, pbf_vec3 *p1,
                           pbf_float4 *q1)
{
    collider_poses_of(P, *c, p0, q0, p1, q1);
}

static void collider_end_pose(const pbf_gpu_params *P, const pbf_gpu_collider *c, pbf_vec3 *p1, pbf_float4 *q1)
{
    pbf_vec3 p0;
    pbf_float4 q0;
    collider_poses(P, c, &p0, &q0, p1, q1);
}

static bool collider_boundary(const pbf_cpu_world *w, const pbf_gpu_params *P, const pbf_gpu_collider *c, pbf_vec3 x,
                              float *V, pbf_vec3 *gradV)
{
    return collider_boundary_of(P, w->collider_data, *c, x, V, gradV);
}

/// colliders_density: adds the colliders' share of the density at x and of grad_i C_i.
void pbf_cpu_colliders_density(const pbf_cpu_world *w, const pbf_gpu_params *P, pbf_vec3 x, float *rho, pbf_vec3 *grad_i)
{
    for (uint32_t b = 0; b < P->collider_count; b++) {
        float V;
        pbf_vec3 gradV;
        if (!collider_boundary(w, P, &w->gpu[b], x, &V, &gradV)) continue;
        *rho += P->rest_density * V;
        *grad_i = pbf_add(*grad_i, gradV);
    }
}

/// Adds v to a fixed-point accumulator as atomicAdd does (two's complement, wrapping).
static void accumulate(int32_t *acc, int32_t v) { *acc = (int32_t)((uint32_t)*acc + (uint32_t)v); }

/// add_force: force f (N) at point `at` on two-way collider b, in its fixed-point scale
/// (GLSL round() is round-half-even on Mesa: rintf in the default rounding mode).
static void add_force(pbf_cpu_world *w, uint32_t b, pbf_vec3 f, pbf_vec3 at)
{
    const pbf_gpu_collider *c = &w->gpu[b];
    if ((c->info.y & PBF_COLLIDER_TWO_WAY) == 0u) return;
    float s = c->center_of_mass.w;
    pbf_vec3 t = pbf_cross(pbf_sub(at, pbf_xyz(c->center_of_mass)), f);
    const float fs[3] = { f.x * s, f.y * s, f.z * s }, ts[3] = { t.x * s, t.y * s, t.z * s };
    for (int k = 0; k < 3; k++) {
        accumulate(&w->forces[b][k], (int32_t)rintf(fs[k]));
        accumulate(&w->forces[b][4 + k], (int32_t)rintf(ts[k]));
    }
}

/// particle_velocity: (x - xs) / dt, at most max_speed.
static pbf_vec3 particle_velocity(const pbf_gpu_params *P, pbf_vec3 xs, pbf_vec3 x)
{
    pbf_vec3 v = pbf_scale(P->inv_dt, pbf_sub(x, xs));
    float speed = sqrtf(pbf_dot(v, v));
    return speed > P->max_speed ? pbf_scale(P->max_speed / speed, v) : v;
}

/// add_wide: v into the 64-bit sum at acc[0] (low, unsigned) and acc[1] (high), as
/// colliders.glsl's add_wide does with two atomics.
static void accumulate_wide(int32_t *acc, int32_t v)
{
    uint64_t s = ((uint64_t)(uint32_t)acc[1] << 32 | (uint32_t)acc[0]) + (uint64_t)(int64_t)v;
    acc[0] = (int32_t)(uint32_t)s;
    acc[1] = (int32_t)(uint32_t)(s >> 32);
}

/// add_water: the velocity of a particle that started the substep at xs and is now at x,
/// weighted by the magnitude of its push f on two-way collider b, into b's sums of the water
/// that pushes it (in its force scale).
static void add_water(pbf_cpu_world *w, const pbf_gpu_params *P, uint32_t b, pbf_vec3 f, pbf_vec3 xs, pbf_vec3 x)
{
    pbf_vec3 v = particle_velocity(P, xs, x);
    float s = w->gpu[b].center_of_mass.w;
    float m = fminf(sqrtf(pbf_dot(f, f)) * s, PBF_WIDE_MAX);
    const float vs[3] = { fmaxf(fminf(m * v.x, PBF_WIDE_MAX), -PBF_WIDE_MAX), fmaxf(fminf(m * v.y, PBF_WIDE_MAX), -PBF_WIDE_MAX),
                          fmaxf(fminf(m * v.z, PBF_WIDE_MAX), -PBF_WIDE_MAX) };
    for (int k = 0; k < 3; k++) accumulate_wide(&w->forces[b][8 + 2 * k], (int32_t)rintf(vs[k]));
    accumulate_wide(&w->forces[b][14], (int32_t)rintf(m));
}

/// colliders_delta: the colliders' part of the position correction of a particle at x with
/// multiplier lambda, and the reaction on two-way colliders (f = -m relax bdp / dt^2), plus
/// in the coarse level's iteration their reaction to its push as to a multiplier
/// level_lambda = -p(x) (no motion of the particle; 0 otherwise); its velocity since xs (where
/// it started the substep) joins the sums of the water that pushes each two-way collider,
/// weighted by its push.
void pbf_cpu_colliders_delta(pbf_cpu_world *w, const pbf_gpu_params *P, pbf_vec3 x, float lambda, float relax,
                             float level_lambda, pbf_vec3 xs, pbf_vec3 *dp)
{
    float to_force = -P->mass * P->inv_dt * P->inv_dt * relax;
    float to_level = -P->mass * P->inv_dt * P->inv_dt;
    for (uint32_t b = 0; b < P->collider_count; b++) {
        const pbf_gpu_collider *c = &w->gpu[b];
        float V;
        pbf_vec3 gradV;
        if (!collider_boundary(w, P, c, x, &V, &gradV)) continue;
        pbf_vec3 bdp = pbf_scale(lambda, gradV);
        *dp = pbf_add(*dp, bdp);
        if ((c->info.y & PBF_COLLIDER_TWO_WAY) == 0u) continue;
        accumulate(&w->forces[b][3], 1);
        if (lambda != 0.0f || level_lambda != 0.0f) {
            // Acting at the particle's nearest surface point.
            pbf_vec3 p1, ln;
            pbf_float4 q1;
            collider_end_pose(P, c, &p1, &q1);
            float d = shape_distance(w, c, quat_rotate_inv(q1, pbf_sub(x, p1)), &ln);
            pbf_vec3 n = quat_rotate(q1, ln);
            pbf_vec3 f = pbf_scale(to_force, bdp);
            if (level_lambda != 0.0f) f = pbf_add(f, pbf_scale(to_level * level_lambda, gradV));
            add_force(w, b, f, pbf_sub(x, pbf_scale(d, n)));
            add_water(w, P, b, f, xs, x);
        }
    }
}

/// colliders_collide: moves a particle now at x, which started the substep at xs, out of
/// every collider to PBF_CONTACT_MARGIN of a particle radius from its surface, sweeping its path in each
/// collider's frame from the previous pose to the current one; particles that started
/// inside (or within r/2) are moved out at PBF_PUSH_OUT_SPEED at most, with no reaction.
pbf_vec3 pbf_cpu_colliders_collide(pbf_cpu_world *w, const pbf_gpu_params *P, pbf_vec3 xs, pbf_vec3 x)
{
    float to_force = -P->mass * P->inv_dt * P->inv_dt;
    float r = PBF_CONTACT_MARGIN * P->radius;
    for (uint32_t b = 0; b < P->collider_count; b++) {
        const pbf_gpu_collider *c = &w->gpu[b];
        pbf_vec3 p0, p1;
        pbf_float4 q0, q1;
        collider_poses(P, c, &p0, &q0, &p1, &q1);
        float turn = 2.0f * acosf(fminf(fabsf(pbf_dot4(q0, q1)), 1.0f)); // rad turned in this substep
        float reach = r + pbf_distance(p0, p1) + pbf_distance(xs, x) + c->position.w * turn;
        if (!collider_near_of(*c, p1, x, reach)) continue;
        pbf_vec3 l0 = quat_rotate_inv(q0, pbf_sub(xs, p0)); // where it started, in the collider's frame
        pbf_vec3 l1 = quat_rotate_inv(q1, pbf_sub(x, p1));  // where it is now
        pbf_vec3 n0, n1;
        float d0 = shape_distance(w, c, l0, &n0);
        float d1 = shape_distance(w, c, l1, &n1);
        pbf_vec3 lnew = l1;
        if (d0 < 0.5f * r) {
            float target = fminf(r, d0 + (float)PBF_PUSH_OUT_SPEED * P->dt);
            if (d1 < target) {
                lnew = pbf_add(l1, pbf_scale(target - d1, n1));
                if ((c->info.y & PBF_COLLIDER_TWO_WAY) != 0u) accumulate(&w->forces[b][7], 1);
            }
            x = pbf_add(p1, quat_rotate(q1, lnew));
            continue;
        }
        float len = pbf_distance(l0, l1);
        if (d1 >= r && 0.5f * (d0 + d1 - len) > r) continue;
        pbf_vec3 hit;
        if (!sweep_hit_of(w->collider_data, *c, l0, l1, d0, r, &hit)) continue;
        pbf_vec3 nh;
        shape_distance(w, c, hit, &nh);
        // Keep the motion along the surface, remove the part into it.
        float into = pbf_dot(pbf_sub(l1, hit), nh);
        lnew = into < 0.0f ? pbf_sub(l1, pbf_scale(into, nh)) : l1;
        float dn = shape_distance(w, c, lnew, &n1);
        if (dn < r) lnew = pbf_add(lnew, pbf_scale(r - dn, n1));
        pbf_vec3 xn = pbf_add(p1, quat_rotate(q1, lnew));
        pbf_vec3 f = pbf_scale(to_force, pbf_sub(xn, x));
        add_force(w, b, f, pbf_sub(xn, pbf_scale(r, quat_rotate(q1, nh))));
        if ((c->info.y & PBF_COLLIDER_TWO_WAY) != 0u) add_water(w, P, b, f, xs, x);
        x = xn;
    }
    return x;
}

static bool finite_n(const float *v, int n)
{
    for (int k = 0; k < n; k++)
        if (!isfinite(v[k])) return false;
    return true;
}

static float len3f(const float *v) { return sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }


/// Fixed-point units per newton for a collider of bounding radius r (pbf_colliders.c): the
/// accumulators hold about 1000 times the weight of the fluid its bounding sphere displaces.
static float force_scale(const pbf_cpu_world *w, float r)
{
    if (!(r < 1e29f)) return (float)PBF_FORCE_SCALE;
    float gm = len3f(w->params.gravity);
    if (gm < 9.81f) gm = 9.81f;
    double weight = (double)w->params.rest_density * (4.0 / 3.0) * 3.14159265f * (double)r * r * r * gm;
    // The substeps of the step under way (set before its colliders begin; the time-step
    // guard may take more than params.substeps).
    int substeps = w->report_substeps > 0 ? (int)w->report_substeps : w->params.substeps;
    double range = 1000.0 * weight * (double)substeps;
    double s = 2147483647.0 / range;
    if (s > 1048576.0) s = 1048576.0;
    if (s < 1e-3) s = 1e-3;
    return (float)s;
}

static pbf_result check_collider(pbf_cpu_world *w, const pbf_collider_def *d)
{
    if ((unsigned)d->type > PBF_SHAPE_SDF)
        return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.type must be a pbf_collider_type 0..6 (got %d)",
                    (int)d->type);
    if (!finite_n(d->size, 4)) return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size must be finite");
    if (!finite_n(d->position, 3)) return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.position must be finite");
    if (!finite_n(d->rotation, 4)) return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.rotation must be finite");
    int need = d->type == PBF_SHAPE_BOX ? 3 : d->type == PBF_SHAPE_SPHERE ? 1
             : (d->type == PBF_SHAPE_CAPSULE || d->type == PBF_SHAPE_CYLINDER) ? 2 : 0;
    for (int k = 0; k < need; k++)
        if (!(d->size[k] > 0.0f))
            return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size[%d] must be > 0 m (got %g)", k,
                        (double)d->size[k]);
    float qn = sqrtf(d->rotation[0] * d->rotation[0] + d->rotation[1] * d->rotation[1] +
                     d->rotation[2] * d->rotation[2] + d->rotation[3] * d->rotation[3]);
    if (fabsf(qn - 1.0f) > 1e-3f)
        return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.rotation must be a unit quaternion (got length %g)",
                    (double)qn);
    if (d->type == PBF_SHAPE_PLANE && !(len3f(d->size) > 0.0f))
        return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size xyz (plane normal) must be non-zero");
    if (d->type == PBF_SHAPE_CONVEX_HULL) {
        if (!d->planes) return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.planes must not be NULL for a convex hull");
        if (d->plane_count < 4 || d->plane_count > PBF_MAX_HULL_PLANES)
            return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.plane_count must be in [4, %d] (got %u)",
                        PBF_MAX_HULL_PLANES, d->plane_count);
        for (uint32_t k = 0; k < d->plane_count; k++) {
            const float *p = d->planes + 4 * k;
            if (!finite_n(p, 4) || fabsf(len3f(p) - 1.0f) > 1e-3f)
                return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.planes[%u] must be finite with a unit normal "
                            "(got normal (%g, %g, %g), length %g, offset %g)", k, (double)p[0], (double)p[1],
                            (double)p[2], (double)len3f(p), (double)p[3]);
        }
        if (!(d->size[0] > 0.0f))
            return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size[0] (the hull's bounding radius about its "
                        "origin) must be > 0 m (got %g)", (double)d->size[0]);
    }
    if (d->type == PBF_SHAPE_SDF) {
        const pbf_sdf_grid *g = &d->grid;
        if (!g->values) return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.values must not be NULL");
        for (int k = 0; k < 3; k++)
            if (g->dims[k] < 2 || g->dims[k] > 1023)
                return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.dims[%d] must be in [2, 1023] (got %u)", k,
                            g->dims[k]);
        if (!isfinite(g->cell) || !(g->cell > 0.0f))
            return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.cell must be > 0 m and finite (got %g)",
                        (double)g->cell);
        if (!finite_n(g->origin, 3)) return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.origin must be finite");
        size_t n = (size_t)g->dims[0] * g->dims[1] * g->dims[2];
        for (size_t i = 0; i < n; i++)
            if (!isfinite(g->values[i]))
                return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.values[%zu] must be finite", i);
    }
    return PBF_OK;
}

pbf_result pbf_cpu_world_add_collider(pbf_cpu_world *w, const pbf_collider_def *d, uint32_t *index)
{
    if (index) *index = UINT32_MAX;
    if (!d) return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_add_collider: def must not be NULL");
    pbf_result r = check_collider(w, d);
    if (r != PBF_OK) return r;
    if (w->collider_count >= PBF_MAX_COLLIDERS)
        return pbf_cpu_fail(w, PBF_ERR_CAPACITY, "pbf_cpu_world_add_collider: all %d colliders in use", PBF_MAX_COLLIDERS);
    // Hull planes or grid samples, appended to the data in the order of addition (the
    // GPU packs them in slot order: the same offsets while nothing is removed).
    uint32_t count = pbf_collider_data_count(d);
    uint32_t offset = w->collider_data_count;
    if (count) {
        float *data = realloc(w->collider_data, ((size_t)offset + count) * sizeof *data);
        if (!data) return pbf_cpu_fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_cpu_world_add_collider: out of memory");
        pbf_collider_data_fill(d, data + offset);
        w->collider_data = data;
        w->collider_data_count += count;
    }
    const float *q = d->rotation;
    float qn = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    pbf_gpu_collider c;
    memset(&c, 0, sizeof c);
    c.position = (pbf_float4){ d->position[0], d->position[1], d->position[2], pbf_collider_bounding_radius(d) };
    c.rotation = (pbf_float4){ q[0] / qn, q[1] / qn, q[2] / qn, q[3] / qn };
    if (d->type == PBF_SHAPE_PLANE) {
        float nl = len3f(d->size);
        c.params = (pbf_float4){ d->size[0] / nl, d->size[1] / nl, d->size[2] / nl, d->size[3] };
    } else if (d->type == PBF_SHAPE_SDF) {
        c.params = (pbf_float4){ d->grid.origin[0], d->grid.origin[1], d->grid.origin[2], d->grid.cell };
    } else {
        c.params = (pbf_float4){ d->size[0], d->size[1], d->size[2], d->size[3] };
    }
    static const uint32_t gpu_type[] = { PBF_COLLIDER_PLANE, PBF_COLLIDER_BOX, PBF_COLLIDER_SPHERE,
                                         PBF_COLLIDER_CAPSULE, PBF_COLLIDER_CYLINDER, PBF_COLLIDER_HULL,
                                         PBF_COLLIDER_GRID };
    uint32_t packed = d->type == PBF_SHAPE_CONVEX_HULL ? d->plane_count
                    : d->type == PBF_SHAPE_SDF ? d->grid.dims[0] | d->grid.dims[1] << 10 | d->grid.dims[2] << 20 : 0u;
    uint32_t flags = (d->two_way ? PBF_COLLIDER_TWO_WAY : 0u) | (d->blocks_sinks ? PBF_COLLIDER_BLOCKS_SINKS : 0u);
    c.info = (pbf_uint4){ gpu_type[d->type], flags, offset, packed };
    c.prev_position = c.position;
    c.prev_rotation = c.rotation;
    c.center_of_mass = c.position;
    c.center_of_mass.w = force_scale(w, c.position.w);
    c.linear_velocity.w = 1.0f;
    c.angular_velocity.w = 1.0f;
    if (index) *index = w->collider_count;
    w->colliders[w->collider_count++] = c;
    return PBF_OK;
}

pbf_result pbf_cpu_world_set_collider_pose(pbf_cpu_world *w, uint32_t index, const float position[3],
                                           const float rotation[4], const float center_of_mass[3])
{
    if (index >= w->collider_count)
        return pbf_cpu_fail(w, PBF_ERR_STALE_ID, "pbf_cpu_world_set_collider_pose: index must be below the %u colliders "
                    "added (got %u)", w->collider_count, index);
    if (!position || !rotation)
        return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_set_collider_pose: position and rotation must not be NULL");
    if (!finite_n(position, 3) || !finite_n(rotation, 4) || (center_of_mass && !finite_n(center_of_mass, 3)))
        return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_set_collider_pose: position, rotation and center_of_mass "
                    "must be finite");
    float qn = sqrtf(rotation[0] * rotation[0] + rotation[1] * rotation[1] + rotation[2] * rotation[2] +
                     rotation[3] * rotation[3]);
    if (fabsf(qn - 1.0f) > 1e-3f)
        return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_set_collider_pose: rotation must be a unit quaternion "
                    "(got length %g)", (double)qn);
    pbf_gpu_collider *g = &w->colliders[index];
    g->prev_position = g->position;
    g->prev_rotation = g->rotation;
    g->position = (pbf_float4){ position[0], position[1], position[2], g->position.w };
    g->rotation = (pbf_float4){ rotation[0] / qn, rotation[1] / qn, rotation[2] / qn, rotation[3] / qn };
    const float *c = center_of_mass ? center_of_mass : position;
    g->center_of_mass = (pbf_float4){ c[0], c[1], c[2], g->center_of_mass.w };
    return PBF_OK;
}

pbf_result pbf_cpu_world_collider_report(const pbf_cpu_world *w, uint32_t index, pbf_collider_report *out)
{
    if (!out) return PBF_ERR_INVALID_ARG;
    memset(out, 0, sizeof *out);
    if (index >= w->collider_count) return PBF_ERR_STALE_ID;
    if (w->steps == 0) return PBF_OK;
    // As pbf_colliders_read_forces: the sums over the step's substeps, averaged, unscaled.
    const int32_t *f = w->forces[index];
    double k = 1.0 / (double)w->report_substeps / (double)w->gpu[index].center_of_mass.w;
    for (int c = 0; c < 3; c++) {
        out->force[c] = (float)(f[c] * k);
        out->torque[c] = (float)(f[4 + c] * k);
    }
    out->contacts = (uint32_t)f[3];
    out->pushed_out = (uint32_t)f[7];
    pbf_water_of_sums(f, w->gpu[index].center_of_mass.w, (int)w->report_substeps, out);
    out->step = w->steps - 1;
    out->ready = true;
    out->existed = true;
    return PBF_OK;
}

static bool moved(const pbf_gpu_collider *g)
{
    return memcmp(&g->prev_position, &g->position, sizeof g->position) != 0 ||
           memcmp(&g->prev_rotation, &g->rotation, sizeof g->rotation) != 0;
}

/// pbf_colliders_begin_step: force scales follow the parameters; poses set since the last
/// step span all of its substeps; the accumulators start from zero.
void pbf_cpu_colliders_begin_step(pbf_cpu_world *w)
{
    for (uint32_t b = 0; b < w->collider_count; b++) {
        pbf_gpu_collider *g = &w->colliders[b];
        g->center_of_mass.w = force_scale(w, g->position.w);
        g->linear_velocity.w = moved(g) ? (float)w->report_substeps : 1.0f;
        w->gpu[b] = *g;
    }
    w->gpu_count = w->collider_count;
    memset(w->forces, 0, sizeof w->forces);
}

/// pbf_colliders_end_step: the pose given for this step is the previous pose of the next.
void pbf_cpu_colliders_end_step(pbf_cpu_world *w)
{
    for (uint32_t b = 0; b < w->collider_count; b++) {
        w->colliders[b].prev_position = w->colliders[b].position;
        w->colliders[b].prev_rotation = w->colliders[b].rotation;
    }
}
