// CPU reference of the fluid step: the world (creation, parameters, particles), the step
// that walks the stages in the GPU's order, and reading back. See pbf_cpu.h.
//
// Layout follows the GPU: particles live in slots (arrays of pbf_float4, as the SSBOs),
// each substep gathers them into cell order by a stable counting sort, and every pass
// reads one parameter block, a pbf_gpu_params filled as pbf_world.c fills the uniform
// block, through `P`. The passes are in pbf_cpu_passes.c and pbf_cpu_colliders.c, each
// naming the shader it mirrors; keep them in step.
#include "fluid/pbf_cpu_internal.h"
#include "fluid/pbf_uniforms.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_CAPACITY (1u << 20)

pbf_result pbf_cpu_fail(pbf_cpu_world *w, pbf_result r, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(w->error, sizeof w->error, fmt, ap);
    va_end(ap);
    return r;
}

// ---- creation, parameters, container ---------------------------------------------------

static pbf_result grid_layout(pbf_cpu_world *w, float h, char *err, size_t err_size)
{
    float origin[3];
    uint32_t dims[3];
    pbf_grid_geometry(w->domain_min, w->domain_max, h, w->cells_per_kernel, origin, dims);
    for (int k = 0; k < 3; k++)
        if (dims[k] > PBF_GRID_MAX_AXIS_CELLS) {
            snprintf(err, err_size, "pbf_cpu_world: the domain needs %u grid cells of size kernel_radius / %u along "
                     "axis %d; at most %u allowed (shrink the domain or enlarge the kernel)", dims[k],
                     w->cells_per_kernel, k, PBF_GRID_MAX_AXIS_CELLS);
            return PBF_ERR_INVALID_ARG;
        }
    // As pbf_world.c: the hashed grid's buckets, the removed bucket (sinks; always empty
    // here) and the total.
    uint32_t buckets = pbf_hash_buckets(w->capacity);
    uint32_t *start = malloc(((size_t)buckets + 2) * 4), *fill = malloc(((size_t)buckets + 1) * 4);
    if (!start || !fill) {
        free(start);
        free(fill);
        snprintf(err, err_size, "pbf_cpu_world: out of memory for %u grid buckets", buckets);
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
    w->cells = buckets;
    return PBF_OK;
}

/// The coarse level's cells for these parameters (pbf_level_layout, as the GPU world), zeroed
/// when the layout changes.
static pbf_result level_alloc(pbf_cpu_world *w, const pbf_params *p, char *err, size_t err_size)
{
    uint32_t dims[4];
    float cell[3];
    pbf_result r = pbf_level_layout(p, w->domain_min, w->domain_max, dims, cell, err, err_size);
    if (r != PBF_OK) return r;
    if (w->level && memcmp(dims, w->level_dims, sizeof dims) == 0 && memcmp(cell, w->level_cell, sizeof cell) == 0)
        return PBF_OK;
    pbf_gpu_level_cell *level = dims[3] ? calloc(dims[3], sizeof *level) : NULL;
    if (dims[3] && !level) {
        snprintf(err, err_size, "pbf_cpu_world: out of memory for %u coarse level cells", dims[3]);
        return PBF_ERR_OUT_OF_MEMORY;
    }
    free(w->level);
    w->level = level;
    memcpy(w->level_dims, dims, sizeof dims);
    memcpy(w->level_cell, cell, sizeof cell);
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
    if (grid_layout(w, params->kernel_radius, err, err_size) != PBF_OK ||
        level_alloc(w, params, err, err_size) != PBF_OK) {
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
    w->tension = calloc(n, sizeof(pbf_float4));
    w->id = malloc(n * 4);
    w->id_out = malloc(n * 4);
    w->lambda_rho = calloc(2 * n, sizeof(float));
    w->cell_of = malloc(n * 4);
    w->sorted = malloc(n * 4);
    w->order = malloc(n * 4);
    w->nb_count = calloc(n, 4);
    w->nb_list = malloc(n * w->max_neighbours * 4);
    if (!w->pos || !w->pos_out || !w->vel || !w->vel_out || !w->pred || !w->pred_out || !w->omega || !w->tension || !w->id ||
        !w->id_out || !w->lambda_rho || !w->cell_of || !w->sorted || !w->order || !w->nb_count || !w->nb_list) {
        snprintf(err, err_size, "pbf_cpu_world_create: out of memory for %u particles", capacity);
        pbf_cpu_world_destroy(w);
        return NULL;
    }
    return w;
}

void pbf_cpu_world_destroy(pbf_cpu_world *w)
{
    if (!w) return;
    void *blocks[] = { w->pos, w->pos_out, w->vel, w->vel_out, w->pred, w->pred_out, w->omega, w->tension,
                       w->id, w->id_out, w->lambda_rho, w->cell_of, w->cell_start, w->cell_fill,
                       w->sorted, w->order, w->nb_list, w->nb_count, w->collider_data, w->level };
    for (size_t i = 0; i < sizeof blocks / sizeof blocks[0]; i++) free(blocks[i]);
    free(w);
}

const char *pbf_cpu_world_last_error(const pbf_cpu_world *w) { return w->error; }
const pbf_params *pbf_cpu_world_params(const pbf_cpu_world *w) { return &w->params; }
uint32_t pbf_cpu_world_particle_count(const pbf_cpu_world *w) { return w->count; }

pbf_result pbf_cpu_world_set_params(pbf_cpu_world *w, const pbf_params *p)
{
    char err[256];
    if (pbf_params_validate(p, err, sizeof err) != PBF_OK) return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "%s", err);
    if (p->kernel_radius != w->params.kernel_radius) {
        pbf_result r = grid_layout(w, p->kernel_radius, err, sizeof err);
        if (r != PBF_OK) return pbf_cpu_fail(w, r, "%s", err);
        w->nb_valid = false;
    }
    if (p->surface_tension > 0.0f && !(w->params.surface_tension > 0.0f)) // as pbf_world_set_params
        memset(w->tension, 0, (size_t)w->capacity * sizeof w->tension[0]);
    pbf_result r = level_alloc(w, p, err, sizeof err);
    if (r != PBF_OK) return pbf_cpu_fail(w, r, "%s", err);
    w->params = *p;
    w->k = pbf_derive_constants(p);
    return PBF_OK;
}

pbf_result pbf_cpu_world_set_max_neighbours(pbf_cpu_world *w, uint32_t max_neighbours)
{
    if (max_neighbours < 8 || max_neighbours > 512)
        return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_set_max_neighbours: max_neighbours must be in [8, 512] "
                    "(got %u)", max_neighbours);
    uint32_t *list = malloc((size_t)w->capacity * max_neighbours * 4);
    if (!list) return pbf_cpu_fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_cpu_world_set_max_neighbours: out of memory");
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
    if (n == 0) return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "%s", err);
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
    w->pred[i] = (pbf_float4){ p[0], p[1], p[2], 0.0f };
    w->vel[i] = (pbf_float4){ v[0], v[1], v[2], 0.0f };
    float speed = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    float *fastest = &w->added_speed[w->steps % PBF_GUARD_HISTORY];
    if (speed > *fastest) *fastest = speed;
    w->id[i] = i; // no removal: ids are 0 .. count - 1 in creation order
    w->tension[i] = (pbf_float4){ 0.0f, 0.0f, 0.0f, 0.0f };
    w->nb_valid = false;
}

