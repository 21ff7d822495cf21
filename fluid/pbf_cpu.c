// CPU reference of the fluid step. See pbf_cpu.h for what it mirrors and what not.
//
// Layout follows the GPU: particles live in slots (arrays of pbf_float4, as the SSBOs),
// each substep gathers them into cell order by a stable counting sort, and every pass
// reads one parameter block, a pbf_gpu_params filled as pbf_world.c fills the uniform
// block, through `P`. Each pass below names the shader it mirrors; keep them in step.
#include "fluid/pbf_cpu.h"
#include "fluid/pbf_uniforms.h"
#include "shaders/fluid/pbf_shared.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CAPACITY (1u << 20)
#define MAX_CELLS (1u << 24)

struct pbf_cpu_world {
    pbf_params params;
    pbf_constants k;
    uint32_t capacity, count, max_neighbours;
    uint32_t cells_per_kernel; // the GPU's default: the same grid, so the same sums in the same order
    float domain_min[3], domain_max[3];
    float grid_origin[3];
    uint32_t grid_dims[3], cells;
    float planes[PBF_MAX_PLANES][4];
    uint32_t plane_count;
    // Colliders as pbf_colliders.c keeps them (`colliders`, the host's copy, whose previous
    // pose catches up at the end of a step) and as the passes see them (`gpu`, uploaded at
    // the start of each step with the span of the poses set since), hull planes and grid
    // samples packed in `collider_data` (info.z offsets), and the step's fixed-point
    // force accumulators (PBF_B_FORCES: force xyz, contacts, torque xyz, push-outs).
    pbf_gpu_collider colliders[PBF_MAX_COLLIDERS], gpu[PBF_MAX_COLLIDERS];
    uint32_t collider_count, gpu_count;
    float *collider_data;
    uint32_t collider_data_count;
    int32_t forces[PBF_MAX_COLLIDERS][8];
    uint64_t steps;          // steps taken (the latest report's step is steps - 1)
    uint32_t report_substeps;// substeps of the latest step (forces are averaged over them)
    uint32_t last_substep;   // P.substep of the latest substep (the metrics pass sees it)

    // Particle slots; the second of each pair is the ping-pong partner.
    pbf_float4 *pos, *pos_out, *vel, *vel_out, *pred, *pred_out, *omega;
    uint32_t *id, *id_out;
    float *lambda, *rho;
    // Grid and neighbour lists.
    uint32_t *cell_of, *cell_start, *cell_fill, *sorted;
    uint32_t *nb_list, *nb_count;
    bool nb_valid; // the lists belong to the current slots and positions
    char error[512];
};

// ---- small vector helpers (float, evaluated in the order the shaders write) ----------

typedef struct v3 {
    float x, y, z;
} v3;

