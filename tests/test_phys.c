// Tests of the Bullet C API wrapper (fluid/bullet/phys.h).
//
// Each test builds a small world, runs it, and checks one behaviour against a
// number worked out by hand (in the comment next to it).

#include <malloc.h>
#include <math.h>
#include <pthread.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "fluid/bullet/phys.h"

#define G 9.81
#define PI 3.14159265358979323846

// ---- helpers ------------------------------------------------------------------

#define assert_near(got, want, tol)                                                     \
    do {                                                                                \
        const double got_ = (double)(got), want_ = (double)(want), tol_ = (double)(tol); \
        if (!(fabs(got_ - want_) <= tol_)) {                                            \
            fail_msg("%s = %.9g, expected %.9g within %g", #got, got_, want_, tol_);    \
        }                                                                               \
    } while (0)

#define assert_contains(text, part)                                                 \
    do {                                                                            \
        const char *text_ = (text);                                                 \
        if (!strstr(text_, (part))) fail_msg("\"%s\" does not contain \"%s\"", text_, (part)); \
    } while (0)

#define assert_ok(expr)                                                             \
    do {                                                                            \
        const phys_result r_ = (expr);                                              \
        if (r_ != PHYS_OK) fail_msg("%s returned %s", #expr, phys_result_string(r_)); \
    } while (0)

typedef struct fixture {
    phys_world *world;
    char log[1024];   // last message given to the log callback
    int log_count;
} fixture;

static void capture_log(void *user, phys_log_level level, const char *message) {
    fixture *f = user;
    (void)level;
    snprintf(f->log, sizeof f->log, "%s", message);
    f->log_count++;
}

static int setup(void **state) {
    fixture *f = calloc(1, sizeof *f);
    if (!f) return -1;
    phys_world_def def = phys_default_world_def();
    def.log = capture_log;
    def.log_user = f;
    if (phys_world_create(&def, &f->world) != PHYS_OK) {
        free(f);
        return -1;
    }
    *state = f;
    return 0;
}

static int teardown(void **state) {
    fixture *f = *state;
    phys_world_destroy(f->world);
    free(f);
    return 0;
}

static const phys_vec3 zero3 = {0, 0, 0};
static const phys_quat identity = {0, 0, 0, 1};

static phys_vec3 v3(float x, float y, float z) {
    phys_vec3 v = {x, y, z};
    return v;
}

static phys_shape_id make_sphere(phys_world *w, float radius) {
    phys_sphere s = {radius};
    phys_shape_id id = {0, 0, 0};
    assert_ok(phys_shape_create_sphere(w, &s, &id));
    return id;
}

static phys_shape_id make_box(phys_world *w, float hx, float hy, float hz) {
    phys_box b = {{hx, hy, hz}};
    phys_shape_id id = {0, 0, 0};
    assert_ok(phys_shape_create_box(w, &b, &id));
    return id;
}

// Ground plane y = 0 on a static body.
static phys_body_id make_ground(phys_world *w) {
    phys_plane p = {{0, 1, 0}, 0};
    phys_shape_id shape = {0, 0, 0};
    assert_ok(phys_shape_create_plane(w, &p, &shape));
    phys_body_def def = phys_default_body_def();
    def.type = PHYS_BODY_STATIC;
    def.shape = shape;
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(w, &def, &id));
    return id;
}

static phys_body_id make_body(phys_world *w, phys_body_type type, phys_shape_id shape,
                              phys_vec3 position) {
    phys_body_def def = phys_default_body_def();
    def.type = type;
    def.shape = shape;
    def.position = position;
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(w, &def, &id));
    return id;
}

static phys_vec3 position_of(phys_world *w, phys_body_id id) {
    phys_vec3 p = zero3;
    assert_ok(phys_body_get_pose(w, id, &p, NULL));
    return p;
}

static phys_vec3 velocity_of(phys_world *w, phys_body_id id) {
    phys_vec3 v = zero3;
    assert_ok(phys_body_get_linear_velocity(w, id, &v));
    return v;
}

static void run(phys_world *w, float dt, int steps) {
    for (int i = 0; i < steps; ++i) assert_ok(phys_world_step(w, dt));
}

// ---- defaults ---------------------------------------------------------------

static void test_defaults_are_the_documented_values(void **state) {
    (void)state;
    phys_world_def wd = phys_default_world_def();
    assert_near(wd.gravity.x, 0, 0);
    assert_near(wd.gravity.y, -9.81f, 0);
    assert_near(wd.gravity.z, 0, 0);
    assert_int_equal(wd.solver_iterations, 10);
    assert_near(wd.collision_margin, 0.04f, 0);
    assert_null(wd.log);

    phys_body_def bd = phys_default_body_def();
    assert_int_equal(bd.type, PHYS_BODY_DYNAMIC);
    assert_int_equal(bd.shape.index1, 0);
    assert_near(bd.orientation.w, 1, 0);
    assert_near(bd.mass, 0, 0);
    assert_near(bd.density, 1000, 0);
    assert_near(bd.friction, 0.5f, 0);
    assert_true(bd.allow_sleep);
}

// ---- stepping and gravity ---------------------------------------------------------

static void test_dropped_sphere_falls_with_g(void **state) {
    fixture *f = *state;
    phys_body_id ball = make_body(f->world, PHYS_BODY_DYNAMIC, make_sphere(f->world, 0.1f),
                                  v3(1, 10, 2));
    const float dt = 1.0f / 240.0f;
    const int n = 240;
    run(f->world, dt, n);
    const double t = n * (double)dt;
    phys_vec3 p = position_of(f->world, ball);
    // Analytic free fall, y = y0 - g t²/2, up to the O(dt) error of any
    // first-order integrator: |error| <= g dt t / 2.
    assert_near(p.y, 10.0 - 0.5 * G * t * t, 0.5 * G * dt * t + 1e-4);
    // Bullet's semi-implicit Euler exactly: after n steps the drop is g dt² n(n+1)/2.
    assert_near(p.y, 10.0 - G * dt * dt * n * (n + 1) / 2.0, 2e-4);
    assert_near(p.x, 1, 1e-6);
    assert_near(p.z, 2, 1e-6);
    assert_near(velocity_of(f->world, ball).y, -G * t, 1e-4);
}

static void test_each_step_is_exactly_one_internal_step_of_dt(void **state) {
    fixture *f = *state;
    phys_body_id ball = make_body(f->world, PHYS_BODY_DYNAMIC, make_sphere(f->world, 0.1f),
                                  v3(0, 10, 0));
    // No accumulator: a step of 1/60 then one of 1/1000 give exactly
    // two velocity updates, v = -g (1/60 + 1/1000).
    assert_ok(phys_world_step(f->world, 1.0f / 60.0f));
    assert_near(velocity_of(f->world, ball).y, -G / 60.0, 1e-5);
    assert_ok(phys_world_step(f->world, 1.0f / 1000.0f));
    assert_near(velocity_of(f->world, ball).y, -G * (1.0 / 60.0 + 1.0 / 1000.0), 1e-5);
}

static void test_box_comes_to_rest_on_plane_at_its_half_height(void **state) {
    fixture *f = *state;
    make_ground(f->world);
    phys_body_id box = make_body(f->world, PHYS_BODY_DYNAMIC, make_box(f->world, 0.5f, 0.25f, 0.5f),
                                 v3(0, 1, 0));
    run(f->world, 1.0f / 120.0f, 360);
    phys_vec3 p;
    phys_quat q;
    assert_ok(phys_body_get_pose(f->world, box, &p, &q));
    assert_near(p.y, 0.25, 0.01);
    assert_near(p.x, 0, 0.02);  // Bullet's box-plane contacts let it slide a few mm on landing
    assert_near(fabs(q.w), 1, 1e-3);  // landed flat, did not tip
    phys_vec3 v = velocity_of(f->world, box);
    assert_near(sqrt(v.x * v.x + v.y * v.y + v.z * v.z), 0, 0.01);
}

