// The fixture of the coupling's tests (tests/test_coupling_*.c): a headless context, a scene
// of a fluid world, a Bullet world and a coupling, bodies, particles read back, box geometry.
//
// Scenes are small for llvmpipe on two cores: 2 cm particles (h = 4 cm), a 0.4 x 0.4 m
// tank, at most about 3000 particles. SEICHE_TEST_VERBOSE=1 prints the measurements.
// Header only: every helper is static (inline), so each test program keeps what it uses.
#ifndef SEICHE_TESTS_COUPLING_FIXTURE_H
#define SEICHE_TESTS_COUPLING_FIXTURE_H

#include "tests/support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fluid/bullet/coupling.h"
#include "fluid/bullet/phys.h"
#include "fluid/pbf.h"

#define RHO0 1000.0f
#define RADIUS 0.01f
#define SPACING (2.0f * RADIUS)
#define TANK 0.40f
#define DT (1.0f / 60.0f)

static inline bool verbose(void)
{
    const char *v = getenv("SEICHE_TEST_VERBOSE");
    return v && *v && *v != '0';
}

static inline double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

#define assert_ok_phys(expr)                                                                  \
    do {                                                                                      \
        phys_result r_ = (expr);                                                              \
        if (r_ != PHYS_OK) fail_msg("%s: %s", #expr, phys_result_string(r_));                 \
    } while (0)

// ---- fixture: a headless context ----------------------------------------------------------

typedef struct fixture {
    eng_context *ctx;
    char shader_dir[1024];
} fixture;

static inline int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    if (!f) return -1;
    f->ctx = support_headless_context(32, 32);
    if (verbose()) printf("GL: %s\n", eng_context_renderer(f->ctx));
    const char *env = getenv("SEICHE_SHADER_DIR");
    if (env && *env) snprintf(f->shader_dir, sizeof f->shader_dir, "%s", env);
    else support_source_path("shaders", f->shader_dir, sizeof f->shader_dir);
    *state = f;
    return 0;
}

static inline int teardown(void **state)
{
    fixture *f = *state;
    eng_context_destroy(f->ctx);
    free(f);
    return 0;
}

// ---- a scene: a fluid world, a Bullet world, a coupling -----------------------------------

typedef struct scene {
    pbf_step_stats last; ///< statistics of the latest step that reached the CPU
    pbf_world *fluid;
    phys_world *phys;
    cpl_coupling *cpl;
    float tank_min[3], tank_max[3];
    uint32_t particles;
    double t0;
} scene;

typedef struct scene_def {
    float gravity;          ///< m/s^2 downwards (9.81 or 0)
    float tank_height;      ///< m
    uint32_t capacity;
    int force_latency;
    int iterations, substeps;
} scene_def;

static inline scene_def default_scene_def(void)
{
    scene_def d = { 9.81f, 0.4f, 4096, 1, 2, 4 };
    const char *it = getenv("SEICHE_TEST_ITERATIONS"), *sub = getenv("SEICHE_TEST_SUBSTEPS");
    if (it) d.iterations = atoi(it);
    if (sub) d.substeps = atoi(sub);
    return d;
}

static inline void scene_create(const fixture *f, scene *s, const scene_def *sd)
{
    memset(s, 0, sizeof *s);
    s->t0 = now_s();
    pbf_world_def def = pbf_default_world_def();
    def.params.particle_radius = RADIUS;
    def.params.kernel_radius = 2.0f * SPACING;
    def.params.rest_density = RHO0;
    def.params.gravity[1] = -sd->gravity;
    def.params.iterations = sd->iterations;
    def.params.substeps = sd->substeps;
    def.capacity = sd->capacity;
    def.max_neighbours = pbf_suggest_max_neighbours(&def.params);
    const float lo[3] = { 0.0f, 0.0f, 0.0f }, hi[3] = { TANK, sd->tank_height, TANK };
    for (int k = 0; k < 3; k++) {
        def.domain_min[k] = lo[k] - 0.02f;
        def.domain_max[k] = hi[k] + 0.02f;
        s->tank_min[k] = lo[k];
        s->tank_max[k] = hi[k];
    }
    def.shader_dir = f->shader_dir;
    char err[1024];
    s->fluid = pbf_world_create(&def, err, sizeof err);
    if (!s->fluid) fail_msg("pbf_world_create: %s", err);
    assert_int_equal(pbf_world_set_container(s->fluid, lo, hi, false), PBF_OK);

    phys_world_def wd = phys_default_world_def();
    wd.gravity = (phys_vec3){ 0.0f, -sd->gravity, 0.0f };
    assert_ok_phys(phys_world_create(&wd, &s->phys));
    // Bullet's own tank (not coupled: the fluid has its container): floor and four walls.
    const phys_plane planes[5] = {
        { { 0, 1, 0 }, 0.0f }, { { 1, 0, 0 }, 0.0f }, { { -1, 0, 0 }, -TANK }, { { 0, 0, 1 }, 0.0f }, { { 0, 0, -1 }, -TANK },
    };
    for (int k = 0; k < 5; k++) {
        phys_shape_id shape;
        assert_ok_phys(phys_shape_create_plane(s->phys, &planes[k], &shape));
        phys_body_def bd = phys_default_body_def();
        bd.type = PHYS_BODY_STATIC;
        bd.shape = shape;
        phys_body_id body;
        assert_ok_phys(phys_body_create(s->phys, &bd, &body));
    }
    cpl_def cd = cpl_default_def();
    cd.phys = s->phys;
    cd.fluid = s->fluid;
    cd.force_latency = sd->force_latency;
    s->cpl = cpl_create(&cd, err, sizeof err);
    if (!s->cpl) fail_msg("cpl_create: %s", err);
}

