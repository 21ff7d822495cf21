// CPU reference of the fluid step. See pbf_cpu.h for what it mirrors and what not.
//
// Layout follows the GPU: particles live in slots (arrays of pbf_float4, as the SSBOs),
// each substep gathers them into cell order by a stable counting sort, and every pass
// reads one parameter block, a pbf_gpu_params filled as pbf_world.c fills the uniform
// block, through `P`. Each pass below names the shader it mirrors; keep them in step.
#include "fluid/pbf_cpu.h"
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
    float domain_min[3], domain_max[3];
    float grid_origin[3];
    uint32_t grid_dims[3], cells;
    float planes[PBF_MAX_PLANES][4];
    uint32_t plane_count;
    pbf_gpu_collider colliders[PBF_MAX_COLLIDERS];
    uint32_t collider_count;

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
        vp[p] = d < P->h ? (P->boundary_scale * pbf_cpu_boundary_volume(d, P->h)) : 0.0f;
        gp[p] = d < P->h ? scale((P->boundary_scale * pbf_cpu_boundary_gradient(d, P->h)), n) : (v3){ 0.0f, 0.0f, 0.0f };
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

static v3 quat_rotate(pbf_float4 q, v3 v)
{
    v3 u = { q.x, q.y, q.z };
    v3 t = scale(2.0f, cross(u, v));
    return add(add(v, scale(q.w, t)), cross(u, t));
}

static v3 quat_rotate_inv(pbf_float4 q, v3 v) { return quat_rotate((pbf_float4){ -q.x, -q.y, -q.z, q.w }, v); }

/// Signed distance (m, positive outside the solid) and outward normal of collider c at
/// its current pose: collider_sdf of shaders/fluid/colliders.glsl.
static float collider_sdf(const pbf_gpu_collider *c, v3 x, v3 *n)
{
    uint32_t type = c->info.x;
    if (type == PBF_COLLIDER_PLANE) {
        *n = xyz(c->params);
        return dot(x, *n) - c->params.w;
    }
    v3 l = quat_rotate_inv(c->rotation, sub(x, xyz(c->position)));
    v3 ln;
    float d;
    if (type == PBF_COLLIDER_SPHERE) {
        float len = length(l);
        ln = len > 1e-9f ? divide(l, len) : (v3){ 0.0f, 1.0f, 0.0f };
        d = len - c->params.x;
    } else if (type == PBF_COLLIDER_BOX) {
        v3 q = { fabsf(l.x) - c->params.x, fabsf(l.y) - c->params.y, fabsf(l.z) - c->params.z };
        if (fmaxf(q.x, fmaxf(q.y, q.z)) > 0.0f) {
            v3 o = { fmaxf(q.x, 0.0f), fmaxf(q.y, 0.0f), fmaxf(q.z, 0.0f) };
            d = length(o);
            ln = divide((v3){ signf(l.x) * o.x, signf(l.y) * o.y, signf(l.z) * o.z }, fmaxf(d, 1e-12f));
        } else {
            if (q.x > q.y && q.x > q.z) ln = (v3){ signf(l.x), 0.0f, 0.0f };
            else if (q.y > q.z) ln = (v3){ 0.0f, signf(l.y), 0.0f };
            else ln = (v3){ 0.0f, 0.0f, signf(l.z) };
            d = fmaxf(q.x, fmaxf(q.y, q.z));
        }
    } else if (type == PBF_COLLIDER_CAPSULE) {
        v3 r = { l.x, l.y - clampf(l.y, -c->params.y, c->params.y), l.z };
        float len = length(r);
        ln = len > 1e-9f ? divide(r, len) : (v3){ 1.0f, 0.0f, 0.0f };
        d = len - c->params.x;
    } else { // cylinder
        float rl = sqrtf(l.x * l.x + l.z * l.z);
        float qx = rl - c->params.x, qy = fabsf(l.y) - c->params.y;
        v3 radial = rl > 1e-9f ? (v3){ l.x / rl, 0.0f, l.z / rl } : (v3){ 1.0f, 0.0f, 0.0f };
        v3 axial = { 0.0f, signf(l.y), 0.0f };
        if (qx > 0.0f && qy > 0.0f) {
            d = sqrtf(qx * qx + qy * qy);
            v3 m = add(scale(qx, radial), scale(qy, axial));
            ln = divide(m, length(m));
        } else if (qx > qy) {
            d = qx;
            ln = radial;
        } else {
            d = qy;
            ln = axial;
        }
    }
    *n = quat_rotate(c->rotation, ln);
    return d;
}

