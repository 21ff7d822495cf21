// The fluid world: GPU buffers, programs and the step. See pbf.h and docs/solver.md.
//
// Design in short. Particle data lives in ping-pong pairs of SSBOs (position, velocity,
// predicted position, id). Each substep rebuilds a uniform grid of cell size h by a
// counting sort (count, exclusive scan, scatter, per-cell sort for determinism) and
// gathers the particles into cell order, so the 27 neighbour cells are 9 contiguous
// runs. The density solver is Jacobi: density+lambda, then correction into the other
// predicted-position buffer. Boundaries (container planes and colliders) add their share
// of density through a closed-form half-space volume V(d) and its gradient, so particles
// at walls reach rest density instead of piling up. Each dispatch is followed by a GL
// timestamp; timestamps, metrics and collider forces of a step are read back through a
// ring of fences, never waiting on the GPU unless asked.
#include "fluid/pbf.h"
#include "fluid/pbf_glsl.h"
#include "fluid/pbf_internal.h"
#include "fluid/pbf_uniforms.h"

#include <epoxy/gl.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(sizeof(pbf_gpu_params) == 624, "pbf_gpu_params must match the std140 block");
_Static_assert(sizeof(pbf_gpu_params) % 16 == 0, "std140 block size");
_Static_assert(sizeof(pbf_gpu_collider) == 144, "pbf_gpu_collider std430 layout");
_Static_assert(sizeof(pbf_gpu_reduce) == 64, "pbf_gpu_reduce std430 layout");
_Static_assert(sizeof(pbf_gpu_metrics) == 64, "pbf_gpu_metrics std430 layout");
_Static_assert(sizeof(pbf_gpu_state) == 32, "pbf_gpu_state std430 layout");


static const char *const program_files[PROG_COUNT] = {
    "fluid/predict.comp",   "fluid/grid_count.comp", "fluid/scan_block.comp",
    "fluid/scan_add.comp",  "fluid/grid_scatter.comp", "fluid/grid_sort.comp",
    "fluid/reorder.comp",   "fluid/neighbours.comp", "fluid/density.comp",    "fluid/delta.comp", "fluid/collide.comp",
    "fluid/velocity.comp",  "fluid/vorticity.comp",  "fluid/viscosity.comp",
    "fluid/metrics.comp",   "fluid/metrics_final.comp", "fluid/count.comp", "fluid/append.comp",
    "fluid/grid_clear.comp", "fluid/tension.comp", "fluid/tint.comp",
    "fluid/level_deposit.comp", "fluid/level_prepare.comp", "fluid/level_sweep.comp",
};

static const char *const stage_names[PBF_STAGE_COUNT] = {
    "predict", "grid_count", "grid_scan", "grid_scatter", "grid_sort", "reorder", "neighbours",
    "density", "delta", "collide", "velocity", "vorticity", "viscosity", "tension", "level", "metrics",
};

const char *pbf_stage_name(pbf_stage stage)
{
    return (unsigned)stage < PBF_STAGE_COUNT ? stage_names[stage] : "?";
}


const char *pbf_world_last_error(const pbf_world *world)
{
    return world ? world->error : "pbf_world_last_error: world is NULL";
}

uint32_t pbf_suggest_max_neighbours(const pbf_params *p)
{
    if (!p) return 0;
    // Twice the neighbours of a rest lattice (compression headroom), a multiple of 8.
    double q = p->kernel_radius / (2.0 * p->particle_radius);
    double n = 2.0 * 4.18879 * q * q * q + 16.0;
    if (!(n >= 8.0)) return 8u; // NaN too (a set pbf_params_validate refuses)
    if (n > 512.0) return 512u;
    return ((uint32_t)n + 7u) & ~7u;
}

pbf_world_def pbf_default_world_def(void)
{
    pbf_world_def d;
    memset(&d, 0, sizeof d);
    d.params = pbf_default_params();
    d.capacity = 65536;
    d.max_neighbours = pbf_suggest_max_neighbours(&d.params);
    d.grid_cells_per_kernel = PBF_GRID_CELLS_PER_KERNEL;
    d.domain_min[0] = d.domain_min[1] = d.domain_min[2] = 0.0f;
    d.domain_max[0] = 1.0f;
    d.domain_max[1] = 1.0f;
    d.domain_max[2] = 1.0f;
    const char *env = getenv("SEICHE_SHADER_DIR");
    d.shader_dir = env && *env ? env : NULL;
    return d;
}

// ---- derived constants --------------------------------------------------------------

static void derive(pbf_world *w)
{
    w->k = pbf_derive_constants(&w->params);
}

static pbf_result grid_layout(pbf_world *w, char *err, size_t err_size)
{
    float h = w->params.kernel_radius;
    pbf_grid_geometry(w->domain_min, w->domain_max, h, w->cells_per_kernel, w->grid_origin, w->grid_dims);
    static const char axis[] = "xyz";
    for (int k = 0; k < 3; k++)
        if (w->grid_dims[k] > PBF_GRID_MAX_AXIS_CELLS) {
            snprintf(err, err_size,
                     "pbf_world_def.domain is %g m along %c: %u cells of kernel_radius / grid_cells_per_kernel = %g m; "
                     "at most %u cells per axis (shrink the domain, enlarge the kernel or lower grid_cells_per_kernel)",
                     (double)(w->domain_max[k] - w->domain_min[k]), axis[k], w->grid_dims[k],
                     (double)h / w->cells_per_kernel, PBF_GRID_MAX_AXIS_CELLS);
            return PBF_ERR_INVALID_ARG;
        }
    // The grid itself is virtual: its cells hash into buckets in proportion to the
    // particles, so memory and time follow the water, not the domain.
    w->cells = pbf_hash_buckets(w->capacity);
    // The scan's first level has a work group per PBF_SCAN_BLOCK buckets and must fit in one
    // dispatch (GL promises 65535 groups; grid_clear strides and has no such limit).
    uint32_t scan_groups = (uint32_t)(((uint64_t)w->cells + 2 + PBF_SCAN_BLOCK - 1) / PBF_SCAN_BLOCK);
    if (scan_groups > w->max_groups) {
        snprintf(err, err_size,
                 "pbf_world_def.capacity %u needs %u grid buckets, whose prefix scan needs %u work groups in one "
                 "dispatch; this GL allows %u (GL_MAX_COMPUTE_WORK_GROUP_COUNT): lower the capacity",
                 w->capacity, w->cells, scan_groups, w->max_groups);
        return PBF_ERR_INVALID_ARG;
    }
    return PBF_OK;
}

