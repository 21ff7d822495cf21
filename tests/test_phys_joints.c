// Tests of the joints and contact reports of the Bullet C API wrapper (fluid/bullet/phys.h).
//
// Each test builds a small world, runs it, and checks one behaviour against a number worked
// out by hand (in the comment next to it). The measured values are printed, so a run's log
// shows how close Bullet came.

#include "phys_fixture.h"

// A call that must fail with `result` and a message containing `part`.
#define assert_refused(expr, result, part)                                          \
    do {                                                                            \
        const phys_result r_ = (expr);                                              \
        if (r_ != (result)) {                                                       \
            fail_msg("%s returned %s, expected %s", #expr, phys_result_string(r_),   \
                     phys_result_string(result));                                   \
        }                                                                           \
        assert_contains(phys_world_last_error(f->world), (part));                   \
    } while (0)

static phys_vec3 sub(phys_vec3 a, phys_vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static double dot(phys_vec3 a, phys_vec3 b) { return (double)a.x * b.x + (double)a.y * b.y + (double)a.z * b.z; }
static double length(phys_vec3 a) { return sqrt(dot(a, a)); }

// q * v * conj(q).
static phys_vec3 rotate(phys_quat q, phys_vec3 v) {
    const double tx = 2.0 * (q.y * v.z - q.z * v.y);
    const double ty = 2.0 * (q.z * v.x - q.x * v.z);
    const double tz = 2.0 * (q.x * v.y - q.y * v.x);
    return v3((float)(v.x + q.w * tx + (q.y * tz - q.z * ty)),
              (float)(v.y + q.w * ty + (q.z * tx - q.x * tz)),
              (float)(v.z + q.w * tz + (q.x * ty - q.y * tx)));
}

static phys_quat conj_q(phys_quat q) {
    phys_quat c = {-q.x, -q.y, -q.z, q.w};
    return c;
}

static phys_quat mul(phys_quat a, phys_quat b) {
    phys_quat r = {a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                   a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                   a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
                   a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
    return r;
}

// Rotation angle of a unit quaternion, rad in [0, π].
static double rotation_angle(phys_quat q) {
    const double v = sqrt((double)q.x * q.x + (double)q.y * q.y + (double)q.z * q.z);
    return 2.0 * atan2(v, fabs((double)q.w));
}

// A dynamic body of `mass` kg (0: density 1000 kg/m³), sleep off unless asked.
static phys_body_id make_dynamic(phys_world *w, phys_shape_id shape, phys_vec3 position,
                                 float mass, bool allow_sleep) {
    phys_body_def def = phys_default_body_def();
    def.shape = shape;
    def.position = position;
    def.mass = mass;
    def.allow_sleep = allow_sleep;
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(w, &def, &id));
    return id;
}

static phys_body_id make_static(phys_world *w, phys_shape_id shape, phys_vec3 position) {
    phys_body_def def = phys_default_body_def();
    def.type = PHYS_BODY_STATIC;
    def.shape = shape;
    def.position = position;
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(w, &def, &id));
    return id;
}

// A static slab 10 m × 0.2 m × 10 m whose top is y = 0: the floor of the game's containers.
static phys_body_id make_floor(phys_world *w) {
    return make_static(w, make_box(w, 5, 0.1f, 5), v3(0, -0.1f, 0));
}

static phys_quat orientation_of(phys_world *w, phys_body_id id) {
    phys_quat q = identity;
    assert_ok(phys_body_get_pose(w, id, NULL, &q));
    return q;
}

static phys_vec3 spin_of(phys_world *w, phys_body_id id) {
    phys_vec3 v = {0, 0, 0};
    assert_ok(phys_body_get_angular_velocity(w, id, &v));
    return v;
}

static float mass_of(phys_world *w, phys_body_id id) {
    phys_mass_data md;
    assert_ok(phys_body_get_mass_data(w, id, &md));
    return md.mass;
}

static float angle_of(phys_world *w, phys_joint_id j) {
    float a = NAN;
    assert_ok(phys_joint_get_angle(w, j, &a));
    return a;
}

static float slider_position(phys_world *w, phys_joint_id j) {
    float s = NAN;
    assert_ok(phys_joint_get_position(w, j, &s));
    return s;
}

static bool same_body(phys_body_id a, phys_body_id b) {
    return a.index1 == b.index1 && a.world0 == b.world0 && a.generation == b.generation;
}

// The contact between bodies a and b (either order) above min_impulse, if any.
static bool find_contact(phys_world *w, phys_body_id a, phys_body_id b, float min_impulse,
                         phys_contact *out) {
    phys_contact c[64];
    int n = 0;
    assert_ok(phys_world_get_contacts(w, min_impulse, c, 64, &n));
    assert_true(n <= 64);
    for (int i = 0; i < n; ++i) {
        if ((same_body(c[i].a, a) && same_body(c[i].b, b)) ||
            (same_body(c[i].a, b) && same_body(c[i].b, a))) {
            *out = c[i];
            return true;
        }
    }
    return false;
}

// ---- defaults -----------------------------------------------------------------

static void test_joint_defs_have_the_documented_defaults(void **state) {
    (void)state;
    phys_hinge_joint_def h = phys_default_hinge_joint_def();
    assert_int_equal(h.body_a.index1, 0);
    assert_int_equal(h.body_b.index1, 0);
    assert_near(h.axis.z, 1, 0);
    assert_false(h.enable_limit);
    assert_false(h.enable_motor);
    assert_near(h.max_motor_torque, 0, 0);
    assert_false(h.collide_connected);
    phys_slider_joint_def s = phys_default_slider_joint_def();
    assert_near(s.axis.x, 1, 0);
    assert_false(s.enable_limit);
    assert_false(s.enable_motor);
    assert_false(s.collide_connected);
    phys_fixed_joint_def x = phys_default_fixed_joint_def();
    assert_false(x.collide_connected);
    phys_point_joint_def p = phys_default_point_joint_def();
    assert_near(p.pivot.y, 0, 0);
    assert_false(p.collide_connected);
}

// ---- hinge ----------------------------------------------------------------------