static v3 xyz(pbf_float4 a) { return (v3){ a.x, a.y, a.z }; }
static v3 add(v3 a, v3 b) { return (v3){ a.x + b.x, a.y + b.y, a.z + b.z }; }
static v3 sub(v3 a, v3 b) { return (v3){ a.x - b.x, a.y - b.y, a.z - b.z }; }
static v3 scale(float s, v3 a) { return (v3){ s * a.x, s * a.y, s * a.z }; }
static v3 divide(v3 a, float s) { return (v3){ a.x / s, a.y / s, a.z / s }; }
static float dot(v3 a, v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static float length(v3 a) { return sqrtf(dot(a, a)); }
static v3 cross(v3 a, v3 b)
{
    return (v3){ a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y };
}
static float clampf(float x, float lo, float hi) { return fminf(fmaxf(x, lo), hi); }
static float signf(float x) { return x > 0.0f ? 1.0f : x < 0.0f ? -1.0f : 0.0f; }
static bool finite3(v3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

static pbf_result fail(pbf_cpu_world *w, pbf_result r, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(w->error, sizeof w->error, fmt, ap);
    va_end(ap);
    return r;
}

// ---- kernels and boundaries (common.glsl, colliders.glsl) -----------------------------

static float w_poly6(const pbf_gpu_params *P, float r2)
{
    float d = P->h * P->h - r2;
    return d > 0.0f ? P->poly6 * d * d * d : 0.0f;
}

/// Gradient of the spiky kernel with respect to x_i for r = x_i - x_j (1/m^4).
static v3 grad_spiky(const pbf_gpu_params *P, v3 r)
{
    float len = length(r);
    if (len <= 1e-9f * P->h || len >= P->h) return (v3){ 0.0f, 0.0f, 0.0f };
    float d = P->h - len;
    return scale(P->spiky_grad * d * d / len, r);
}

float pbf_cpu_boundary_volume(float d, float h)
{
    float u = clampf(d / h, 0.0f, 1.0f);
    float u2 = u * u;
    // F(u) = u - 4u^3/3 + 6u^5/5 - 4u^7/7 + u^9/9, the antiderivative of (1 - u^2)^4.
    float F = u * (1.0f + u2 * (-4.0f / 3.0f + u2 * (6.0f / 5.0f + u2 * (-4.0f / 7.0f + u2 / 9.0f))));
    return (315.0f / 256.0f) * (128.0f / 315.0f - F);
}

float pbf_cpu_boundary_gradient(float d, float h)
{
    float u = clampf(d / h, 0.0f, 1.0f);
    // H(u) = u^2/2 - u^3 + 3u^4/4 - u^5/5, the antiderivative of u (1 - u)^3.
    float H = u * u * (0.5f + u * (-1.0f + u * (0.75f - u * 0.2f)));
    return (30.0f / h) * (0.05f - H);
}

/// common.glsl boundary_volume with the lattice calibration, in the shader's order of
/// operations (pbf_cpu_boundary_volume is the continuous V(d) the tests integrate).
static float boundary_volume(const pbf_gpu_params *P, float d)
{
    float u = clampf(d / P->h, 0.0f, 1.0f);
    float u2 = u * u;
    float F = u * (1.0f + u2 * (-4.0f / 3.0f + u2 * (6.0f / 5.0f + u2 * (-4.0f / 7.0f + u2 / 9.0f))));
    return P->boundary_scale * (315.0f / 256.0f) * (128.0f / 315.0f - F);
}

/// common.glsl boundary_gradient, likewise (1/m).
static float boundary_gradient(const pbf_gpu_params *P, float d)
{
    float u = clampf(d / P->h, 0.0f, 1.0f);
    float H = u * u * (0.5f + u * (-1.0f + u * (0.75f - u * 0.2f)));
    return P->boundary_scale * (30.0f / P->h) * (0.05f - H);
}

static float plane_distance(const pbf_gpu_params *P, uint32_t p, v3 x, v3 *n)
{
    *n = xyz(P->planes[p]);
    return dot(x, *n) - P->planes[p].w;
}

/// common.glsl container_boundary: the union of the planes' half-spaces.
static float container_boundary(const pbf_gpu_params *P, v3 x, v3 *grad)
{
    float keep = 1.0f;
    float vp[PBF_MAX_PLANES];
    v3 gp[PBF_MAX_PLANES];
    for (uint32_t p = 0; p < P->plane_count; p++) {
        v3 n;
        float d = plane_distance(P, p, x, &n);
        vp[p] = d < P->h ? boundary_volume(P, d) : 0.0f;
        gp[p] = d < P->h ? scale(boundary_gradient(P, d), n) : (v3){ 0.0f, 0.0f, 0.0f };
        keep *= 1.0f - vp[p];
    }
    *grad = (v3){ 0.0f, 0.0f, 0.0f };
    for (uint32_t p = 0; p < P->plane_count; p++) {
        if (vp[p] <= 0.0f) continue;
        float others = 1.0f;
        for (uint32_t q = 0; q < P->plane_count; q++)
            if (q != p) others *= 1.0f - vp[q];
        *grad = sub(*grad, scale(others, gp[p]));
    }
    return 1.0f - keep;
}

// ---- colliders (colliders.glsl) ---------------------------------------------------------

static float dot4(pbf_float4 a, pbf_float4 b) { return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w; }
static float distance3(v3 a, v3 b) { return length(sub(a, b)); }
static v3 normalize3(v3 a) { return divide(a, length(a)); }
/// GLSL mix as the specification writes it: x (1 - a) + y a.
static float mixf(float x, float y, float a) { return x * (1.0f - a) + y * a; }
static v3 mix3(v3 x, v3 y, float a) { return (v3){ mixf(x.x, y.x, a), mixf(x.y, y.y, a), mixf(x.z, y.z, a) }; }
static int clampi(int x, int lo, int hi) { return x < lo ? lo : x > hi ? hi : x; }

static v3 quat_rotate(pbf_float4 q, v3 v)
{
    v3 u = { q.x, q.y, q.z };
    v3 t = scale(2.0f, cross(u, v));
    return add(add(v, scale(q.w, t)), cross(u, t));
}

static v3 quat_rotate_inv(pbf_float4 q, v3 v) { return quat_rotate((pbf_float4){ -q.x, -q.y, -q.z, q.w }, v); }

static float grid_sample(const float *data, uint32_t base, const uint32_t dims[3], int x, int y, int z)
{
    return data[base + (uint32_t)x + dims[0] * ((uint32_t)y + dims[1] * (uint32_t)z)];
}

/// grid_distance: trilinear distance and its gradient; outside the grid's box the distance
/// to the box is added.
static float grid_distance(const float *data, uint32_t base, uint32_t packed, pbf_float4 frame, v3 l, v3 *ln)
{
    const uint32_t dims[3] = { packed & 1023u, (packed >> 10) & 1023u, (packed >> 20) & 1023u };
    v3 lo = xyz(frame);
    v3 hi = add(lo, scale(frame.w, (v3){ (float)(dims[0] - 1u), (float)(dims[1] - 1u), (float)(dims[2] - 1u) }));
    v3 lc = { clampf(l.x, lo.x, hi.x), clampf(l.y, lo.y, hi.y), clampf(l.z, lo.z, hi.z) };
    v3 g = divide(sub(lc, lo), frame.w);
    int i0[3] = { clampi((int)floorf(g.x), 0, (int)dims[0] - 2), clampi((int)floorf(g.y), 0, (int)dims[1] - 2),
                  clampi((int)floorf(g.z), 0, (int)dims[2] - 2) };
    v3 f = { g.x - (float)i0[0], g.y - (float)i0[1], g.z - (float)i0[2] };
    float c000 = grid_sample(data, base, dims, i0[0], i0[1], i0[2]);
    float c100 = grid_sample(data, base, dims, i0[0] + 1, i0[1], i0[2]);
    float c010 = grid_sample(data, base, dims, i0[0], i0[1] + 1, i0[2]);
    float c110 = grid_sample(data, base, dims, i0[0] + 1, i0[1] + 1, i0[2]);
    float c001 = grid_sample(data, base, dims, i0[0], i0[1], i0[2] + 1);
    float c101 = grid_sample(data, base, dims, i0[0] + 1, i0[1], i0[2] + 1);
    float c011 = grid_sample(data, base, dims, i0[0], i0[1] + 1, i0[2] + 1);
    float c111 = grid_sample(data, base, dims, i0[0] + 1, i0[1] + 1, i0[2] + 1);
    float x00 = mixf(c000, c100, f.x), x10 = mixf(c010, c110, f.x);
    float x01 = mixf(c001, c101, f.x), x11 = mixf(c011, c111, f.x);
    float y0 = mixf(x00, x10, f.y), y1 = mixf(x01, x11, f.y);
    float d = mixf(y0, y1, f.z);
    v3 grad;
    grad.x = mixf(mixf(c100 - c000, c110 - c010, f.y), mixf(c101 - c001, c111 - c011, f.y), f.z);
    grad.y = mixf(x10 - x00, x11 - x01, f.z);
    grad.z = y1 - y0;
    float gl = length(grad);
    *ln = gl > 1e-12f ? divide(grad, gl) : (v3){ 0.0f, 1.0f, 0.0f };
    v3 out_of_box = sub(l, lc);
    float ob = length(out_of_box);
    if (ob > 0.0f) {
        d += ob;
        *ln = normalize3(add(out_of_box, scale(fmaxf(d - ob, 0.0f), *ln)));
    }
    return d;
}

/// hull_distance: the largest face-plane distance.
static float hull_distance(const float *data, uint32_t base, uint32_t count, v3 l, v3 *ln)
{
    float best = -1e30f;
    *ln = (v3){ 0.0f, 1.0f, 0.0f };
    for (uint32_t k = 0; k < count; k++) {
        const float *o = data + base + 4u * k;
        v3 n = { o[0], o[1], o[2] };
        float d = dot(n, l) - o[3];
        if (d > best) {
            best = d;
            *ln = n;
        }
    }
    return best;
}

/// shape_distance: signed distance (m, positive outside the solid) from local point l to
/// the surface of collider c's shape, and the outward unit normal, both in its frame.
static float shape_distance(const pbf_cpu_world *w, const pbf_gpu_collider *c, v3 l, v3 *ln)
{
    uint32_t type = c->info.x;
    pbf_float4 s = c->params;
    float d;
    if (type == PBF_COLLIDER_PLANE) {
        *ln = xyz(s);
        d = dot(l, *ln) - s.w;
    } else if (type == PBF_COLLIDER_SPHERE) {
        float len = length(l);
        *ln = len > 1e-9f ? divide(l, len) : (v3){ 0.0f, 1.0f, 0.0f };
        d = len - s.x;
    } else if (type == PBF_COLLIDER_BOX) {
        v3 q3 = { fabsf(l.x) - s.x, fabsf(l.y) - s.y, fabsf(l.z) - s.z };
        if (fmaxf(q3.x, fmaxf(q3.y, q3.z)) > 0.0f) {
            v3 o = { fmaxf(q3.x, 0.0f), fmaxf(q3.y, 0.0f), fmaxf(q3.z, 0.0f) };
            d = length(o);
            *ln = divide((v3){ signf(l.x) * o.x, signf(l.y) * o.y, signf(l.z) * o.z }, fmaxf(d, 1e-12f));
        } else {
            // inside: nearest face
            if (q3.x > q3.y && q3.x > q3.z) *ln = (v3){ l.x < 0.0f ? -1.0f : 1.0f, 0.0f, 0.0f };
            else if (q3.y > q3.z) *ln = (v3){ 0.0f, l.y < 0.0f ? -1.0f : 1.0f, 0.0f };
            else *ln = (v3){ 0.0f, 0.0f, l.z < 0.0f ? -1.0f : 1.0f };
            d = fmaxf(q3.x, fmaxf(q3.y, q3.z));
        }
    } else if (type == PBF_COLLIDER_CAPSULE) {
        v3 r = { l.x - 0.0f, l.y - clampf(l.y, -s.y, s.y), l.z - 0.0f };
        float len = length(r);
        *ln = len > 1e-9f ? divide(r, len) : (v3){ 1.0f, 0.0f, 0.0f };
        d = len - s.x;
    } else if (type == PBF_COLLIDER_CYLINDER) {
        float rl = sqrtf(l.x * l.x + l.z * l.z);
        float qx = rl - s.x, qy = fabsf(l.y) - s.y;
        v3 radial = rl > 1e-9f ? divide((v3){ l.x, 0.0f, l.z }, rl) : (v3){ 1.0f, 0.0f, 0.0f };
        v3 axial = { 0.0f, l.y < 0.0f ? -1.0f : 1.0f, 0.0f };
        if (qx > 0.0f && qy > 0.0f) {
            d = sqrtf(qx * qx + qy * qy);
            *ln = normalize3(add(scale(qx, radial), scale(qy, axial)));
        } else if (qx > qy) {
            d = qx;
            *ln = radial;
        } else {
            d = qy;
            *ln = axial;
        }
    } else if (type == PBF_COLLIDER_HULL) {
        d = hull_distance(w->collider_data, c->info.z, c->info.w, l, ln);
    } else {
        d = grid_distance(w->collider_data, c->info.z, c->info.w, s, l, ln);
    }
    return d;
}

static pbf_float4 quat_nlerp(pbf_float4 a, pbf_float4 b, float t)
{
    if (dot4(a, b) < 0.0f) b = (pbf_float4){ -b.x, -b.y, -b.z, -b.w };
    pbf_float4 m = { mixf(a.x, b.x, t), mixf(a.y, b.y, t), mixf(a.z, b.z, t), mixf(a.w, b.w, t) };
    float len = sqrtf(dot4(m, m));
    return (pbf_float4){ m.x / len, m.y / len, m.z / len, m.w / len };
}

/// collider_poses: the pose at the start (p0, q0) and at the end (p1, q1) of substep
/// P->substep; a pose that spans several substeps (linear_velocity.w > 1) is interpolated.
static void collider_poses(const pbf_gpu_params *P, const pbf_gpu_collider *c, v3 *p0, pbf_float4 *q0, v3 *p1,
                           pbf_float4 *q1)
{
    v3 pa = xyz(c->prev_position), pb = xyz(c->position);
    pbf_float4 qa = c->prev_rotation, qb = c->rotation;
    float span = c->linear_velocity.w;
    if (span > 1.5f) {
        float t0 = (float)P->substep / span, t1 = fminf((float)(P->substep + 1u) / span, 1.0f);
        *p0 = mix3(pa, pb, t0);
        *q0 = quat_nlerp(qa, qb, t0);
        *p1 = mix3(pa, pb, t1);
        *q1 = quat_nlerp(qa, qb, t1);
    } else {
        *p0 = pa;
        *q0 = qa;
        *p1 = pb;
        *q1 = qb;
    }
}

static void collider_end_pose(const pbf_gpu_params *P, const pbf_gpu_collider *c, v3 *p1, pbf_float4 *q1)
{
    v3 p0;
    pbf_float4 q0;
    collider_poses(P, c, &p0, &q0, p1, q1);
}

static bool collider_near(v3 p1, const pbf_gpu_collider *c, v3 x, float reach)
{
    if (c->info.x == PBF_COLLIDER_PLANE) return true;
    return distance3(x, p1) <= c->position.w + reach;
}

/// Share of the kernel beyond a plane at signed distance d, and its slope in d, for the
/// continuous kernel (the lattice factor divided out): colliders.glsl's beyond().
static float boundary_factor(const pbf_gpu_params *P) { return 2.0f * boundary_volume(P, 0.0f); }
static float beyond(const pbf_gpu_params *P, float d, float inv_factor)
{
    return d >= 0.0f ? boundary_volume(P, d) * inv_factor : 1.0f - boundary_volume(P, -d) * inv_factor;
}
static float beyond_slope(const pbf_gpu_params *P, float d, float inv_factor)
{
    return -boundary_gradient(P, fabsf(d)) * inv_factor;
}

/// collider_boundary: the share V of a filled neighbourhood that collider c takes at x and
/// its gradient (1/m), at the end pose; boxes as a product of three slabs, other shapes as
/// the half-space at the signed distance; false when out of reach or inside.
static bool collider_boundary(const pbf_cpu_world *w, const pbf_gpu_params *P, const pbf_gpu_collider *c, v3 x,
                              float *V, v3 *gradV)
{
    *V = 0.0f;
    *gradV = (v3){ 0.0f, 0.0f, 0.0f };
    v3 p1;
    pbf_float4 q1;
    collider_end_pose(P, c, &p1, &q1);
    if (!collider_near(p1, c, x, P->h)) return false;
    v3 l = quat_rotate_inv(q1, sub(x, p1));
    v3 ln;
    float d = shape_distance(w, c, l, &ln);
    if (d >= P->h || d < 0.0f) return false;
    if (c->info.x == PBF_COLLIDER_BOX) {
        v3 e = xyz(c->params);
        v3 a = sub(e, l), b = add(e, l); // distances to the + and - faces of each slab
        float k = boundary_factor(P), ik = 1.0f / k;
        v3 F = { 1.0f - beyond(P, a.x, ik) - beyond(P, b.x, ik), 1.0f - beyond(P, a.y, ik) - beyond(P, b.y, ik),
                 1.0f - beyond(P, a.z, ik) - beyond(P, b.z, ik) };
        F = (v3){ fmaxf(F.x, 0.0f), fmaxf(F.y, 0.0f), fmaxf(F.z, 0.0f) };
        v3 dF = { beyond_slope(P, a.x, ik) - beyond_slope(P, b.x, ik), beyond_slope(P, a.y, ik) - beyond_slope(P, b.y, ik),
                  beyond_slope(P, a.z, ik) - beyond_slope(P, b.z, ik) };
        *V = k * F.x * F.y * F.z;
        *gradV = scale(k, quat_rotate(q1, (v3){ dF.x * F.y * F.z, F.x * dF.y * F.z, F.x * F.y * dF.z }));
    } else {
        *V = boundary_volume(P, d);
        *gradV = scale(-boundary_gradient(P, d), quat_rotate(q1, ln));
    }
    return true;
}

/// colliders_density: adds the colliders' share of the density at x and of grad_i C_i.
static void colliders_density(const pbf_cpu_world *w, const pbf_gpu_params *P, v3 x, float *rho, v3 *grad_i)
{
    for (uint32_t b = 0; b < P->collider_count; b++) {
        float V;
        v3 gradV;
        if (!collider_boundary(w, P, &w->gpu[b], x, &V, &gradV)) continue;
        *rho += P->rest_density * V;
        *grad_i = add(*grad_i, gradV);
    }
}

/// Adds v to a fixed-point accumulator as atomicAdd does (two's complement, wrapping).
static void accumulate(int32_t *acc, int32_t v) { *acc = (int32_t)((uint32_t)*acc + (uint32_t)v); }

/// add_force: force f (N) at point `at` on two-way collider b, in its fixed-point scale
/// (GLSL round() is round-half-even on Mesa: rintf in the default rounding mode).
static void add_force(pbf_cpu_world *w, uint32_t b, v3 f, v3 at)
{
    const pbf_gpu_collider *c = &w->gpu[b];
    if ((c->info.y & PBF_COLLIDER_TWO_WAY) == 0u) return;
    float s = c->center_of_mass.w;
    v3 t = cross(sub(at, xyz(c->center_of_mass)), f);
    const float fs[3] = { f.x * s, f.y * s, f.z * s }, ts[3] = { t.x * s, t.y * s, t.z * s };
    for (int k = 0; k < 3; k++) {
        accumulate(&w->forces[b][k], (int32_t)rintf(fs[k]));
        accumulate(&w->forces[b][4 + k], (int32_t)rintf(ts[k]));
    }
}

/// colliders_delta: the colliders' part of the position correction of a particle at x with
/// multiplier lambda, and the reaction on two-way colliders (f = -m omega bdp / dt^2).
static void colliders_delta(pbf_cpu_world *w, const pbf_gpu_params *P, v3 x, float lambda, v3 *dp)
{
    float to_force = -P->mass * P->inv_dt * P->inv_dt * P->omega;
    for (uint32_t b = 0; b < P->collider_count; b++) {
        const pbf_gpu_collider *c = &w->gpu[b];
        float V;
        v3 gradV;
        if (!collider_boundary(w, P, c, x, &V, &gradV)) continue;
        v3 bdp = scale(lambda, gradV);
        *dp = add(*dp, bdp);
        if ((c->info.y & PBF_COLLIDER_TWO_WAY) == 0u) continue;
        accumulate(&w->forces[b][3], 1);
        if (lambda != 0.0f) {
            // Acting at the particle's nearest surface point.
            v3 p1, ln;
            pbf_float4 q1;
            collider_end_pose(P, c, &p1, &q1);
            float d = shape_distance(w, c, quat_rotate_inv(q1, sub(x, p1)), &ln);
            v3 n = quat_rotate(q1, ln);
            add_force(w, b, scale(to_force, bdp), sub(x, scale(d, n)));
        }
    }
}

/// sweep_hit: the first point of the local path a -> e that comes within r of the surface,
/// by sphere tracing on the distance; false when none.
static bool sweep_hit(const pbf_cpu_world *w, const pbf_gpu_collider *c, v3 a, v3 e, float da, float r, v3 *hit)
{
    v3 seg = sub(e, a);
    float len = length(seg);
    *hit = e;
    if (len < 1e-9f) return false;
    float t = 0.0f, d = da;
    for (int k = 0; k < 24; k++) {
        if (d <= r * 1.001f) {
            *hit = add(a, scale(t, seg));
            return true;
        }
        t += (d - r) / len;
        if (t >= 1.0f) return false;
        v3 unused;
        d = shape_distance(w, c, add(a, scale(t, seg)), &unused);
    }
    *hit = add(a, scale(t, seg));
    return true;
}

/// colliders_collide: moves a particle now at x, which started the substep at xs, out of
/// every collider to a particle radius from its surface, sweeping its path in each
/// collider's frame from the previous pose to the current one; particles that started
/// inside (or within r/2) are moved out at PBF_PUSH_OUT_SPEED at most, with no reaction.
static v3 colliders_collide(pbf_cpu_world *w, const pbf_gpu_params *P, v3 xs, v3 x)
{
    float to_force = -P->mass * P->inv_dt * P->inv_dt;
    float r = P->radius;
    for (uint32_t b = 0; b < P->collider_count; b++) {
        const pbf_gpu_collider *c = &w->gpu[b];
        v3 p0, p1;
        pbf_float4 q0, q1;
        collider_poses(P, c, &p0, &q0, &p1, &q1);
        float turn = 2.0f * acosf(fminf(fabsf(dot4(q0, q1)), 1.0f)); // rad turned in this substep
        float reach = r + distance3(p0, p1) + distance3(xs, x) + c->position.w * turn;
        if (!collider_near(p1, c, x, reach)) continue;
        v3 l0 = quat_rotate_inv(q0, sub(xs, p0)); // where it started, in the collider's frame
        v3 l1 = quat_rotate_inv(q1, sub(x, p1));  // where it is now
        v3 n0, n1;
        float d0 = shape_distance(w, c, l0, &n0);
        float d1 = shape_distance(w, c, l1, &n1);
        v3 lnew = l1;
        if (d0 < 0.5f * r) {
            float target = fminf(r, d0 + (float)PBF_PUSH_OUT_SPEED * P->dt);
            if (d1 < target) {
                lnew = add(l1, scale(target - d1, n1));
                if ((c->info.y & PBF_COLLIDER_TWO_WAY) != 0u) accumulate(&w->forces[b][7], 1);
            }
            x = add(p1, quat_rotate(q1, lnew));
            continue;
        }
        float len = distance3(l0, l1);
        if (d1 >= r && 0.5f * (d0 + d1 - len) > r) continue;
        v3 hit;
        if (!sweep_hit(w, c, l0, l1, d0, r, &hit)) continue;
        v3 nh;
        shape_distance(w, c, hit, &nh);
        // Keep the motion along the surface, remove the part into it.
        float into = dot(sub(l1, hit), nh);
        lnew = into < 0.0f ? sub(l1, scale(into, nh)) : l1;
        float dn = shape_distance(w, c, lnew, &n1);
        if (dn < r) lnew = add(lnew, scale(r - dn, n1));
        v3 xn = add(p1, quat_rotate(q1, lnew));
        add_force(w, b, scale(to_force, sub(xn, x)), sub(xn, scale(r, quat_rotate(q1, nh))));
        x = xn;
    }
    return x;
}

// ---- creation, parameters, container ---------------------------------------------------

static pbf_result grid_layout(pbf_cpu_world *w, float h, char *err, size_t err_size)
{
    float origin[3];
    uint32_t dims[3];
    double total = (double)pbf_grid_geometry(w->domain_min, w->domain_max, h, w->cells_per_kernel, origin, dims);
    if (total > (double)MAX_CELLS) {
        snprintf(err, err_size, "pbf_cpu_world: the domain needs %.0f grid cells of size kernel_radius / %u; "
                 "at most %u allowed on the CPU (shrink the domain or enlarge the kernel)", total,
                 w->cells_per_kernel, MAX_CELLS);
        return PBF_ERR_INVALID_ARG;
    }
    uint32_t *start = malloc(((size_t)total + 1) * 4), *fill = malloc((size_t)total * 4);
    if (!start || !fill) {
        free(start);
        free(fill);
        snprintf(err, err_size, "pbf_cpu_world: out of memory for %.0f grid cells", total);
        return PBF_ERR_OUT_OF_MEMORY;
    }
    free(w->cell_start);
    free(w->cell_fill);
    w->cell_start = start;
    w->cell_fill = fill;
    for (int k = 0; k < 3; k++) {
        w->grid_origin[k] = origin[k];
        w->grid_dims[k] = dims[k];
    }
    w->cells = (uint32_t)total;
    return PBF_OK;
}

pbf_cpu_world *pbf_cpu_world_create(const pbf_params *params, uint32_t capacity, const float domain_min[3],
                                    const float domain_max[3], char *err, size_t err_size)
{
    char scratch[8];
    if (!err || err_size == 0) {
        err = scratch;
        err_size = sizeof scratch;
    }
    err[0] = 0;
    if (!params || !domain_min || !domain_max) {
        snprintf(err, err_size, "pbf_cpu_world_create: params, domain_min and domain_max must not be NULL");
        return NULL;
    }
    if (pbf_params_validate(params, err, err_size) != PBF_OK) return NULL;
    if (capacity < 1 || capacity > MAX_CAPACITY) {
        snprintf(err, err_size, "pbf_cpu_world_create: capacity must be in [1, %u] (got %u)", MAX_CAPACITY, capacity);
        return NULL;
    }
    for (int k = 0; k < 3; k++) {
        if (!isfinite(domain_min[k]) || !isfinite(domain_max[k]) || !(domain_max[k] > domain_min[k])) {
            snprintf(err, err_size, "pbf_cpu_world_create: domain_max[%d] must be finite and greater than "
                     "domain_min[%d] (got min %g, max %g)", k, k, (double)domain_min[k], (double)domain_max[k]);
            return NULL;
        }
    }
    pbf_cpu_world *w = calloc(1, sizeof *w);
    if (!w) {
        snprintf(err, err_size, "pbf_cpu_world_create: out of memory");
        return NULL;
    }
    w->params = *params;
    w->k = pbf_derive_constants(params);
    w->capacity = capacity;
    w->max_neighbours = pbf_suggest_max_neighbours(params);
    w->cells_per_kernel = PBF_GRID_CELLS_PER_KERNEL;
    memcpy(w->domain_min, domain_min, sizeof w->domain_min);
    memcpy(w->domain_max, domain_max, sizeof w->domain_max);
    if (grid_layout(w, params->kernel_radius, err, err_size) != PBF_OK) {
        pbf_cpu_world_destroy(w);
        return NULL;
    }
    size_t n = capacity, v4 = n * sizeof(pbf_float4);
    w->pos = malloc(v4);
    w->pos_out = malloc(v4);
    w->vel = malloc(v4);
    w->vel_out = malloc(v4);
    w->pred = malloc(v4);
    w->pred_out = malloc(v4);
    w->omega = calloc(n, sizeof(pbf_float4));
    w->id = malloc(n * 4);
    w->id_out = malloc(n * 4);
    w->lambda = calloc(n, sizeof(float));
    w->rho = calloc(n, sizeof(float));
    w->cell_of = malloc(n * 4);
    w->sorted = malloc(n * 4);
    w->nb_count = calloc(n, 4);
    w->nb_list = malloc(n * w->max_neighbours * 4);
    if (!w->pos || !w->pos_out || !w->vel || !w->vel_out || !w->pred || !w->pred_out || !w->omega || !w->id ||
        !w->id_out || !w->lambda || !w->rho || !w->cell_of || !w->sorted || !w->nb_count || !w->nb_list) {
        snprintf(err, err_size, "pbf_cpu_world_create: out of memory for %u particles", capacity);
        pbf_cpu_world_destroy(w);
        return NULL;
    }
    return w;
}

void pbf_cpu_world_destroy(pbf_cpu_world *w)
{
    if (!w) return;
    void *blocks[] = { w->pos, w->pos_out, w->vel, w->vel_out, w->pred, w->pred_out, w->omega,
                       w->id, w->id_out, w->lambda, w->rho, w->cell_of, w->cell_start, w->cell_fill,
                       w->sorted, w->nb_list, w->nb_count, w->collider_data };
    for (size_t i = 0; i < sizeof blocks / sizeof blocks[0]; i++) free(blocks[i]);
    free(w);
}

const char *pbf_cpu_world_last_error(const pbf_cpu_world *w) { return w->error; }
const pbf_params *pbf_cpu_world_params(const pbf_cpu_world *w) { return &w->params; }
uint32_t pbf_cpu_world_particle_count(const pbf_cpu_world *w) { return w->count; }

pbf_result pbf_cpu_world_set_params(pbf_cpu_world *w, const pbf_params *p)
{
    char err[256];
    if (pbf_params_validate(p, err, sizeof err) != PBF_OK) return fail(w, PBF_ERR_INVALID_ARG, "%s", err);
    if (p->kernel_radius != w->params.kernel_radius) {
        pbf_result r = grid_layout(w, p->kernel_radius, err, sizeof err);
        if (r != PBF_OK) return fail(w, r, "%s", err);
        w->nb_valid = false;
    }
    w->params = *p;
    w->k = pbf_derive_constants(p);
    return PBF_OK;
}

pbf_result pbf_cpu_world_set_max_neighbours(pbf_cpu_world *w, uint32_t max_neighbours)
{
    if (max_neighbours < 8 || max_neighbours > 512)
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_set_max_neighbours: max_neighbours must be in [8, 512] "
                    "(got %u)", max_neighbours);
    uint32_t *list = malloc((size_t)w->capacity * max_neighbours * 4);
    if (!list) return fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_cpu_world_set_max_neighbours: out of memory");
    free(w->nb_list);
    w->nb_list = list;
    w->max_neighbours = max_neighbours;
    w->nb_valid = false;
    return PBF_OK;
}

pbf_result pbf_cpu_world_set_container(pbf_cpu_world *w, const float min[3], const float max[3], bool closed_top)
{
    char err[256];
    int n = pbf_container_planes(min, max, closed_top, w->domain_min, w->domain_max, w->planes, err, sizeof err);
    if (n == 0) return fail(w, PBF_ERR_INVALID_ARG, "%s", err);
    w->plane_count = (uint32_t)n;
    return PBF_OK;
}

void pbf_cpu_world_remove_container(pbf_cpu_world *w) { w->plane_count = 0; }

// ---- particles and colliders -----------------------------------------------------------

/// Colour parameter: height in the domain, in [0, 1] (pbf_world.c's colour_of).
static float colour_of(const pbf_cpu_world *w, float y)
{
    float t = (y - w->domain_min[1]) / (w->domain_max[1] - w->domain_min[1]);
    return t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
}

static void append(pbf_cpu_world *w, const float p[3], const float v[3])
{
    uint32_t i = w->count++;
    w->pos[i] = (pbf_float4){ p[0], p[1], p[2], colour_of(w, p[1]) };
    w->pred[i] = w->pos[i];
    w->vel[i] = (pbf_float4){ v[0], v[1], v[2], 0.0f };
    w->id[i] = i; // no removal: ids are 0 .. count - 1 in creation order
    w->nb_valid = false;
}

pbf_result pbf_cpu_world_add_particles(pbf_cpu_world *w, const float *positions, const float *velocities,
                                       uint32_t n)
{
    if (!positions && n > 0)
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_add_particles: positions must not be NULL");
    if (n > w->capacity - w->count)
        return fail(w, PBF_ERR_CAPACITY, "pbf_cpu_world_add_particles: %u particles do not fit: %u of capacity %u "
                    "in use", n, w->count, w->capacity);
    char err[256];
    if (!pbf_points_check("pbf_cpu_world_add_particles", positions, velocities, n, w->domain_min, w->domain_max, err, sizeof err))
        return fail(w, PBF_ERR_INVALID_ARG, "%s", err);
    static const float rest[3] = { 0.0f, 0.0f, 0.0f };
    for (uint32_t i = 0; i < n; i++) append(w, positions + 3 * i, velocities ? velocities + 3 * i : rest);
    return PBF_OK;
}

pbf_result pbf_cpu_world_add_block(pbf_cpu_world *w, const pbf_block_def *b, uint32_t *added)
{
    if (added) *added = 0;
    // The lattice of pbf_world_add_block (the same function lays it out).
    float s = w->k.spacing;
    uint32_t n[3];
    char err[256];
    uint64_t total = pbf_block_lattice(b, s, w->domain_min, w->domain_max, n, err, sizeof err);
    if (total == 0) return fail(w, PBF_ERR_INVALID_ARG, "%s", err);
    if (total > w->capacity - w->count)
        return fail(w, PBF_ERR_CAPACITY, "pbf_block_def: the block holds %llu particles but only %u of capacity %u "
                    "are free", (unsigned long long)total, w->capacity - w->count, w->capacity);
    for (uint32_t z = 0; z < n[2]; z++)
        for (uint32_t y = 0; y < n[1]; y++)
            for (uint32_t x = 0; x < n[0]; x++) {
                float p[3];
                pbf_block_point(b, s, x, y, z, p);
                append(w, p, b->velocity);
            }
    if (added) *added = (uint32_t)total;
    return PBF_OK;
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
    double range = 1000.0 * weight * (double)w->params.substeps;
    double s = 2147483647.0 / range;
    if (s > 1048576.0) s = 1048576.0;
    if (s < 1e-3) s = 1e-3;
    return (float)s;
}

static pbf_result check_collider(pbf_cpu_world *w, const pbf_collider_def *d)
{
    if ((unsigned)d->type > PBF_SHAPE_SDF)
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.type must be a pbf_collider_type 0..6 (got %d)",
                    (int)d->type);
    if (!finite_n(d->size, 4)) return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size must be finite");
    if (!finite_n(d->position, 3)) return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.position must be finite");
    if (!finite_n(d->rotation, 4)) return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.rotation must be finite");
    int need = d->type == PBF_SHAPE_BOX ? 3 : d->type == PBF_SHAPE_SPHERE ? 1
             : (d->type == PBF_SHAPE_CAPSULE || d->type == PBF_SHAPE_CYLINDER) ? 2 : 0;
    for (int k = 0; k < need; k++)
        if (!(d->size[k] > 0.0f))
            return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size[%d] must be > 0 m (got %g)", k,
                        (double)d->size[k]);
    float qn = sqrtf(d->rotation[0] * d->rotation[0] + d->rotation[1] * d->rotation[1] +
                     d->rotation[2] * d->rotation[2] + d->rotation[3] * d->rotation[3]);
    if (fabsf(qn - 1.0f) > 1e-3f)
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.rotation must be a unit quaternion (got length %g)",
                    (double)qn);
    if (d->type == PBF_SHAPE_PLANE && !(len3f(d->size) > 0.0f))
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size xyz (plane normal) must be non-zero");
    if (d->type == PBF_SHAPE_CONVEX_HULL) {
        if (!d->planes) return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.planes must not be NULL for a convex hull");
        if (d->plane_count < 4 || d->plane_count > PBF_MAX_HULL_PLANES)
            return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.plane_count must be in [4, %d] (got %u)",
                        PBF_MAX_HULL_PLANES, d->plane_count);
        for (uint32_t k = 0; k < d->plane_count; k++) {
            const float *p = d->planes + 4 * k;
            if (!finite_n(p, 4) || fabsf(len3f(p) - 1.0f) > 1e-3f)
                return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.planes[%u] must be finite with a unit normal "
                            "(got normal length %g)", k, (double)len3f(p));
        }
        if (!(d->size[0] > 0.0f))
            return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size[0] (the hull's bounding radius about its "
                        "origin) must be > 0 m (got %g)", (double)d->size[0]);
    }
    if (d->type == PBF_SHAPE_SDF) {
        const pbf_sdf_grid *g = &d->grid;
        if (!g->values) return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.values must not be NULL");
        for (int k = 0; k < 3; k++)
            if (g->dims[k] < 2 || g->dims[k] > 1023)
                return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.dims[%d] must be in [2, 1023] (got %u)", k,
                            g->dims[k]);
        if (!isfinite(g->cell) || !(g->cell > 0.0f))
            return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.cell must be > 0 m and finite (got %g)",
                        (double)g->cell);
        if (!finite_n(g->origin, 3)) return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.origin must be finite");
        size_t n = (size_t)g->dims[0] * g->dims[1] * g->dims[2];
        for (size_t i = 0; i < n; i++)
            if (!isfinite(g->values[i]))
                return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.grid.values[%zu] must be finite", i);
    }
    return PBF_OK;
}