static void alloc_level(pbf_world *w)
{
    if (w->level) glDeleteBuffers(1, &w->level);
    uint32_t n = w->level_dims[3] ? w->level_dims[3] : 1u;
    w->level = pbf_gpu_buffer((GLsizeiptr)n * (GLsizeiptr)sizeof(pbf_gpu_level_cell), "pbf.level");
}

// ---- GL resources ---------------------------------------------------------------------

static GLintptr align_up(GLintptr x, GLint a) { return (x + a - 1) / a * a; }

static void free_grid(pbf_world *w)
{
    GLuint bufs[] = { w->cell_start, w->cell_fill, w->scan };
    glDeleteBuffers(3, bufs);
    w->cell_start = w->cell_fill = w->scan = 0;
}

static pbf_result alloc_grid(pbf_world *w)
{
    // Buckets 0..cells-1, the removed bucket `cells` (sinks), and one more entry so that the
    // exclusive scan leaves the total at cell_start[cells + 1].
    w->cell_start = pbf_gpu_buffer((GLsizeiptr)(w->cells + 2) * 4, "pbf.cell_start");
    w->cell_fill = pbf_gpu_buffer((GLsizeiptr)(w->cells + 1) * 4, "pbf.cell_fill");
    // Scan levels: level 0 is cell_start itself; the block sums of level l are level l+1.
    uint32_t n = w->cells + 2;
    GLintptr off = 0;
    w->scan_levels = 0;
    w->scan_level[0].offset = 0;
    w->scan_level[0].n = n;
    int l = 0;
    while (n > PBF_SCAN_BLOCK) {
        n = (n + PBF_SCAN_BLOCK - 1) / PBF_SCAN_BLOCK;
        l++;
        if (l >= MAX_SCAN_LEVELS) return PBF_ERR_INVALID_ARG;
        w->scan_level[l].offset = off;
        w->scan_level[l].n = n;
        off = align_up(off + (GLintptr)n * 4, w->ssbo_align);
    }
    w->scan_levels = l + 1;
    w->scan_dummy = off;
    w->scan = pbf_gpu_buffer(off + 64, "pbf.scan");
    return PBF_OK;
}

static pbf_result build_programs(pbf_world *w, char *err, size_t err_size)
{
    for (int i = 0; i < PROG_COUNT; i++) {
        pbf_glsl_stage st = { GL_COMPUTE_SHADER, program_files[i] };
        pbf_glsl_source src = pbf_glsl_fluid_sources();
        if (w->shader_dir[0]) src.dir = w->shader_dir;
        w->programs[i] = pbf_glsl_build_from(&src, &st, 1, NULL, err, err_size);
        if (!w->programs[i]) return PBF_ERR_GL;
    }
    w->u_scan_n[0] = glGetUniformLocation(w->programs[PROG_SCAN_BLOCK], "scan_n");
    w->u_scan_n[1] = glGetUniformLocation(w->programs[PROG_SCAN_ADD], "scan_n");
    w->u_frame = glGetUniformLocation(w->programs[PROG_METRICS_FINAL], "frame");
    w->u_relax[0] = glGetUniformLocation(w->programs[PROG_DELTA], "relax");
    w->u_relax[1] = glGetUniformLocation(w->programs[PROG_COLLIDE], "relax");
    w->u_apply_level[0] = glGetUniformLocation(w->programs[PROG_DELTA], "apply_level");
    w->u_apply_level[1] = glGetUniformLocation(w->programs[PROG_COLLIDE], "apply_level");
    w->u_level_parity = glGetUniformLocation(w->programs[PROG_LEVEL_SWEEP], "parity");
    pbf_tint_locate(w);
    return PBF_OK;
}

static void stats_alloc(pbf_world *w)
{
    const pbf_params *p = &w->params;
    int per_substep = 7 + 2 * MAX_SCAN_LEVELS + 2 + 3 * p->iterations + 3 + 2 + 1; // + 2: tension, + 1: level
    // Room for the most substeps a step may take: the tension's floor and the compression
    // guard raise them with cfl off too (sized by cfl alone, their later substeps' timestamps
    // were dropped: 35.8 ms a step read for 63.2 at 200 N/m).
    int need = 1 + per_substep * pbf_most_substeps(p) + 4;
    if (need <= w->max_queries) return;
    // The steps in flight read their timestamps from these queries: read them first (their
    // records wait for the next poll). Deleted under them, a poll read queries that were
    // never issued (GL_INVALID_OPERATION; found by fuzz_pbf_api: more iterations set between
    // steps and a poll).
    for (int k = 0; k < RING; k++) {
        stats_slot *r = &w->ring[(w->ring_head + k) % RING];
        if (r->pending) pbf_read_early(w, r);
    }
    for (int s = 0; s < RING; s++) {
        stats_slot *r = &w->ring[s];
        if (r->queries) glDeleteQueries(w->max_queries, r->queries);
        free(r->queries);
        free(r->stage_of);
        r->queries = calloc((size_t)need, sizeof(GLuint));
        r->stage_of = calloc((size_t)need, 1);
        glGenQueries(need, r->queries);
    }
    w->max_queries = need;
}