// A trapdoor: a 1 m × 0.05 m × 0.5 m plank hinged along z at its left edge, held level at
// first. Gravity turns it about +z by a negative angle (its free end falls); the lower limit
// at -60° must stop it there, where without the limit it would swing through -180°.
static void test_door_on_hinge_swings_down_and_stops_at_its_limit(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 60.0f;
    phys_body_id door = make_dynamic(f->world, make_box(f->world, 0.5f, 0.025f, 0.25f),
                                     v3(0.5f, 1, 0), 10, true);
    phys_hinge_joint_def def = phys_default_hinge_joint_def();
    def.body_a = door;
    def.pivot = v3(0, 1, 0);
    def.axis = v3(0, 0, 2);  // any length
    def.enable_limit = true;
    def.lower_angle = (float)(-PI / 3);
    def.upper_angle = (float)(PI / 2);
    phys_joint_id hinge;
    assert_ok(phys_joint_create_hinge(f->world, &def, &hinge));
    assert_near(angle_of(f->world, hinge), 0, 1e-6);

    double lowest = 0, highest_after_stop = -10, worst_pivot = 0;
    int first_stop = -1;
    for (int i = 0; i < 240; ++i) {
        assert_ok(phys_world_step(f->world, dt));
        const double a = angle_of(f->world, hinge);
        if (a < lowest) lowest = a;
        if (first_stop < 0 && a <= -PI / 3 + 0.01) first_stop = i;
        if (first_stop >= 0 && a > highest_after_stop) highest_after_stop = a;
        // The plank's hinge edge (local x = -0.5) stays on the pivot.
        const phys_vec3 edge = rotate(orientation_of(f->world, door), v3(-0.5f, 0, 0));
        const phys_vec3 p = position_of(f->world, door);
        const double off = length(sub(v3(p.x + edge.x, p.y + edge.y, p.z + edge.z), v3(0, 1, 0)));
        if (off > worst_pivot) worst_pivot = off;
    }
    const double final_angle = angle_of(f->world, hinge);
    // The body's own turn about z agrees with the joint's angle.
    const phys_vec3 x_axis = rotate(orientation_of(f->world, door), v3(1, 0, 0));
    const double body_angle = atan2(x_axis.y, x_axis.x);
    print_message("door: reached the limit at step %d, lowest %.4f rad, highest after %.4f, "
                  "final %.4f (limit %.4f), body %.4f, pivot drift %.2f mm, spin %.2g rad/s\n",
                  first_stop, lowest, highest_after_stop, final_angle, -PI / 3, body_angle,
                  worst_pivot * 1e3, length(spin_of(f->world, door)));
    assert_true(first_stop > 0);
    assert_near(final_angle, -PI / 3, 0.01);
    assert_near(body_angle, final_angle, 1e-3);
    assert_true(lowest > -PI / 3 - 0.05);            // overshoot into the stop: < 3°
    assert_true(highest_after_stop < -PI / 3 + 0.01); // no bounce (Bullet's default: +0.021 rad)
    assert_true(worst_pivot < 0.01);  // soft: the slam into the stop stretches the hinge
    assert_true(length(spin_of(f->world, door)) < 0.01);
}

// A wheel (cylinder, r 0.5 m, half height 0.1 m, 1000 kg/m³) on a vertical axle driven at
// 2 rad/s with at most 50 N·m: it speeds up at α = τ / I, then turns at the target speed.
static void test_motorised_hinge_turns_at_the_target_speed(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 60.0f;
    phys_cylinder cyl = {0.5f, 0.1f};
    phys_shape_id shape;
    assert_ok(phys_shape_create_cylinder(f->world, &cyl, &shape));
    phys_body_id wheel = make_dynamic(f->world, shape, v3(0, 1, 0), 0, true);
    phys_hinge_joint_def def = phys_default_hinge_joint_def();
    def.body_a = wheel;
    def.pivot = v3(0, 1, 0);
    def.axis = v3(0, 1, 0);
    def.enable_motor = true;
    def.motor_speed = 2.0f;
    def.max_motor_torque = 50.0f;
    phys_joint_id hinge;
    assert_ok(phys_joint_create_hinge(f->world, &def, &hinge));

    // I about the axis = m r² / 2 = 157.08 kg × 0.25 m² / 2 = 19.63 kg·m²: α = 2.546 rad/s².
    phys_mass_data md;
    assert_ok(phys_body_get_mass_data(f->world, wheel, &md));
    const double alpha = 50.0 / md.inertia_local.y;
    run(f->world, dt, 30);  // 0.5 s: ω = α t = 1.27 rad/s, below the target
    const double w_half = spin_of(f->world, wheel).y;
    // Then let it reach the target (0.8 s) and measure over 2 s by the hinge angle, unwrapped.
    run(f->world, dt, 60);
    double turned = 0, last = angle_of(f->world, hinge);
    for (int i = 0; i < 120; ++i) {
        assert_ok(phys_world_step(f->world, dt));
        const double a = angle_of(f->world, hinge);
        double d = a - last;
        if (d > PI) d -= 2 * PI;
        if (d < -PI) d += 2 * PI;
        turned += d;
        last = a;
    }
    const double speed = turned / (120 * dt);
    print_message("motor: I %.3f kg m^2, at 0.5 s w %.4f rad/s (alpha t = %.4f), then %.4f rad/s "
                  "by the angle, %.4f by the body (target 2)\n",
                  md.inertia_local.y, w_half, alpha * 0.5, speed, spin_of(f->world, wheel).y);
    assert_near(w_half, alpha * 0.5, 0.02 * alpha * 0.5);
    assert_near(speed, 2.0, 0.01);
    assert_near(spin_of(f->world, wheel).y, 2.0, 0.01);

    // Reversed, then off: the wheel keeps its speed without a motor (no friction).
    assert_ok(phys_joint_set_motor(f->world, hinge, true, -1.0f, 50.0f));
    run(f->world, dt, 120);
    assert_near(spin_of(f->world, wheel).y, -1.0, 0.01);
    assert_ok(phys_joint_set_motor(f->world, hinge, false, 0, 0));
    run(f->world, dt, 60);
    assert_near(spin_of(f->world, wheel).y, -1.0, 0.01);
    // A slow motor (below Bullet's 1 rad/s sleep threshold) keeps the wheel awake: still
    // turning after 4 s, where an idle body would sleep after 2 s.
    assert_ok(phys_joint_set_motor(f->world, hinge, true, 0.3f, 50.0f));
    run(f->world, dt, 240);
    assert_near(spin_of(f->world, wheel).y, 0.3, 0.003);
}