pbf_result pbf_cpu_world_add_collider(pbf_cpu_world *w, const pbf_collider_def *d, uint32_t *index)
{
    if (index) *index = UINT32_MAX;
    if (!d) return fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_add_collider: def must not be NULL");
    pbf_result r = check_collider(w, d);
    if (r != PBF_OK) return r;
    if (w->collider_count >= PBF_MAX_COLLIDERS)
        return fail(w, PBF_ERR_CAPACITY, "pbf_cpu_world_add_collider: all %d colliders in use", PBF_MAX_COLLIDERS);
    // Hull planes or grid samples, appended to the data in the order of addition (the
    // GPU packs them in slot order: the same offsets while nothing is removed).
    uint32_t count = d->type == PBF_SHAPE_CONVEX_HULL ? 4 * d->plane_count
                   : d->type == PBF_SHAPE_SDF ? d->grid.dims[0] * d->grid.dims[1] * d->grid.dims[2] : 0;
    uint32_t offset = w->collider_data_count;
    if (count) {
        float *data = realloc(w->collider_data, ((size_t)offset + count) * sizeof *data);
        if (!data) return fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_cpu_world_add_collider: out of memory");
        memcpy(data + offset, d->type == PBF_SHAPE_SDF ? d->grid.values : d->planes, (size_t)count * sizeof *data);
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
    c.info = (pbf_uint4){ gpu_type[d->type], d->two_way ? PBF_COLLIDER_TWO_WAY : 0u, offset, packed };
    c.prev_position = c.position;
    c.prev_rotation = c.rotation;
    c.center_of_mass = c.position;
    c.center_of_mass.w = force_scale(w, c.position.w);
    c.linear_velocity.w = 1.0f;
    if (index) *index = w->collider_count;
    w->colliders[w->collider_count++] = c;
    return PBF_OK;
}

pbf_result pbf_cpu_world_set_collider_pose(pbf_cpu_world *w, uint32_t index, const float position[3],
                                           const float rotation[4], const float center_of_mass[3])
{
    if (index >= w->collider_count)
        return fail(w, PBF_ERR_STALE_ID, "pbf_cpu_world_set_collider_pose: index must be below the %u colliders "
                    "added (got %u)", w->collider_count, index);
    if (!position || !rotation)
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_set_collider_pose: position and rotation must not be NULL");
    if (!finite_n(position, 3) || !finite_n(rotation, 4) || (center_of_mass && !finite_n(center_of_mass, 3)))
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_set_collider_pose: position, rotation and center_of_mass "
                    "must be finite");
    float qn = sqrtf(rotation[0] * rotation[0] + rotation[1] * rotation[1] + rotation[2] * rotation[2] +
                     rotation[3] * rotation[3]);
    if (fabsf(qn - 1.0f) > 1e-3f)
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_set_collider_pose: rotation must be a unit quaternion "
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
    out->step = w->steps - 1;
    out->ready = true;
    return PBF_OK;
}