// ---- kinematic bodies ------------------------------------------------------------

static void test_kinematic_target_moves_body_and_it_pushes_a_dynamic_body(void **state) {
    fixture *f = *state;
    assert_ok(phys_world_set_gravity(f->world, zero3));
    phys_body_id pusher = make_body(f->world, PHYS_BODY_KINEMATIC,
                                    make_box(f->world, 0.5f, 0.5f, 0.5f), v3(0, 0, 0));
    phys_body_id ball = make_body(f->world, PHYS_BODY_DYNAMIC, make_sphere(f->world, 0.5f),
                                  v3(1.5f, 0, 0));
    const float dt = 1.0f / 60.0f;
    for (int i = 1; i <= 60; ++i) {
        phys_vec3 target = v3(i * dt * 1.0f, 0, 0);  // 1 m/s along +x
        assert_ok(phys_body_set_kinematic_target(f->world, pusher, target, identity));
        assert_ok(phys_world_step(f->world, dt));
        assert_near(position_of(f->world, pusher).x, target.x, 1e-5);
    }
    assert_near(velocity_of(f->world, pusher).x, 1.0, 1e-3);
    // The pusher's face reached x = 1.5 after 1 s; the ball (left face at 1.0)
    // was hit after 0.5 s and must be ahead of the face, moving at >= 1 m/s.
    phys_vec3 p = position_of(f->world, ball);
    assert_true(p.x >= 1.5f + 0.5f - 0.02f);
    assert_true(velocity_of(f->world, ball).x >= 0.9f);
}

static void test_kinematic_target_derives_velocity_for_one_step_then_stops(void **state) {
    fixture *f = *state;
    phys_body_id k = make_body(f->world, PHYS_BODY_KINEMATIC, make_box(f->world, 0.5f, 0.5f, 0.5f),
                               v3(0, 0, 0));
    // 90° about +y: q = (0, sin 45°, 0, cos 45°).
    const float s = (float)sqrt(0.5);
    phys_quat quarter = {0, s, 0, s};
    assert_ok(phys_body_set_kinematic_target(f->world, k, v3(0.1f, 0, 0), quarter));
    phys_vec3 before = position_of(f->world, k);
    assert_near(before.x, 0, 0);  // the target is reached during the step, not before
    assert_ok(phys_world_step(f->world, 0.5f));
    phys_vec3 w = zero3;
    assert_ok(phys_body_get_angular_velocity(f->world, k, &w));
    assert_near(velocity_of(f->world, k).x, 0.2, 1e-5);  // 0.1 m in 0.5 s
    assert_near(w.y, PI, 1e-4);                         // π/2 rad in 0.5 s
    phys_quat q;
    assert_ok(phys_body_get_pose(f->world, k, NULL, &q));
    assert_near(fabs(q.y), s, 1e-5);
    // No new target: it stays put, with zero velocity.
    assert_ok(phys_world_step(f->world, 0.5f));
    assert_near(position_of(f->world, k).x, 0.1, 1e-6);
    assert_near(velocity_of(f->world, k).x, 0, 1e-6);
}

static void test_kinematic_velocity_moves_body_steadily(void **state) {
    fixture *f = *state;
    phys_body_id k = make_body(f->world, PHYS_BODY_KINEMATIC, make_sphere(f->world, 0.5f),
                               v3(0, 0, 0));
    assert_ok(phys_body_set_linear_velocity(f->world, k, v3(2, 0, 0)));
    run(f->world, 0.1f, 10);
    assert_near(position_of(f->world, k).x, 2.0, 1e-4);  // 2 m/s for 1 s
    assert_near(position_of(f->world, k).y, 0.0, 1e-6);  // gravity does not act on it
}

// ---- forces and impulses -------------------------------------------------------------

static phys_body_id make_weightless_sphere(fixture *f, float mass) {
    assert_ok(phys_world_set_gravity(f->world, zero3));
    phys_body_def def = phys_default_body_def();
    def.shape = make_sphere(f->world, 0.25f);
    def.mass = mass;
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(f->world, &def, &id));
    return id;
}

static void test_force_changes_velocity_by_f_over_m_dt_for_one_step_only(void **state) {
    fixture *f = *state;
    phys_body_id b = make_weightless_sphere(f, 2.0f);
    const float dt = 0.01f;
    assert_ok(phys_body_apply_force(f->world, b, v3(4, 0, -6), true));
    assert_ok(phys_world_step(f->world, dt));
    // Δv = F/m dt = (2, 0, -3) × 0.01.
    phys_vec3 v = velocity_of(f->world, b);
    assert_near(v.x, 0.02, 1e-6);
    assert_near(v.z, -0.03, 1e-6);
    // The force was cleared after the step: the next step leaves v alone.
    assert_ok(phys_world_step(f->world, dt));
    v = velocity_of(f->world, b);
    assert_near(v.x, 0.02, 1e-6);
    assert_near(v.z, -0.03, 1e-6);
}

static void test_impulse_changes_velocity_by_j_over_m_at_once(void **state) {
    fixture *f = *state;
    phys_body_id b = make_weightless_sphere(f, 2.0f);
    assert_ok(phys_body_apply_impulse(f->world, b, v3(0, 3, 0), true));
    assert_near(velocity_of(f->world, b).y, 1.5, 1e-6);  // 3 N·s / 2 kg
}

// A cube of side 1 m and mass 6 kg has I = m (1² + 1²) / 12 = 1 kg·m² on every axis.
static phys_body_id make_unit_inertia_cube(fixture *f) {
    assert_ok(phys_world_set_gravity(f->world, zero3));
    phys_body_def def = phys_default_body_def();
    def.shape = make_box(f->world, 0.5f, 0.5f, 0.5f);
    def.mass = 6.0f;
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(f->world, &def, &id));
    return id;
}

static void test_mass_data_reports_mass_and_inverse_inertia(void **state) {
    fixture *f = *state;
    phys_body_id cube = make_unit_inertia_cube(f);
    phys_mass_data m;
    assert_ok(phys_body_get_mass_data(f->world, cube, &m));
    assert_near(m.mass, 6, 1e-5);
    assert_near(m.inv_mass, 1.0 / 6.0, 1e-6);
    assert_near(m.inertia_local.x, 1, 1e-5);
    assert_near(m.inertia_local.z, 1, 1e-5);
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) assert_near(m.inv_inertia_world[r * 3 + c], r == c, 1e-5);
    }
    phys_body_id wall = make_body(f->world, PHYS_BODY_STATIC, make_sphere(f->world, 1), v3(0, 5, 0));
    assert_ok(phys_body_get_mass_data(f->world, wall, &m));
    assert_near(m.mass, 0, 0);
    assert_near(m.inv_mass, 0, 0);
    assert_near(m.center_of_mass.y, 5, 0);
}

static void test_impulse_at_point_spins_body_by_inverse_inertia(void **state) {
    fixture *f = *state;
    phys_body_id cube = make_unit_inertia_cube(f);
    // J = (0, 0, 1) N·s at r = (0.5, 0, 0): Δv = J/m, Δω = I⁻¹ (r × J) = (0, -0.5, 0).
    assert_ok(phys_body_apply_impulse_at_point(f->world, cube, v3(0, 0, 1), v3(0.5f, 0, 0), true));
    phys_vec3 w = zero3;
    assert_ok(phys_body_get_angular_velocity(f->world, cube, &w));
    assert_near(velocity_of(f->world, cube).z, 1.0 / 6.0, 1e-6);
    assert_near(w.x, 0, 1e-6);
    assert_near(w.y, -0.5, 1e-5);
    assert_near(w.z, 0, 1e-6);
}