// A crate hanging 0.5 m under a kinematic trolley that rolls at 0.3 m/s: it follows for 4 s.
// Both are slower than Bullet's sleep threshold; the joint keeps the crate awake, or it would
// fall asleep after 2 s and be left behind.
static void test_body_hanging_from_a_kinematic_body_follows_it(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 60.0f;
    phys_body_def kd = phys_default_body_def();
    kd.type = PHYS_BODY_KINEMATIC;
    kd.shape = make_box(f->world, 0.5f, 0.1f, 0.5f);
    kd.position = v3(0, 2, 0);
    kd.linear_velocity = v3(0.3f, 0, 0);
    phys_body_id trolley;
    assert_ok(phys_body_create(f->world, &kd, &trolley));
    phys_body_id crate = make_dynamic(f->world, make_box(f->world, 0.2f, 0.2f, 0.2f), v3(0, 1.5f, 0), 5, true);
    phys_point_joint_def def = phys_default_point_joint_def();
    def.body_a = crate;
    def.body_b = trolley;
    def.pivot = v3(0, 1.9f, 0);
    phys_joint_id rope;
    assert_ok(phys_joint_create_point(f->world, &def, &rope));
    run(f->world, dt, 240);
    const double lag = position_of(f->world, trolley).x - position_of(f->world, crate).x;
    print_message("trolley: at %.3f m, crate %.4f m behind\n", position_of(f->world, trolley).x, lag);
    assert_near(position_of(f->world, trolley).x, 1.2, 1e-3);
    // It swings behind and ahead: amplitude v / √(g/l) = 0.3 / 4.43 = 0.068 m.
    assert_true(fabs(lag) < 0.075);
    bool awake = false;
    assert_ok(phys_body_is_awake(f->world, crate, &awake));
    assert_true(awake);
}

// ---- slider -------------------------------------------------------------------------

// A box on a frictionless 45° rail (axis (1, -1, 0)) slides down it at a = g sin 45°,
// s = a t² / 2, without leaving the line or turning.
static void test_slider_moves_only_along_its_axis(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 120.0f;
    const phys_vec3 start = v3(0, 2, 0);
    phys_body_id box = make_dynamic(f->world, make_box(f->world, 0.2f, 0.1f, 0.3f), start, 3, false);
    // A sideways push and a twist the slider must absorb.
    assert_ok(phys_body_set_angular_velocity(f->world, box, v3(1, 2, 3)));
    phys_slider_joint_def def = phys_default_slider_joint_def();
    def.body_a = box;
    def.anchor = start;
    def.axis = v3(1, -1, 0);
    phys_joint_id slider;
    assert_ok(phys_joint_create_slider(f->world, &def, &slider));

    const phys_vec3 u = v3((float)(1 / sqrt(2)), (float)(-1 / sqrt(2)), 0);
    double worst_off = 0, worst_turn = 0;
    const int n = 120;
    for (int i = 0; i < n; ++i) {
        assert_ok(phys_world_step(f->world, dt));
        const phys_vec3 d = sub(position_of(f->world, box), start);
        const double along = dot(d, u);
        const phys_vec3 off = v3((float)(d.x - along * u.x), (float)(d.y - along * u.y), d.z);
        if (length(off) > worst_off) worst_off = length(off);
        const double turn = rotation_angle(orientation_of(f->world, box));
        if (turn > worst_turn) worst_turn = turn;
        assert_near(slider_position(f->world, slider), along, 1e-4);
    }
    const double t = n * dt, a = G * sin(PI / 4);
    const double s = slider_position(f->world, slider);
    print_message("slider: s %.5f m after %.2f s (a t^2/2 = %.5f), off-axis drift %.3f mm, "
                  "turn %.2g rad\n",
                  s, t, 0.5 * a * t * t, worst_off * 1e3, worst_turn);
    // Semi-implicit Euler: s = a dt² n(n+1)/2, within 1% of a t²/2 here.
    assert_near(s, a * dt * dt * n * (n + 1) / 2.0, 0.01 * s);
    assert_true(worst_off < 0.001);
    assert_true(worst_turn < 0.01);
}

// The same rail with a stop 0.5 m down: the box rests there; then a motor pulls it back up
// at 0.4 m/s with at most 100 N (gravity along the rail: 3 kg × 6.94 = 20.8 N).
static void test_slider_stops_at_its_limit_and_its_motor_drives_it(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 120.0f;
    phys_body_id box = make_dynamic(f->world, make_box(f->world, 0.2f, 0.1f, 0.3f), v3(0, 2, 0), 3, true);
    phys_slider_joint_def def = phys_default_slider_joint_def();
    def.body_a = box;
    def.anchor = v3(0, 2, 0);
    def.axis = v3(1, -1, 0);
    def.enable_limit = true;
    def.lower_translation = -1.0f;
    def.upper_translation = 0.5f;
    phys_joint_id slider;
    assert_ok(phys_joint_create_slider(f->world, &def, &slider));
    double highest = 0;
    for (int i = 0; i < 240; ++i) {
        assert_ok(phys_world_step(f->world, dt));
        const double s = slider_position(f->world, slider);
        if (s > highest) highest = s;
    }
    const double rest = slider_position(f->world, slider);

    assert_ok(phys_joint_set_motor(f->world, slider, true, -0.4f, 100.0f));
    run(f->world, dt, 30);  // reach the speed
    const double s0 = slider_position(f->world, slider);
    run(f->world, dt, 60);
    const double speed = (slider_position(f->world, slider) - s0) / (60 * dt);
    // Too weak a motor (10 N < 20.8 N) loses: the box slides down again.
    assert_ok(phys_joint_set_motor(f->world, slider, true, -0.4f, 10.0f));
    const double s1 = slider_position(f->world, slider);
    run(f->world, dt, 30);
    const double s2 = slider_position(f->world, slider);
    print_message("slider limit: highest %.4f m, rest %.4f m (limit 0.5); motor %.4f m/s "
                  "(target -0.4); weak motor moved it %+.4f m\n",
                  highest, rest, speed, s2 - s1);
    assert_near(rest, 0.5, 0.005);
    assert_true(highest < 0.53);
    assert_near(speed, -0.4, 0.004);
    assert_true(s2 > s1 + 0.01);
}