uint64_t pbf_world_def_memory(const pbf_world_def *def)
{
    if (!def) return 0;
    uint64_t cap = def->capacity;
    // pos, vel, pred (two vec4 each), ids (two), cell_of, sorted, order, lambda (vec2),
    // omega and normal (vec4), neighbour count and list, and the metrics partials.
    uint64_t per_particle = 6 * 16 + 2 * 4 + 3 * 4 + 8 + 2 * 16 + 4 + 4ull * def->max_neighbours;
    uint64_t bytes = cap * per_particle + (cap / PBF_WG + 1) * sizeof(pbf_gpu_reduce);
    uint64_t cells = pbf_hash_buckets(def->capacity);
    bytes += (2 * cells + 3) * 4 + cells / PBF_SCAN_BLOCK * 4 + 4096; // bucket starts, fills, scan
    uint32_t level_dims[4];
    float level_cell[3];
    char err[8];
    if (pbf_level_layout(&def->params, def->domain_min, def->domain_max, level_dims, level_cell, err, sizeof err) == PBF_OK)
        bytes += (uint64_t)level_dims[3] * sizeof(pbf_gpu_level_cell); // the coarse level
    return bytes;
}

pbf_world *pbf_world_create(const pbf_world_def *def, char *err, size_t err_size)
{
    char scratch[8];
    if (!err) {
        err = scratch;
        err_size = sizeof scratch;
    }
    err[0] = 0;
    if (!def) {
        snprintf(err, err_size, "pbf_world_create: def must not be NULL");
        return NULL;
    }
    if (pbf_params_validate(&def->params, err, err_size) != PBF_OK) return NULL;
    if (def->capacity < 1 || def->capacity > (1u << 26)) {
        snprintf(err, err_size, "pbf_world_def.capacity must be in [1, %u] (got %u)", 1u << 26, def->capacity);
        return NULL;
    }
    for (int k = 0; k < 3; k++) {
        if (!isfinite(def->domain_min[k]) || !isfinite(def->domain_max[k]) ||
            !(def->domain_max[k] > def->domain_min[k])) {
            snprintf(err, err_size, "pbf_world_def.domain_max[%d] must be finite and greater than domain_min[%d] "
                     "(got min %g, max %g)", k, k, (double)def->domain_min[k], (double)def->domain_max[k]);
            return NULL;
        }
    }
    if (def->max_neighbours < 8 || def->max_neighbours > 512) {
        snprintf(err, err_size, "pbf_world_def.max_neighbours must be in [8, 512] (got %u; pbf_suggest_max_neighbours "
                 "gives %u for these parameters)", def->max_neighbours, pbf_suggest_max_neighbours(&def->params));
        return NULL;
    }
    if (def->grid_cells_per_kernel < 1 || def->grid_cells_per_kernel > 4) {
        snprintf(err, err_size, "pbf_world_def.grid_cells_per_kernel must be in [1, 4] (got %u)", def->grid_cells_per_kernel);
        return NULL;
    }
    if ((uint64_t)def->capacity * def->max_neighbours * 4u > (1ull << 34)) {
        snprintf(err, err_size, "pbf_world_def.capacity %u x max_neighbours %u needs %llu MiB of neighbour lists; "
                 "at most 16384 MiB allowed", def->capacity, def->max_neighbours,
                 (unsigned long long)((uint64_t)def->capacity * def->max_neighbours * 4u >> 20));
        return NULL;
    }
    if (def->shader_dir && (!*def->shader_dir || strlen(def->shader_dir) >= sizeof(((pbf_world *)0)->shader_dir))) {
        snprintf(err, err_size, "pbf_world_def.shader_dir must be NULL (the embedded shaders) or name the directory "
                 "holding fluid/*.comp in at most %zu characters (got \"%.64s\")", sizeof(((pbf_world *)0)->shader_dir) - 1,
                 def->shader_dir);
        return NULL;
    }
    if (!glGetString(GL_VERSION)) {
        snprintf(err, err_size, "pbf_world_create: no OpenGL context is current on this thread (make the host's 4.3+ "
                 "context current first)");
        return NULL;
    }
    if (epoxy_gl_version() < 43 && !epoxy_has_gl_extension("GL_ARB_compute_shader")) {
        snprintf(err, err_size, "pbf_world_create: the current GL context is %d.%d; Seiche needs OpenGL 4.3 compute shaders",
                 epoxy_gl_version() / 10, epoxy_gl_version() % 10);
        return NULL;
    }
    // The passes use up to 10 storage blocks each and binding points up to
    // PBF_B_COLLIDER_DATA; GL 4.3 only promises 8 of each, so say so when they are missing.
    GLint blocks = 0, bindings = 0;
    glGetIntegerv(GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS, &blocks);
    glGetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
    if (blocks < 10 || bindings < PBF_B_COLLIDER_DATA + 1) {
        snprintf(err, err_size, "pbf_world_create: Seiche needs 10 shader storage blocks per compute shader and %d "
                 "storage buffer bindings; this GL offers %d and %d", PBF_B_COLLIDER_DATA + 1, blocks, bindings);
        return NULL;
    }
    // One dispatch covers every particle: a work group per PBF_WG of them (GL promises
    // 65535 groups, so 8.4M particles; NVIDIA's drivers allow 2^31 - 1).
    GLint max_groups = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &max_groups);
    if (max_groups < 65535) max_groups = 65535;
    if ((uint64_t)def->capacity > (uint64_t)max_groups * PBF_WG) {
        snprintf(err, err_size, "pbf_world_def.capacity %u needs %u work groups of %d particles in one dispatch; this "
                 "GL allows %d (GL_MAX_COMPUTE_WORK_GROUP_COUNT): at most %llu particles", def->capacity,
                 (def->capacity + PBF_WG - 1) / PBF_WG, PBF_WG, max_groups,
                 (unsigned long long)max_groups * PBF_WG);
        return NULL;
    }
    pbf_world *w = calloc(1, sizeof *w);
    if (!w) {
        snprintf(err, err_size, "pbf_world_create: out of memory");
        return NULL;
    }
    w->max_groups = (uint32_t)max_groups;
    w->params = def->params;
    w->step_substeps = def->params.substeps;
    w->capacity = def->capacity;
    w->max_neighbours = def->max_neighbours;
    w->cells_per_kernel = def->grid_cells_per_kernel;
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    w->flush_timestamps = renderer && strstr(renderer, "llvmpipe");
    memcpy(w->domain_min, def->domain_min, sizeof w->domain_min);
    memcpy(w->domain_max, def->domain_max, sizeof w->domain_max);
    snprintf(w->shader_dir, sizeof w->shader_dir, "%s", def->shader_dir ? def->shader_dir : "");
    w->log = def->log;
    w->log_user = def->log_user;
    derive(w);
    glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &w->ssbo_align);
    if (w->ssbo_align < 4) w->ssbo_align = 4;
    if (grid_layout(w, err, err_size) != PBF_OK ||
        pbf_level_layout(&w->params, w->domain_min, w->domain_max, w->level_dims, w->level_cell, err, err_size) != PBF_OK ||
        build_programs(w, err, err_size) != PBF_OK) {
        pbf_world_destroy(w);
        return NULL;
    }
    GLsizeiptr cap = w->capacity;
    for (int k = 0; k < 2; k++) {
        w->pos[k] = pbf_gpu_buffer(cap * 16, k ? "pbf.pos[1]" : "pbf.pos[0]");
        w->vel[k] = pbf_gpu_buffer(cap * 16, k ? "pbf.vel[1]" : "pbf.vel[0]");
        w->pred[k] = pbf_gpu_buffer(cap * 16, k ? "pbf.pred[1]" : "pbf.pred[0]");
        w->ids[k] = pbf_gpu_buffer(cap * 4, k ? "pbf.ids[1]" : "pbf.ids[0]");
    }
    w->cell_of = pbf_gpu_buffer(cap * 4, "pbf.cell_of");
    w->sorted = pbf_gpu_buffer(cap * 4, "pbf.sorted");
    w->order = pbf_gpu_buffer(cap * 4, "pbf.order");
    w->lambda = pbf_gpu_buffer(cap * 8, "pbf.lambda");
    w->omega = pbf_gpu_buffer(cap * 16, "pbf.omega");
    w->tension = pbf_gpu_buffer(cap * 16, "pbf.tension");
    alloc_level(w);
    w->nb_list = pbf_gpu_buffer(cap * (GLsizeiptr)w->max_neighbours * 4, "pbf.nb_list");
    w->nb_count = pbf_gpu_buffer(cap * 4, "pbf.nb_count");
    w->colliders = pbf_cpu_buffer(PBF_MAX_COLLIDERS * (GLsizeiptr)sizeof(pbf_gpu_collider), NULL, "pbf.colliders");
    w->forces = pbf_gpu_buffer(PBF_FORCES_BYTES, "pbf.forces");
    w->forces_ring = pbf_read_buffer((GLsizeiptr)RING * PBF_FORCES_BYTES, "pbf.forces_ring");
    w->reduce = pbf_gpu_buffer(((cap + PBF_WG - 1) / PBF_WG) * (GLsizeiptr)sizeof(pbf_gpu_reduce), "pbf.reduce");
    // One record per step, written by one invocation of metrics_final: read by the CPU as is.
    w->metrics = pbf_read_buffer(RING * (GLsizeiptr)sizeof(pbf_gpu_metrics), "pbf.metrics");
    w->draw = pbf_cpu_buffer(16, NULL, "pbf.draw");
    w->state = pbf_cpu_buffer(sizeof(pbf_gpu_state), NULL, "pbf.state");
    glGenBuffers(1, &w->params_ubo);
    glBindBuffer(GL_UNIFORM_BUFFER, w->params_ubo);
    glBufferData(GL_UNIFORM_BUFFER, sizeof(pbf_gpu_params), NULL, GL_DYNAMIC_DRAW);
    glObjectLabel(GL_BUFFER, w->params_ubo, -1, "pbf.params");
    if (alloc_grid(w) != PBF_OK) {
        snprintf(err, err_size, "pbf_world_create: grid of %u cells needs too many scan levels", w->cells);
        pbf_world_destroy(w);
        return NULL;
    }
    pbf_world_clear(w);
    stats_alloc(w);
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        snprintf(err, err_size, "pbf_world_create: GL error 0x%x while allocating buffers for %u particles "
                 "(out of GPU memory?)", e, w->capacity);
        pbf_world_destroy(w);
        return NULL;
    }
    if (!pbf_live_add(w)) {
        snprintf(err, err_size, "pbf_world_create: out of memory");
        pbf_world_destroy(w);
        return NULL;
    }
    return w;
}