pbf_result pbf_cpu_world_add_particles(pbf_cpu_world *w, const float *positions, const float *velocities,
                                       uint32_t n)
{
    if (!positions && n > 0)
        return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_add_particles: positions must not be NULL");
    if (n > w->capacity - w->count)
        return pbf_cpu_fail(w, PBF_ERR_CAPACITY, "pbf_cpu_world_add_particles: %u particles do not fit: %u of capacity %u "
                    "in use", n, w->count, w->capacity);
    char err[256];
    if (!pbf_points_check("pbf_cpu_world_add_particles", positions, velocities, n, w->domain_min, w->domain_max, err, sizeof err))
        return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "%s", err);
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
    uint64_t total;
    pbf_result fit = pbf_block_lattice(b, s, w->domain_min, w->domain_max, w->count, w->capacity, n, &total, err, sizeof err);
    if (fit != PBF_OK) return pbf_cpu_fail(w, fit, "%s", err);
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
    pbf_uniforms_level(&g, p, w->level_dims, w->level_cell);
    g.count = w->count;
    g.collider_count = w->gpu_count;
    g.substep = w->last_substep;
    return g;
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

static void stage_done(pbf_cpu_world *w, pbf_stage stage, int substep, int iteration)
{
    if (w->hook) w->hook(w->hook_user, stage, substep, iteration);
}