// ---- fixed and point ----------------------------------------------------------------

// Two boxes welded side by side (5 kg and 2 kg, overlapping), thrown spinning: their relative
// pose stays as it was while they tumble through the air; the landing on a static floor bends
// the weld for a moment (the solver is iterative and soft) and it springs back; the joined
// pair never collides with itself.
static void test_fixed_joint_keeps_the_relative_pose(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 60.0f;
    phys_body_id floor_body = make_floor(f->world);
    phys_shape_id cube = make_box(f->world, 0.25f, 0.25f, 0.25f);
    phys_body_id a = make_dynamic(f->world, cube, v3(0, 2, 0), 5, true);
    phys_body_id b = make_dynamic(f->world, cube, v3(0.49f, 2.1f, 0), 2, true);
    run(f->world, dt, 1);  // they touch: Bullet has made a contact manifold for them
    phys_contact c;
    assert_true(find_contact(f->world, a, b, 0, &c));
    const phys_vec3 pa = position_of(f->world, a), pb = position_of(f->world, b);
    const phys_quat qa = orientation_of(f->world, a), qb = orientation_of(f->world, b);
    const phys_vec3 rel0 = rotate(conj_q(qa), sub(pb, pa));
    const phys_quat relq0 = mul(conj_q(qa), qb);
    phys_fixed_joint_def def = phys_default_fixed_joint_def();
    def.body_a = a;
    def.body_b = b;
    phys_joint_id weld;
    assert_ok(phys_joint_create_fixed(f->world, &def, &weld));
    assert_ok(phys_body_set_angular_velocity(f->world, a, v3(3, 1, 5)));
    assert_ok(phys_body_set_linear_velocity(f->world, a, v3(2, 1, 0)));

    double air_shift = 0, air_turn = 0, landing_shift = 0, landing_turn = 0, shift = 0, turn = 0;
    int self_contacts = 0, landed_at = -1;
    for (int i = 0; i < 240; ++i) {
        assert_ok(phys_world_step(f->world, dt));
        const phys_quat qa_now = orientation_of(f->world, a);
        const phys_vec3 rel = rotate(conj_q(qa_now), sub(position_of(f->world, b), position_of(f->world, a)));
        shift = length(sub(rel, rel0));
        turn = rotation_angle(mul(conj_q(relq0), mul(conj_q(qa_now), orientation_of(f->world, b))));
        if (find_contact(f->world, a, b, 0, &c)) self_contacts++;
        if (landed_at < 0 && (find_contact(f->world, floor_body, a, 0, &c) ||
                              find_contact(f->world, floor_body, b, 0, &c))) {
            landed_at = i;
        }
        double *worst_shift = landed_at < 0 ? &air_shift : &landing_shift;
        double *worst_turn = landed_at < 0 ? &air_turn : &landing_turn;
        if (shift > *worst_shift) *worst_shift = shift;
        if (turn > *worst_turn) *worst_turn = turn;
    }
    print_message("fixed: in the air (%d steps) worst shift %.3f mm, turn %.5f rad; landing worst "
                  "%.2f mm, %.4f rad; at rest %.3f mm, %.5f rad; %d steps with a self-contact\n",
                  landed_at, air_shift * 1e3, air_turn, landing_shift * 1e3, landing_turn,
                  shift * 1e3, turn, self_contacts);
    assert_true(landed_at > 10);  // it did fly, then hit the floor
    assert_int_equal(self_contacts, 0);
    assert_true(air_shift < 0.001);
    assert_true(air_turn < 0.002);
    assert_true(landing_shift < 0.05);
    assert_true(shift < 0.001);
    assert_true(turn < 0.002);
}

// A bob (1 kg sphere, r 0.1 m) on a 1 m massless arm from a point joint, let go at 5°, stepped
// at 1/120 s: small-angle period 2π √(L/g) = 2.006 s. The exact one for this bob is 0.25%
// longer: its own inertia makes L_eff = L + 2r²/5L (+0.2%) and the amplitude adds θ0²/16.
// Bullet's iterative solver converges slowly for a pivot far from a light body's centre: a
// smaller bob or a longer step swings slower (r 5 cm at 1/60 s: +8%; see phys.h, Joints).
static void test_pendulum_on_point_joint_keeps_its_length_and_period(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 120.0f;
    const double L = 1.0, r = 0.1, theta0 = 5.0 * PI / 180.0;
    const phys_vec3 pivot = v3(0, 2, 0);
    phys_body_id bob = make_dynamic(f->world, make_sphere(f->world, (float)r),
                                    v3((float)(L * sin(theta0)), (float)(2 - L * cos(theta0)), 0),
                                    1, false);
    phys_point_joint_def def = phys_default_point_joint_def();
    def.body_a = bob;
    def.pivot = pivot;
    phys_joint_id joint;
    assert_ok(phys_joint_create_point(f->world, &def, &joint));

    // Upward zero crossings of x, interpolated linearly within the step.
    double crossings[8];
    int n_cross = 0;
    double worst_stretch = 0, last_x = position_of(f->world, bob).x, max_x_late = 0;
    const int steps = (int)(11.0 / dt);
    for (int i = 1; i <= steps; ++i) {
        assert_ok(phys_world_step(f->world, dt));
        const phys_vec3 p = position_of(f->world, bob);
        const double stretch = fabs(length(sub(p, pivot)) - L);
        if (stretch > worst_stretch) worst_stretch = stretch;
        if (last_x < 0 && p.x >= 0 && n_cross < 8) {
            crossings[n_cross++] = dt * (i - 1 + last_x / (last_x - p.x));
        }
        if (i * dt > 9.0 && fabs(p.x) > max_x_late) max_x_late = fabs(p.x);
        last_x = p.x;
    }
    assert_true(n_cross >= 5);
    const double period = (crossings[n_cross - 1] - crossings[0]) / (n_cross - 1);
    const double simple = 2 * PI * sqrt(L / G);
    const double exact = simple * sqrt(1 + 0.4 * r * r / (L * L)) * (1 + theta0 * theta0 / 16);
    print_message("pendulum: period %.5f s over %d swings; 2 pi sqrt(L/g) = %.5f s (%+.3f%%), "
                  "with this bob's corrections %.5f s (%+.3f%%); length drift %.3f mm; "
                  "amplitude after 9 s %.4f m (start %.4f)\n",
                  period, n_cross - 1, simple, 100 * (period / simple - 1), exact,
                  100 * (period / exact - 1), worst_stretch * 1e3, max_x_late, L * sin(theta0));
    assert_near(period, simple, 0.03 * simple);
    assert_near(period, exact, 0.01 * exact);
    assert_true(worst_stretch < 0.001);
    assert_true(max_x_late > 0.95 * L * sin(theta0));  // the swing is not damped away
}

