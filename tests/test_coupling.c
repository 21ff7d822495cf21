// Bullet bodies as two-way coupled fluid boundaries (fluid/bullet/coupling.h): buoyancy
// against Archimedes, sinking, no fluid inside bodies, constant particle count, no
// tunnelling through fluid or thin walls, gentle push-out, and input checks that name
// the field.
//
// Scenes are small for llvmpipe on two cores: 2 cm particles (h = 4 cm), a 0.4 x 0.4 m
// tank, at most about 3000 particles. SEICHE_TEST_VERBOSE=1 prints the measurements.
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

static bool verbose(void)
{
    const char *v = getenv("SEICHE_TEST_VERBOSE");
    return v && *v && *v != '0';
}

static double now_s(void)
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

static int setup(void **state)
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

static int teardown(void **state)
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

static scene_def default_scene_def(void)
{
    scene_def d = { 9.81f, 0.4f, 4096, 1, 2, 4 };
    const char *it = getenv("SEICHE_TEST_ITERATIONS"), *sub = getenv("SEICHE_TEST_SUBSTEPS");
    if (it) d.iterations = atoi(it);
    if (sub) d.substeps = atoi(sub);
    return d;
}

static void scene_create(const fixture *f, scene *s, const scene_def *sd)
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

static void scene_destroy(scene *s)
{
    cpl_destroy(s->cpl);
    pbf_world_destroy(s->fluid);
    phys_world_destroy(s->phys);
}

static void scene_step(scene *s, int steps)
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
static uint32_t scene_particle_count(scene *s)
{
    pbf_step_stats st[8];
    int n = pbf_world_poll_stats(s->fluid, st, 8, true);
    if (n > 0) s->last = st[n - 1];
    return s->last.particles;
}