/// pbf_world.c's substep, pass for pass: the same stages in the same order, the ping-pong
/// pairs flipped where it flips them, the stage hook called where it calls its own.
static void substep(pbf_cpu_world *w, const pbf_gpu_params *P, int s)
{
    const pbf_params *p = &w->params;
    pbf_cpu_predict(w, P);
    stage_done(w, PBF_STAGE_PREDICT, s, -1);
    pbf_cpu_grid_count(w, P, w->pred);
    stage_done(w, PBF_STAGE_GRID_COUNT, s, -1);
    pbf_cpu_grid_scan(w);
    stage_done(w, PBF_STAGE_GRID_SCAN, s, -1);
    pbf_cpu_grid_scatter(w);
    stage_done(w, PBF_STAGE_GRID_SCATTER, s, -1);
    pbf_cpu_grid_sort(w);
    stage_done(w, PBF_STAGE_GRID_SORT, s, -1);
    pbf_cpu_reorder(w);
    stage_done(w, PBF_STAGE_REORDER, s, -1);
    swap4(&w->pos, &w->pos_out);
    swap4(&w->vel, &w->vel_out);
    swap4(&w->pred, &w->pred_out);
    swap_ids(&w->id, &w->id_out);
    pbf_cpu_neighbours(w, P, w->pred, NULL, true);
    stage_done(w, PBF_STAGE_NEIGHBOURS, s, -1);
    if (p->surface_tension > 0.0f) {
        pbf_cpu_tension(w, P);
        stage_done(w, PBF_STAGE_TENSION, s, -1);
        swap4(&w->pred, &w->pred_out);
    }
    int level_at = pbf_level_iteration(p);
    for (int it = 0; it < p->iterations; it++) {
        // The first iteration's density came with the neighbour lists.
        if (it > 0) {
            pbf_cpu_density(w, P);
            stage_done(w, PBF_STAGE_DENSITY, s, it);
        }
        if (it == level_at) {
            pbf_cpu_level(w, P);
            stage_done(w, PBF_STAGE_LEVEL, s, -1);
        }
        float relax = pbf_relaxation(p, &w->k, it); // the shaders' uniform relax
        pbf_cpu_delta(w, P, relax, it == level_at);
        stage_done(w, PBF_STAGE_DELTA, s, it);
        if (w->gpu_count > 0) {
            pbf_cpu_collide(w, P, relax, it == level_at);
            stage_done(w, PBF_STAGE_COLLIDE, s, it);
        }
        swap4(&w->pred, &w->pred_out);
    }
    pbf_cpu_velocity(w, P);
    stage_done(w, PBF_STAGE_VELOCITY, s, -1);
    if (p->vorticity > 0.0f || p->viscosity > 0.0f) {
        if (p->vorticity > 0.0f) {
            pbf_cpu_vorticity(w, P);
            stage_done(w, PBF_STAGE_VORTICITY, s, -1);
        }
        pbf_cpu_viscosity(w, P);
        stage_done(w, PBF_STAGE_VISCOSITY, s, -1);
        swap4(&w->vel, &w->vel_out);
    }
}