// A 2 kg bob hanging still from a point joint: the joint holds it with m g dt per step,
// straight up, and no torque about its centre (the pivot is right above it).
static void test_joint_reports_the_impulse_that_holds_a_hanging_body(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 60.0f;
    phys_body_id bob = make_dynamic(f->world, make_sphere(f->world, 0.1f), v3(0, 1, 0), 2, false);
    phys_point_joint_def def = phys_default_point_joint_def();
    def.body_a = bob;
    def.pivot = v3(0, 1.5f, 0);
    phys_joint_id joint;
    assert_ok(phys_joint_create_point(f->world, &def, &joint));
    phys_vec3 j, aj;
    assert_ok(phys_joint_get_applied_impulse(f->world, joint, &j, &aj));
    assert_near(length(j), 0, 0);  // before the first step
    run(f->world, dt, 120);
    assert_ok(phys_joint_get_applied_impulse(f->world, joint, &j, &aj));
    print_message("hanging: joint impulse (%.5f, %.5f, %.5f) N s per step, m g dt = %.5f; "
                  "angular %.2g\n",
                  j.x, j.y, j.z, 2 * G * dt, length(aj));
    assert_near(j.y, 2 * G * dt, 0.01 * 2 * G * dt);
    assert_near(j.x, 0, 1e-4);
    assert_near(j.z, 0, 1e-4);
    assert_near(length(aj), 0, 1e-4);
    assert_ok(phys_joint_get_applied_impulse(f->world, joint, NULL, NULL));  // both optional
}

// Two overlapping boxes joined by a ball socket do not push each other apart by default;
// with collide_connected they do (and report the contact).
static void test_joined_bodies_collide_only_when_asked(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 60.0f;
    phys_world_set_gravity(f->world, v3(0, 0, 0));
    phys_shape_id cube = make_box(f->world, 0.25f, 0.25f, 0.25f);
    for (int collide = 0; collide < 2; ++collide) {
        const float z = 3.0f * (float)collide;
        phys_body_id a = make_dynamic(f->world, cube, v3(0, 1, z), 1, false);
        phys_body_id b = make_dynamic(f->world, cube, v3(0.45f, 1, z), 1, false);
        phys_point_joint_def def = phys_default_point_joint_def();
        def.body_a = a;
        def.body_b = b;
        def.pivot = v3(0.225f, 1, z);
        def.collide_connected = collide != 0;
        phys_joint_id joint;
        assert_ok(phys_joint_create_point(f->world, &def, &joint));
        run(f->world, dt, 10);
        phys_contact c;
        const bool touching = find_contact(f->world, a, b, 0, &c);
        print_message("collide_connected %d: contact reported %d\n", collide, touching);
        assert_int_equal(touching, collide != 0);
    }
}

// ---- refusals and lifetime ------------------------------------------------------------