static bool moved(const pbf_gpu_collider *g)
{
    return memcmp(&g->prev_position, &g->position, sizeof g->position) != 0 ||
           memcmp(&g->prev_rotation, &g->rotation, sizeof g->rotation) != 0;
}

/// pbf_colliders_begin_step: force scales follow the parameters; poses set since the last
/// step span all of its substeps; the accumulators start from zero.
static void colliders_begin_step(pbf_cpu_world *w)
{
    for (uint32_t b = 0; b < w->collider_count; b++) {
        pbf_gpu_collider *g = &w->colliders[b];
        g->center_of_mass.w = force_scale(w, g->position.w);
        g->linear_velocity.w = moved(g) ? (float)w->params.substeps : 1.0f;
        w->gpu[b] = *g;
    }
    w->gpu_count = w->collider_count;
    memset(w->forces, 0, sizeof w->forces);
}

/// pbf_colliders_end_step: the pose given for this step is the previous pose of the next.
static void colliders_end_step(pbf_cpu_world *w)
{
    for (uint32_t b = 0; b < w->collider_count; b++) {
        w->colliders[b].prev_position = w->colliders[b].position;
        w->colliders[b].prev_rotation = w->colliders[b].rotation;
    }
}

// ---- the step --------------------------------------------------------------------------