static bool collider_near(const pbf_gpu_collider *c, v3 x, float reach)
{
    return !(length(sub(x, xyz(c->position))) > c->position.w + reach);
}

// ---- creation, parameters, container ---------------------------------------------------

static pbf_result grid_layout(pbf_cpu_world *w, float h, char *err, size_t err_size)
{
    double total = 1.0;
    uint32_t dims[3];
    for (int k = 0; k < 3; k++) {
        double n = ceil((double)(w->domain_max[k] - w->domain_min[k]) / h) + 2.0;
        dims[k] = n < (double)MAX_CELLS ? (uint32_t)n : MAX_CELLS;
        total *= n;
    }
    if (total > (double)MAX_CELLS) {
        snprintf(err, err_size, "pbf_cpu_world: the domain needs %.0f grid cells of size kernel_radius %g m; "
                 "at most %u allowed on the CPU (shrink the domain or enlarge the kernel)", total, (double)h,
                 MAX_CELLS);
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
        w->grid_origin[k] = w->domain_min[k] - h;
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
                       w->sorted, w->nb_list, w->nb_count };
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
    static const char *const axis = "xyz";
    for (int k = 0; k < 3; k++) {
        if (!isfinite(min[k]) || !isfinite(max[k]) || !(max[k] > min[k]))
            return fail(w, PBF_ERR_INVALID_ARG, "container.max.%c must be finite and greater than min.%c "
                        "(got min %g, max %g)", axis[k], axis[k], (double)min[k], (double)max[k]);
        if (min[k] < w->domain_min[k] || max[k] > w->domain_max[k])
            return fail(w, PBF_ERR_INVALID_ARG, "container.%c range [%g, %g] must lie inside the domain [%g, %g]",
                        axis[k], (double)min[k], (double)max[k], (double)w->domain_min[k], (double)w->domain_max[k]);
    }
    // Inward normal xyz and offset w, in pbf_world_set_container's order: floor, -x, +x,
    // -z, +z walls, lid.
    const float planes[PBF_MAX_PLANES][4] = {
        { 0, 1, 0, min[1] },  { 1, 0, 0, min[0] },   { -1, 0, 0, -max[0] },
        { 0, 0, 1, min[2] },  { 0, 0, -1, -max[2] }, { 0, -1, 0, -max[1] },
    };
    memcpy(w->planes, planes, sizeof planes);
    w->plane_count = closed_top ? 6u : 5u;
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

static bool inside_domain(const pbf_cpu_world *w, const float *x)
{
    for (int k = 0; k < 3; k++)
        if (!(x[k] >= w->domain_min[k] && x[k] <= w->domain_max[k])) return false;
    return true;
}

pbf_result pbf_cpu_world_add_particles(pbf_cpu_world *w, const float *positions, const float *velocities,
                                       uint32_t n)
{
    if (!positions && n > 0)
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_add_particles: positions must not be NULL");
    if (n > w->capacity - w->count)
        return fail(w, PBF_ERR_CAPACITY, "pbf_cpu_world_add_particles: %u particles do not fit: %u of capacity %u "
                    "in use", n, w->count, w->capacity);
    for (uint32_t i = 0; i < n; i++) {
        if (!inside_domain(w, positions + 3 * i))
            return fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_add_particles: positions[%u] = (%g, %g, %g) must be "
                        "finite and inside the domain", i, (double)positions[3 * i], (double)positions[3 * i + 1],
                        (double)positions[3 * i + 2]);
        if (velocities)
            for (int k = 0; k < 3; k++)
                if (!isfinite(velocities[3 * i + k]))
                    return fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_add_particles: velocities[%u] must be finite "
                                "(got %g)", i, (double)velocities[3 * i + k]);
    }
    static const float rest[3] = { 0.0f, 0.0f, 0.0f };
    for (uint32_t i = 0; i < n; i++) append(w, positions + 3 * i, velocities ? velocities + 3 * i : rest);
    return PBF_OK;
}