static void test_bad_joint_input_is_refused_naming_the_field(void **state) {
    fixture *f = *state;
    phys_shape_id cube = make_box(f->world, 0.25f, 0.25f, 0.25f);
    phys_body_id a = make_dynamic(f->world, cube, v3(0, 1, 0), 1, true);
    phys_body_id b = make_dynamic(f->world, cube, v3(1, 1, 0), 1, true);
    phys_body_id wall = make_static(f->world, cube, v3(3, 1, 0));
    phys_joint_id j = {0, 0, 0};

    phys_hinge_joint_def h = phys_default_hinge_joint_def();
    assert_refused(phys_joint_create_hinge(f->world, &h, &j), PHYS_ERR_INVALID_ARG,
                   "phys_joint_create_hinge: phys_hinge_joint_def.body_a is the null id");
    h.body_a = wall;  // a static body and the world: nothing to move
    assert_refused(phys_joint_create_hinge(f->world, &h, &j), PHYS_ERR_INVALID_ARG,
                   "phys_hinge_joint_def.body_a must be PHYS_BODY_DYNAMIC (got PHYS_BODY_STATIC)");
    h.body_a = a;
    h.body_b = a;
    assert_refused(phys_joint_create_hinge(f->world, &h, &j), PHYS_ERR_INVALID_ARG,
                   "phys_hinge_joint_def.body_a and body_b are the same body (index1 1)");
    h.body_b = b;
    h.pivot.y = NAN;
    assert_refused(phys_joint_create_hinge(f->world, &h, &j), PHYS_ERR_INVALID_ARG,
                   "phys_hinge_joint_def.pivot.y must be finite (got nan)");
    h.pivot.y = 1;
    h.axis = v3(0, 0, 0);
    assert_refused(phys_joint_create_hinge(f->world, &h, &j), PHYS_ERR_INVALID_ARG,
                   "phys_hinge_joint_def.axis must be a direction of length >= 1e-06 (got 0, 0, 0)");
    h.axis = v3(0, 0, 1);
    h.lower_angle = 1.0f;
    h.upper_angle = 0.5f;
    assert_refused(phys_joint_create_hinge(f->world, &h, &j), PHYS_ERR_INVALID_ARG,
                   "phys_hinge_joint_def.lower_angle (1) must be <= phys_hinge_joint_def.upper_angle (0.5)");
    h.lower_angle = -4.0f;  // checked even with the limit off
    assert_refused(phys_joint_create_hinge(f->world, &h, &j), PHYS_ERR_INVALID_ARG,
                   "phys_hinge_joint_def.lower_angle must be finite and in [-3.14159, 3.14159] (got -4)");
    h.lower_angle = 0;
    h.max_motor_torque = -1;
    assert_refused(phys_joint_create_hinge(f->world, &h, &j), PHYS_ERR_INVALID_ARG,
                   "phys_hinge_joint_def.max_motor_torque must be finite and >= 0 (got -1)");
    h.max_motor_torque = 0;
    h.motor_speed = INFINITY;
    assert_refused(phys_joint_create_hinge(f->world, &h, &j), PHYS_ERR_INVALID_ARG,
                   "phys_hinge_joint_def.motor_speed must be finite (got inf)");
    assert_int_equal(j.index1, 0);  // nothing was created
    assert_refused(phys_joint_create_hinge(f->world, NULL, &j), PHYS_ERR_INVALID_ARG,
                   "phys_joint_create_hinge: def must not be NULL");

    phys_slider_joint_def s = phys_default_slider_joint_def();
    s.body_a = a;
    s.axis = v3(NAN, 0, 0);
    assert_refused(phys_joint_create_slider(f->world, &s, &j), PHYS_ERR_INVALID_ARG,
                   "phys_slider_joint_def.axis.x must be finite (got nan)");
    s.axis = v3(1, 0, 0);
    s.lower_translation = 2;
    s.upper_translation = -INFINITY;
    assert_refused(phys_joint_create_slider(f->world, &s, &j), PHYS_ERR_INVALID_ARG,
                   "phys_slider_joint_def.upper_translation must be finite (got -inf)");

    // Calls that belong to other joint types, and bad motor and limit values.
    phys_point_joint_def p = phys_default_point_joint_def();
    p.body_a = a;
    p.body_b = wall;
    phys_joint_id ball;
    assert_ok(phys_joint_create_point(f->world, &p, &ball));
    assert_refused(phys_joint_set_motor(f->world, ball, true, 1, 1), PHYS_ERR_INVALID_ARG,
                   "phys_joint_set_motor: the joint is a PHYS_JOINT_POINT; only hinge and slider joints have motors");
    assert_refused(phys_joint_set_limits(f->world, ball, true, 0, 1), PHYS_ERR_INVALID_ARG,
                   "only hinge and slider joints have limits");
    float v;
    assert_refused(phys_joint_get_angle(f->world, ball, &v), PHYS_ERR_INVALID_ARG,
                   "the joint is a PHYS_JOINT_POINT; only hinge joints have an angle");
    h = phys_default_hinge_joint_def();
    h.body_a = a;
    phys_joint_id hinge;
    assert_ok(phys_joint_create_hinge(f->world, &h, &hinge));
    assert_refused(phys_joint_get_position(f->world, hinge, &v), PHYS_ERR_INVALID_ARG,
                   "only slider joints have a position (hinges: phys_joint_get_angle)");
    assert_refused(phys_joint_set_limits(f->world, hinge, true, 0.5f, -0.5f), PHYS_ERR_INVALID_ARG,
                   "phys_joint_set_limits: lower (0.5) must be <= upper (-0.5)");
    assert_refused(phys_joint_set_motor(f->world, hinge, false, NAN, 1), PHYS_ERR_INVALID_ARG,
                   "phys_joint_set_motor: target_velocity must be finite (got nan)");
    assert_refused(phys_joint_set_motor(f->world, hinge, true, 1, -2), PHYS_ERR_INVALID_ARG,
                   "max_force must be finite and >= 0 (got -2)");
    assert_refused(phys_joint_get_angle(f->world, hinge, NULL), PHYS_ERR_INVALID_ARG,
                   "out must not be NULL");

    // Contact queries.
    int count = -1;
    phys_contact c[2];
    assert_refused(phys_world_get_contacts(f->world, -1, c, 2, &count), PHYS_ERR_INVALID_ARG,
                   "phys_world_get_contacts: min_impulse must be finite and >= 0 N·s (got -1)");
    assert_int_equal(count, 0);
    assert_refused(phys_world_get_contacts(f->world, 0, c, -1, &count), PHYS_ERR_INVALID_ARG,
                   "max must be >= 0 (got -1)");
    assert_refused(phys_world_get_contacts(f->world, 0, NULL, 2, &count), PHYS_ERR_INVALID_ARG,
                   "out (with max > 0) must not be NULL");
    assert_ok(phys_world_get_contacts(f->world, 0, NULL, 0, &count));
}

static void test_stale_joint_ids_are_refused(void **state) {
    fixture *f = *state;
    phys_body_id a = make_dynamic(f->world, make_sphere(f->world, 0.1f), v3(0, 1, 0), 1, true);
    phys_hinge_joint_def def = phys_default_hinge_joint_def();
    def.body_a = a;
    phys_joint_id old;
    assert_ok(phys_joint_create_hinge(f->world, &def, &old));
    assert_true(phys_joint_is_valid(f->world, old));
    phys_joint_type type;
    assert_ok(phys_joint_get_type(f->world, old, &type));
    assert_int_equal(type, PHYS_JOINT_HINGE);
    assert_ok(phys_joint_destroy(f->world, old));
    assert_false(phys_joint_is_valid(f->world, old));
    assert_refused(phys_joint_set_motor(f->world, old, true, 1, 1), PHYS_ERR_STALE_ID,
                   "phys_joint_set_motor: phys_joint_id is stale (index1 1, generation 1, current 2): "
                   "attempt to use a destroyed joint");
    assert_refused(phys_joint_destroy(f->world, old), PHYS_ERR_STALE_ID, "attempt to use a destroyed joint");
    // The slot is reused; the old id stays stale.
    phys_joint_id fresh;
    assert_ok(phys_joint_create_hinge(f->world, &def, &fresh));
    assert_int_equal(fresh.index1, old.index1);
    assert_false(phys_joint_is_valid(f->world, old));
    assert_true(phys_joint_is_valid(f->world, fresh));
    phys_joint_id null_joint = {0, 0, 0};
    assert_refused(phys_joint_destroy(f->world, null_joint), PHYS_ERR_INVALID_ARG,
                   "phys_joint_id is the null id (all zero): no joint given");
    assert_false(phys_joint_is_valid(NULL, fresh));
    // A destroyed body cannot be joined.
    phys_body_id gone = make_dynamic(f->world, make_sphere(f->world, 0.1f), v3(1, 1, 0), 1, true);
    assert_ok(phys_body_destroy(f->world, gone));
    def.body_b = gone;
    assert_refused(phys_joint_create_hinge(f->world, &def, &fresh), PHYS_ERR_STALE_ID,
                   "phys_hinge_joint_def.body_b is stale");
}