// A body with a box shape.
static phys_body_id add_box(scene *s, phys_body_type type, const float half[3], const float pos[3], float density,
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

static phys_body_id add_sphere(scene *s, float radius, const float pos[3], float density)
{
    phys_sphere sphere = { radius };
    phys_shape_id shape;
    assert_ok_phys(phys_shape_create_sphere(s->phys, &sphere, &shape));
    phys_body_def bd = phys_default_body_def();
    bd.shape = shape;
    bd.position = (phys_vec3){ pos[0], pos[1], pos[2] };
    bd.density = density;
    bd.allow_sleep = false;
    phys_body_id body;
    assert_ok_phys(phys_body_create(s->phys, &bd, &body));
    if (cpl_add_body(s->cpl, body, NULL) != CPL_OK) fail_msg("cpl_add_body: %s", cpl_last_error(s->cpl));
    return body;
}

// ---- geometry on the test side ---------------------------------------------------------------

static void quat_rotate(const phys_quat q, const float v[3], float out[3])
{
    // v + 2 w (q x v) + 2 q x (q x v)
    float t[3] = { 2.0f * (q.y * v[2] - q.z * v[1]), 2.0f * (q.z * v[0] - q.x * v[2]), 2.0f * (q.x * v[1] - q.y * v[0]) };
    out[0] = v[0] + q.w * t[0] + (q.y * t[2] - q.z * t[1]);
    out[1] = v[1] + q.w * t[1] + (q.z * t[0] - q.x * t[2]);
    out[2] = v[2] + q.w * t[2] + (q.x * t[1] - q.y * t[0]);
}

static void to_local(const phys_vec3 p, const phys_quat q, const float x[3], float l[3])
{
    float d[3] = { x[0] - p.x, x[1] - p.y, x[2] - p.z };
    phys_quat qi = { -q.x, -q.y, -q.z, q.w };
    quat_rotate(qi, d, l);
}

/// Signed distance to a box of half extents `half` at pose (p, q), m (negative inside).
static float box_distance(const float half[3], phys_vec3 p, phys_quat q, const float x[3])
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

static particles read_particles(scene *s)
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

static void free_particles(particles *p)
{
    free(p->pos);
    free(p->vel);
    free(p->id);
}

/// Free-surface height from mass per area in the columns away from a body footprint
/// [fx0, fx1] x [fz0, fz1] (expanded by 2 h): y = floor + particles * spacing^3 / area. This
/// is the level that sets the hydrostatic pressure, whatever the compression.
static float free_surface(const scene *s, const particles *p, const float foot_lo[2], const float foot_hi[2])
{
    float m = 2.0f * SPACING;
    float x0 = foot_lo[0] - m, x1 = foot_hi[0] + m, z0 = foot_lo[1] - m, z1 = foot_hi[1] + m;
    x0 = fmaxf(x0, s->tank_min[0]);
    z0 = fmaxf(z0, s->tank_min[2]);
    x1 = fminf(x1, s->tank_max[0]);
    z1 = fminf(z1, s->tank_max[2]);
    float area = (s->tank_max[0] - s->tank_min[0]) * (s->tank_max[2] - s->tank_min[2]) - (x1 - x0) * (z1 - z0);
    uint32_t count = 0;
    for (uint32_t i = 0; i < p->n; i++) {
        const float *x = p->pos + 4 * i;
        if (x[0] >= x0 && x[0] <= x1 && x[2] >= z0 && x[2] <= z1) continue;
        count++;
    }
    return s->tank_min[1] + (float)count * SPACING * SPACING * SPACING / area;
}

/// Free-surface height from the top particle of each far-field lattice column (+ radius),
/// averaged over the columns: the visible surface.
static float top_surface(const scene *s, const particles *p, const float foot_lo[2], const float foot_hi[2])
{
    enum { N = 64 };
    float top[N][N];
    for (int i = 0; i < N; i++)
        for (int k = 0; k < N; k++) top[i][k] = -1.0f;
    float m = 2.0f * SPACING;
    for (uint32_t i = 0; i < p->n; i++) {
        const float *x = p->pos + 4 * i;
        if (x[0] >= foot_lo[0] - m && x[0] <= foot_hi[0] + m && x[2] >= foot_lo[1] - m && x[2] <= foot_hi[1] + m) continue;
        int cx = (int)((x[0] - s->tank_min[0]) / SPACING), cz = (int)((x[2] - s->tank_min[2]) / SPACING);
        if (cx < 0 || cz < 0 || cx >= N || cz >= N) continue;
        if (x[1] > top[cx][cz]) top[cx][cz] = x[1];
    }
    double sum = 0.0;
    int n = 0;
    for (int i = 0; i < N; i++)
        for (int k = 0; k < N; k++)
            if (top[i][k] >= 0.0f) {
                sum += top[i][k] + RADIUS;
                n++;
            }
    return n ? (float)(sum / n) : 0.0f;
}

/// Fraction of a box's volume below the plane y = level (sampled on a 24^3 grid).
static float submerged_fraction(const float half[3], phys_vec3 p, phys_quat q, float level)
{
    const int n = 24;
    int below = 0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            for (int k = 0; k < n; k++) {
                float l[3] = { half[0] * (2.0f * (i + 0.5f) / n - 1.0f), half[1] * (2.0f * (j + 0.5f) / n - 1.0f),
                               half[2] * (2.0f * (k + 0.5f) / n - 1.0f) };
                float wv[3];
                quat_rotate(q, l, wv);
                if (p.y + wv[1] < level) below++;
            }
    return (float)below / (float)(n * n * n);
}

/// Fills the tank with water up to `level` on the particle lattice, leaving out the lattice
/// sites inside `skip_box` (half extents at a position; NULL: none). Returns the count.
static uint32_t fill_water(scene *s, float level, const float *skip_half, const float *skip_pos, float y0)
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

// ---- Archimedes -------------------------------------------------------------------------------

typedef struct float_result {
    float fraction;        ///< mean submerged fraction over the last second
    float fraction_spread; ///< max - min over that second
    float level;           ///< free surface, m
    uint32_t inside;       ///< particles inside the box at the end
    uint32_t count_start, count_end;
    double seconds;
} float_result;

static float_result float_box(const fixture *f, float density, bool verbose_trace)
{
    scene s;
    scene_def sd = default_scene_def();
    scene_create(f, &s, &sd);
    // A flat box (stable upright for any density: width / height = 2 > sqrt(6 f (1 - f))).
    const float half[3] = { 0.08f, 0.04f, 0.08f };
    const float depth = 0.16f;  // water depth without the box
    float frac = density / RHO0;
    // Start near equilibrium: the box's bottom below the final level by frac * height.
    float tank_area = TANK * TANK;
    float rise = frac * 8.0f * half[0] * half[1] * half[2] / tank_area;
    float level = depth + rise;
    float pos[3] = { 0.5f * TANK, level - frac * 2.0f * half[1] + half[1], 0.5f * TANK };
    uint32_t n0 = fill_water(&s, level, half, pos, 0.0f);
    (void)n0;
    phys_body_id box = add_box(&s, PHYS_BODY_DYNAMIC, half, pos, density, NULL);
    float_result r;
    memset(&r, 0, sizeof r);
    r.count_start = s.particles;
    const float foot_lo[2] = { pos[0] - half[0], pos[2] - half[2] }, foot_hi[2] = { pos[0] + half[0], pos[2] + half[2] };
    const int settle = 90, measure = 60;
    const int every = getenv("SEICHE_TEST_EVERY") ? atoi(getenv("SEICHE_TEST_EVERY")) : 6;
    double sum = 0.0;
    int samples = 0;
    float fmin = 1.0f, fmax = 0.0f;
    for (int step = 0; step < settle + measure; step += every) {
        scene_step(&s, every);
        if (step + every <= settle && !verbose_trace) continue;
        particles p = read_particles(&s);
        phys_vec3 bp;
        phys_quat bq;
        assert_ok_phys(phys_body_get_pose(s.phys, box, &bp, &bq));
        float lv = free_surface(&s, &p, foot_lo, foot_hi);
        float fr = submerged_fraction(half, bp, bq, lv);
        if (verbose_trace) {
            cpl_body_stats st;
            cpl_body_get_stats(s.cpl, box, &st);
            // Diagnostics: gap of the lowest layer at the floor, gap under the box, far-field
            // mass above the box's bottom as an equivalent depth.
            double floor_sum = 0, under_sum = 0;
            int floor_n = 0, under_n = 0, above_n = 0;
            float yb = bp.y - half[1];
            for (uint32_t i = 0; i < p.n; i++) {
                const float *x = p.pos + 4 * i;
                if (x[1] < SPACING) {
                    floor_sum += x[1] - RADIUS;
                    floor_n++;
                }
                if (fabsf(x[0] - bp.x) < half[0] - SPACING && fabsf(x[2] - bp.z) < half[2] - SPACING && x[1] < yb &&
                    x[1] > yb - SPACING) {
                    under_sum += yb - x[1] - RADIUS;
                    under_n++;
                }
                bool far = !(x[0] >= foot_lo[0] - 2 * SPACING && x[0] <= foot_hi[0] + 2 * SPACING &&
                             x[2] >= foot_lo[1] - 2 * SPACING && x[2] <= foot_hi[1] + 2 * SPACING);
                if (far && x[1] > yb) above_n++;
            }
            float far_area = TANK * TANK - (foot_hi[0] - foot_lo[0] + 4 * SPACING) * (foot_hi[1] - foot_lo[1] + 4 * SPACING);
            float depth_eq = (float)above_n * SPACING * SPACING * SPACING / far_area;
            float top = top_surface(&s, &p, foot_lo, foot_hi);
            printf("  rho %4.0f step %3d top %.4f frac_top %.3f y %.4f level %.4f frac %.3f force %.3f N (weight %.3f N) contacts %u | floor gap "
                   "%.2f mm, box gap %.2f mm (%d), depth_eq/H %.3f, rho_avg %.1f\n",
                   (double)density, step + every, (double)top, (double)submerged_fraction(half, bp, bq, top),
                   (double)bp.y, (double)lv, (double)fr, (double)st.force[1], (double)(density * 8.0f * half[0] * half[1] * half[2] * 9.81f), st.contacts,
                   1e3 * floor_sum / (floor_n ? floor_n : 1), 1e3 * under_sum / (under_n ? under_n : 1), under_n,
                   (double)(depth_eq / (2 * half[1])), (double)s.last.density_avg);
        }
        if (step + every > settle) {
            sum += fr;
            samples++;
            fmin = fminf(fmin, fr);
            fmax = fmaxf(fmax, fr);
            r.level = lv;
            if (step + every >= settle + measure) {
                for (uint32_t i = 0; i < p.n; i++)
                    if (box_distance(half, bp, bq, p.pos + 4 * i) < 0.0f) r.inside++;
            }
        }
        free_particles(&p);
    }
    cpl_body_stats bs;
    assert_int_equal(cpl_body_get_stats(s.cpl, box, &bs), CPL_OK);
    // Lockstep with one step of latency: the last step applied the force of the one before.
    assert_true(bs.force_step + 2 == cpl_step_count(s.cpl));
    r.fraction = (float)(sum / samples);
    r.fraction_spread = fmax - fmin;
    r.count_end = scene_particle_count(&s);
    r.seconds = now_s() - s.t0;
    scene_destroy(&s);
    if (verbose())
        printf("float_box rho %.0f: submerged %.3f (want %.3f, spread %.3f), level %.4f m, inside %u, particles %u -> %u, "
               "%.1f s\n", (double)density, (double)r.fraction, (double)frac, (double)r.fraction_spread, (double)r.level,
               r.inside, r.count_start, r.count_end, r.seconds);
    return r;
}

static void check_float(void **state, float density)
{
    float_result r = float_box(*state, density, verbose() && getenv("SEICHE_TEST_TRACE"));
    float want = density / RHO0;
    if (!(fabsf(r.fraction - want) <= 0.05f))
        fail_msg("box of %.0f kg/m^3 floats %.3f submerged; Archimedes says %.3f (+-0.05)", (double)density,
                 (double)r.fraction, (double)want);
    assert_int_equal(r.inside, 0);
    assert_int_equal(r.count_end, r.count_start);
}

static void box_of_250_floats_a_quarter_submerged(void **state) { check_float(state, 250.0f); }
static void box_of_500_floats_half_submerged(void **state) { check_float(state, 500.0f); }
static void box_of_750_floats_three_quarters_submerged(void **state) { check_float(state, 750.0f); }


// ---- sinking ----------------------------------------------------------------------------------

static void ball_denser_than_water_sinks_and_rests_on_the_bottom(void **state)
{
    scene s;
    scene_def sd = default_scene_def();
    scene_create(*state, &s, &sd);
    fill_water(&s, 0.16f, NULL, NULL, 0.0f);
    const float r = 0.05f, start[3] = { 0.2f, 0.27f, 0.2f };
    phys_body_id ball = add_sphere(&s, r, start, 2500.0f);
    scene_step(&s, 120);
    phys_vec3 p, v;
    assert_ok_phys(phys_body_get_pose(s.phys, ball, &p, NULL));
    assert_ok_phys(phys_body_get_linear_velocity(s.phys, ball, &v));
    particles ps = read_particles(&s);
    uint32_t inside = 0;
    for (uint32_t i = 0; i < ps.n; i++) {
        const float *x = ps.pos + 4 * i;
        float dx = x[0] - p.x, dy = x[1] - p.y, dz = x[2] - p.z;
        if (dx * dx + dy * dy + dz * dz < r * r) inside++;
    }
    if (verbose())
        printf("ball of 2500 kg/m^3: rests at y %.4f m (radius %.3f), speed %.4f m/s, %u particles inside, %.1f s\n",
               (double)p.y, (double)r, (double)sqrtf(v.x * v.x + v.y * v.y + v.z * v.z), inside, now_s() - s.t0);
    assert_true(fabsf(p.y - r) < 0.01f);
    assert_true(sqrtf(v.x * v.x + v.y * v.y + v.z * v.z) < 0.05f);
    assert_int_equal(inside, 0);
    assert_int_equal(ps.n, s.particles);
    free_particles(&ps);
    scene_destroy(&s);
}

/// A light box hitting the water fast does not come back out faster than it went in (an
/// explicit, one-step-late coupling can pump energy into light bodies at impact; the
/// coupling limits the fluid's impulse per step, cpl_def.impulse_limit).
static void light_box_hitting_water_does_not_gain_energy(void **state)
{
    scene s;
    scene_def sd = default_scene_def();
    scene_create(*state, &s, &sd);
    const float level = 0.12f;
    fill_water(&s, level, NULL, NULL, 0.0f);
    const float half[3] = { 0.06f, 0.03f, 0.06f }, start[3] = { 0.2f, level + 0.15f, 0.2f }, v0[3] = { 0, -2.0f, 0 };
    phys_body_id box = add_box(&s, PHYS_BODY_DYNAMIC, half, start, 300.0f, v0);
    float impact = 0.0f, rebound = 0.0f;
    bool hit = false;
    for (int i = 0; i < 90; i++) {
        scene_step(&s, 1);
        phys_vec3 p, v;
        assert_ok_phys(phys_body_get_pose(s.phys, box, &p, NULL));
        assert_ok_phys(phys_body_get_linear_velocity(s.phys, box, &v));
        float speed = sqrtf(v.x * v.x + v.y * v.y + v.z * v.z);
        if (!hit && p.y - half[1] <= level) {
            hit = true;
            impact = speed;
        }
        if (hit && v.y > rebound) rebound = v.y;
        if (verbose()) printf("step %2d: y %.3f vy %+.3f\n", i, (double)p.y, (double)v.y);
    }
    if (verbose())
        printf("light box (300 kg/m^3): hits the water at %.2f m/s, fastest rise afterwards %.2f m/s\n",
               (double)impact, (double)rebound);
    assert_true(hit);
    assert_true(impact > 2.0f);
    // No energy from nothing: it rises slower than it fell in, by a good margin.
    assert_true(rebound < 0.5f * impact);
    scene_destroy(&s);
}

// ---- tunnelling -------------------------------------------------------------------------------

/// A slab of still water (no gravity) across the tank: x in [x0, x0 + thickness].
static void fill_slab(scene *s, float x0, float thickness)
{
    int nx = (int)floorf(thickness / SPACING + 1e-4f), n1 = (int)floorf(TANK / SPACING + 1e-4f);
    float *xyz = malloc((size_t)nx * n1 * n1 * 12);
    assert_non_null(xyz);
    uint32_t n = 0;
    for (int k = 0; k < n1; k++)
        for (int j = 0; j < n1; j++)
            for (int i = 0; i < nx; i++) {
                xyz[3 * n] = x0 + SPACING * (i + 0.5f);
                xyz[3 * n + 1] = SPACING * (j + 0.5f);
                xyz[3 * n + 2] = SPACING * (k + 0.5f);
                n++;
            }
    assert_int_equal(pbf_world_add_particles(s->fluid, xyz, NULL, n), PBF_OK);
    s->particles += n;
    free(xyz);
}

/// A plate's pose at the end of a step.
typedef struct pose {
    phys_vec3 p;
    phys_quat q;
} pose;

/// Particle paths over one step that crossed a plate's mid-plane (local x = 0 of a box with
/// half extents `half`), sorted by where they crossed it.
typedef struct crossings {
    uint32_t through;      ///< crossed inside the plate's outline: tunnelled
    uint32_t around;       ///< crossed outside it: went round an edge
    float deepest_through; ///< m: how far inside the outline the deepest "through" crossing was
    float closest_around;  ///< m: how far outside the outline the nearest "around" crossing was
} crossings;

/// Adds the crossings of the step from `a` (plate pose `pa`) to `b` (pose `pb`), particles
/// matched by id. Each path is taken in the plate's frame, where the plate stands still: a
/// particle on one side of the mid-plane before the step and on the other side after it
/// crossed the plane where the straight line between its two positions meets it. The plate
/// keeps fluid a particle radius off its faces, so a particle that went round an edge
/// crosses outside the outline; one that crosses inside went through the plate.
static void add_crossings(const float half[3], pose pa, pose pb, const particles *a, const particles *b, crossings *c)
{
    uint32_t i = 0, j = 0;
    while (i < a->n && j < b->n) {
        if (a->id[i] < b->id[j]) {
            i++;
            continue;
        }
        if (b->id[j] < a->id[i]) {
            j++;
            continue;
        }
        float l0[3], l1[3];
        to_local(pa.p, pa.q, a->pos + 4 * i, l0);
        to_local(pb.p, pb.q, b->pos + 4 * j, l1);
        i++;
        j++;
        if (!((l0[0] > 0.0f && l1[0] < 0.0f) || (l0[0] < 0.0f && l1[0] > 0.0f))) continue;
        float t = l0[0] / (l0[0] - l1[0]);
        float y = l0[1] + t * (l1[1] - l0[1]), z = l0[2] + t * (l1[2] - l0[2]);
        float out = fmaxf(fabsf(y) - half[1], fabsf(z) - half[2]); // < 0: inside the outline
        if (out < 0.0f) {
            c->through++;
            c->deepest_through = fmaxf(c->deepest_through, -out);
            if (verbose() && c->through <= 8)
                printf("  through the plate: particle %u, %.4f m inside its outline\n", a->id[i - 1], (double)-out);
        } else {
            c->around++;
            c->closest_around = fminf(c->closest_around, out);
        }
    }
}

static void thrown_thin_box_does_not_tunnel_through_water(void **state)
{
    scene s;
    scene_def sd = default_scene_def();
    sd.gravity = 0.0f;
    scene_create(*state, &s, &sd);
    fill_slab(&s, 0.2f, 0.08f);
    // A 1 cm plate, face on, thrown at 10 m/s: it moves 4 plate thicknesses per substep.
    // It waits one step at rest first, for the particles to reach the GPU (where the
    // paths below start).
    const float half[3] = { 0.005f, 0.08f, 0.08f }, pos[3] = { 0.1f, 0.2f, 0.2f };
    phys_body_id plate = add_box(&s, PHYS_BODY_DYNAMIC, half, pos, 1000.0f, NULL);
    scene_step(&s, 1);
    assert_ok_phys(phys_body_set_linear_velocity(s.phys, plate, (phys_vec3){ 10.0f, 0.0f, 0.0f }));
    crossings c = { 0, 0, 0.0f, INFINITY };
    pose before, after;
    assert_ok_phys(phys_body_get_pose(s.phys, plate, &before.p, &before.q));
    particles prev = read_particles(&s);
    assert_int_equal(prev.n, s.particles);
    for (int step = 0; step < 12; step++) {
        scene_step(&s, 1);
        assert_ok_phys(phys_body_get_pose(s.phys, plate, &after.p, &after.q));
        particles now = read_particles(&s);
        assert_int_equal(now.n, prev.n);
        add_crossings(half, before, after, &prev, &now, &c);
        free_particles(&prev);
        prev = now;
        before = after;
    }
    free_particles(&prev);
    phys_vec3 v;
    assert_ok_phys(phys_body_get_linear_velocity(s.phys, plate, &v));
    uint32_t count = scene_particle_count(&s);
    if (verbose())
        printf("thrown plate: x %.3f m, speed %.2f m/s after 0.2 s (from 10); paths across its plane: %u through it "
               "(deepest %.4f m inside), %u round its edges (nearest %.4f m outside); count %u -> %u, %.1f s\n",
               (double)after.p.x, (double)v.x, c.through, (double)c.deepest_through, c.around, (double)c.closest_around,
               s.particles, count, now_s() - s.t0);
    // It gives its momentum to the water (0.26 kg against 5 kg) and passes the slab: the
    // water in its way flows round the plate (smaller than the tank's cross-section), none
    // through it, at any step.
    assert_true(v.x < 5.0f);
    assert_true(after.p.x > 0.28f + half[0]);
    assert_true(c.around > 0);
    assert_int_equal(c.through, 0);
    assert_int_equal(count, s.particles);
    scene_destroy(&s);
}

static void fast_thin_kinematic_wall_lets_no_water_through(void **state)
{
    scene s;
    scene_def sd = default_scene_def();
    sd.gravity = 0.0f;
    scene_create(*state, &s, &sd);
    fill_slab(&s, 0.12f, 0.06f);
    // A 1 cm wall across the whole tank, moving at 10 m/s for one step (16.7 cm), then still.
    const float half[3] = { 0.005f, 0.25f, 0.25f }, pos[3] = { 0.05f, 0.2f, 0.2f }; // beyond the domain
    phys_body_id wall = add_box(&s, PHYS_BODY_KINEMATIC, half, pos, 1000.0f, NULL);
    assert_ok_phys(phys_body_set_linear_velocity(s.phys, wall, (phys_vec3){ 10.0f, 0.0f, 0.0f }));
    scene_step(&s, 1);
    assert_ok_phys(phys_body_set_linear_velocity(s.phys, wall, (phys_vec3){ 0.0f, 0.0f, 0.0f }));
    scene_step(&s, 30);
    phys_vec3 p;
    assert_ok_phys(phys_body_get_pose(s.phys, wall, &p, NULL));
    particles ps = read_particles(&s);
    uint32_t behind = 0;
    for (uint32_t i = 0; i < ps.n; i++)
        if (ps.pos[4 * i] < p.x + half[0]) {
            if (verbose() && behind < 8)
                printf("  behind: %.4f %.4f %.4f\n", (double)ps.pos[4 * i], (double)ps.pos[4 * i + 1], (double)ps.pos[4 * i + 2]);
            behind++;
        }
    if (verbose())
        printf("kinematic wall: at x %.3f m, %u of %u particles behind it or in it, %.1f s\n", (double)p.x, behind, ps.n,
               now_s() - s.t0);
    assert_true(p.x > 0.2f);
    assert_int_equal(behind, 0);
    assert_int_equal(ps.n, s.particles);
    free_particles(&ps);
    scene_destroy(&s);
}

// ---- overlap at the start -------------------------------------------------------------------

static void water_that_starts_inside_a_body_is_pushed_out_gently(void **state)
{
    scene s;
    scene_def sd = default_scene_def();
    scene_create(*state, &s, &sd);
    fill_water(&s, 0.14f, NULL, NULL, 0.0f);
    // A static box in the middle of the water: 6 x 4 x 6 = 144 particles start inside it.
    const float half[3] = { 0.06f, 0.04f, 0.06f }, pos[3] = { 0.2f, 0.08f, 0.2f };
    add_box(&s, PHYS_BODY_STATIC, half, pos, 1000.0f, NULL);
    phys_vec3 bp = { pos[0], pos[1], pos[2] };
    phys_quat bq = { 0, 0, 0, 1 };
    float vmax = 0.0f;
    uint32_t inside = 0;
    for (int step = 0; step < 90; step += 3) {
        scene_step(&s, 3);
        particles ps = read_particles(&s);
        inside = 0;
        for (uint32_t i = 0; i < ps.n; i++) {
            const float *v = ps.vel + 4 * i;
            vmax = fmaxf(vmax, sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]));
            if (box_distance(half, bp, bq, ps.pos + 4 * i) < 0.0f) inside++;
        }
        free_particles(&ps);
    }
    if (verbose())
        printf("overlap: fastest particle %.2f m/s while pushed out, %u inside after 1.5 s, %.1f s\n", (double)vmax, inside,
               now_s() - s.t0);
    // Out at 0.5 m/s at most; the water it joins then settles (2.4 m/s measured; moving
    // them out at once, as before, gave 5.4 m/s).
    assert_true(vmax < 3.0f);
    assert_int_equal(inside, 0);
    assert_int_equal(scene_particle_count(&s), s.particles);
    scene_destroy(&s);
}

