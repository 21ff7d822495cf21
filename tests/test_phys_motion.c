// The Bullet wrapper (fluid/bullet/phys.h) in motion: defaults, stepping and gravity, kinematic
// bodies, forces, impulses and mass data, sleeping, and point constraints.

#include "tests/phys_fixture.h"

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

// A held force acts in every step until released, on top of the one-step forces; a torque too.
static void test_held_force_acts_in_every_step_until_released(void **state) {
    fixture *f = *state;
    phys_body_id b = make_weightless_sphere(f, 2.0f);
    const float dt = 0.01f;
    assert_ok(phys_body_set_held_force(f->world, b, v3(4, 0, 0), v3(0, 0, 0)));
    phys_vec3 held, torque = v3(9, 9, 9);
    assert_ok(phys_body_get_held_force(f->world, b, &held, &torque));
    assert_near(held.x, 4, 0);
    assert_near(torque.z, 0, 0);
    assert_ok(phys_body_apply_force(f->world, b, v3(2, 0, 0), true));  // one step only
    for (int i = 0; i < 3; i++) assert_ok(phys_world_step(f->world, dt));
    // Δv = (4 × 3 + 2 × 1) / 2 × 0.01 = 0.07.
    assert_near(velocity_of(f->world, b).x, 0.07, 1e-6);
    assert_ok(phys_body_set_held_force(f->world, b, v3(0, 0, 0), v3(0, 0, 0)));
    assert_ok(phys_world_step(f->world, dt));
    assert_near(velocity_of(f->world, b).x, 0.07, 1e-6);
    assert_ok(phys_body_get_held_force(f->world, b, NULL, NULL));

    assert_int_equal(phys_body_set_held_force(f->world, b, v3(NAN, 0, 0), v3(0, 0, 0)), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "force.x must be finite (got nan)");
    assert_int_equal(phys_body_set_held_force(f->world, b, v3(0, 0, 0), v3(0, INFINITY, 0)), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "torque.y must be finite (got inf)");
    assert_ok(phys_body_destroy(f->world, b));
    assert_int_equal(phys_body_set_held_force(f->world, b, v3(1, 0, 0), v3(0, 0, 0)), PHYS_ERR_STALE_ID);
    assert_int_equal(phys_body_get_held_force(f->world, b, &held, NULL), PHYS_ERR_STALE_ID);
}