pbf_result pbf_cpu_world_step(pbf_cpu_world *w, float dt)
{
    if (!(dt > 0.0f && dt <= 1.0f))
        return pbf_cpu_fail(w, PBF_ERR_INVALID_ARG, "pbf_cpu_world_step: dt must be in (0, 1] s (got %g)", (double)dt);
    // The time-step guard sees what the GPU world sees (pbf_guard_substeps).
    float seen = w->steps >= PBF_GUARD_LATENCY ? w->speed_of[(w->steps - PBF_GUARD_LATENCY) % PBF_GUARD_HISTORY] : -1.0f;
    int substeps = pbf_guard_substeps(&w->params, w->k.spacing, dt, w->steps, seen, w->added_speed, NULL);
    if (w->params.guard_compression > 0.0f) {
        uint64_t back = w->steps - PBF_GUARD_LATENCY; // used only from step 2 on
        const pbf_guard_seen *record = w->steps >= PBF_GUARD_LATENCY ? &w->seen_of[back % PBF_GUARD_HISTORY] : NULL;
        const pbf_guard_seen *before = w->steps > PBF_GUARD_LATENCY ? &w->seen_of[(back - 1) % PBF_GUARD_HISTORY] : NULL;
        int level = pbf_guard_compression(&w->params, &w->compression, record, before, NULL);
        if (level > substeps) substeps = level;
    }
    pbf_gpu_params P = uniforms(w, dt / (float)substeps);
    w->report_substeps = (uint32_t)substeps; // the colliders' force scales follow it
    pbf_cpu_colliders_begin_step(w);
    P.collider_count = w->gpu_count;
    w->stepping = true;
    for (int s = 0; s < substeps; s++) {
        P.substep = (uint32_t)s;
        substep(w, &P, s);
    }
    w->stepping = false;
    pbf_cpu_colliders_end_step(w);
    w->last_substep = (uint32_t)(substeps - 1);
    // The fastest finite particle at the end of the step (the metrics pass's speed_max).
    float fastest = 0.0f;
    for (uint32_t i = 0; i < w->count; i++) {
        pbf_float4 v = w->vel[i];
        pbf_float4 x = w->pos[i];
        if (!(isfinite(v.x) && isfinite(v.y) && isfinite(v.z) && isfinite(x.x) && isfinite(x.y) && isfinite(x.z)))
            continue;
        fastest = fmaxf(fastest, sqrtf(v.x * v.x + v.y * v.y + v.z * v.z));
    }
    w->speed_of[w->steps % PBF_GUARD_HISTORY] = fastest;
    if (w->params.guard_compression > 0.0f) {
        // What the metrics pass measures after the step (pbf_cpu_world_density_stats).
        w->nb_valid = true;
        pbf_cpu_stats st = pbf_cpu_world_density_stats(w);
        w->seen_of[w->steps % PBF_GUARD_HISTORY] = (pbf_guard_seen){
            .density_error_max = st.density_max / w->params.rest_density - 1.0f,
            .density_error_avg = st.density_error_avg,
            .substeps = substeps,
        };
    }
    w->steps++;
    w->added_speed[w->steps % PBF_GUARD_HISTORY] = 0.0f;
    w->nb_valid = true;
    return PBF_OK;
}

void pbf_cpu_world_set_stage_hook(pbf_cpu_world *w, pbf_cpu_stage_hook_fn *fn, void *user)
{
    w->hook = fn;
    w->hook_user = user;
}