// ---- convex hulls and triangle meshes -------------------------------------------------------

static void hull_and_mesh_bodies_keep_water_out(void **state)
{
    scene s;
    scene_def sd = default_scene_def();
    scene_create(*state, &s, &sd);
    // A box-shaped convex hull and a closed box mesh, both static, side by side on the floor.
    const float e = 0.05f;
    phys_vec3 corners[8];
    for (int k = 0; k < 8; k++)
        corners[k] = (phys_vec3){ (k & 1) ? e : -e, (k & 2) ? e : -e, (k & 4) ? e : -e };
    phys_convex_hull hull = { corners, 8 };
    phys_shape_id hull_shape, mesh_shape;
    assert_ok_phys(phys_shape_create_convex_hull(s.phys, &hull, &hull_shape));
    // 12 triangles, counter-clockwise seen from outside.
    static const uint32_t idx[36] = { 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
                                      2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5 };
    phys_triangle_mesh mesh = { corners, 8, idx, 12 };
    assert_ok_phys(phys_shape_create_triangle_mesh(s.phys, &mesh, &mesh_shape));
    const float at[2][3] = { { 0.1f, e, 0.2f }, { 0.3f, e, 0.2f } };
    phys_shape_id shapes[2] = { hull_shape, mesh_shape };
    for (int b = 0; b < 2; b++) {
        phys_body_def bd = phys_default_body_def();
        bd.type = PHYS_BODY_STATIC;
        bd.shape = shapes[b];
        bd.position = (phys_vec3){ at[b][0], at[b][1], at[b][2] };
        phys_body_id body;
        assert_ok_phys(phys_body_create(s.phys, &bd, &body));
        if (cpl_add_body(s.cpl, body, NULL) != CPL_OK) fail_msg("cpl_add_body: %s", cpl_last_error(s.cpl));
    }
    // Water falls onto both from above.
    fill_water(&s, 0.30f, NULL, NULL, 0.16f);
    scene_step(&s, 60);
    particles ps = read_particles(&s);
    const float half[3] = { e, e, e };
    phys_quat q = { 0, 0, 0, 1 };
    uint32_t inside[2] = { 0, 0 };
    for (uint32_t i = 0; i < ps.n; i++)
        for (int b = 0; b < 2; b++)
            if (box_distance(half, (phys_vec3){ at[b][0], at[b][1], at[b][2] }, q, ps.pos + 4 * i) < 0.0f) {
                if (verbose() && inside[b] < 5)
                    printf("  inside %d: %.4f %.4f %.4f\n", b, (double)ps.pos[4 * i], (double)ps.pos[4 * i + 1],
                           (double)ps.pos[4 * i + 2]);
                inside[b]++;
            }
    if (verbose())
        printf("hull / mesh: %u / %u particles inside after 1 s, %.1f s\n", inside[0], inside[1], now_s() - s.t0);
    assert_int_equal(inside[0], 0);
    assert_int_equal(inside[1], 0);
    free_particles(&ps);
    scene_destroy(&s);
}