// Bullet integrates in floats: a body given 3.6e27 m/s was NaN two steps later (fuzz_phys_api).
// Velocities over PHYS_MAX_SPEED are refused; one an impulse or a force makes is held to it,
// and the log is told once for the body.
static void test_speed_over_the_limit_is_refused_or_held(void **state) {
    fixture *f = *state;
    phys_body_id b = make_weightless_sphere(f, 1.0f);
    assert_int_equal(phys_body_set_linear_velocity(f->world, b, v3(0, 2e5f, 0)), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "velocity must be at most PHYS_MAX_SPEED = 100000 m/s in size (got 200000)");
    assert_int_equal(phys_body_set_angular_velocity(f->world, b, v3(0, 0, -3e5f)), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "PHYS_MAX_ANGULAR_SPEED = 100000 rad/s");
    phys_body_def def = phys_default_body_def();
    def.shape = make_sphere(f->world, 0.1f);
    def.linear_velocity = v3(-3.75f, 3.6e27f, 1.45f);
    phys_body_id other = {0, 0, 0};
    assert_int_equal(phys_body_create(f->world, &def, &other), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_body_def.linear_velocity must be at most PHYS_MAX_SPEED");

    int logged = f->log_count;
    assert_ok(phys_body_apply_impulse(f->world, b, v3(1e30f, 0, 0), true));
    assert_ok(phys_body_apply_angular_impulse(f->world, b, v3(0, 1e30f, 0), true));
    for (int i = 0; i < 3; i++) {
        assert_ok(phys_world_step(f->world, 1.0f / 60.0f));
        assert_ok(phys_body_apply_force(f->world, b, v3(3e38f, 0, 0), true));
    }
    phys_vec3 v = velocity_of(f->world, b), p, w;
    phys_quat q;
    assert_ok(phys_body_get_angular_velocity(f->world, b, &w));
    assert_ok(phys_body_get_pose(f->world, b, &p, &q));
    assert_near(v.x, PHYS_MAX_SPEED, 1.0);
    assert_near(w.y, PHYS_MAX_ANGULAR_SPEED, 1.0);
    assert_true(isfinite(p.x) && isfinite(q.x) && isfinite(q.y) && isfinite(q.z) && isfinite(q.w));
    assert_int_equal(f->log_count, logged + 1);  // once for the body
    assert_contains(f->log, "held to PHYS_MAX_SPEED = 100000 m/s");

    // A force that would add more than the limit in one step is scaled to it before the step
    // (3e38 N on a milligram made the position infinite inside Bullet's step).
    def.linear_velocity = v3(0, 0, 0);
    def.mass = PHYS_MIN_MASS;
    phys_body_id speck = {0, 0, 0};
    assert_ok(phys_body_create(f->world, &def, &speck));
    assert_ok(phys_body_set_held_force(f->world, speck, v3(0, 0, -3e38f), v3(3e38f, 0, 0)));
    for (int i = 0; i < 4; i++) assert_ok(phys_world_step(f->world, 0.5f));
    assert_ok(phys_body_get_pose(f->world, speck, &p, &q));
    assert_true(isfinite(p.z) && isfinite(q.x) && isfinite(q.w));
    // Each step starts at most at the limit and adds at most the limit: between 1 and 2 times
    // the limit's distance per step.
    assert_true(p.z <= -PHYS_MAX_SPEED * 0.5 * 4 && p.z >= -2 * PHYS_MAX_SPEED * 0.5 * 4);
    assert_contains(f->log, "would change its speed by");

    // Gravity is bounded too (1.7e38 m/s^2 at dt 0.5 s made a position infinite).
    assert_int_equal(phys_world_set_gravity(f->world, v3(-4, 1.45f, -1.7e38f)), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "gravity must be at most PHYS_MAX_GRAVITY = 10000 m/s^2 in size");
    assert_ok(phys_world_set_gravity(f->world, v3(0, -PHYS_MAX_GRAVITY, 0)));
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

// ---- constraints ----------------------------------------------------------------------

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
        cmocka_unit_test_setup_teardown(test_held_force_acts_in_every_step_until_released, setup, teardown),
        cmocka_unit_test_setup_teardown(test_speed_over_the_limit_is_refused_or_held, setup, teardown),
        cmocka_unit_test_setup_teardown(test_impulse_changes_velocity_by_j_over_m_at_once, setup, teardown),
        cmocka_unit_test_setup_teardown(test_mass_data_reports_mass_and_inverse_inertia, setup, teardown),
        cmocka_unit_test_setup_teardown(test_impulse_at_point_spins_body_by_inverse_inertia, setup, teardown),
        cmocka_unit_test_setup_teardown(test_torque_changes_angular_velocity_for_one_step, setup, teardown),
        cmocka_unit_test_setup_teardown(test_force_at_point_adds_torque_about_centre_of_mass, setup, teardown),
        cmocka_unit_test_setup_teardown(test_velocity_at_point_includes_spin, setup, teardown),
        cmocka_unit_test_setup_teardown(test_sleeping_body_wakes_only_when_asked, setup, teardown),
        cmocka_unit_test_setup_teardown(test_body_with_sleep_disabled_stays_awake, setup, teardown),
        cmocka_unit_test_setup_teardown(test_point_constraint_drags_body_to_the_pivot, setup, teardown),
        cmocka_unit_test_setup_teardown(test_point_constraint_needs_a_dynamic_body, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