static void test_torque_changes_angular_velocity_for_one_step(void **state) {
    fixture *f = *state;
    phys_body_id cube = make_unit_inertia_cube(f);
    assert_ok(phys_body_apply_torque(f->world, cube, v3(0, 0, 2), true));
    assert_ok(phys_world_step(f->world, 0.01f));
    phys_vec3 w = zero3;
    assert_ok(phys_body_get_angular_velocity(f->world, cube, &w));
    assert_near(w.z, 0.02, 1e-5);  // τ / I × dt
    assert_ok(phys_world_step(f->world, 0.01f));
    assert_ok(phys_body_get_angular_velocity(f->world, cube, &w));
    assert_near(w.z, 0.02, 1e-5);
}

static void test_force_at_point_adds_torque_about_centre_of_mass(void **state) {
    fixture *f = *state;
    phys_body_id cube = make_unit_inertia_cube(f);
    // F = (0, 6, 0) N at r = (0.5, 0, 0): a = 1 m/s², α = r × F / I = (0, 0, 3).
    assert_ok(phys_body_apply_force_at_point(f->world, cube, v3(0, 6, 0), v3(0.5f, 0, 0), true));
    assert_ok(phys_world_step(f->world, 0.01f));
    phys_vec3 w = zero3;
    assert_ok(phys_body_get_angular_velocity(f->world, cube, &w));
    assert_near(velocity_of(f->world, cube).y, 0.01, 1e-6);
    assert_near(w.z, 0.03, 1e-5);
}

static void test_velocity_at_point_includes_spin(void **state) {
    fixture *f = *state;
    phys_body_id b = make_weightless_sphere(f, 1.0f);
    assert_ok(phys_body_set_linear_velocity(f->world, b, v3(1, 0, 0)));
    assert_ok(phys_body_set_angular_velocity(f->world, b, v3(0, 0, 1)));
    // v + ω × r with r = (0, 1, 0): (1, 0, 0) + (-1, 0, 0) = 0.
    phys_vec3 v = v3(9, 9, 9);
    assert_ok(phys_body_get_velocity_at_point(f->world, b, v3(0, 1, 0), &v));
    assert_near(v.x, 0, 1e-6);
    assert_near(v.y, 0, 1e-6);
    // At r = (0, -1, 0): (1, 0, 0) + (1, 0, 0).
    assert_ok(phys_body_get_velocity_at_point(f->world, b, v3(0, -1, 0), &v));
    assert_near(v.x, 2, 1e-6);
}

// ---- sleeping -----------------------------------------------------------------------

static void test_sleeping_body_wakes_only_when_asked(void **state) {
    fixture *f = *state;
    make_ground(f->world);
    phys_body_id ball = make_body(f->world, PHYS_BODY_DYNAMIC, make_sphere(f->world, 0.2f),
                                  v3(0, 0.2f, 0));
    run(f->world, 1.0f / 60.0f, 240);  // Bullet sleeps bodies that rested for 2 s
    bool awake = true;
    assert_ok(phys_body_is_awake(f->world, ball, &awake));
    assert_false(awake);
    // wake = false: no effect on a sleeping body.
    assert_ok(phys_body_apply_impulse(f->world, ball, v3(1, 0, 0), false));
    assert_near(velocity_of(f->world, ball).x, 0, 0);
    // wake = true: woken and moving.
    assert_ok(phys_body_apply_impulse(f->world, ball, v3(1, 0, 0), true));
    assert_ok(phys_body_is_awake(f->world, ball, &awake));
    assert_true(awake);
    assert_true(velocity_of(f->world, ball).x > 0);
}

static void test_body_with_sleep_disabled_stays_awake(void **state) {
    fixture *f = *state;
    make_ground(f->world);
    phys_body_def def = phys_default_body_def();
    def.shape = make_sphere(f->world, 0.2f);
    def.position = v3(0, 0.2f, 0);
    def.allow_sleep = false;
    phys_body_id ball = {0, 0, 0};
    assert_ok(phys_body_create(f->world, &def, &ball));
    run(f->world, 1.0f / 60.0f, 300);
    bool awake = false;
    assert_ok(phys_body_is_awake(f->world, ball, &awake));
    assert_true(awake);
    // And a body that fell asleep is woken by disabling sleep.
    phys_body_id other = make_body(f->world, PHYS_BODY_DYNAMIC, def.shape, v3(2, 0.2f, 0));
    run(f->world, 1.0f / 60.0f, 240);
    assert_ok(phys_body_is_awake(f->world, other, &awake));
    assert_false(awake);
    assert_ok(phys_body_set_sleep_enabled(f->world, other, false));
    run(f->world, 1.0f / 60.0f, 240);
    assert_ok(phys_body_is_awake(f->world, other, &awake));
    assert_true(awake);
}

// ---- ray cast -------------------------------------------------------------------

static void test_ray_cast_hits_nearest_body_at_right_distance(void **state) {
    fixture *f = *state;
    phys_shape_id s = make_sphere(f->world, 0.5f);
    phys_body_id near_ball = make_body(f->world, PHYS_BODY_STATIC, s, v3(3, 0, 0));
    phys_body_id far_ball = make_body(f->world, PHYS_BODY_STATIC, s, v3(6, 0, 0));
    (void)far_ball;
    phys_ray_hit hit;
    assert_ok(phys_world_ray_cast(f->world, v3(0, 0, 0), v3(10, 0, 0), &hit));
    assert_true(hit.hit);
    assert_memory_equal(&hit.body, &near_ball, sizeof near_ball);
    assert_near(hit.point.x, 2.5, 1e-3);    // sphere surface facing the ray
    assert_near(hit.fraction, 0.25, 1e-4);  // 2.5 m of 10 m
    assert_near(hit.normal.x, -1, 1e-3);

    // A box: its face at x = 8 - 0.5 even though Bullet keeps a margin inside it.
    phys_body_id box = make_body(f->world, PHYS_BODY_DYNAMIC, make_box(f->world, 0.5f, 0.5f, 0.5f),
                                 v3(8, 3, 0));
    assert_ok(phys_world_ray_cast(f->world, v3(0, 3, 0), v3(10, 3, 0), &hit));
    assert_true(hit.hit);
    assert_memory_equal(&hit.body, &box, sizeof box);
    assert_near(hit.point.x, 7.5, 2e-3);

    // A miss is not an error.
    assert_ok(phys_world_ray_cast(f->world, v3(0, 10, 0), v3(10, 10, 0), &hit));
    assert_false(hit.hit);
}

// ---- mass from density ------------------------------------------------------------

static double body_mass(fixture *f, phys_shape_id shape, float density) {
    phys_body_def def = phys_default_body_def();
    def.shape = shape;
    def.density = density;
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(f->world, &def, &id));
    phys_mass_data m;
    assert_ok(phys_body_get_mass_data(f->world, id, &m));
    return m.mass;
}

static void test_density_times_volume_gives_mass(void **state) {
    fixture *f = *state;
    phys_world *w = f->world;
    // Box 1 × 0.5 × 0.2 m = 0.1 m³ at 800 kg/m³.
    assert_near(body_mass(f, make_box(w, 0.5f, 0.25f, 0.1f), 800), 80.0, 80.0 * 1e-5);
    // Sphere r = 0.3: 4/3 π r³ = 0.113097 m³ at 500 kg/m³.
    const double sphere = 4.0 / 3.0 * PI * 0.027;
    assert_near(body_mass(f, make_sphere(w, 0.3f), 500), 500 * sphere, 1e-3);
    // Cylinder r = 0.2, height 1: π r² h = 0.125664 m³.
    phys_cylinder cyl = {0.2f, 0.5f};
    phys_shape_id cyl_id;
    assert_ok(phys_shape_create_cylinder(w, &cyl, &cyl_id));
    assert_near(body_mass(f, cyl_id, 1000), 1000 * PI * 0.04, 1e-3);
    // Capsule r = 0.1, half height 0.3: π r² 0.6 + 4/3 π r³ = 0.0230383 m³.
    phys_capsule cap = {0.1f, 0.3f};
    phys_shape_id cap_id;
    assert_ok(phys_shape_create_capsule(w, &cap, &cap_id));
    const double capsule = PI * 0.01 * 0.6 + 4.0 / 3.0 * PI * 0.001;
    assert_near(body_mass(f, cap_id, 1000), 1000 * capsule, 1e-3);
    float vol = 0;
    assert_ok(phys_shape_get_volume(w, cap_id, &vol));
    assert_near(vol, capsule, 1e-7);
}