pbf_result pbf_cpu_world_add_block(pbf_cpu_world *w, const pbf_block_def *b, uint32_t *added)
{
    static const char *const axis = "xyz";
    if (added) *added = 0;
    for (int k = 0; k < 3; k++) {
        if (!isfinite(b->min[k]) || !isfinite(b->max[k]) || !(b->max[k] > b->min[k]))
            return fail(w, PBF_ERR_INVALID_ARG, "pbf_block_def.max.%c must be finite and greater than min.%c "
                        "(got min %g, max %g)", axis[k], axis[k], (double)b->min[k], (double)b->max[k]);
        if (b->min[k] < w->domain_min[k] || b->max[k] > w->domain_max[k])
            return fail(w, PBF_ERR_INVALID_ARG, "pbf_block_def.%c range [%g, %g] must lie inside the domain [%g, %g]",
                        axis[k], (double)b->min[k], (double)b->max[k], (double)w->domain_min[k],
                        (double)w->domain_max[k]);
        if (!isfinite(b->velocity[k]))
            return fail(w, PBF_ERR_INVALID_ARG, "pbf_block_def.velocity.%c must be finite (got %g)", axis[k],
                        (double)b->velocity[k]);
    }
    // The lattice of pbf_world_add_block: cell centres of spacing s, x fastest.
    float s = w->k.spacing;
    uint32_t n[3];
    uint64_t total = 1;
    for (int k = 0; k < 3; k++) {
        double c = floor((double)(b->max[k] - b->min[k]) / s + 1e-4);
        n[k] = c < 1.0 ? 1u : (uint32_t)c;
        total *= n[k];
    }
    if (total > w->capacity - w->count)
        return fail(w, PBF_ERR_CAPACITY, "pbf_block_def: the block holds %llu particles but only %u of capacity %u "
                    "are free", (unsigned long long)total, w->capacity - w->count, w->capacity);
    for (uint32_t z = 0; z < n[2]; z++)
        for (uint32_t y = 0; y < n[1]; y++)
            for (uint32_t x = 0; x < n[0]; x++) {
                float p[3] = { b->min[0] + s * (0.5f + (float)x), b->min[1] + s * (0.5f + (float)y),
                               b->min[2] + s * (0.5f + (float)z) };
                append(w, p, b->velocity);
            }
    if (added) *added = (uint32_t)total;
    return PBF_OK;
}