// ---- input checks -----------------------------------------------------------------------------

#define assert_contains(text, part)                                                            \
    do {                                                                                       \
        const char *t_ = (text);                                                               \
        if (!strstr(t_, (part))) fail_msg("\"%s\" does not name \"%s\"", t_, (part));          \
    } while (0)

static void bad_input_is_rejected_with_the_field_named(void **state)
{
    scene s;
    scene_def sd = default_scene_def();
    scene_create(*state, &s, &sd);
    phys_box box = { { 0.05f, 0.05f, 0.05f } };
    phys_shape_id shape;
    assert_ok_phys(phys_shape_create_box(s.phys, &box, &shape));
    // Negative mass.
    phys_body_def bd = phys_default_body_def();
    bd.shape = shape;
    bd.mass = -1.0f;
    phys_body_id body;
    assert_int_equal(phys_body_create(s.phys, &bd, &body), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(s.phys), "mass");
    // Zero-size box.
    phys_box flat = { { 0.05f, 0.0f, 0.05f } };
    assert_int_equal(phys_shape_create_box(s.phys, &flat, &shape), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(s.phys), "half_extents.y");
    // A stale body id.
    bd.mass = 1.0f;
    assert_ok_phys(phys_shape_create_box(s.phys, &box, &shape));
    bd.shape = shape;
    assert_ok_phys(phys_body_create(s.phys, &bd, &body));
    assert_int_equal(cpl_add_body(s.cpl, body, NULL), CPL_OK);
    assert_ok_phys(phys_body_destroy(s.phys, body));
    assert_int_equal(cpl_add_body(s.cpl, body, NULL), CPL_ERR_STALE_ID);
    assert_contains(cpl_last_error(s.cpl), "destroyed body");
    assert_int_equal(cpl_teleport_body(s.cpl, body, (phys_vec3){ 0, 0, 0 }, (phys_quat){ 0, 0, 0, 1 }), CPL_ERR_STALE_ID);
    scene_step(&s, 1); // uncouples it (and removes its collider)
    assert_int_equal(cpl_body_count(s.cpl), 0);
    assert_int_equal(cpl_remove_body(s.cpl, body), CPL_ERR_STALE_ID);
    assert_contains(cpl_last_error(s.cpl), "not coupled");
    // NaN poses, in the coupling and in the fluid's collider API.
    assert_ok_phys(phys_body_create(s.phys, &bd, &body));
    assert_int_equal(cpl_add_body(s.cpl, body, NULL), CPL_OK);
    assert_int_equal(cpl_teleport_body(s.cpl, body, (phys_vec3){ NAN, 0, 0 }, (phys_quat){ 0, 0, 0, 1 }),
                     CPL_ERR_INVALID_ARG);
    assert_contains(cpl_last_error(s.cpl), "position.x");
    assert_int_equal(cpl_teleport_body(s.cpl, body, (phys_vec3){ 0, 0, 0 }, (phys_quat){ 0, 0, NAN, 1 }),
                     CPL_ERR_INVALID_ARG);
    assert_contains(cpl_last_error(s.cpl), "orientation.z");
    pbf_collider_id id;
    assert_int_equal(cpl_body_collider(s.cpl, body, &id), CPL_OK);
    const float bad[3] = { 0.0f, NAN, 0.0f }, q[4] = { 0, 0, 0, 1 };
    assert_int_equal(pbf_world_set_collider_pose(s.fluid, id, bad, q, NULL, NULL, NULL), PBF_ERR_INVALID_ARG);
    assert_contains(pbf_world_last_error(s.fluid), "position");
    // Collider definitions.
    pbf_collider_def cd = pbf_default_collider_def();
    cd.size[1] = 0.0f;
    assert_int_equal(pbf_world_add_collider(s.fluid, &cd, &id), PBF_ERR_INVALID_ARG);
    assert_contains(pbf_world_last_error(s.fluid), "size[1]");
    cd = pbf_default_collider_def();
    cd.type = PBF_SHAPE_CONVEX_HULL;
    const float planes[8] = { 1, 0, 0, 0.1f, -1, 0, 0, 0.1f };
    cd.planes = planes;
    cd.plane_count = 2;
    assert_int_equal(pbf_world_add_collider(s.fluid, &cd, &id), PBF_ERR_INVALID_ARG);
    assert_contains(pbf_world_last_error(s.fluid), "plane_count");
    // Coupling settings.
    cpl_def def = cpl_default_def();
    def.phys = s.phys;
    def.fluid = s.fluid;
    def.force_latency = 0;
    char err[256];
    assert_null(cpl_create(&def, err, sizeof err));
    assert_contains(err, "force_latency");
    def = cpl_default_def();
    def.phys = s.phys;
    assert_null(cpl_create(&def, err, sizeof err));
    assert_contains(err, "cpl_def.fluid");
    scene_destroy(&s);
}