void pbf_world_destroy(pbf_world *w)
{
    if (!w) return;
    if (pbf_refused_in_step(w, "pbf_world_destroy", ": ignored")) return; // the step goes on with the world
    pbf_live_remove(w);
    for (int i = 0; i < PROG_COUNT; i++)
        if (w->programs[i]) glDeleteProgram(w->programs[i]);
    GLuint bufs[] = { w->pos[0], w->pos[1], w->vel[0], w->vel[1], w->pred[0], w->pred[1],
                      w->ids[0], w->ids[1], w->cell_of, w->sorted, w->lambda, w->omega, w->tension,
                      w->colliders, w->forces, w->reduce, w->metrics, w->draw, w->params_ubo,
                      w->nb_list, w->nb_count, w->state, w->stage_pos, w->stage_vel, w->stage_id, w->order,
                      w->forces_ring, w->readback, w->level };
    glDeleteBuffers((GLsizei)(sizeof bufs / sizeof bufs[0]), bufs);
    free_grid(w);
    pbf_emitters_free(w);
    pbf_colliders_free(w);
    for (int s = 0; s < RING; s++) {
        if (w->ring[s].queries) glDeleteQueries(w->max_queries, w->ring[s].queries);
        if (w->ring[s].fence) glDeleteSync(w->ring[s].fence);
        free(w->ring[s].queries);
        free(w->ring[s].stage_of);
    }
    free(w);
}