static float bounding_radius(const pbf_collider_def *d)
{
    const float *z = d->size;
    if (d->type == PBF_SHAPE_BOX) return sqrtf(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    if (d->type == PBF_SHAPE_SPHERE) return z[0];
    if (d->type == PBF_SHAPE_CAPSULE) return z[0] + z[1];
    if (d->type == PBF_SHAPE_CYLINDER) return sqrtf(z[0] * z[0] + z[1] * z[1]);
    return 1e30f; // a plane reaches everywhere
}

pbf_result pbf_cpu_world_add_collider(pbf_cpu_world *w, const pbf_collider_def *d)
{
    if ((unsigned)d->type > PBF_SHAPE_CYLINDER)
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.type must be plane, box, sphere, capsule or cylinder "
                    "(0..4) in the CPU reference (got %d)", (int)d->type);
    for (int k = 0; k < 4; k++)
        if (!isfinite(d->size[k]) || !isfinite(d->rotation[k]) || (k < 3 && !isfinite(d->position[k])))
            return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size/position/rotation must be finite");
    int need = d->type == PBF_SHAPE_BOX ? 3 : d->type == PBF_SHAPE_SPHERE ? 1 : d->type == PBF_SHAPE_PLANE ? 0 : 2;
    for (int k = 0; k < need; k++)
        if (!(d->size[k] > 0.0f))
            return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size[%d] must be > 0 m (got %g)", k,
                        (double)d->size[k]);
    const float *q = d->rotation;
    float qn = sqrtf(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    if (fabsf(qn - 1.0f) > 1e-3f)
        return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.rotation must be a unit quaternion (got length %g)",
                    (double)qn);
    if (w->collider_count >= PBF_MAX_COLLIDERS)
        return fail(w, PBF_ERR_CAPACITY, "pbf_cpu_world_add_collider: all %d colliders in use", PBF_MAX_COLLIDERS);
    pbf_gpu_collider c;
    memset(&c, 0, sizeof c);
    c.position = (pbf_float4){ d->position[0], d->position[1], d->position[2], bounding_radius(d) };
    c.rotation = (pbf_float4){ q[0], q[1], q[2], q[3] };
    c.params = (pbf_float4){ d->size[0], d->size[1], d->size[2], d->size[3] };
    if (d->type == PBF_SHAPE_PLANE) {
        float nl = sqrtf(d->size[0] * d->size[0] + d->size[1] * d->size[1] + d->size[2] * d->size[2]);
        if (!(nl > 0.0f))
            return fail(w, PBF_ERR_INVALID_ARG, "pbf_collider_def.size xyz (plane normal) must be non-zero");
        c.params = (pbf_float4){ d->size[0] / nl, d->size[1] / nl, d->size[2] / nl, d->size[3] };
    }
    c.prev_position = c.position;
    c.prev_rotation = c.rotation;
    c.center_of_mass = c.position;
    c.info = (pbf_uint4){ (uint32_t)d->type, 0u, 0u, 0u };
    w->colliders[w->collider_count++] = c;
    return PBF_OK;
}

// ---- the step --------------------------------------------------------------------------

/// The parameter block of one substep, filled as pbf_world.c's write_params fills it.
static pbf_gpu_params uniforms(const pbf_cpu_world *w, float dt)
{
    const pbf_params *p = &w->params;
    const pbf_constants *k = &w->k;
    pbf_gpu_params g;
    memset(&g, 0, sizeof g);
    double h = p->kernel_radius;
    g.gravity = (pbf_float4){ p->gravity[0], p->gravity[1], p->gravity[2], 0.0f };
    g.grid_origin = (pbf_float4){ w->grid_origin[0], w->grid_origin[1], w->grid_origin[2], 0.0f };
    g.grid_dims = (pbf_uint4){ w->grid_dims[0], w->grid_dims[1], w->grid_dims[2], w->cells };
    g.domain_min = (pbf_float4){ w->domain_min[0], w->domain_min[1], w->domain_min[2], 0.0f };
    g.domain_max = (pbf_float4){ w->domain_max[0], w->domain_max[1], w->domain_max[2], 0.0f };
    for (uint32_t i = 0; i < w->plane_count; i++)
        g.planes[i] = (pbf_float4){ w->planes[i][0], w->planes[i][1], w->planes[i][2], w->planes[i][3] };
    g.plane_count = w->plane_count;
    g.max_neighbours = w->max_neighbours;
    g.dt = dt;
    g.inv_dt = 1.0f / dt;
    g.h = (float)h;
    g.inv_cell = (float)(1.0 / h);
    g.poly6 = k->poly6;
    g.spiky_grad = k->spiky_grad;
    g.rest_density = p->rest_density;
    g.inv_rest_density = 1.0f / p->rest_density;
    g.mass_density = k->mass_density;
    g.mass = k->mass;
    g.epsilon = k->epsilon;
    g.omega = p->sor;
    g.scorr_k = p->scorr_k;
    g.scorr_n = p->scorr_n;
    g.scorr_inv_wdq = k->scorr_inv_wdq;
    g.scorr_scale = k->scorr_scale;
    g.boundary_scale = k->boundary_scale;
    g.vorticity = p->vorticity;
    g.viscosity = p->viscosity;
    g.damping = p->damping;
    g.max_speed = p->max_speed;
    g.radius = p->particle_radius;
    g.count = w->count;
    g.collider_count = w->collider_count;
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
        for (int dz = -1; dz <= 1; dz++)
            for (int dy = -1; dy <= 1; dy++) {
                int y = c[1] + dy, z = c[2] + dz;
                if (y < 0 || z < 0 || y >= dims[1] || z >= dims[2]) continue;
                int x0 = c[0] > 0 ? c[0] - 1 : 0, x1 = c[0] + 1 < dims[0] ? c[0] + 1 : dims[0] - 1;
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
        for (uint32_t b = 0; b < P->collider_count; b++) {
            if (!collider_near(&w->colliders[b], xi, P->h)) continue;
            v3 n;
            float d = collider_sdf(&w->colliders[b], xi, &n);
            if (d < P->h) {
                rho += P->rest_density * (P->boundary_scale * pbf_cpu_boundary_volume(d, P->h));
                grad_i = sub(grad_i, scale((P->boundary_scale * pbf_cpu_boundary_gradient(d, P->h)), n));
            }
        }
        float C = fmaxf(rho * P->inv_rest_density - 1.0f, 0.0f);
        w->lambda[i] = -C / (dot(grad_i, grad_i) + sum_grad2 + P->epsilon);
        w->rho[i] = rho;
    }
}