/// The parameter block of one substep, filled as pbf_world.c's write_params fills it.
static pbf_gpu_params uniforms(const pbf_cpu_world *w, float dt)
{
    const pbf_params *p = &w->params;
    pbf_gpu_params g;
    memset(&g, 0, sizeof g);
    pbf_uniforms_solver(&g, p, &w->k, dt);
    pbf_uniforms_space(&g, w->grid_origin, w->grid_dims, w->cells, p->kernel_radius / (float)w->cells_per_kernel,
                       w->domain_min, w->domain_max,
                       (const float(*)[4])w->planes, w->plane_count, w->max_neighbours);
    g.count = w->count;
    g.collider_count = w->gpu_count;
    g.substep = w->last_substep;
    return g;
}

/// predict.comp: gravity, damping, speed clamp; x* = x + dt v.
static void predict(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 v = add(xyz(w->vel[i]), scale(P->dt, xyz(P->gravity)));
        v = scale(1.0f / (1.0f + P->damping * P->dt), v);
        float s = length(v);
        if (s > P->max_speed) v = scale(P->max_speed / s, v);
        w->vel[i] = (pbf_float4){ v.x, v.y, v.z, w->vel[i].w };
        v3 x = add(xyz(w->pos[i]), scale(P->dt, v));
        w->pred[i] = (pbf_float4){ x.x, x.y, x.z, 0.0f };
    }
}