static inline void scene_destroy(scene *s)
{
    cpl_destroy(s->cpl);
    pbf_world_destroy(s->fluid);
    phys_world_destroy(s->phys);
}

static inline void scene_step(scene *s, int steps)
{
    for (int i = 0; i < steps; i++) {
        cpl_result r = cpl_step(s->cpl, DT);
        if (r != CPL_OK) fail_msg("cpl_step: %s", cpl_last_error(s->cpl));
        pbf_step_stats st[8];
        int n = pbf_world_poll_stats(s->fluid, st, 8, false);
        if (n > 0) s->last = st[n - 1];
    }
}

/// Exact live particle count of the latest step (waits for the GPU).
static inline uint32_t scene_particle_count(scene *s)
{
    pbf_step_stats st[8];
    int n = pbf_world_poll_stats(s->fluid, st, 8, true);
    if (n > 0) s->last = st[n - 1];
    return s->last.particles;
}

// A body with a box shape.
static inline phys_body_id add_box(scene *s, phys_body_type type, const float half[3], const float pos[3], float density,
                                   const float velocity[3])
{
    phys_box box = { { half[0], half[1], half[2] } };
    phys_shape_id shape;
    assert_ok_phys(phys_shape_create_box(s->phys, &box, &shape));
    phys_body_def bd = phys_default_body_def();
    bd.type = type;
    bd.shape = shape;
    bd.position = (phys_vec3){ pos[0], pos[1], pos[2] };
    bd.density = density;
    bd.allow_sleep = false;
    if (velocity) bd.linear_velocity = (phys_vec3){ velocity[0], velocity[1], velocity[2] };
    phys_body_id body;
    assert_ok_phys(phys_body_create(s->phys, &bd, &body));
    if (cpl_add_body(s->cpl, body, NULL) != CPL_OK) fail_msg("cpl_add_body: %s", cpl_last_error(s->cpl));
    return body;
}

// ---- geometry on the test side ---------------------------------------------------------------

static inline void quat_rotate(const phys_quat q, const float v[3], float out[3])
{
    // v + 2 w (q x v) + 2 q x (q x v)
    float t[3] = { 2.0f * (q.y * v[2] - q.z * v[1]), 2.0f * (q.z * v[0] - q.x * v[2]), 2.0f * (q.x * v[1] - q.y * v[0]) };
    out[0] = v[0] + q.w * t[0] + (q.y * t[2] - q.z * t[1]);
    out[1] = v[1] + q.w * t[1] + (q.z * t[0] - q.x * t[2]);
    out[2] = v[2] + q.w * t[2] + (q.x * t[1] - q.y * t[0]);
}

static inline void to_local(const phys_vec3 p, const phys_quat q, const float x[3], float l[3])
{
    float d[3] = { x[0] - p.x, x[1] - p.y, x[2] - p.z };
    phys_quat qi = { -q.x, -q.y, -q.z, q.w };
    quat_rotate(qi, d, l);
}

/// Signed distance to a box of half extents `half` at pose (p, q), m (negative inside).
static inline float box_distance(const float half[3], phys_vec3 p, phys_quat q, const float x[3])
{
    float l[3];
    to_local(p, q, x, l);
    float o2 = 0.0f, in = -INFINITY;
    for (int k = 0; k < 3; k++) {
        float e = fabsf(l[k]) - half[k];
        if (e > 0.0f) o2 += e * e;
        if (e > in) in = e;
    }
    return o2 > 0.0f ? sqrtf(o2) : in;
}

typedef struct particles {
    float *pos; // xyzw
    float *vel;
    uint32_t *id; // ascending
    uint32_t n;
} particles;

static inline particles read_particles(scene *s)
{
    particles p;
    uint32_t n = scene_particle_count(s);
    p.pos = malloc((size_t)(n + 1) * 16);
    p.vel = malloc((size_t)(n + 1) * 16);
    p.id = malloc((size_t)(n + 1) * 4);
    assert_non_null(p.pos);
    assert_non_null(p.vel);
    assert_non_null(p.id);
    p.n = pbf_world_read_particles(s->fluid, p.pos, p.vel, p.id, n);
    return p;
}

static inline void free_particles(particles *p)
{
    free(p->pos);
    free(p->vel);
    free(p->id);
}

/// Fills the tank with water up to `level` on the particle lattice, leaving out the lattice
/// sites inside `skip_box` (half extents at a position; NULL: none). Returns the count.
static inline uint32_t fill_water(scene *s, float level, const float *skip_half, const float *skip_pos, float y0)
{
    int nx = (int)floorf((s->tank_max[0] - s->tank_min[0]) / SPACING + 1e-4f);
    int nz = (int)floorf((s->tank_max[2] - s->tank_min[2]) / SPACING + 1e-4f);
    int ny = (int)floorf((level - y0) / SPACING + 1e-4f);
    float *xyz = malloc((size_t)nx * ny * nz * 12 + 12);
    assert_non_null(xyz);
    uint32_t n = 0;
    for (int k = 0; k < nz; k++)
        for (int j = 0; j < ny; j++)
            for (int i = 0; i < nx; i++) {
                float x[3] = { s->tank_min[0] + SPACING * (i + 0.5f), y0 + SPACING * (j + 0.5f),
                               s->tank_min[2] + SPACING * (k + 0.5f) };
                if (skip_half) {
                    bool inside = true;
                    for (int a = 0; a < 3; a++)
                        if (fabsf(x[a] - skip_pos[a]) > skip_half[a] + 0.5f * SPACING) inside = false;
                    if (inside) continue;
                }
                memcpy(xyz + 3 * n, x, 12);
                n++;
            }
    if (n) assert_int_equal(pbf_world_add_particles(s->fluid, xyz, NULL, n), PBF_OK);
    free(xyz);
    s->particles += n;
    return n;
}

#endif