// ---- a paddle wheel: a compound body on a fixed axle ------------------------------------------

#define WHEEL_PADDLES 6
static const float WHEEL_AT[3] = { 0.20f, 0.22f, 0.20f };
static const float PADDLE_HALF[3] = { 0.05f, 0.01f, 0.06f }; // radial, thickness, along the axle
#define PADDLE_R 0.08f                                          // hub axis to paddle centre, m

// A hub (cylinder along z, r 3 cm) and six paddles, density 500 kg/m^3, on an axle along
// world z: linear factor 0, angular factor (0, 0, 1).
static phys_body_id add_wheel(scene *s)
{
    phys_compound_part parts[1 + WHEEL_PADDLES];
    memset(parts, 0, sizeof parts);
    const float c45 = 0.70710678f;
    parts[0].type = PHYS_SHAPE_CYLINDER;
    parts[0].cylinder.radius = 0.03f;
    parts[0].cylinder.half_height = 0.06f;
    parts[0].rotation = (phys_quat){ c45, 0, 0, c45 }; // local y onto z
    for (int k = 0; k < WHEEL_PADDLES; k++) {
        float a = (float)k * 2.0f * 3.14159265f / WHEEL_PADDLES;
        phys_compound_part *p = &parts[1 + k];
        p->type = PHYS_SHAPE_BOX;
        p->box.half_extents = (phys_vec3){ PADDLE_HALF[0], PADDLE_HALF[1], PADDLE_HALF[2] };
        p->position = (phys_vec3){ PADDLE_R * cosf(a), PADDLE_R * sinf(a), 0.0f };
        p->rotation = (phys_quat){ 0, 0, sinf(0.5f * a), cosf(0.5f * a) };
    }
    phys_compound c = { parts, 1 + WHEEL_PADDLES };
    phys_shape_id shape;
    assert_ok_phys(phys_shape_create_compound(s->phys, &c, &shape));
    // Symmetric about its hub: the parts frame is the body frame (centre of mass at the hub
    // centre, the parts' axes kept although any axes in the wheel's plane are principal).
    phys_shape_desc d;
    assert_ok_phys(phys_shape_get_desc(s->phys, shape, &d));
    assert_true(fabsf(d.compound.frame_origin.x) < 1e-6f && fabsf(d.compound.frame_origin.y) < 1e-6f);
    assert_true(d.compound.frame_rotation.w == 1.0f);
    phys_body_def bd = phys_default_body_def();
    bd.shape = shape;
    bd.position = (phys_vec3){ WHEEL_AT[0], WHEEL_AT[1], WHEEL_AT[2] };
    bd.density = 500.0f;
    bd.angular_damping = 0.9f; // the mill's load: 90 % of the spin taken away per second
    bd.allow_sleep = false;
    phys_body_id body;
    assert_ok_phys(phys_body_create(s->phys, &bd, &body));
    assert_ok_phys(phys_body_set_linear_factor(s->phys, body, (phys_vec3){ 0, 0, 0 }));
    assert_ok_phys(phys_body_set_angular_factor(s->phys, body, (phys_vec3){ 0, 0, 1 }));
    if (cpl_add_body(s->cpl, body, NULL) != CPL_OK) fail_msg("cpl_add_body: %s", cpl_last_error(s->cpl));
    return body;
}