/// Cell of a position along one axis, clamped to the grid (common.glsl's cell_coord).
static int cell_axis(float x, float origin, float inv_cell, uint32_t dim)
{
    float f = floorf((x - origin) * inv_cell);
    if (!(f >= 0.0f)) return 0; // also NaN
    if (f >= (float)(dim - 1)) return (int)dim - 1;
    return (int)f;
}

static void cell_coord(const pbf_gpu_params *P, v3 x, int c[3])
{
    c[0] = cell_axis(x.x, P->grid_origin.x, P->inv_cell, P->grid_dims.x);
    c[1] = cell_axis(x.y, P->grid_origin.y, P->inv_cell, P->grid_dims.y);
    c[2] = cell_axis(x.z, P->grid_origin.z, P->inv_cell, P->grid_dims.z);
}

static uint32_t cell_index(const pbf_gpu_params *P, int x, int y, int z)
{
    return (uint32_t)x + P->grid_dims.x * ((uint32_t)y + P->grid_dims.y * (uint32_t)z);
}

/// grid_count, scan, grid_scatter and grid_sort together: a stable counting sort of the
/// slots by the cell of x. sorted[k] is the slot in place k of cell order.
static void build_grid(pbf_cpu_world *w, const pbf_float4 *x, const pbf_gpu_params *P)
{
    memset(w->cell_start, 0, ((size_t)w->cells + 1) * 4);
    memset(w->cell_fill, 0, (size_t)w->cells * 4);
    for (uint32_t i = 0; i < w->count; i++) {
        int c[3];
        cell_coord(P, xyz(x[i]), c);
        w->cell_of[i] = cell_index(P, c[0], c[1], c[2]);
        w->cell_start[w->cell_of[i]]++;
    }
    uint32_t sum = 0;
    for (uint32_t c = 0; c <= w->cells; c++) {
        uint32_t n = w->cell_start[c];
        w->cell_start[c] = sum;
        sum += n;
    }
    for (uint32_t i = 0; i < w->count; i++) {
        uint32_t c = w->cell_of[i];
        w->sorted[w->cell_start[c] + w->cell_fill[c]++] = i;
    }
}

static void swap4(pbf_float4 **a, pbf_float4 **b)
{
    pbf_float4 *t = *a;
    *a = *b;
    *b = t;
}

static void swap_ids(uint32_t **a, uint32_t **b)
{
    uint32_t *t = *a;
    *a = *b;
    *b = t;
}