const pbf_params *pbf_world_params(const pbf_world *world) { return world ? &world->params : NULL; }
uint32_t pbf_world_particle_count(const pbf_world *world) { return world ? world->count : 0; }
uint32_t pbf_world_capacity(const pbf_world *world) { return world ? world->capacity : 0; }
float pbf_world_particle_mass(const pbf_world *world) { return world ? world->k.mass : 0.0f; }

pbf_result pbf_world_set_params(pbf_world *w, const pbf_params *p)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!p) return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_params: params must not be NULL");
    if (pbf_refused_in_step(w, "pbf_world_set_params", "")) return PBF_ERR_INVALID_ARG;
    if (pbf_without_context(w, "pbf_world_set_params")) return PBF_ERR_GL;
    char err[256];
    if (pbf_params_validate(p, err, sizeof err) != PBF_OK) return pbf_fail(w, PBF_ERR_INVALID_ARG, "%s", err);
    if (p->particle_radius != w->params.particle_radius && w->count > 0 && (pbf_count_settle(w), w->count > 0))
        return pbf_fail(w, PBF_ERR_INVALID_ARG,
                        "pbf_world_set_params: particle_radius %g differs from the world's %g while it holds %u "
                        "particles: their mass and spacing come from it (set it before adding water, or once "
                        "the world is empty)",
                        (double)p->particle_radius, (double)w->params.particle_radius, w->count);
    for (int i = 0; i < PBF_MAX_EMITTERS; i++)
        if (w->emitters[i].used && w->emitters[i].def.speed > p->max_speed)
            return pbf_fail(w, PBF_ERR_INVALID_ARG,
                            "pbf_world_set_params: max_speed %g m/s is under the speed %g m/s of an emitter (the solver "
                            "would slow its jet and its layers pile up): slow or remove the emitter first",
                            (double)p->max_speed, (double)w->emitters[i].def.speed);
    bool regrid = p->kernel_radius != w->params.kernel_radius;
    uint32_t level_dims[4];
    float level_cell[3];
    if (pbf_level_layout(p, w->domain_min, w->domain_max, level_dims, level_cell, err, sizeof err) != PBF_OK)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "%s", err);
    pbf_params old = w->params;
    w->params = *p;
    if (p->surface_tension > 0.0f && !(old.surface_tension > 0.0f)) {
        // The pulls kept (for inspection) from when it was last on belong to particles since
        // reordered: the buffer reads zero until the next tension pass writes it (every tension
        // pass and append wrote before this).
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->tension);
        glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32F, GL_RED, GL_FLOAT, NULL);
    }
    if (regrid) {
        if (grid_layout(w, err, sizeof err) != PBF_OK) {
            w->params = old;
            grid_layout(w, err, sizeof err);
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "%s", err);
        }
        free_grid(w);
        alloc_grid(w);
    }
    // A larger kernel (or smaller particles) means more neighbours: grow the lists to hold
    // the suggested length rather than overflow (which is counted, never out of bounds).
    uint32_t need = pbf_suggest_max_neighbours(p);
    if (need > w->max_neighbours && (uint64_t)w->capacity * need * 4u <= (1ull << 34)) {
        glDeleteBuffers(1, &w->nb_list);
        w->nb_list = pbf_gpu_buffer((GLsizeiptr)w->capacity * (GLsizeiptr)need * 4, "pbf.nb_list");
        w->max_neighbours = need;
    }
    if (memcmp(level_dims, w->level_dims, sizeof level_dims) != 0 ||
        memcmp(level_cell, w->level_cell, sizeof level_cell) != 0) {
        memcpy(w->level_dims, level_dims, sizeof level_dims);
        memcpy(w->level_cell, level_cell, sizeof level_cell);
        alloc_level(w);
    }
    derive(w);
    stats_alloc(w);
    w->step_substeps = p->substeps; // never inside a step: refused above
    return PBF_OK;
}

// ---- particles (blocks and point lists: pbf_emitters.c) --------------------------------

void pbf_world_clear(pbf_world *w)
{
    if (!w || pbf_refused_in_step(w, "pbf_world_clear", ": ignored")) return;
    w->compression = (pbf_guard_state){ 0, 0 }; // the compression guard starts afresh with the water
    // Wait for the steps in flight: their stats would describe particles now gone.
    pbf_world_poll_stats(w, NULL, 0, true);
    w->count = w->known_count = 0;
    w->known_appended = w->appended_total;
    w->known_step = w->step_index;
    pbf_gpu_state st = { 0, 0, 1, 1, 0, 0, 0, 0 };
    // The count pass of an append (or of a step with sinks) writes both buffers in a
    // shader: order these uploads after it.
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->state);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof st, &st);
    uint32_t cmd[4] = { 4, 0, 0, 0 };
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->draw);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof cmd, cmd);
}

pbf_result pbf_world_set_container(pbf_world *w, const float min[3], const float max[3], bool closed_top)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (!min || !max)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_set_container: %s must not be NULL", !min ? "min" : "max");
    if (pbf_without_context(w, "pbf_world_set_container")) return PBF_ERR_GL;
    char err[256];
    float planes[PBF_MAX_PLANES][4];
    int n = pbf_container_planes(min, max, closed_top, w->domain_min, w->domain_max, planes, err, sizeof err);
    if (n == 0) return pbf_fail(w, PBF_ERR_INVALID_ARG, "%s", err);
    w->plane_count = n;
    memcpy(w->planes, planes, sizeof planes);
    return PBF_OK;
}