/// delta.comp: the position correction, then collisions and the domain clamp, into pred_out.
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
        for (uint32_t b = 0; b < P->collider_count; b++) {
            if (!collider_near(&w->colliders[b], xi, P->h)) continue;
            v3 n;
            float d = collider_sdf(&w->colliders[b], xi, &n);
            if (d < P->h) dp = add(dp, scale(-li * (P->boundary_scale * pbf_cpu_boundary_gradient(d, P->h)), n));
        }
        v3 x = add(xi, scale(P->omega, dp));
        for (uint32_t p = 0; p < P->plane_count; p++) {
            v3 n;
            float d = plane_distance(P, p, x, &n);
            if (d < P->radius) x = add(x, scale(P->radius - d, n));
        }
        for (uint32_t b = 0; b < P->collider_count; b++) {
            if (!collider_near(&w->colliders[b], x, P->radius)) continue;
            v3 n;
            float d = collider_sdf(&w->colliders[b], x, &n);
            if (d < P->radius) x = add(x, scale(P->radius - d, n));
        }
        x.x = clampf(x.x, P->domain_min.x + P->radius, P->domain_max.x - P->radius);
        x.y = clampf(x.y, P->domain_min.y + P->radius, P->domain_max.y - P->radius);
        x.z = clampf(x.z, P->domain_min.z + P->radius, P->domain_max.z - P->radius);
        w->pred_out[i] = (pbf_float4){ x.x, x.y, x.z, 0.0f };
    }
    swap4(&w->pred, &w->pred_out);
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
    for (int s = 0; s < p->substeps; s++) {
        predict(w, &P);
        build_grid(w, w->pred, &P);
        reorder(w);
        find_neighbours(w, w->pred, &P);
        for (int it = 0; it < p->iterations; it++) {
            density(w, &P);
            delta(w, &P);
        }
        velocity(w, &P);
        if (p->vorticity > 0.0f || p->viscosity > 0.0f) {
            if (p->vorticity > 0.0f) vorticity(w, &P);
            viscosity(w, &P);
        }
    }
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
    for (uint32_t b = 0; b < P->collider_count; b++) {
        v3 n;
        float d = collider_sdf(&w->colliders[b], xi, &n);
        if (d < P->h) rho += P->rest_density * (P->boundary_scale * pbf_cpu_boundary_volume(d, P->h));
    }
    return rho;
}

pbf_cpu_stats pbf_cpu_world_density_stats(pbf_cpu_world *w)
{
    pbf_gpu_params P = uniforms(w, 1.0f);
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
    pbf_gpu_params P = uniforms(w, 1.0f);
    neighbours_at_positions(w, &P);
    for (uint32_t i = 0; i < w->count; i++) w->rho[i] = density_at(w, &P, i);
    vorticity(w, &P);
    uint32_t m = w->count < max ? w->count : max;
    for (uint32_t i = 0; i < w->count; i++)
        if (w->id[i] < m) memcpy(omega + 4 * (size_t)w->id[i], &w->omega[i], 16);
    return m;
}