/// reorder.comp: gathers the particle data into cell order; afterwards slot k is place k.
static void reorder(pbf_cpu_world *w)
{
    for (uint32_t i = 0; i < w->count; i++) {
        uint32_t j = w->sorted[i];
        w->pos_out[i] = w->pos[j];
        w->vel_out[i] = w->vel[j];
        w->pred_out[i] = w->pred[j];
        w->id_out[i] = w->id[j];
    }
    swap4(&w->pos, &w->pos_out);
    swap4(&w->vel, &w->vel_out);
    swap4(&w->pred, &w->pred_out);
    swap_ids(&w->id, &w->id_out);
    for (uint32_t i = 0; i < w->count; i++) w->sorted[i] = i;
}

/// neighbours.comp: for each slot, the slots within h of x, walked as FOR_NEIGHBOURS walks
/// them (9 runs of 3 cells); a list keeps the first max_neighbours, the count all of them.
static void find_neighbours(pbf_cpu_world *w, const pbf_float4 *x, const pbf_gpu_params *P)
{
    int dims[3] = { (int)P->grid_dims.x, (int)P->grid_dims.y, (int)P->grid_dims.z };
    float h2 = P->h * P->h;
    for (uint32_t i = 0; i < w->count; i++) {
        v3 xi = xyz(x[i]);
        int c[3];
        cell_coord(P, xi, c);
        uint32_t n = 0, *list = w->nb_list + (size_t)i * w->max_neighbours;
        // The cells within `reach` of the particle's, rows in z then y order, x ascending
        // (neighbours.comp skips rows and trims x ranges that hold nothing within h: the
        // same neighbours in the same order).
        int reach = (int)ceilf(P->h * P->inv_cell - 1e-4f);
        for (int dz = -reach; dz <= reach; dz++)
            for (int dy = -reach; dy <= reach; dy++) {
                int y = c[1] + dy, z = c[2] + dz;
                if (y < 0 || z < 0 || y >= dims[1] || z >= dims[2]) continue;
                int x0 = c[0] - reach > 0 ? c[0] - reach : 0;
                int x1 = c[0] + reach < dims[0] ? c[0] + reach : dims[0] - 1;
                uint32_t b = w->cell_start[cell_index(P, x0, y, z)], e = w->cell_start[cell_index(P, x1, y, z) + 1];
                for (uint32_t k = b; k < e; k++) {
                    uint32_t j = w->sorted[k];
                    v3 r = sub(xi, xyz(x[j]));
                    if (dot(r, r) < h2 && j != i) {
                        if (n < w->max_neighbours) list[n] = j;
                        n++;
                    }
                }
            }
        w->nb_count[i] = n;
    }
}

static uint32_t nb_len(const pbf_cpu_world *w, uint32_t i)
{
    return w->nb_count[i] < w->max_neighbours ? w->nb_count[i] : w->max_neighbours;
}

static const uint32_t *nb_of(const pbf_cpu_world *w, uint32_t i) { return w->nb_list + (size_t)i * w->max_neighbours; }

/// density.comp: rho_i (fluid + boundary share) and lambda_i.
static void density(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    float k = P->mass_density * P->inv_rest_density;
    for (uint32_t i = 0; i < w->count; i++) {
        v3 xi = xyz(w->pred[i]);
        float sum_w = w_poly6(P, 0.0f);
        v3 grad_i = { 0.0f, 0.0f, 0.0f };
        float sum_grad2 = 0.0f;
        const uint32_t *nb = nb_of(w, i);
        for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++) {
            v3 r = sub(xi, xyz(w->pred[nb[q]]));
            sum_w += w_poly6(P, dot(r, r));
            v3 g = scale(k, grad_spiky(P, r));
            grad_i = add(grad_i, g);
            sum_grad2 += dot(g, g);
        }
        float rho = P->mass_density * sum_w;
        v3 wall_grad;
        rho += P->rest_density * container_boundary(P, xi, &wall_grad);
        grad_i = add(grad_i, wall_grad);
        if (P->collider_count > 0u) colliders_density(w, P, xi, &rho, &grad_i);
        float C = fmaxf(rho * P->inv_rest_density - 1.0f, 0.0f);
        w->lambda[i] = -C / (dot(grad_i, grad_i) + sum_grad2 + P->epsilon);
        w->rho[i] = rho;
    }
}

/// The collisions both delta.comp and collide.comp end with: a particle radius from every
/// container plane, then the domain clamp, on pred_out[i].
static void container_collide(pbf_cpu_world *w, const pbf_gpu_params *P, uint32_t i)
{
    v3 x = xyz(w->pred_out[i]);
    for (uint32_t p = 0; p < P->plane_count; p++) {
        v3 n;
        float d = plane_distance(P, p, x, &n);
        if (d < P->radius) x = add(x, scale(P->radius - d, n));
    }
    x.x = clampf(x.x, P->domain_min.x + P->radius, P->domain_max.x - P->radius);
    x.y = clampf(x.y, P->domain_min.y + P->radius, P->domain_max.y - P->radius);
    x.z = clampf(x.z, P->domain_min.z + P->radius, P->domain_max.z - P->radius);
    w->pred_out[i] = (pbf_float4){ x.x, x.y, x.z, 0.0f };
}

/// delta.comp: the correction from the fluid and the container, then the container's
/// collisions and the domain clamp, into pred_out.
static void delta(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 xi = xyz(w->pred[i]);
        float li = w->lambda[i];
        v3 dp = { 0.0f, 0.0f, 0.0f };
        const uint32_t *nb = nb_of(w, i);
        uint32_t nn = nb_len(w, i);
        if (P->scorr_k > 0.0f) {
            for (uint32_t q = 0; q < nn; q++) {
                uint32_t j = nb[q];
                v3 r = sub(xi, xyz(w->pred[j]));
                float s = -P->scorr_k * powf(w_poly6(P, dot(r, r)) * P->scorr_inv_wdq, P->scorr_n) * P->scorr_scale;
                dp = add(dp, scale(li + w->lambda[j] + s, grad_spiky(P, r)));
            }
        } else {
            for (uint32_t q = 0; q < nn; q++) {
                uint32_t j = nb[q];
                dp = add(dp, scale(li + w->lambda[j], grad_spiky(P, sub(xi, xyz(w->pred[j])))));
            }
        }
        dp = scale(P->mass_density * P->inv_rest_density, dp);
        v3 wall_grad;
        container_boundary(P, xi, &wall_grad);
        dp = add(dp, scale(li, wall_grad));
        v3 x = add(xi, scale(P->omega, dp));
        w->pred_out[i] = (pbf_float4){ x.x, x.y, x.z, 0.0f };
        container_collide(w, P, i);
    }
}

/// collide.comp (only with colliders): the colliders' part of the correction, computed at
/// the iteration's start (pred, lambda) and added with omega to what delta wrote, then the
/// swept collisions from the substep's start position pos[i], then the container again.
static void collide(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 bdp = { 0.0f, 0.0f, 0.0f };
        colliders_delta(w, P, xyz(w->pred[i]), w->lambda[i], &bdp);
        v3 x = add(xyz(w->pred_out[i]), scale(P->omega, bdp));
        x = colliders_collide(w, P, xyz(w->pos[i]), x);
        w->pred_out[i] = (pbf_float4){ x.x, x.y, x.z, 0.0f };
        container_collide(w, P, i);
    }
}

/// velocity.comp: v = (x* - x) / dt with the speed clamp; x = x*.
static void velocity(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 x = xyz(w->pred[i]);
        v3 v = scale(P->inv_dt, sub(x, xyz(w->pos[i])));
        float s = length(v);
        if (s > P->max_speed) v = scale(P->max_speed / s, v);
        w->vel[i] = (pbf_float4){ v.x, v.y, v.z, w->vel[i].w };
        w->pos[i] = (pbf_float4){ x.x, x.y, x.z, w->pos[i].w };
    }
}

static float volume_of(const pbf_gpu_params *P, float rho)
{
    return P->mass_density / fmaxf(rho, 1e-6f * P->rest_density);
}