static void test_explicit_mass_wins_over_density(void **state) {
    fixture *f = *state;
    phys_body_def def = phys_default_body_def();
    def.shape = make_box(f->world, 1, 1, 1);  // 8 m³: 8000 kg at the default density
    def.mass = 3;
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(f->world, &def, &id));
    phys_mass_data m;
    assert_ok(phys_body_get_mass_data(f->world, id, &m));
    assert_near(m.mass, 3, 1e-6);
}

// ---- hulls and meshes ------------------------------------------------------------

static bool has_point(const phys_vec3 *pts, uint32_t n, phys_vec3 p) {
    for (uint32_t i = 0; i < n; ++i) {
        if (fabsf(pts[i].x - p.x) < 1e-5f && fabsf(pts[i].y - p.y) < 1e-5f &&
            fabsf(pts[i].z - p.z) < 1e-5f) {
            return true;
        }
    }
    return false;
}

static void test_convex_hull_query_returns_points_and_planes(void **state) {
    fixture *f = *state;
    phys_vec3 pts[9];
    int n = 0;
    for (int i = 0; i < 8; ++i) {
        pts[n++] = v3(i & 1 ? 0.5f : -0.5f, i & 2 ? 0.5f : -0.5f, i & 4 ? 0.5f : -0.5f);
    }
    pts[n++] = v3(0.1f, 0, 0);  // inside: dropped
    phys_convex_hull hull = {pts, 9};
    phys_shape_id shape;
    assert_ok(phys_shape_create_convex_hull(f->world, &hull, &shape));

    phys_body_id body = make_body(f->world, PHYS_BODY_DYNAMIC, shape, v3(0, 3, 0));
    phys_shape_desc d;
    assert_ok(phys_body_get_shape(f->world, body, &d));
    assert_int_equal(d.type, PHYS_SHAPE_CONVEX_HULL);
    assert_memory_equal(&d.shape, &shape, sizeof shape);
    assert_near(d.volume, 1.0, 1e-5);
    assert_int_equal(d.hull.point_count, 8);
    for (int i = 0; i < 8; ++i) assert_true(has_point(d.hull.points, d.hull.point_count, pts[i]));
    assert_int_equal(d.hull.plane_count, 6);
    for (uint32_t i = 0; i < d.hull.plane_count; ++i) {
        const phys_hull_plane pl = d.hull.planes[i];
        const double big = fmax(fabs(pl.normal.x), fmax(fabs(pl.normal.y), fabs(pl.normal.z)));
        assert_near(big, 1, 1e-5);           // an axis direction
        assert_near(pl.offset, 0.5, 1e-5);   // outward: the face is 0.5 m out
    }
    phys_mass_data m;
    assert_ok(phys_body_get_mass_data(f->world, body, &m));
    assert_near(m.mass, 1000, 1e-2);  // default density × 1 m³

    // Bullet's hull was shrunk by its margin: hull + margin rests on its real faces.
    make_ground(f->world);
    run(f->world, 1.0f / 120.0f, 360);
    assert_near(position_of(f->world, body).y, 0.5, 0.01);
}

static void test_degenerate_convex_hull_is_rejected(void **state) {
    fixture *f = *state;
    phys_vec3 flat[4] = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {1, 0, 1}};
    phys_convex_hull hull = {flat, 4};
    phys_shape_id shape;
    assert_int_equal(phys_shape_create_convex_hull(f->world, &hull, &shape), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_convex_hull.points must span a volume");
    hull.point_count = 3;
    assert_int_equal(phys_shape_create_convex_hull(f->world, &hull, &shape), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world),
                    "phys_convex_hull.point_count must be in [4, 65536] (got 3)");
}

static void test_triangle_mesh_query_returns_vertices_and_indices(void **state) {
    fixture *f = *state;
    // A 10 × 10 m floor at y = 0, two triangles wound counter-clockwise seen from +y.
    const phys_vec3 verts[4] = {{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}};
    const uint32_t idx[6] = {0, 2, 1, 0, 3, 2};
    phys_triangle_mesh mesh = {verts, 4, idx, 2};
    phys_shape_id shape;
    assert_ok(phys_shape_create_triangle_mesh(f->world, &mesh, &shape));
    phys_body_id floor = make_body(f->world, PHYS_BODY_STATIC, shape, zero3);

    phys_shape_desc d;
    assert_ok(phys_body_get_shape(f->world, floor, &d));
    assert_int_equal(d.type, PHYS_SHAPE_TRIANGLE_MESH);
    assert_int_equal(d.mesh.vertex_count, 4);
    assert_int_equal(d.mesh.triangle_count, 2);
    assert_memory_equal(d.mesh.vertices, verts, sizeof verts);
    assert_memory_equal(d.mesh.indices, idx, sizeof idx);
    assert_true(d.mesh.vertices != verts);  // copied
    assert_near(d.volume, 0, 0);

    phys_ray_hit hit;
    assert_ok(phys_world_ray_cast(f->world, v3(1, 2, 1), v3(1, -2, 1), &hit));
    assert_true(hit.hit);
    assert_memory_equal(&hit.body, &floor, sizeof floor);
    assert_near(hit.point.y, 0, 1e-4);
    assert_near(hit.normal.y, 1, 1e-4);

    phys_body_id box = make_body(f->world, PHYS_BODY_DYNAMIC, make_box(f->world, 0.3f, 0.3f, 0.3f),
                                 v3(1, 1, 1));
    run(f->world, 1.0f / 120.0f, 240);
    assert_near(position_of(f->world, box).y, 0.3, 0.01);
}

// ---- bad input --------------------------------------------------------------------