void pbf_world_remove_container(pbf_world *w)
{
    if (w && !pbf_refused_in_step(w, "pbf_world_remove_container", ": ignored")) w->plane_count = 0;
}

// ---- the step -----------------------------------------------------------------------------




// Everything a step's passes read: the world's buffers and the colliders' data.
static void bind_step(pbf_world *w)
{
    pbf_bind_all(w);
    pbf_colliders_bind(w);
}

typedef struct step_ctx {
    pbf_world *w;
    stats_slot *slot;
    int substep;
} step_ctx;

// The stage hook (pbf_internal.h): after a stage's passes, before any ping-pong flip.
static void stage_done(step_ctx *s, pbf_stage stage, int iteration)
{
    if (s->w->stage_hook) s->w->stage_hook(s->w->stage_hook_user, stage, s->substep, iteration);
}

static void mark(step_ctx *s, pbf_stage stage)
{
    stats_slot *r = s->slot;
    if (r->nq >= s->w->max_queries) return;
    if (getenv("PBF_FINISH_EACH")) glFinish();
    glQueryCounter(r->queries[r->nq], GL_TIMESTAMP);
    if (s->w->flush_timestamps) glFlush();
    r->stage_of[r->nq] = (uint8_t)stage;
    r->nq++;
}

static void dispatch(step_ctx *s, int prog, uint32_t groups, pbf_stage stage)
{
    if (groups > 0) {
        glUseProgram(s->w->programs[prog]);
        glDispatchCompute(groups, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    mark(s, stage);
}

// A pass over the live particles: one thread each, the group count read on the GPU.
static void dispatch_particles(step_ctx *s, int prog, pbf_stage stage)
{
    glUseProgram(s->w->programs[prog]);
    glDispatchComputeIndirect(offsetof(pbf_gpu_state, groups_x));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    mark(s, stage);
}

static uint32_t groups_for(uint32_t n, uint32_t wg) { return (n + wg - 1) / wg; }

static void run_scan(step_ctx *s)
{
    pbf_world *w = s->w;
    for (int l = 0; l < w->scan_levels; l++) {
        GLuint data_buf = l == 0 ? w->cell_start : w->scan;
        GLintptr data_off = l == 0 ? 0 : w->scan_level[l].offset;
        uint32_t n = w->scan_level[l].n;
        GLintptr sums_off = l + 1 < w->scan_levels ? w->scan_level[l + 1].offset : w->scan_dummy;
        uint32_t blocks = groups_for(n, PBF_SCAN_BLOCK);
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PBF_B_SCAN_DATA, data_buf, data_off, (GLsizeiptr)n * 4);
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PBF_B_SCAN_SUMS, w->scan, sums_off, (GLsizeiptr)blocks * 4);
        glUseProgram(w->programs[PROG_SCAN_BLOCK]);
        glUniform1ui(w->u_scan_n[0], n);
        glDispatchCompute(blocks, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    for (int l = w->scan_levels - 2; l >= 0; l--) {
        GLuint data_buf = l == 0 ? w->cell_start : w->scan;
        GLintptr data_off = l == 0 ? 0 : w->scan_level[l].offset;
        uint32_t n = w->scan_level[l].n;
        uint32_t blocks = groups_for(n, PBF_SCAN_BLOCK);
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PBF_B_SCAN_DATA, data_buf, data_off, (GLsizeiptr)n * 4);
        glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PBF_B_SCAN_SUMS, w->scan, w->scan_level[l + 1].offset, (GLsizeiptr)blocks * 4);
        glUseProgram(w->programs[PROG_SCAN_ADD]);
        glUniform1ui(w->u_scan_n[1], n);
        glDispatchCompute(blocks, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    }
    mark(s, PBF_STAGE_GRID_SCAN);
}

// The coarse level (docs/solver.md, "The coarse level"), in the substep's last iteration:
// the particles' compression at that iteration's density onto the coarse cells, then
// red-black sweeps of its pressure solve; that iteration's delta pass applies the correction.

static void level_solve(step_ctx *s)
{
    pbf_world *w = s->w;
    glUseProgram(w->programs[PROG_LEVEL_DEPOSIT]);
    glDispatchComputeIndirect(offsetof(pbf_gpu_state, groups_x));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    uint32_t groups = groups_for(w->level_dims[3], PBF_WG);
    if (groups > w->max_groups) groups = w->max_groups; // the cell passes stride
    glUseProgram(w->programs[PROG_LEVEL_PREPARE]);
    glDispatchCompute(groups, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(w->programs[PROG_LEVEL_SWEEP]);
    for (int k = 0; k < w->params.level_sweeps; k++)
        for (unsigned parity = 0; parity < 2; parity++) {
            glProgramUniform1ui(w->programs[PROG_LEVEL_SWEEP], w->u_level_parity, parity);
            glDispatchCompute(groups, 1, 1);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        }
    mark(s, PBF_STAGE_LEVEL);
    stage_done(s, PBF_STAGE_LEVEL, -1);
}

static void substep(step_ctx *s, float dt, int sub, int slot)
{
    pbf_world *w = s->w;
    const pbf_params *p = &w->params;
    s->substep = sub;
    pbf_write_params(w, dt, sub, slot);
    bind_step(w);
    dispatch_particles(s, PROG_PREDICT, PBF_STAGE_PREDICT);
    stage_done(s, PBF_STAGE_PREDICT, -1);

    uint32_t clear_groups = groups_for(w->cells + 2, PBF_WG);
    if (clear_groups > w->max_groups) clear_groups = w->max_groups; // grid_clear strides
    dispatch(s, PROG_GRID_CLEAR, clear_groups, PBF_STAGE_GRID_COUNT);
    dispatch_particles(s, PROG_GRID_COUNT, PBF_STAGE_GRID_COUNT);
    stage_done(s, PBF_STAGE_GRID_COUNT, -1);
    run_scan(s);
    stage_done(s, PBF_STAGE_GRID_SCAN, -1);
    bind_step(w);
    dispatch_particles(s, PROG_GRID_SCATTER, PBF_STAGE_GRID_SCATTER);
    stage_done(s, PBF_STAGE_GRID_SCATTER, -1);
    dispatch_particles(s, PROG_GRID_SORT, PBF_STAGE_GRID_SORT);
    stage_done(s, PBF_STAGE_GRID_SORT, -1);
    dispatch_particles(s, PROG_REORDER, PBF_STAGE_REORDER);
    stage_done(s, PBF_STAGE_REORDER, -1);
    w->cur_pos ^= 1;
    w->cur_vel ^= 1;
    w->cur_pred ^= 1;
    w->cur_ids ^= 1;
    pbf_bind_particles(w);
    if (w->sinks_active) {
        // Particles that entered a sink sit after the live ones now: drop them.
        glUseProgram(w->programs[PROG_LIVE_COUNT]);
        glDispatchCompute(1, 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    }
    dispatch_particles(s, PROG_NEIGHBOURS, PBF_STAGE_NEIGHBOURS);
    stage_done(s, PBF_STAGE_NEIGHBOURS, -1);
    if (p->surface_tension > 0.0f) {
        // The cohesion pull at x*, into x* (tension.comp): the solve below answers it.
        dispatch_particles(s, PROG_TENSION, PBF_STAGE_TENSION);
        stage_done(s, PBF_STAGE_TENSION, -1);
        w->cur_pred ^= 1;
        pbf_bind_particles(w);
    }

    int level_at = pbf_level_iteration(p);
    for (int it = 0; it < p->iterations; it++) {
        // The first iteration's density came with the neighbour lists.
        if (it > 0) {
            dispatch_particles(s, PROG_DENSITY, PBF_STAGE_DENSITY);
            stage_done(s, PBF_STAGE_DENSITY, it);
        }
        if (it == level_at) level_solve(s);
        float relax = pbf_relaxation(p, &w->k, it);
        glProgramUniform1f(w->programs[PROG_DELTA], w->u_relax[0], relax);
        glProgramUniform1i(w->programs[PROG_DELTA], w->u_apply_level[0], it == level_at);
        glProgramUniform1f(w->programs[PROG_COLLIDE], w->u_relax[1], relax);
        glProgramUniform1i(w->programs[PROG_COLLIDE], w->u_apply_level[1], it == level_at);
        dispatch_particles(s, PROG_DELTA, PBF_STAGE_DELTA);
        stage_done(s, PBF_STAGE_DELTA, it);
        if (w->gpu_colliders > 0) {
            dispatch_particles(s, PROG_COLLIDE, PBF_STAGE_COLLIDE);
            stage_done(s, PBF_STAGE_COLLIDE, it);
        }
        w->cur_pred ^= 1;
        pbf_bind_particles(w);
    }
    dispatch_particles(s, PROG_VELOCITY, PBF_STAGE_VELOCITY);
    stage_done(s, PBF_STAGE_VELOCITY, -1);
    if (p->vorticity > 0.0f || p->viscosity > 0.0f) {
        if (p->vorticity > 0.0f) {
            dispatch_particles(s, PROG_VORTICITY, PBF_STAGE_VORTICITY);
            stage_done(s, PBF_STAGE_VORTICITY, -1);
        }
        dispatch_particles(s, PROG_VISCOSITY, PBF_STAGE_VISCOSITY);
        stage_done(s, PBF_STAGE_VISCOSITY, -1);
        w->cur_vel ^= 1;
        pbf_bind_particles(w);
    }
}

pbf_result pbf_world_step(pbf_world *w, float dt) { return pbf_world_step_with(w, dt, NULL, NULL); }

// The cohesion force is explicit: a step needs pbf_tension_substeps of it to stay quiet and,
// far short of them, stable.
// When max_substeps allows fewer, say so (once, until the need is met again).
static void warn_tension(pbf_world *w, float dt)
{
    const pbf_params *p = &w->params;
    int need = pbf_tension_substeps(p, dt);
    int most = pbf_most_substeps(p);
    bool short_of = need > most;
    if (short_of && !w->tension_warned && w->log) {
        char msg[512];
        snprintf(msg, sizeof msg, "surface_tension = %g N/m needs %d substeps of a %.3g s step to stay stable and "
                 "max_substeps = %d allows %d: the water may blow up (lower surface_tension or the step, or raise "
                 "max_substeps; docs/solver.md, \"Surface tension\")", (double)p->surface_tension, need, (double)dt,
                 p->max_substeps, most);
        w->log(w->log_user, 2, msg);
    }
    w->tension_warned = short_of;
}

// The coarse level's push has only a partial reaction (docs/solver.md, "The coarse level"):
// bodies feel it through the multiplier -p at the particles next to them (collide.comp),
// which is about right at the defaults' spacing where the level's cells see the body whole
// (a floor, a box on the cells' lines) but not where a cell is part body, part water, nor
// at finer spacings, and the forces on two-way bodies (and on static ones that measure
// theirs) then miss part of the share of the water's weight it carries. Say so once while
// the level is on and such a body is there.
static void warn_level(pbf_world *w)
{
    bool two_way = false;
    if (w->params.level_sweeps > 0)
        for (int i = 0; i < PBF_MAX_COLLIDERS && !two_way; i++)
            two_way = w->slots[i].used && (w->slots[i].gpu.info.y & PBF_COLLIDER_TWO_WAY) != 0u;
    if (two_way && !w->level_warned && w->log) {
        char msg[512];
        snprintf(msg, sizeof msg, "level_sweeps = %d with two-way bodies: the coarse level's push has only a partial reaction, "
                 "so the forces on bodies miss part of the share of the water's weight it carries (measured: a floor "
                 "+2.8 %% to -17.5 %%, a submerged sphere 35-53 %% light; docs/solver.md, \"The coarse level\")", w->params.level_sweeps);
        w->log(w->log_user, 2, msg);
    }
    w->level_warned = two_way;
}

// The time-step guard (params.cfl, pbf_guard_substeps; params.guard_compression,
// pbf_guard_compression): the substeps this step takes, with a warning (once while it
// lasts) when max_substeps is not enough. They read the records of steps now - 2 (and, for
// the compression's pace, now - 3), which the GPU has normally finished: no stall.
static int guard_substeps(pbf_world *w, float dt)
{
    const pbf_params *p = &w->params;
    float seen = -1.0f;
    const pbf_guard_seen *record = NULL, *before = NULL;
    if (w->step_index >= PBF_GUARD_LATENCY) {
        uint64_t back = w->step_index - PBF_GUARD_LATENCY;
        seen = pbf_speed_of_step(w, back);
        int k = (int)(back % PBF_GUARD_HISTORY), k1 = (int)((back + PBF_GUARD_HISTORY - 1) % PBF_GUARD_HISTORY);
        if (w->speed_step[k] == back + 1) record = &w->seen_of[k];
        if (back >= 1 && w->speed_step[k1] == back) before = &w->seen_of[k1];
    }
    bool capped = false;
    int n = pbf_guard_substeps(p, w->k.spacing, dt, w->step_index, seen, w->added_speed, &capped);
    if (capped && !w->guard_capped && w->log) {
        char msg[384];
        snprintf(msg, sizeof msg, "time-step guard: the fastest particles need more than max_substeps = %d substeps of "
                 "a %.3g s step to move at most cfl = %.3g spacings in one: the solver may diverge (lower the step, "
                 "or raise max_substeps)", n, (double)dt, (double)p->cfl);
        w->log(w->log_user, 2, msg);
    }
    w->guard_capped = capped;
    bool squeezed = false;
    int level = pbf_guard_compression(p, &w->compression, record, before, &squeezed);
    if (squeezed && !w->compression_capped && w->log) {
        char msg[384];
        snprintf(msg, sizeof msg, "time-step guard: step %llu compressed the water to +%.1f %% at worst, %.2f %% on "
                 "average (guard_compression = %.3g: worst under it, mean under a tenth of it), and max_substeps = %d "
                 "substeps of a %.3g s step cannot bring that back (lower the step, raise iterations or max_substeps)",
                 (unsigned long long)(w->step_index - PBF_GUARD_LATENCY), 100.0 * record->density_error_max,
                 100.0 * record->density_error_avg, (double)p->guard_compression, level, (double)dt);
        w->log(w->log_user, 2, msg);
    }
    w->compression_capped = squeezed;
    return level > n ? level : n;
}

pbf_result pbf_world_step_with(pbf_world *w, float dt, pbf_substep_fn *hook, void *user)
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (pbf_refused_in_step(w, "pbf_world_step", "; set poses or forces there, step after it returns"))
        return PBF_ERR_INVALID_ARG;
    if (pbf_without_context(w, "pbf_world_step")) return PBF_ERR_GL;
    if (!(dt >= PBF_MIN_DT && dt <= 1.0f))
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_step: dt must be in [%g, 1] s (got %g)", (double)PBF_MIN_DT,
                        (double)dt);
    pbf_result er = pbf_emitters_emit(w, dt);
    if (er != PBF_OK) return er;
    w->sinks_active = false;
    for (int k = 0; k < PBF_MAX_SINKS; k++) w->sinks_active |= w->sinks[k].used;
    int slot_index = w->ring_head;
    stats_slot *slot = &w->ring[slot_index];
    // The GPU is RING steps behind, or nobody polls: read the oldest record now.
    if (slot->pending) pbf_read_early(w, slot);
    int substeps = guard_substeps(w, dt);
    w->step_substeps = substeps;
    warn_tension(w, dt);
    warn_level(w);
    slot->nq = 0;
    slot->step = w->step_index;
    slot->appended_total = w->appended_total;
    slot->substeps = substeps;
    pbf_colliders_begin_step(w, slot);
    step_ctx s = { w, slot, 0 };
    mark(&s, PBF_STAGE_PREDICT);
    float sub_dt = dt / (float)substeps;
    for (int k = 0; k < substeps; k++) {
        if (hook) {
            w->in_step = true;
            hook(user, w, k, sub_dt);
            w->in_step = false;
            if (w->colliders_dirty) pbf_colliders_upload(w);
        }
        substep(&s, sub_dt, k, slot_index);
    }
    // Metrics of the final state (partials per work group, then one group folds them).
    dispatch_particles(&s, PROG_METRICS, PBF_STAGE_METRICS);
    glUseProgram(w->programs[PROG_METRICS_FINAL]);
    glUniform1ui(w->u_frame, (GLuint)w->step_index);
    dispatch(&s, PROG_METRICS_FINAL, 1, PBF_STAGE_METRICS);
    stage_done(&s, PBF_STAGE_METRICS, -1);
    pbf_colliders_end_step(w);
    w->time += dt;
    slot->time = w->time;
    slot->fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    slot->pending = true;
    w->ring_head = (w->ring_head + 1) % RING;
    w->step_index++;
    w->added_speed[w->step_index % PBF_GUARD_HISTORY] = 0.0f; // appends from here belong to the next step
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) return pbf_fail(w, PBF_ERR_GL, "pbf_world_step: GL error 0x%x", e);
    return PBF_OK;
}

pbf_gpu_buffers pbf_world_gpu_buffers(const pbf_world *w)
{
    if (!w) {
        pbf_gpu_buffers none = { 0, 0, 0, 0 };
        return none;
    }
    pbf_gpu_buffers b = { w->pos[w->cur_pos], w->vel[w->cur_vel], w->draw, w->count };
    return b;
}