// A chain: world - A - B - C by ball sockets. Destroying B ends the joints A-B and B-C; C,
// no longer held, falls; A still hangs from the world.
static void test_destroying_a_body_invalidates_its_joints(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 60.0f;
    phys_shape_id link = make_sphere(f->world, 0.1f);
    phys_body_id a = make_dynamic(f->world, link, v3(0, 3.0f, 0), 1, true);
    phys_body_id b = make_dynamic(f->world, link, v3(0, 2.6f, 0), 1, true);
    phys_body_id c = make_dynamic(f->world, link, v3(0, 2.2f, 0), 1, true);
    phys_point_joint_def def = phys_default_point_joint_def();
    phys_joint_id j[3];
    def.body_a = a;
    def.pivot = v3(0, 3.2f, 0);
    assert_ok(phys_joint_create_point(f->world, &def, &j[0]));
    def.body_b = a;
    def.body_a = b;
    def.pivot = v3(0, 2.8f, 0);
    assert_ok(phys_joint_create_point(f->world, &def, &j[1]));
    def.body_b = b;
    def.body_a = c;
    def.pivot = v3(0, 2.4f, 0);
    assert_ok(phys_joint_create_point(f->world, &def, &j[2]));
    run(f->world, dt, 180);  // 3 s hanging still: long enough to fall asleep
    bool awake = true;
    assert_ok(phys_body_is_awake(f->world, c, &awake));
    const double c_before = position_of(f->world, c).y;

    assert_ok(phys_body_destroy(f->world, b));
    assert_true(phys_joint_is_valid(f->world, j[0]));
    assert_false(phys_joint_is_valid(f->world, j[1]));
    assert_false(phys_joint_is_valid(f->world, j[2]));
    assert_refused(phys_joint_destroy(f->world, j[2]), PHYS_ERR_STALE_ID, "attempt to use a destroyed joint");
    run(f->world, dt, 30);
    // Woken and falling freely: 30 semi-implicit Euler steps drop it g dt² 30·31/2 = 1.267 m.
    const double c_drop = c_before - position_of(f->world, c).y;
    const double free_fall = G * dt * dt * 30 * 31 / 2.0;
    print_message("chain: C asleep before: %d; fell %.4f m in 0.5 s after B went (free fall %.4f)\n",
                  !awake, c_drop, free_fall);
    assert_false(awake);  // asleep before: destroying B must wake it
    assert_near(c_drop, free_fall, 0.001);
    assert_near(position_of(f->world, a).y, 3.0, 0.01);
}

// Everything freed with joints of every type still alive (valgrind checks the leaks).
static void test_destroying_the_world_frees_its_joints(void **state) {
    (void)state;
    phys_world_def wd = phys_default_world_def();
    phys_world *w = NULL;
    assert_ok(phys_world_create(&wd, &w));
    phys_shape_id cube = make_box(w, 0.2f, 0.2f, 0.2f);
    phys_body_id ground = make_ground(w);
    phys_body_id body[4];
    for (int i = 0; i < 4; ++i) body[i] = make_dynamic(w, cube, v3((float)i, 1, 0), 1, true);
    phys_hinge_joint_def h = phys_default_hinge_joint_def();
    h.body_a = body[0];
    h.body_b = ground;
    h.enable_motor = true;
    h.max_motor_torque = 1;
    phys_slider_joint_def s = phys_default_slider_joint_def();
    s.body_a = body[1];
    phys_fixed_joint_def x = phys_default_fixed_joint_def();
    x.body_a = body[2];
    x.body_b = body[1];
    phys_point_joint_def p = phys_default_point_joint_def();
    p.body_a = body[3];
    p.body_b = body[2];
    phys_joint_id j;
    assert_ok(phys_joint_create_hinge(w, &h, &j));
    assert_ok(phys_joint_create_slider(w, &s, &j));
    assert_ok(phys_joint_create_fixed(w, &x, &j));
    assert_ok(phys_joint_create_point(w, &p, &j));
    run(w, 1.0f / 60.0f, 10);
    phys_world_destroy(w);
}

// ---- contact reports ------------------------------------------------------------------

// A 2 kg box (0.4 m cube) dropped from 0.5 m onto a static floor (a box, as the game's
// containers have) hits at v = 3.1 m/s. At the first step with a contact the floor's impulse
// is the momentum it took out, m (v_after - v_before + g dt), and the box stops in that step
// (restitution 0), so that is m |v| within 15%. The point is under the box, the normal up.
static void test_box_dropped_on_floor_reports_impulse_m_dv_at_first_touch(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 60.0f;
    phys_body_id floor_body = make_floor(f->world);
    phys_body_id box = make_dynamic(f->world, make_box(f->world, 0.2f, 0.2f, 0.2f),
                                    v3(0.3f, 0.7f, -0.2f), 2, true);
    phys_contact c;
    int step = -1;
    double v_before = 0, v_after = 0;
    for (int i = 0; i < 120 && step < 0; ++i) {
        v_before = velocity_of(f->world, box).y;
        assert_ok(phys_world_step(f->world, dt));
        v_after = velocity_of(f->world, box).y;
        if (find_contact(f->world, floor_body, box, 0, &c)) step = i;
    }
    assert_true(step > 0);
    const double m = mass_of(f->world, box);
    const double m_dv = m * (v_after - v_before + G * dt);  // what the contact did
    const phys_vec3 p = position_of(f->world, box);
    phys_contact next;
    assert_ok(phys_world_step(f->world, dt));
    const bool second = find_contact(f->world, floor_body, box, 0, &next);
    print_message("drop: first contact at step %d, impulse %.4f N s, m dv = %.4f, m |v_before| = %.4f "
                  "(%+.1f%%), next step %.4f; point (%.3f, %.3f, %.3f) under (%.3f, %.3f), "
                  "normal (%.3f, %.3f, %.3f), v after %.3f m/s\n",
                  step, c.impulse, m_dv, m * fabs(v_before), 100 * (c.impulse / (m * fabs(v_before)) - 1),
                  second ? next.impulse : 0.0, c.point.x, c.point.y, c.point.z, p.x, p.z,
                  c.normal.x, c.normal.y, c.normal.z, v_after);
    assert_true(same_body(c.a, floor_body));  // created first: lower index1
    assert_true(same_body(c.b, box));
    assert_near(c.impulse, m_dv, 0.01 * m_dv);
    assert_near(c.impulse, m * fabs(v_before), 0.15 * m * fabs(v_before));
    assert_true(!second || next.impulse < 0.1 * c.impulse);  // one report for the hit
    assert_near(c.point.x, p.x, 0.01);
    assert_near(c.point.z, p.z, 0.01);
    assert_near(c.point.y, 0, 0.02);
    assert_near(c.normal.y, 1, 1e-3);  // from the floor (a) towards the box (b)
}