/// vorticity.comp: omega_i = sum_j V_j grad_i W_ij x (v_j - v_i), w = |omega_i|.
static void vorticity(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 xi = xyz(w->pos[i]), vi = xyz(w->vel[i]);
        v3 o = { 0.0f, 0.0f, 0.0f };
        const uint32_t *nb = nb_of(w, i);
        for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++) {
            uint32_t j = nb[q];
            float vol = volume_of(P, w->rho[j]);
            o = add(o, scale(vol, cross(grad_spiky(P, sub(xi, xyz(w->pos[j]))), sub(xyz(w->vel[j]), vi))));
        }
        w->omega[i] = (pbf_float4){ o.x, o.y, o.z, length(o) };
    }
}

/// viscosity.comp: vorticity confinement eps (N x omega) when eps > 0, then XSPH, into
/// vel_out (the additions in the shader's order).
static void viscosity(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    for (uint32_t i = 0; i < w->count; i++) {
        v3 xi = xyz(w->pos[i]), vi = xyz(w->vel[i]);
        v3 eta = { 0.0f, 0.0f, 0.0f }, xsph = { 0.0f, 0.0f, 0.0f };
        float wi = w->omega[i].w;
        const uint32_t *nb = nb_of(w, i);
        for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++) {
            uint32_t j = nb[q];
            v3 r = sub(xi, xyz(w->pos[j]));
            float vol = volume_of(P, w->rho[j]);
            if (P->vorticity > 0.0f) eta = add(eta, scale(vol * (w->omega[j].w - wi), grad_spiky(P, r)));
            xsph = add(xsph, scale(w_poly6(P, dot(r, r)), scale(vol, sub(xyz(w->vel[j]), vi))));
        }
        v3 v = vi;
        float le = length(eta);
        if (P->vorticity > 0.0f && le > 1e-9f)
            v = add(v, scale(P->dt * P->vorticity, cross(divide(eta, le), xyz(w->omega[i]))));
        v = add(v, scale(P->viscosity, xsph));
        w->vel_out[i] = (pbf_float4){ v.x, v.y, v.z, w->vel[i].w };
    }
    swap4(&w->vel, &w->vel_out);
}

pbf_result pbf_cpu_world_step(pbf_cpu_world *w, float dt)
{
    if (!(dt > 0.0f && dt <= 1.0f))
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_step: dt must be in (0, 1] s (got %g)", (double)dt);
    const pbf_params *p = &w->params;
    pbf_gpu_params P = uniforms(w, dt / (float)p->substeps);
    colliders_begin_step(w);
    P.collider_count = w->gpu_count;
    for (int s = 0; s < p->substeps; s++) {
        P.substep = (uint32_t)s;
        predict(w, &P);
        build_grid(w, w->pred, &P);
        reorder(w);
        find_neighbours(w, w->pred, &P);
        for (int it = 0; it < p->iterations; it++) {
            density(w, &P);
            delta(w, &P);
            if (w->gpu_count > 0) collide(w, &P);
            swap4(&w->pred, &w->pred_out);
        }
        velocity(w, &P);
        if (p->vorticity > 0.0f || p->viscosity > 0.0f) {
            if (p->vorticity > 0.0f) vorticity(w, &P);
            viscosity(w, &P);
        }
    }
    colliders_end_step(w);
    w->last_substep = (uint32_t)(p->substeps - 1);
    w->report_substeps = (uint32_t)p->substeps;
    w->steps++;
    w->nb_valid = true;
    return PBF_OK;
}

// ---- reading back ----------------------------------------------------------------------

uint32_t pbf_cpu_world_read_particles(const pbf_cpu_world *w, float *positions, float *velocities, uint32_t *ids,
                                      uint32_t max)
{
    uint32_t m = w->count < max ? w->count : max;
    for (uint32_t i = 0; i < w->count; i++) {
        uint32_t k = w->id[i]; // ids are 0 .. count - 1: the id is the place in id order
        if (k >= m) continue;
        if (positions) memcpy(positions + 4 * (size_t)k, &w->pos[i], 16);
        if (velocities) memcpy(velocities + 4 * (size_t)k, &w->vel[i], 16);
        if (ids) ids[k] = k;
    }
    return m;
}

uint64_t pbf_cpu_world_state_hash(const pbf_cpu_world *w)
{
    uint64_t h = 1469598103934665603ull;
    size_t n = w->count;
    float *data = malloc(n * 32 + 16);
    if (!data) return 0;
    pbf_cpu_world_read_particles(w, data, data + 4 * n, NULL, w->count);
    const unsigned char *bytes = (const unsigned char *)data;
    for (size_t i = 0; i < n * 32; i++) {
        h ^= bytes[i];
        h *= 1099511628211ull;
    }
    free(data);
    return h;
}

/// Lists at the current positions, through the grid order without moving the slots.
static void neighbours_at_positions(pbf_cpu_world *w, const pbf_gpu_params *P)
{
    build_grid(w, w->pos, P);
    find_neighbours(w, w->pos, P);
    w->nb_valid = true;
}

/// metrics.comp's density of slot i at its position (fluid over the list + boundaries).
static float density_at(const pbf_cpu_world *w, const pbf_gpu_params *P, uint32_t i)
{
    v3 xi = xyz(w->pos[i]);
    float sum_w = w_poly6(P, 0.0f);
    const uint32_t *nb = nb_of(w, i);
    for (uint32_t q = 0, nn = nb_len(w, i); q < nn; q++) {
        v3 r = sub(xi, xyz(w->pos[nb[q]]));
        sum_w += w_poly6(P, dot(r, r));
    }
    float rho = P->mass_density * sum_w;
    v3 unused_wall_grad;
    rho += P->rest_density * container_boundary(P, xi, &unused_wall_grad);
    v3 unused_grad = { 0.0f, 0.0f, 0.0f };
    if (P->collider_count > 0u) colliders_density(w, P, xi, &rho, &unused_grad);
    return rho;
}

/// The parameters the metrics pass sees after a step: those of the last substep, with the
/// colliders as uploaded for that step. Before the first step the colliders stand where
/// they were put.
static pbf_gpu_params stats_params(pbf_cpu_world *w)
{
    if (w->steps == 0) {
        for (uint32_t b = 0; b < w->collider_count; b++) {
            w->gpu[b] = w->colliders[b];
            w->gpu[b].linear_velocity.w = 1.0f;
        }
        w->gpu_count = w->collider_count;
    }
    return uniforms(w, 1.0f);
}

pbf_cpu_stats pbf_cpu_world_density_stats(pbf_cpu_world *w)
{
    pbf_gpu_params P = stats_params(w);
    if (!w->nb_valid) neighbours_at_positions(w, &P);
    pbf_cpu_stats st;
    memset(&st, 0, sizeof st);
    st.particles = w->count;
    double sum = 0.0, err = 0.0;
    for (uint32_t i = 0; i < w->count; i++) {
        v3 xi = xyz(w->pos[i]);
        if (!finite3(xi) || !finite3(xyz(w->vel[i]))) {
            st.nan_count++;
            continue;
        }
        float rho = density_at(w, &P, i);
        sum += rho;
        err += fmaxf(rho * P.inv_rest_density - 1.0f, 0.0f);
        if (rho > st.density_max) st.density_max = rho;
        if (w->nb_count[i] > w->max_neighbours) st.overflow_count++;
        if (xi.x < w->domain_min[0] || xi.y < w->domain_min[1] || xi.z < w->domain_min[2] ||
            xi.x > w->domain_max[0] || xi.y > w->domain_max[1] || xi.z > w->domain_max[2])
            st.outside_count++;
    }
    uint32_t good = w->count - st.nan_count;
    st.density_avg = w->count > 0 ? (float)(sum / (good > 0 ? good : 1)) : 0.0f;
    st.density_error_avg = w->count > 0 ? (float)(err / (good > 0 ? good : 1)) : 0.0f;
    return st;
}

uint32_t pbf_cpu_world_vorticity(pbf_cpu_world *w, float *omega, uint32_t max)
{
    pbf_gpu_params P = stats_params(w);
    neighbours_at_positions(w, &P);
    for (uint32_t i = 0; i < w->count; i++) w->rho[i] = density_at(w, &P, i);
    vorticity(w, &P);
    uint32_t m = w->count < max ? w->count : max;
    for (uint32_t i = 0; i < w->count; i++)
        if (w->id[i] < m) memcpy(omega + 4 * (size_t)w->id[i], &w->omega[i], 16);
    return m;
}