static void paddle_wheel_under_a_stream_turns_the_way_the_water_pushes(void **state)
{
    fixture *f = *state;
    scene s;
    scene_def sd = default_scene_def();
    sd.tank_height = 0.5f;
    scene_create(f, &s, &sd);
    phys_body_id wheel = add_wheel(&s);
    assert_int_equal(cpl_body_count(s.cpl), 1);
    // Water poured straight down onto the paddles on the +x side, 0.1 m from the axle; a
    // sink on the floor keeps the particle count bounded.
    pbf_emitter_def e = pbf_default_emitter_def();
    const float pos[3] = { WHEEL_AT[0] + 0.10f, 0.44f, WHEEL_AT[2] }, dir[3] = { 0, -1, 0 };
    memcpy(e.position, pos, sizeof pos);
    memcpy(e.direction, dir, sizeof dir);
    e.speed = 2.0f;
    e.radius = 0.03f;
    e.rate = 0.9f * pbf_emitter_max_rate(s.fluid, e.speed, e.radius);
    e.enabled = true;
    pbf_emitter_id em;
    if (pbf_world_add_emitter(s.fluid, &e, &em) != PBF_OK) fail_msg("%s", pbf_world_last_error(s.fluid));
    const float smin[3] = { -0.1f, -0.1f, -0.1f }, smax[3] = { 0.5f, 0.04f, 0.5f };
    pbf_sink_id sink;
    assert_int_equal(pbf_world_add_sink(s.fluid, smin, smax, &sink), PBF_OK);

    scene_step(&s, 90);
    phys_vec3 w, p;
    phys_quat q;
    assert_ok_phys(phys_body_get_angular_velocity(s.phys, wheel, &w));
    assert_ok_phys(phys_body_get_pose(s.phys, wheel, &p, &q));
    cpl_body_stats st;
    assert_int_equal(cpl_body_get_stats(s.cpl, wheel, &st), CPL_OK);
    // Inside: particle centres inside the hub's bounding box or a paddle at the end.
    particles ps = read_particles(&s);
    uint32_t inside = 0;
    for (int k = 0; k < WHEEL_PADDLES; k++) {
        float a = (float)k * 2.0f * 3.14159265f / WHEEL_PADDLES;
        const phys_quat lq = { 0, 0, sinf(0.5f * a), cosf(0.5f * a) };
        const float lp[3] = { PADDLE_R * cosf(a), PADDLE_R * sinf(a), 0.0f };
        float wp[3];
        quat_rotate(q, lp, wp);
        phys_vec3 cp = { p.x + wp[0], p.y + wp[1], p.z + wp[2] };
        phys_quat cq = { q.w * lq.x + q.x * lq.w + q.y * lq.z - q.z * lq.y, q.w * lq.y - q.x * lq.z + q.y * lq.w + q.z * lq.x,
                         q.w * lq.z + q.x * lq.y - q.y * lq.x + q.z * lq.w, q.w * lq.w - q.x * lq.x - q.y * lq.y - q.z * lq.z };
        for (uint32_t i = 0; i < ps.n; i++) {
            float d = box_distance(PADDLE_HALF, cp, cq, ps.pos + 4 * i);
            if (d < 0.0f) {
                inside++;
                if (verbose()) printf("  inside paddle %d by %.4f m\n", k, (double)-d);
            }
        }
    }
    if (verbose())
        printf("wheel: w = (%.4f, %.4f, %.4f) rad/s after 1.5 s, torque z %.4f N m, %u particles, %u inside paddles, "
               "centre (%.4f, %.4f, %.4f), %.1f s\n", (double)w.x, (double)w.y, (double)w.z, (double)st.torque[2], ps.n,
               inside, (double)p.x, (double)p.y, (double)p.z, now_s() - s.t0);
    free_particles(&ps);
    // Falling water on the +x paddles pushes them down: r x F = (+x) x (-y) = -z.
    assert_true(w.z < -1.0f);
    assert_true(w.z > -60.0f);
    assert_true(fabsf(w.x) < 1e-4f && fabsf(w.y) < 1e-4f);
    // The axle holds: the centre does not move.
    assert_true(fabsf(p.x - WHEEL_AT[0]) < 1e-4f && fabsf(p.y - WHEEL_AT[1]) < 1e-4f && fabsf(p.z - WHEEL_AT[2]) < 1e-4f);
    assert_int_equal(inside, 0);
    scene_destroy(&s);
}