void *pbf_cpu_world_binding(pbf_cpu_world *w, int binding, size_t *bytes)
{
    size_t n = w->count, v4 = n * sizeof(pbf_float4);
    void *a = NULL;
    size_t size = 0;
    switch (binding) {
    case PBF_B_POS: a = w->pos, size = v4; break;
    case PBF_B_VEL: a = w->vel, size = v4; break;
    case PBF_B_PRED: a = w->pred, size = v4; break;
    case PBF_B_ID: a = w->id, size = n * 4; break;
    case PBF_B_POS_OUT: a = w->pos_out, size = v4; break;
    case PBF_B_VEL_OUT: a = w->vel_out, size = v4; break;
    case PBF_B_PRED_OUT: a = w->pred_out, size = v4; break;
    case PBF_B_ID_OUT: a = w->id_out, size = n * 4; break;
    case PBF_B_CELL: a = w->cell_of, size = n * 4; break;
    case PBF_B_CELL_START: a = w->cell_start, size = ((size_t)w->cells + 2) * 4; break;
    case PBF_B_CELL_FILL: a = w->cell_fill, size = ((size_t)w->cells + 1) * 4; break;
    case PBF_B_SORTED: a = w->sorted, size = n * 4; break;
    case PBF_B_ORDER: a = w->order, size = n * 4; break;
    case PBF_B_LAMBDA: a = w->lambda_rho, size = n * 8; break;
    case PBF_B_OMEGA: a = w->omega, size = v4; break;
    case PBF_B_TENSION: a = w->tension, size = v4; break;
    case PBF_B_LEVEL: a = w->level, size = (size_t)w->level_dims[3] * sizeof(pbf_gpu_level_cell); break;
    case PBF_B_NB_LIST: a = w->nb_list, size = n * w->max_neighbours * 4; break;
    case PBF_B_NB_COUNT: a = w->nb_count, size = n * 4; break;
    case PBF_B_FORCES: a = w->forces, size = (size_t)w->gpu_count * sizeof w->forces[0]; break;
    default: break;
    }
    if (bytes) *bytes = a ? size : 0;
    return a;
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
        if (velocities) {
            memcpy(velocities + 4 * (size_t)k, &w->vel[i], 12);
            velocities[4 * (size_t)k + 3] = 0.0f; // w is the solver's scratch (particle volume)
        }
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
    pbf_cpu_grid_count(w, P, w->pos);
    pbf_cpu_grid_scan(w);
    pbf_cpu_grid_scatter(w);
    pbf_cpu_grid_sort(w);
    pbf_cpu_neighbours(w, P, w->pos, w->order, false);
    w->nb_valid = true;
}


static pbf_gpu_params stats_params(pbf_cpu_world *w)
{
    // Before the first step the colliders have not been handed to gpu[] yet; within a step
    // (a stage hook) gpu[] holds the substep's and must not be touched.
    if (w->steps == 0 && !w->stepping) {
        for (uint32_t b = 0; b < w->collider_count; b++) {
            w->gpu[b] = w->colliders[b];
            w->gpu[b].linear_velocity.w = 1.0f;
        }
        w->gpu_count = w->collider_count;
    }
    return uniforms(w, 1.0f);
}

float pbf_cpu_world_collider_share(pbf_cpu_world *w, const float x[3], float grad[3])
{
    pbf_gpu_params P = stats_params(w);
    float rho = 0.0f;
    pbf_vec3 g = { 0.0f, 0.0f, 0.0f };
    pbf_cpu_colliders_density(w, &P, (pbf_vec3){ x[0], x[1], x[2] }, &rho, &g);
    grad[0] = g.x, grad[1] = g.y, grad[2] = g.z;
    return rho * P.inv_rest_density;
}

int pbf_cpu_world_last_substeps(const pbf_cpu_world *w) { return w && w->steps > 0 ? (int)w->report_substeps : 0; }

pbf_cpu_stats pbf_cpu_world_density_stats(pbf_cpu_world *w)
{
    pbf_gpu_params P = stats_params(w);
    if (!w->nb_valid) neighbours_at_positions(w, &P);
    pbf_cpu_stats st;
    memset(&st, 0, sizeof st);
    st.particles = w->count;
    double sum = 0.0, err = 0.0;
    for (uint32_t i = 0; i < w->count; i++) {
        pbf_vec3 xi = pbf_xyz(w->pos[i]);
        if (!pbf_cpu_finite3(xi) || !pbf_cpu_finite3(pbf_xyz(w->vel[i]))) {
            st.nan_count++;
            continue;
        }
        float rho = pbf_cpu_density_at(w, &P, i);
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
    // The volumes the velocity pass would leave in vel.w, from the densities at the positions.
    for (uint32_t i = 0; i < w->count; i++)
        w->vel[i].w = P.mass / fmaxf(pbf_cpu_density_at(w, &P, i), 1e-6f * P.rest_density);
    pbf_cpu_vorticity(w, &P);
    uint32_t m = w->count < max ? w->count : max;
    for (uint32_t i = 0; i < w->count; i++)
        if (w->id[i] < m) memcpy(omega + 4 * (size_t)w->id[i], &w->omega[i], 16);
    return m;
}