// At rest the floor pushes m g dt each step: reported at threshold 0, not above 2 m g dt;
// asleep, nothing is reported at all.
static void test_resting_box_reports_m_g_dt_per_step_and_nothing_asleep(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 60.0f;
    phys_body_id floor_body = make_ground(f->world);
    phys_shape_id cube = make_box(f->world, 0.2f, 0.2f, 0.2f);
    phys_body_id awake_box = make_dynamic(f->world, cube, v3(0, 0.2f, 0), 2, false);
    phys_body_id sleepy_box = make_dynamic(f->world, cube, v3(2, 0.2f, 0), 2, true);
    run(f->world, dt, 60);
    const double mgdt = 2 * G * dt;
    phys_contact c;
    assert_true(find_contact(f->world, floor_body, awake_box, 0, &c));
    const double resting = c.impulse;
    assert_false(find_contact(f->world, floor_body, awake_box, (float)(2 * mgdt), &c));
    run(f->world, dt, 180);  // 3 s: the other box is asleep
    bool awake = true;
    assert_ok(phys_body_is_awake(f->world, sleepy_box, &awake));
    print_message("resting: %.5f N s per step, m g dt = %.5f (%+.2f%%); sleeping box awake: %d\n",
                  resting, mgdt, 100 * (resting / mgdt - 1), awake);
    assert_near(resting, mgdt, 0.02 * mgdt);
    assert_false(awake);
    assert_false(find_contact(f->world, floor_body, sleepy_box, 0, &c));
    assert_true(find_contact(f->world, floor_body, awake_box, 0, &c));
}

// A stack and a row of boxes: pairs come sorted by (a.index1, b.index1), a.index1 < b.index1,
// and count says how many there are even when fewer fit.
static void test_contacts_come_sorted_and_count_all_pairs(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 60.0f;
    phys_shape_id cube = make_box(f->world, 0.2f, 0.2f, 0.2f);
    phys_body_id top = make_dynamic(f->world, cube, v3(0, 0.6f, 0), 1, false);
    phys_body_id floor_body = make_ground(f->world);
    phys_body_id bottom = make_dynamic(f->world, cube, v3(0, 0.2f, 0), 1, false);
    make_dynamic(f->world, cube, v3(1, 0.2f, 0), 1, false);
    run(f->world, dt, 60);
    phys_contact c[8];
    int n = 0;
    assert_ok(phys_world_get_contacts(f->world, 0, c, 8, &n));
    assert_int_equal(n, 3);  // top-bottom, floor-bottom, floor-other
    for (int i = 0; i < n; ++i) {
        assert_true(c[i].a.index1 < c[i].b.index1);
        if (i > 0) {
            assert_true(c[i - 1].a.index1 < c[i].a.index1 ||
                        (c[i - 1].a.index1 == c[i].a.index1 && c[i - 1].b.index1 < c[i].b.index1));
        }
    }
    // top (index1 1) sits on bottom: normal from top towards bottom is down; it carries 1 kg.
    assert_true(same_body(c[0].a, top) && same_body(c[0].b, bottom));
    assert_near(c[0].normal.y, -1, 1e-3);
    assert_near(c[0].impulse, 1 * G * dt, 0.02 * G * dt);
    assert_true(same_body(c[1].a, floor_body) && same_body(c[1].b, bottom));
    assert_near(c[1].impulse, 2 * G * dt, 0.02 * 2 * G * dt);  // both boxes
    phys_contact one;
    assert_ok(phys_world_get_contacts(f->world, 0, &one, 1, &n));
    assert_int_equal(n, 3);
    assert_memory_equal(&one, &c[0], sizeof one);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_joint_defs_have_the_documented_defaults),
        cmocka_unit_test_setup_teardown(test_door_on_hinge_swings_down_and_stops_at_its_limit, setup, teardown),
        cmocka_unit_test_setup_teardown(test_motorised_hinge_turns_at_the_target_speed, setup, teardown),
        cmocka_unit_test_setup_teardown(test_slider_moves_only_along_its_axis, setup, teardown),
        cmocka_unit_test_setup_teardown(test_slider_stops_at_its_limit_and_its_motor_drives_it, setup, teardown),
        cmocka_unit_test_setup_teardown(test_fixed_joint_keeps_the_relative_pose, setup, teardown),
        cmocka_unit_test_setup_teardown(test_pendulum_on_point_joint_keeps_its_length_and_period, setup, teardown),
        cmocka_unit_test_setup_teardown(test_joint_reports_the_impulse_that_holds_a_hanging_body, setup, teardown),
        cmocka_unit_test_setup_teardown(test_joined_bodies_collide_only_when_asked, setup, teardown),
        cmocka_unit_test_setup_teardown(test_body_hanging_from_a_kinematic_body_follows_it, setup, teardown),
        cmocka_unit_test_setup_teardown(test_bad_joint_input_is_refused_naming_the_field, setup, teardown),
        cmocka_unit_test_setup_teardown(test_stale_joint_ids_are_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_destroying_a_body_invalidates_its_joints, setup, teardown),
        cmocka_unit_test(test_destroying_the_world_frees_its_joints),
        cmocka_unit_test_setup_teardown(test_box_dropped_on_floor_reports_impulse_m_dv_at_first_touch, setup, teardown),
        cmocka_unit_test_setup_teardown(test_resting_box_reports_m_g_dt_per_step_and_nothing_asleep, setup, teardown),
        cmocka_unit_test_setup_teardown(test_contacts_come_sorted_and_count_all_pairs, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