static void paddle_wheel_without_water_stays_still(void **state)
{
    fixture *f = *state;
    scene s;
    scene_def sd = default_scene_def();
    sd.tank_height = 0.5f;
    scene_create(f, &s, &sd);
    phys_body_id wheel = add_wheel(&s);
    scene_step(&s, 60);
    phys_vec3 w, p;
    assert_ok_phys(phys_body_get_angular_velocity(s.phys, wheel, &w));
    assert_ok_phys(phys_body_get_pose(s.phys, wheel, &p, NULL));
    if (verbose()) printf("still wheel: w = (%g, %g, %g) rad/s\n", (double)w.x, (double)w.y, (double)w.z);
    assert_true(fabsf(w.x) + fabsf(w.y) + fabsf(w.z) < 1e-3f);
    assert_true(fabsf(p.y - WHEEL_AT[1]) < 1e-5f);
    scene_destroy(&s);
}

static void compound_beyond_the_collider_limit_is_refused(void **state)
{
    fixture *f = *state;
    scene s;
    scene_def sd = default_scene_def();
    scene_create(f, &s, &sd);
    enum { PARTS = 65 };
    phys_compound_part parts[PARTS];
    memset(parts, 0, sizeof parts);
    for (int k = 0; k < PARTS; k++) {
        parts[k].type = PHYS_SHAPE_SPHERE;
        parts[k].sphere.radius = 0.01f;
        parts[k].position = (phys_vec3){ 0.02f * (float)k, 0, 0 };
        parts[k].rotation = (phys_quat){ 0, 0, 0, 1 };
    }
    phys_compound c = { parts, PARTS };
    phys_shape_id shape;
    assert_ok_phys(phys_shape_create_compound(s.phys, &c, &shape));
    phys_body_def bd = phys_default_body_def();
    bd.shape = shape;
    bd.position = (phys_vec3){ 0.2f, 0.2f, 0.2f };
    phys_body_id body;
    assert_ok_phys(phys_body_create(s.phys, &bd, &body));
    assert_int_equal(cpl_add_body(s.cpl, body, NULL), CPL_ERR_CAPACITY);
    assert_contains(cpl_last_error(s.cpl), "compound of 65 parts, which needs 65 fluid colliders");
    assert_int_equal(cpl_body_count(s.cpl), 0);
    scene_destroy(&s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(box_of_250_floats_a_quarter_submerged),
        cmocka_unit_test(box_of_500_floats_half_submerged),
        cmocka_unit_test(box_of_750_floats_three_quarters_submerged),
        cmocka_unit_test(ball_denser_than_water_sinks_and_rests_on_the_bottom),
        cmocka_unit_test(light_box_hitting_water_does_not_gain_energy),
        cmocka_unit_test(thrown_thin_box_does_not_tunnel_through_water),
        cmocka_unit_test(fast_thin_kinematic_wall_lets_no_water_through),
        cmocka_unit_test(water_that_starts_inside_a_body_is_pushed_out_gently),
        cmocka_unit_test(hull_and_mesh_bodies_keep_water_out),
        cmocka_unit_test(bad_input_is_rejected_with_the_field_named),
        cmocka_unit_test(paddle_wheel_under_a_stream_turns_the_way_the_water_pushes),
        cmocka_unit_test(paddle_wheel_without_water_stays_still),
        cmocka_unit_test(compound_beyond_the_collider_limit_is_refused),
    };
    const char *filter = getenv("SEICHE_TEST_FILTER"); // e.g. "*750*"
    if (filter && *filter) cmocka_set_test_filter(filter);
    return cmocka_run_group_tests(tests, setup, teardown);
}
