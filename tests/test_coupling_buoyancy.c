// Bullet bodies in the fluid (fluid/bullet/coupling.h), up and down: boxes float as deep as
// Archimedes says, a dense ball sinks and rests on the bottom, a light box gains no energy.
#include "tests/coupling_fixture.h"

// ---- bodies and free surfaces on the test side ------------------------------------------------

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

/// Free-surface height from mass per area in the columns away from a body footprint
/// [fx0, fx1] x [fz0, fz1] (expanded by 2 h): y = floor + particles * spacing^3 / area. This
/// is the level that sets the hydrostatic pressure, whatever the compression.
static float free_surface(const scene *s, const particles *p, const float foot_lo[2], const float foot_hi[2])
{
    // The particles' volume at the density the solver holds them (its mean, GPU-reduced):
    // with 2 iterations x 4 substeps and sor 0.6 an 8-layer tank sits about 1 % over rho0,
    // and N s^3 alone would put the level that much above the water (docs/validation.md).
    float squeeze = RHO0 / s->last.density_avg;
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
    return s->tank_min[1] + (float)count * SPACING * SPACING * SPACING * squeeze / area;
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(box_of_250_floats_a_quarter_submerged),
        cmocka_unit_test(box_of_500_floats_half_submerged),
        cmocka_unit_test(box_of_750_floats_three_quarters_submerged),
        cmocka_unit_test(ball_denser_than_water_sinks_and_rests_on_the_bottom),
        cmocka_unit_test(light_box_hitting_water_does_not_gain_energy),
    };
    const char *filter = getenv("SEICHE_TEST_FILTER"); // e.g. "*750*"
    if (filter && *filter) cmocka_set_test_filter(filter);
    return cmocka_run_group_tests(tests, setup, teardown);
}