static void test_negative_mass_is_rejected_naming_the_field(void **state) {
    fixture *f = *state;
    phys_body_def def = phys_default_body_def();
    def.shape = make_sphere(f->world, 1);
    def.mass = -1;
    phys_body_id id = {0, 0, 0};
    assert_int_equal(phys_body_create(f->world, &def, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world),
                    "phys_body_def.mass must be >= 0 and finite (got -1)");
    assert_contains(f->log, "phys_body_def.mass must be >= 0 and finite (got -1)");
    assert_int_equal(f->log_count, 1);
    assert_int_equal(phys_world_get_body_count(f->world), 0);
    def.mass = 0;
    def.density = 0;
    assert_int_equal(phys_body_create(f->world, &def, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_body_def.density must be > 0");
}

static void test_zero_size_box_is_rejected_naming_the_field(void **state) {
    fixture *f = *state;
    phys_box box = {{1, 0, 1}};
    phys_shape_id id = {0, 0, 0};
    assert_int_equal(phys_shape_create_box(f->world, &box, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_box.half_extents.y must be > 0 (got 0)");
    phys_sphere sphere = {NAN};
    assert_int_equal(phys_shape_create_sphere(f->world, &sphere, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_sphere.radius must be finite (got nan)");
    phys_capsule cap = {0.1f, -2};
    assert_int_equal(phys_shape_create_capsule(f->world, &cap, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_capsule.half_height must be > 0 (got -2)");
    phys_plane plane = {{0, 2, 0}, 0};
    assert_int_equal(phys_shape_create_plane(f->world, &plane, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_plane.normal must have unit length");
}

static void test_nan_pose_is_rejected_naming_the_field(void **state) {
    fixture *f = *state;
    phys_body_def def = phys_default_body_def();
    def.shape = make_sphere(f->world, 1);
    def.position.y = NAN;
    phys_body_id id = {0, 0, 0};
    assert_int_equal(phys_body_create(f->world, &def, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_body_def.position.y must be finite (got nan)");

    def.position = v3(1, 2, 3);
    phys_body_id ok = {0, 0, 0};
    assert_ok(phys_body_create(f->world, &def, &ok));
    phys_quat bad = {0, 0, 0, INFINITY};
    assert_int_equal(phys_body_set_pose(f->world, ok, zero3, bad), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_body_set_pose: orientation.w must be finite (got inf)");
    phys_quat half = {0, 0, 0, 0.5f};
    assert_int_equal(phys_body_set_pose(f->world, ok, zero3, half), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "orientation must be a unit quaternion");
    assert_contains(phys_world_last_error(f->world), "(got length 0.5)");
    assert_near(position_of(f->world, ok).y, 2, 0);  // a failed call changes nothing

    assert_int_equal(phys_body_apply_force(f->world, ok, v3(NAN, 0, 0), true), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "force.x must be finite (got nan)");
    assert_int_equal(phys_world_step(f->world, INFINITY), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "dt must be finite");
}

static void test_stale_id_is_rejected_after_destroy(void **state) {
    fixture *f = *state;
    phys_shape_id s = make_sphere(f->world, 1);
    phys_body_id old = make_body(f->world, PHYS_BODY_DYNAMIC, s, zero3);
    assert_true(phys_body_is_valid(f->world, old));
    assert_ok(phys_body_destroy(f->world, old));
    assert_false(phys_body_is_valid(f->world, old));
    assert_int_equal(phys_body_get_pose(f->world, old, NULL, NULL), PHYS_ERR_STALE_ID);
    assert_contains(phys_world_last_error(f->world),
                    "phys_body_id is stale (index1 1, generation 1, current 2): attempt to use a "
                    "destroyed body");
    // The slot is reused; the old id stays stale, the new one works.
    phys_body_id fresh = make_body(f->world, PHYS_BODY_DYNAMIC, s, zero3);
    assert_int_equal(fresh.index1, old.index1);
    assert_true(phys_body_is_valid(f->world, fresh));
    assert_int_equal(phys_body_destroy(f->world, old), PHYS_ERR_STALE_ID);
    assert_int_equal(phys_world_get_body_count(f->world), 1);
    // The null id is named as such.
    phys_body_id null_id = {0, 0, 0};
    assert_int_equal(phys_body_wake(f->world, null_id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_body_id is the null id");
}

static void test_id_from_another_world_is_rejected(void **state) {
    fixture *f = *state;
    phys_world_def def = phys_default_world_def();
    phys_world *other = NULL;
    assert_ok(phys_world_create(&def, &other));
    phys_body_id mine = make_body(f->world, PHYS_BODY_DYNAMIC, make_sphere(f->world, 1), zero3);
    phys_body_id theirs = make_body(other, PHYS_BODY_DYNAMIC, make_sphere(other, 1), zero3);
    if (theirs.world0 != mine.world0) {  // tags are address hashes; equal ones are legal
        assert_false(phys_body_is_valid(f->world, theirs));
        assert_int_equal(phys_body_wake(f->world, theirs), PHYS_ERR_INVALID_ARG);
        assert_contains(phys_world_last_error(f->world), "the id comes from another world");
    }
    phys_world_destroy(other);
}

static void test_triangle_mesh_on_dynamic_body_is_rejected(void **state) {
    fixture *f = *state;
    const phys_vec3 verts[3] = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}};
    const uint32_t idx[3] = {0, 2, 1};
    phys_triangle_mesh mesh = {verts, 3, idx, 1};
    phys_shape_id shape;
    assert_ok(phys_shape_create_triangle_mesh(f->world, &mesh, &shape));
    phys_body_def def = phys_default_body_def();
    def.shape = shape;
    phys_body_id id = {0, 0, 0};
    assert_int_equal(phys_body_create(f->world, &def, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world),
                    "phys_body_def.type is PHYS_BODY_DYNAMIC but phys_body_def.shape is a "
                    "triangle mesh");
    def.type = PHYS_BODY_KINEMATIC;  // allowed
    assert_ok(phys_body_create(f->world, &def, &id));

    const uint32_t bad_idx[3] = {0, 2, 7};
    phys_triangle_mesh bad = {verts, 3, bad_idx, 1};
    assert_int_equal(phys_shape_create_triangle_mesh(f->world, &bad, &shape), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world),
                    "phys_triangle_mesh.indices[2] must be < vertex_count 3 (got 7)");
}

static void test_static_body_velocity_is_rejected(void **state) {
    fixture *f = *state;
    phys_body_id wall = make_body(f->world, PHYS_BODY_STATIC, make_sphere(f->world, 1), zero3);
    assert_int_equal(phys_body_set_linear_velocity(f->world, wall, v3(1, 0, 0)), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "static bodies cannot be given a velocity");
    assert_int_equal(phys_body_set_kinematic_target(f->world, wall, zero3, identity),
                     PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "body must be PHYS_BODY_KINEMATIC (got PHYS_BODY_STATIC)");
}

static void test_invalid_world_def_is_reported_through_the_log(void **state) {
    (void)state;
    fixture f;
    memset(&f, 0, sizeof f);
    phys_world_def def = phys_default_world_def();
    def.log = capture_log;
    def.log_user = &f;
    def.solver_iterations = 0;
    phys_world *w = (phys_world *)&f;  // must be overwritten with NULL
    assert_int_equal(phys_world_create(&def, &w), PHYS_ERR_INVALID_ARG);
    assert_null(w);
    assert_contains(f.log, "phys_world_def.solver_iterations must be in [1, 1000] (got 0)");
    def.solver_iterations = 10;
    def.gravity.z = NAN;
    assert_int_equal(phys_world_create(&def, &w), PHYS_ERR_INVALID_ARG);
    assert_contains(f.log, "phys_world_def.gravity.z must be finite (got nan)");
}

// ---- constraints and shapes in use ---------------------------------------------------

static void test_point_constraint_drags_body_to_the_pivot(void **state) {
    fixture *f = *state;
    phys_body_id ball = make_body(f->world, PHYS_BODY_DYNAMIC, make_sphere(f->world, 0.2f),
                                  v3(0, 1, 0));
    phys_point_constraint_def def = phys_default_point_constraint_def();
    def.body = ball;
    def.pivot = v3(0, 1.2f, 0);  // top of the ball
    phys_constraint_id c;
    assert_ok(phys_point_constraint_create(f->world, &def, &c));
    assert_ok(phys_point_constraint_set_pivot(f->world, c, v3(1, 2.2f, 0)));
    // Dragged along: the ball's top stays on the moved pivot, so its centre
    // stays 0.2 m from it (it swings, undamped, around the pivot).
    for (int i = 0; i < 180; ++i) {
        assert_ok(phys_world_step(f->world, 1.0f / 60.0f));
        if (i < 60) continue;  // first let the constraint pull it there
        phys_vec3 p = position_of(f->world, ball);
        const double dx = p.x - 1.0, dy = p.y - 2.2, dz = p.z;
        assert_near(sqrt(dx * dx + dy * dy + dz * dz), 0.2, 0.025);  // soft: stretches ~6% swinging
    }

    assert_ok(phys_constraint_destroy(f->world, c));
    assert_false(phys_constraint_is_valid(f->world, c));
    run(f->world, 1.0f / 60.0f, 30);
    assert_true(position_of(f->world, ball).y < 1.9f);  // released: falls

    // A constraint dies with its body.
    assert_ok(phys_point_constraint_create(f->world, &def, &c));
    assert_ok(phys_body_destroy(f->world, ball));
    assert_false(phys_constraint_is_valid(f->world, c));
    assert_int_equal(phys_constraint_destroy(f->world, c), PHYS_ERR_STALE_ID);
    assert_contains(phys_world_last_error(f->world), "attempt to use a destroyed constraint");
}

static void test_point_constraint_needs_a_dynamic_body(void **state) {
    fixture *f = *state;
    phys_body_id wall = make_body(f->world, PHYS_BODY_STATIC, make_sphere(f->world, 1), zero3);
    phys_point_constraint_def def = phys_default_point_constraint_def();
    def.body = wall;
    phys_constraint_id c;
    assert_int_equal(phys_point_constraint_create(f->world, &def, &c), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world),
                    "phys_point_constraint_def.body must be PHYS_BODY_DYNAMIC (got PHYS_BODY_STATIC)");
}

// ---- compounds and motion factors ----------------------------------------------

// Two unit cubes, one at the parts-frame origin and one at x = 2 (a dumbbell
// without a bar): volume 2 m³, centre of mass at x = 1.
static phys_shape_id make_two_cubes(fixture *f) {
    phys_compound_part parts[2];
    memset(parts, 0, sizeof parts);
    for (int i = 0; i < 2; ++i) {
        parts[i].type = PHYS_SHAPE_BOX;
        parts[i].box.half_extents = v3(0.5f, 0.5f, 0.5f);
        parts[i].position = v3(2.0f * (float)i, 0, 0);
        parts[i].rotation = identity;
    }
    phys_compound c = {parts, 2};
    phys_shape_id id = {0, 0, 0};
    assert_ok(phys_shape_create_compound(f->world, &c, &id));
    return id;
}

static void test_compound_mass_and_inertia_come_from_density(void **state) {
    fixture *f = *state;
    phys_shape_id shape = make_two_cubes(f);
    phys_body_def def = phys_default_body_def();
    def.shape = shape;
    def.density = 500.0f;
    phys_body_id body = {0, 0, 0};
    assert_ok(phys_body_create(f->world, &def, &body));
    phys_mass_data md;
    assert_ok(phys_body_get_mass_data(f->world, body, &md));
    // 500 kg/m³ × 2 m³ = 1000 kg. Each cube (500 kg, edge 1) has m/6 = 83.33 about its own
    // centre; about the common centre 1 m away: Ixx = 2 × 83.33 = 166.67,
    // Iyy = Izz = 2 × (83.33 + 500 × 1²) = 1166.67 kg·m².
    assert_near(md.mass, 1000.0, 1e-2);
    assert_near(md.inertia_local.x, 166.667, 0.05);
    assert_near(md.inertia_local.y, 1166.667, 0.2);
    assert_near(md.inertia_local.z, 1166.667, 0.2);
}

static void test_compound_desc_round_trips_children_and_frame(void **state) {
    fixture *f = *state;
    phys_shape_id shape = make_two_cubes(f);
    phys_shape_desc d;
    assert_ok(phys_shape_get_desc(f->world, shape, &d));
    assert_int_equal(d.type, PHYS_SHAPE_COMPOUND);
    assert_near(d.volume, 2.0, 1e-5);
    assert_int_equal(d.compound.child_count, 2);
    // The shape frame's origin is the centre of mass, at x = 1 in the parts frame; the
    // parts' axes are already principal, so no rotation.
    assert_near(d.compound.frame_origin.x, 1.0, 1e-5);
    assert_near(d.compound.frame_origin.y, 0.0, 1e-5);
    assert_near(d.compound.frame_rotation.w, 1.0, 1e-5);
    for (int i = 0; i < 2; ++i) {
        const phys_compound_child *c = &d.compound.children[i];
        assert_int_equal(c->desc.type, PHYS_SHAPE_BOX);
        assert_near(c->desc.box.half_extents.y, 0.5, 1e-6);
        assert_near(c->desc.volume, 1.0, 1e-6);
        assert_near(c->position.x, i == 0 ? -1.0 : 1.0, 1e-5);
        assert_near(c->position.y, 0.0, 1e-5);
        assert_near(c->rotation.w, 1.0, 1e-5);
    }
    // A body reports the same description; the shape cannot go while the body uses it.
    phys_body_id body = make_body(f->world, PHYS_BODY_DYNAMIC, shape, v3(0, 3, 0));
    phys_shape_desc bd;
    assert_ok(phys_body_get_shape(f->world, body, &bd));
    assert_int_equal(bd.type, PHYS_SHAPE_COMPOUND);
    assert_ptr_equal(bd.compound.children, d.compound.children);
    assert_int_equal(phys_shape_destroy(f->world, shape), PHYS_ERR_INVALID_ARG);
    assert_ok(phys_body_destroy(f->world, body));
    assert_ok(phys_shape_destroy(f->world, shape));
    assert_false(phys_shape_is_valid(f->world, shape));
}

static void test_compound_rests_on_a_plane(void **state) {
    fixture *f = *state;
    make_ground(f->world);
    // An L: a 2 × 0.2 × 1 m plank with a 0.2 × 1 × 1 m post standing on one end. Dropped
    // from 1 m, it comes to rest lying on its plank, the post upright.
    phys_compound_part parts[2];
    memset(parts, 0, sizeof parts);
    parts[0].type = PHYS_SHAPE_BOX;
    parts[0].box.half_extents = v3(1.0f, 0.1f, 0.5f);
    parts[0].position = v3(0, 0, 0);
    parts[0].rotation = identity;
    parts[1].type = PHYS_SHAPE_BOX;
    parts[1].box.half_extents = v3(0.1f, 0.5f, 0.5f);
    parts[1].position = v3(0.9f, 0.6f, 0);
    parts[1].rotation = identity;
    phys_compound c = {parts, 2};
    phys_shape_id shape = {0, 0, 0};
    assert_ok(phys_shape_create_compound(f->world, &c, &shape));
    phys_shape_desc d;
    assert_ok(phys_shape_get_desc(f->world, shape, &d));
    // Volumes 0.4 and 0.2 m³: the centre of mass is at x = 0.2 × 0.9 / 0.6 = 0.3,
    // y = 0.2 × 0.6 / 0.6 = 0.2 in the parts frame.
    assert_near(d.compound.frame_origin.x, 0.3, 1e-4);
    assert_near(d.compound.frame_origin.y, 0.2, 1e-4);
    // The L's parts axes are not principal (the post makes Ixy non-zero): the shape frame
    // is turned about z. Place the parts frame upright, 1 m up: the body takes the frame's
    // pose (position frame_origin, orientation frame_rotation).
    assert_true(fabs(d.compound.frame_rotation.z) > 0.05);
    phys_body_def def = phys_default_body_def();
    def.shape = shape;
    def.position = v3(d.compound.frame_origin.x, d.compound.frame_origin.y + 1.0f, 0);
    def.orientation = d.compound.frame_rotation;
    phys_body_id body = {0, 0, 0};
    assert_ok(phys_body_create(f->world, &def, &body));
    run(f->world, 1.0f / 120.0f, 360);
    // Lying on the plank: its bottom (0.1 below the parts origin, 0.3 below the centre of
    // mass) on y = 0, so the centre of mass at y = 0.3, the parts frame still upright.
    phys_vec3 p = position_of(f->world, body);
    phys_quat q;
    assert_ok(phys_body_get_pose(f->world, body, NULL, &q));
    assert_near(p.y, 0.3, 0.005);
    assert_near(p.x, 0.3, 0.01);
    const phys_quat fr = d.compound.frame_rotation;
    assert_near(fabs(q.x * fr.x + q.y * fr.y + q.z * fr.z + q.w * fr.w), 1.0, 1e-4);
    phys_vec3 v = velocity_of(f->world, body);
    assert_near(v.y, 0.0, 0.01);
}

static void test_angular_factor_keeps_rotation_to_one_axis(void **state) {
    fixture *f = *state;
    phys_body_id body = make_body(f->world, PHYS_BODY_DYNAMIC, make_box(f->world, 0.5f, 0.5f, 0.5f),
                                  v3(0, 2, 0));
    assert_ok(phys_body_set_linear_factor(f->world, body, v3(0, 0, 0)));
    assert_ok(phys_body_set_angular_factor(f->world, body, v3(0, 0, 1)));
    phys_vec3 lf, af;
    assert_ok(phys_body_get_linear_factor(f->world, body, &lf));
    assert_ok(phys_body_get_angular_factor(f->world, body, &af));
    assert_near(lf.y, 0.0, 0);
    assert_near(af.z, 1.0, 0);
    // 1000 kg cube, I = 1000/6 = 166.67 kg·m²; a torque (10, 20, 30) N·m for 1 s spins it
    // about z only: ωz = 30 / 166.67 = 0.18 rad/s; gravity does not move it.
    for (int i = 0; i < 60; ++i) {
        assert_ok(phys_body_apply_torque(f->world, body, v3(10, 20, 30), true));
        assert_ok(phys_world_step(f->world, 1.0f / 60.0f));
    }
    phys_vec3 w;
    assert_ok(phys_body_get_angular_velocity(f->world, body, &w));
    assert_near(w.x, 0.0, 1e-6);
    assert_near(w.y, 0.0, 1e-6);
    assert_near(w.z, 0.18, 1e-3);
    phys_vec3 p = position_of(f->world, body);
    assert_near(p.x, 0.0, 1e-6);
    assert_near(p.y, 2.0, 1e-6);
    assert_near(p.z, 0.0, 1e-6);
}

static void test_bad_compound_and_factors_are_rejected_naming_the_field(void **state) {
    fixture *f = *state;
    phys_shape_id out = {0, 0, 0};
    phys_compound_part parts[2];
    memset(parts, 0, sizeof parts);
    parts[0].type = PHYS_SHAPE_SPHERE;
    parts[0].sphere.radius = 0.5f;
    parts[0].rotation = identity;
    parts[1].type = PHYS_SHAPE_BOX;
    parts[1].box.half_extents = v3(0.5f, -1.0f, 0.5f);
    parts[1].rotation = identity;
    phys_compound c = {parts, 0};
    assert_int_equal(phys_shape_create_compound(f->world, &c, &out), PHYS_ERR_INVALID_ARG);
    assert_contains(f->log, "phys_compound.part_count must be in [1, 256] (got 0)");
    c.part_count = 2;
    assert_int_equal(phys_shape_create_compound(f->world, &c, &out), PHYS_ERR_INVALID_ARG);
    assert_contains(f->log, "phys_compound.parts[1]: phys_box.half_extents.y must be > 0 (got -1)");
    parts[1].box.half_extents.y = 0.5f;
    parts[1].rotation.w = 2.0f;
    assert_int_equal(phys_shape_create_compound(f->world, &c, &out), PHYS_ERR_INVALID_ARG);
    assert_contains(f->log, "phys_compound.parts[1].rotation must be a unit quaternion");
    parts[1].rotation = identity;
    parts[1].type = PHYS_SHAPE_PLANE;
    assert_int_equal(phys_shape_create_compound(f->world, &c, &out), PHYS_ERR_INVALID_ARG);
    assert_contains(f->log, "phys_compound.parts[1].type must be PHYS_SHAPE_BOX");
    assert_contains(f->log, "(got 1, plane)");
    assert_int_equal(out.index1, 0u); // untouched
    c.parts = NULL;
    assert_int_equal(phys_shape_create_compound(f->world, &c, &out), PHYS_ERR_INVALID_ARG);
    assert_contains(f->log, "phys_compound.parts must not be NULL");

    phys_body_id body = make_body(f->world, PHYS_BODY_DYNAMIC, make_sphere(f->world, 0.5f), v3(0, 0, 0));
    assert_int_equal(phys_body_set_angular_factor(f->world, body, v3(0, 1.5f, 0)), PHYS_ERR_INVALID_ARG);
    assert_contains(f->log, "phys_body_set_angular_factor: factor.y must be finite and in [0, 1] (got 1.5)");
    assert_int_equal(phys_body_set_linear_factor(f->world, body, v3(NAN, 0, 0)), PHYS_ERR_INVALID_ARG);
    assert_contains(f->log, "phys_body_set_linear_factor: factor.x must be finite and in [0, 1]");
    assert_int_equal(phys_body_set_linear_factor(f->world, body, v3(0, 0, -0.5f)), PHYS_ERR_INVALID_ARG);
    assert_contains(f->log, "factor.z");
}

static void test_shape_in_use_cannot_be_destroyed(void **state) {
    fixture *f = *state;
    phys_shape_id s = make_box(f->world, 1, 1, 1);
    phys_body_id b = make_body(f->world, PHYS_BODY_STATIC, s, zero3);
    assert_int_equal(phys_shape_destroy(f->world, s), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "the box is used by 1 bodies");
    assert_ok(phys_body_destroy(f->world, b));
    assert_ok(phys_shape_destroy(f->world, s));
    assert_false(phys_shape_is_valid(f->world, s));
    phys_shape_desc d;
    assert_int_equal(phys_shape_get_desc(f->world, s, &d), PHYS_ERR_STALE_ID);
}

// ---- whole-world behaviour ------------------------------------------------------------

// A bit of everything: every shape kind, all body types, a constraint, 120
// steps. No cmocka asserts here (it also runs on a helper thread); returns the
// number of calls that failed. The 20 dynamic bodies go to `dynamic` if given.
static int build_scene(phys_world *w, phys_body_id dynamic[20]) {
    int failed = 0;
#define TRY(expr) failed += (expr) != PHYS_OK
    phys_plane ground = {{0, 1, 0}, 0};
    phys_box box = {{0.2f, 0.2f, 0.2f}};
    phys_sphere sphere = {0.2f};
    phys_capsule capsule = {0.1f, 0.2f};
    phys_cylinder cylinder = {0.2f, 0.2f};
    const phys_vec3 pts[5] = {{0, 0.3f, 0}, {-0.3f, -0.2f, -0.3f}, {0.3f, -0.2f, -0.3f},
                              {0.3f, -0.2f, 0.3f}, {-0.3f, -0.2f, 0.3f}};
    phys_convex_hull hull = {pts, 5};
    const phys_vec3 verts[3] = {{-3, 0.01f, -3}, {3, 0.01f, 0}, {-3, 0.01f, 3}};
    const uint32_t idx[3] = {0, 2, 1};
    phys_triangle_mesh mesh = {verts, 3, idx, 1};
    phys_shape_id plane_shape = {0, 0, 0}, mesh_shape = {0, 0, 0}, shapes[5];
    memset(shapes, 0, sizeof shapes);
    TRY(phys_shape_create_plane(w, &ground, &plane_shape));
    TRY(phys_shape_create_box(w, &box, &shapes[0]));
    TRY(phys_shape_create_sphere(w, &sphere, &shapes[1]));
    TRY(phys_shape_create_capsule(w, &capsule, &shapes[2]));
    TRY(phys_shape_create_cylinder(w, &cylinder, &shapes[3]));
    TRY(phys_shape_create_convex_hull(w, &hull, &shapes[4]));
    TRY(phys_shape_create_triangle_mesh(w, &mesh, &mesh_shape));

    phys_body_def def = phys_default_body_def();
    phys_body_id id = {0, 0, 0}, first = {0, 0, 0};
    def.type = PHYS_BODY_STATIC;
    def.shape = plane_shape;
    TRY(phys_body_create(w, &def, &id));
    def.type = PHYS_BODY_KINEMATIC;
    def.shape = mesh_shape;
    TRY(phys_body_create(w, &def, &id));
    def.type = PHYS_BODY_DYNAMIC;
    for (int i = 0; i < 20; ++i) {
        def.shape = shapes[i % 5];
        def.position = v3(0.1f * (i % 3), 0.5f + 0.45f * i, 0.05f * (i % 2));
        TRY(phys_body_create(w, &def, &id));
        if (i == 0) first = id;
        if (dynamic) dynamic[i] = id;
    }
    phys_point_constraint_def pd = phys_default_point_constraint_def();
    pd.body = first;
    pd.pivot = v3(0, 0.7f, 0);
    phys_constraint_id c;
    TRY(phys_point_constraint_create(w, &pd, &c));
    for (int i = 0; i < 120; ++i) TRY(phys_world_step(w, 1.0f / 120.0f));
#undef TRY
    return failed;
}

static size_t heap_in_use(void) {
    struct mallinfo2 mi = mallinfo2();
    return mi.uordblks + mi.hblkhd;
}

typedef struct lifetime {
    int failed;
    size_t peak;
} lifetime;

// One world lifetime: create, fill, destroy with everything still alive.
static void *world_lifetime(void *arg) {
    lifetime *life = arg;
    phys_world_def def = phys_default_world_def();
    phys_world *w = NULL;
    if (phys_world_create(&def, &w) != PHYS_OK) {
        life->failed++;
        return NULL;
    }
    life->failed += build_scene(w, NULL);
    life->peak = heap_in_use();
    phys_world_destroy(w);
    return NULL;
}

static void test_destroying_world_with_live_objects_frees_everything(void **state) {
    (void)state;
    // Bytes in use come from mallinfo2. Two things make that exact: one malloc
    // arena for all threads (so the helper thread's blocks are counted), and
    // running each world lifetime on its own thread, whose exit returns the
    // blocks parked in its glibc thread cache. The first lifetime absorbs the
    // one-time allocations of Bullet and the runtime; the next must return
    // the heap to exactly where it was.
    // Under valgrind or ASan malloc is not glibc's and these numbers mean
    // nothing; the lifetimes still run and those tools check for leaks.
    const bool exact = mallopt(M_ARENA_MAX, 1) == 1;
    lifetime life = {0, 0};
    size_t before = 0;
    for (int round = 0; round < 3; ++round) {
        if (round == 1) before = heap_in_use();
        pthread_t thread;
        assert_int_equal(pthread_create(&thread, NULL, world_lifetime, &life), 0);
        assert_int_equal(pthread_join(thread, NULL), 0);
    }
    assert_int_equal(life.failed, 0);
    if (!exact || life.peak == 0) skip();  // no meaningful mallinfo2 numbers: see above
    assert_true(life.peak > before + 10000);  // the scene did allocate
    if (heap_in_use() != before) {
        fail_msg("heap in use after 2 world lifetimes: %zu bytes, before: %zu", heap_in_use(), before);
    }
}

static void final_state(phys_world *w, float out[7 * 20]) {
    phys_body_id ids[20];
    assert_int_equal(build_scene(w, ids), 0);
    for (int i = 0; i < 20; ++i) {
        phys_vec3 p;
        phys_quat q;
        assert_ok(phys_body_get_pose(w, ids[i], &p, &q));
        const float v[7] = {p.x, p.y, p.z, q.x, q.y, q.z, q.w};
        memcpy(out + 7 * i, v, sizeof v);
    }
}

static void test_same_scene_gives_bit_identical_state(void **state) {
    (void)state;
    phys_world_def def = phys_default_world_def();
    static float a[7 * 20], b[7 * 20];
    phys_world *w = NULL;
    assert_ok(phys_world_create(&def, &w));
    final_state(w, a);
    phys_world_destroy(w);
    assert_ok(phys_world_create(&def, &w));
    final_state(w, b);
    phys_world_destroy(w);
    assert_memory_equal(a, b, sizeof a);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_defaults_are_the_documented_values),
        cmocka_unit_test_setup_teardown(test_dropped_sphere_falls_with_g, setup, teardown),
        cmocka_unit_test_setup_teardown(test_each_step_is_exactly_one_internal_step_of_dt, setup, teardown),
        cmocka_unit_test_setup_teardown(test_box_comes_to_rest_on_plane_at_its_half_height, setup, teardown),
        cmocka_unit_test_setup_teardown(test_kinematic_target_moves_body_and_it_pushes_a_dynamic_body, setup, teardown),
        cmocka_unit_test_setup_teardown(test_kinematic_target_derives_velocity_for_one_step_then_stops, setup, teardown),
        cmocka_unit_test_setup_teardown(test_kinematic_velocity_moves_body_steadily, setup, teardown),
        cmocka_unit_test_setup_teardown(test_force_changes_velocity_by_f_over_m_dt_for_one_step_only, setup, teardown),
        cmocka_unit_test_setup_teardown(test_impulse_changes_velocity_by_j_over_m_at_once, setup, teardown),
        cmocka_unit_test_setup_teardown(test_mass_data_reports_mass_and_inverse_inertia, setup, teardown),
        cmocka_unit_test_setup_teardown(test_impulse_at_point_spins_body_by_inverse_inertia, setup, teardown),
        cmocka_unit_test_setup_teardown(test_torque_changes_angular_velocity_for_one_step, setup, teardown),
        cmocka_unit_test_setup_teardown(test_force_at_point_adds_torque_about_centre_of_mass, setup, teardown),
        cmocka_unit_test_setup_teardown(test_velocity_at_point_includes_spin, setup, teardown),
        cmocka_unit_test_setup_teardown(test_sleeping_body_wakes_only_when_asked, setup, teardown),
        cmocka_unit_test_setup_teardown(test_body_with_sleep_disabled_stays_awake, setup, teardown),
        cmocka_unit_test_setup_teardown(test_ray_cast_hits_nearest_body_at_right_distance, setup, teardown),
        cmocka_unit_test_setup_teardown(test_density_times_volume_gives_mass, setup, teardown),
        cmocka_unit_test_setup_teardown(test_explicit_mass_wins_over_density, setup, teardown),
        cmocka_unit_test_setup_teardown(test_convex_hull_query_returns_points_and_planes, setup, teardown),
        cmocka_unit_test_setup_teardown(test_degenerate_convex_hull_is_rejected, setup, teardown),
        cmocka_unit_test_setup_teardown(test_triangle_mesh_query_returns_vertices_and_indices, setup, teardown),
        cmocka_unit_test_setup_teardown(test_negative_mass_is_rejected_naming_the_field, setup, teardown),
        cmocka_unit_test_setup_teardown(test_zero_size_box_is_rejected_naming_the_field, setup, teardown),
        cmocka_unit_test_setup_teardown(test_nan_pose_is_rejected_naming_the_field, setup, teardown),
        cmocka_unit_test_setup_teardown(test_stale_id_is_rejected_after_destroy, setup, teardown),
        cmocka_unit_test_setup_teardown(test_id_from_another_world_is_rejected, setup, teardown),
        cmocka_unit_test_setup_teardown(test_triangle_mesh_on_dynamic_body_is_rejected, setup, teardown),
        cmocka_unit_test_setup_teardown(test_static_body_velocity_is_rejected, setup, teardown),
        cmocka_unit_test(test_invalid_world_def_is_reported_through_the_log),
        cmocka_unit_test_setup_teardown(test_point_constraint_drags_body_to_the_pivot, setup, teardown),
        cmocka_unit_test_setup_teardown(test_point_constraint_needs_a_dynamic_body, setup, teardown),
        cmocka_unit_test_setup_teardown(test_shape_in_use_cannot_be_destroyed, setup, teardown),
        cmocka_unit_test_setup_teardown(test_compound_mass_and_inertia_come_from_density, setup, teardown),
        cmocka_unit_test_setup_teardown(test_compound_desc_round_trips_children_and_frame, setup, teardown),
        cmocka_unit_test_setup_teardown(test_compound_rests_on_a_plane, setup, teardown),
        cmocka_unit_test_setup_teardown(test_angular_factor_keeps_rotation_to_one_axis, setup, teardown),
        cmocka_unit_test_setup_teardown(test_bad_compound_and_factors_are_rejected_naming_the_field, setup, teardown),
        cmocka_unit_test(test_destroying_world_with_live_objects_frees_everything),
        cmocka_unit_test(test_same_scene_gives_bit_identical_state),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
