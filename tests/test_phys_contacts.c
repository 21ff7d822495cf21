// Tests of the contact sums of the Bullet C API wrapper (fluid/bullet/phys.h,
// phys_world_set_contact_sums / phys_world_take_contact_sums): a host that steps the world
// several times per frame gets each pair's hits over the frame, as the sum of what each
// step reported.
#include "tests/phys_fixture.h"

static phys_body_id make_dynamic(phys_world *w, phys_shape_id shape, phys_vec3 position, float mass) {
    phys_body_def def = phys_default_body_def();
    def.shape = shape;
    def.position = position;
    def.mass = mass;
    def.allow_sleep = false;
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(w, &def, &id));
    return id;
}

static phys_body_id make_floor(phys_world *w) {
    phys_body_def def = phys_default_body_def();
    def.type = PHYS_BODY_STATIC;
    def.shape = make_box(w, 5, 0.1f, 5);
    def.position = v3(0, -0.1f, 0);
    phys_body_id id = {0, 0, 0};
    assert_ok(phys_body_create(w, &def, &id));
    return id;
}

static bool same_body(phys_body_id a, phys_body_id b) {
    return a.index1 == b.index1 && a.world0 == b.world0 && a.generation == b.generation;
}

// The pair (a, b) in a list of contacts, or NULL.
static const phys_contact *pair_in(const phys_contact *c, int n, phys_body_id a, phys_body_id b) {
    for (int i = 0; i < n; ++i) {
        if (same_body(c[i].a, a) && same_body(c[i].b, b)) return &c[i];
    }
    return NULL;
}

// Two boxes drop on a floor and onto each other, stepped 8 times per "frame": each frame's
// sums are the sums of the 8 steps' reports, pair by pair (impulse; point and normal as
// impulse-weighted means), sorted, and taking them empties them.
static void test_sums_are_the_steps_reports_added_up(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 480.0f;
    phys_body_id floor_body = make_floor(f->world);
    phys_shape_id cube = make_box(f->world, 0.1f, 0.1f, 0.1f);
    phys_body_id low = make_dynamic(f->world, cube, v3(0, 0.3f, 0), 1);
    phys_body_id high = make_dynamic(f->world, cube, v3(0.05f, 0.6f, 0.02f), 3);
    assert_ok(phys_world_set_contact_sums(f->world, true));
    int frames_with_both = 0, frames_with_any = 0;
    for (int frame = 0; frame < 60; ++frame) {
        double want[2] = {0, 0};
        phys_vec3 point[2] = {zero3, zero3}, normal[2] = {zero3, zero3};
        const phys_body_id pa[2] = {floor_body, low}, pb[2] = {low, high};
        for (int s = 0; s < 8; ++s) {
            assert_ok(phys_world_step(f->world, dt));
            phys_contact c[8];
            int n = 0;
            assert_ok(phys_world_get_contacts(f->world, 0, c, 8, &n));
            for (int k = 0; k < 2; ++k) {
                const phys_contact *p = pair_in(c, n, pa[k], pb[k]);
                if (!p) continue;
                want[k] += p->impulse;
                point[k] = v3(point[k].x + p->impulse * p->point.x, point[k].y + p->impulse * p->point.y,
                              point[k].z + p->impulse * p->point.z);
                normal[k] = v3(normal[k].x + p->impulse * p->normal.x, normal[k].y + p->impulse * p->normal.y,
                               normal[k].z + p->impulse * p->normal.z);
            }
        }
        phys_contact got[8];
        int n = -1;
        assert_ok(phys_world_take_contact_sums(f->world, 0, got, 8, &n));
        assert_true(n <= 3);
        for (int i = 1; i < n; ++i) assert_true(got[i - 1].a.index1 < got[i].a.index1 ||
                                                (got[i - 1].a.index1 == got[i].a.index1 &&
                                                 got[i - 1].b.index1 < got[i].b.index1));
        int present = 0;
        for (int k = 0; k < 2; ++k) {
            const phys_contact *p = pair_in(got, n, pa[k], pb[k]);
            if (want[k] == 0) {
                assert_null(p);
                continue;
            }
            assert_non_null(p);
            present++;
            assert_near(p->impulse, want[k], 1e-5 * want[k] + 1e-7);
            assert_near(p->point.x, point[k].x / want[k], 1e-4);
            assert_near(p->point.y, point[k].y / want[k], 1e-4);
            assert_near(p->point.z, point[k].z / want[k], 1e-4);
            const double len = sqrt(normal[k].x * normal[k].x + normal[k].y * normal[k].y + normal[k].z * normal[k].z);
            assert_near(p->normal.y, normal[k].y / len, 1e-4);
        }
        frames_with_any += present > 0;
        frames_with_both += present == 2;
        int again = -1;
        assert_ok(phys_world_take_contact_sums(f->world, 0, NULL, 0, &again));
        assert_int_equal(again, 0);  // taken: empty until the next step
    }
    print_message("contact sums: %d of 60 frames with a contact, %d with both pairs\n", frames_with_any,
                  frames_with_both);
    assert_true(frames_with_both > 20);  // the boxes came to rest on each other
}

// A 2 kg box falls 0.45 m onto the floor (3.0 m/s) in frames of 4 steps of 1/240 s. The first
// frame whose summed impulse passes 10 m g dt_frame holds the whole hit: the box's change of
// momentum in that frame, less gravity's, m (dv + g dt_frame); about m |v| (Bullet also
// pushes the box out of the overlap), and no later frame passes the threshold: the box lies
// still, each frame's sum m g dt_frame.
static void test_a_dropped_box_gives_one_frame_of_m_dv_then_its_weight(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 240.0f, frame_dt = 4 * dt;
    const double m = 2.0;
    phys_body_id floor_body = make_floor(f->world);
    phys_body_id box = make_dynamic(f->world, make_box(f->world, 0.15f, 0.1f, 0.15f), v3(0, 0.55f, 0), (float)m);
    assert_ok(phys_world_set_contact_sums(f->world, true));
    const double threshold = 10 * m * G * frame_dt;
    int hit_frame = -1, hits = 0;
    double hit = 0, v_before = 0, m_dv = 0, last = 0;
    for (int frame = 0; frame < 90; ++frame) {
        const double v0 = velocity_of(f->world, box).y;
        run(f->world, dt, 4);
        const double v1 = velocity_of(f->world, box).y;
        phys_contact c[4];
        int n = 0;
        assert_ok(phys_world_take_contact_sums(f->world, 0, c, 4, &n));
        const phys_contact *p = pair_in(c, n, floor_body, box);
        const double j = p ? p->impulse : 0;
        if (j > threshold) {
            hits++;
            if (hit_frame < 0) hit_frame = frame, hit = j, v_before = v0, m_dv = m * (v1 - v0 + G * frame_dt);
        }
        last = j;
    }
    print_message("dropped box: hit in frame %d, %.4f N s, m (dv + g dt) %.4f N s, %.3f m |v| (v %.3f m/s); "
                  "frames above %.3f N s: %d; at rest %.5f N s per frame (m g dt %.5f)\n",
                  hit_frame, hit, m_dv, hit / (m * fabs(v_before)), v_before, threshold, hits, last, m * G * frame_dt);
    assert_true(hit_frame > 0);
    assert_int_equal(hits, 1);
    assert_true(v_before < -2.5);
    assert_near(hit, m_dv, 0.01 * m_dv);
    assert_near(hit, m * fabs(v_before), 0.25 * m * fabs(v_before));
    assert_near(last, m * G * frame_dt, 0.02 * m * G * frame_dt);
}

// Sums are off in a new world: taking them is refused, naming the call to make; turning
// them off and on empties them; bad arguments are named; a pair whose body was destroyed
// after the step keeps the ids it had, now stale.
static void test_sums_must_be_on_and_arguments_are_checked(void **state) {
    fixture *f = *state;
    const float dt = 1.0f / 240.0f;
    int n = -1;
    phys_contact c[4];
    assert_int_equal(phys_world_take_contact_sums(f->world, 0, c, 4, &n), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_world_set_contact_sums(world, true)");
    assert_int_equal(n, 0);
    phys_body_id floor_body = make_floor(f->world);
    phys_body_id box = make_dynamic(f->world, make_box(f->world, 0.1f, 0.1f, 0.1f), v3(0, 0.1f, 0), 1);
    assert_ok(phys_world_set_contact_sums(f->world, true));
    run(f->world, dt, 3);
    assert_ok(phys_world_set_contact_sums(f->world, false));
    assert_ok(phys_world_set_contact_sums(f->world, true));
    assert_ok(phys_world_take_contact_sums(f->world, 0, c, 4, &n));
    assert_int_equal(n, 0);
    run(f->world, dt, 3);
    assert_int_equal(phys_world_take_contact_sums(f->world, -1, c, 4, &n), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "min_impulse must be finite and >= 0");
    assert_int_equal(phys_world_take_contact_sums(f->world, NAN, c, 4, &n), PHYS_ERR_INVALID_ARG);
    assert_int_equal(phys_world_take_contact_sums(f->world, 0, NULL, 4, &n), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "out (with max > 0) must not be NULL");
    assert_int_equal(phys_world_take_contact_sums(f->world, 0, c, -1, &n), PHYS_ERR_INVALID_ARG);
    assert_int_equal(phys_world_take_contact_sums(f->world, 0, c, 4, NULL), PHYS_ERR_INVALID_ARG);
    // The refused calls took nothing: the three steps are still there (3 m g dt).
    assert_ok(phys_body_destroy(f->world, box));
    assert_ok(phys_world_take_contact_sums(f->world, 0, c, 4, &n));
    assert_int_equal(n, 1);
    assert_true(same_body(c[0].a, floor_body) && same_body(c[0].b, box));
    assert_false(phys_body_is_valid(f->world, c[0].b));
    assert_near(c[0].impulse, 3 * G * dt, 0.05 * 3 * G * dt);
    // A threshold leaves out the pairs at or below it, and still empties the sums.
    run(f->world, dt, 2);
    assert_ok(phys_world_take_contact_sums(f->world, 1e9f, c, 4, &n));
    assert_int_equal(n, 0);
    assert_ok(phys_world_take_contact_sums(f->world, 0, c, 4, &n));
    assert_int_equal(n, 0);
    assert_int_equal(phys_world_set_contact_sums(NULL, true), PHYS_ERR_INVALID_ARG);
}


// phys_world_def.split_impulse_depth: with Bullet's 4 cm, a 2 kg box landing at 2.9 m/s
// (frames of 4 steps of 1/240 s) overlaps by about v dt and leaves again at about 0.2 v: its
// hit is about 1.2 m v, and it lands a second time 3 frames later. With 0 it does not hop: it
// lands once, with m v plus the frame's gravity. A depth outside [0, 1] m is refused.
static double landing(float depth, int *hits, double *second)
{
    phys_world_def def = phys_default_world_def();
    def.split_impulse_depth = depth;
    phys_world *w = NULL;
    assert_ok(phys_world_create(&def, &w));
    phys_body_id floor_body = make_floor(w);
    phys_body_id box = make_dynamic(w, make_box(w, 0.15f, 0.1f, 0.15f), v3(0, 0.55f, 0), 2);
    assert_ok(phys_world_set_contact_sums(w, true));
    const float dt = 1.0f / 240.0f;
    double first = 0, v_before = 0;
    *hits = 0;
    *second = 0;
    bool touching = false;
    for (int frame = 0; frame < 90; ++frame) {
        const double v0 = velocity_of(w, box).y;
        run(w, dt, 4);
        phys_contact c[4];
        int n = 0;
        assert_ok(phys_world_take_contact_sums(w, 0, c, 4, &n));
        const phys_contact *p = pair_in(c, n, floor_body, box);
        // A landing: contact after a frame without.
        if (p && !touching) {
            if (*hits == 0) first = p->impulse, v_before = v0;
            else if (*hits == 1) *second = p->impulse;
            (*hits)++;
        }
        if (getenv("SEICHE_TEST_TRACE")) print_message("depth %.2f frame %d: %.4f\n", (double)depth, frame, p ? p->impulse : 0.0);
        touching = p != NULL;
    }
    phys_world_destroy(w);
    return first / (2 * fabs(v_before));
}

static void test_split_impulse_depth_0_stops_landings_from_hopping(void **state)
{
    (void)state;
    int hits_default = 0, hits_zero = 0;
    double second_default = 0, second_zero = 0;
    const double r_default = landing(0.04f, &hits_default, &second_default);
    const double r_zero = landing(0.0f, &hits_zero, &second_zero);
    print_message("landing at depth 0.04: hit %.3f m v, %d landings (the second %.3f N s); at depth 0: hit %.3f m v, "
                  "%d landings\n",
                  r_default, hits_default, second_default, r_zero, hits_zero);
    assert_true(r_default > 1.12);
    assert_true(hits_default >= 2);
    assert_int_equal(hits_zero, 1);
    // m v and the gravity of the frame's steps during and after the hit (at most 4 m g dt).
    assert_true(r_zero >= 1.0 && r_zero < 1.0 + 4 * G * (1.0 / 240) / 2.9 + 0.01);
    phys_world_def def = phys_default_world_def();
    assert_near(def.split_impulse_depth, 0.04, 1e-7);
    phys_world *w = NULL;
    def.split_impulse_depth = -0.01f;
    assert_int_equal(phys_world_create(&def, &w), PHYS_ERR_INVALID_ARG);
    assert_null(w);
    def.split_impulse_depth = NAN;
    assert_int_equal(phys_world_create(&def, &w), PHYS_ERR_INVALID_ARG);
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_sums_are_the_steps_reports_added_up, setup, teardown),
        cmocka_unit_test_setup_teardown(test_a_dropped_box_gives_one_frame_of_m_dv_then_its_weight, setup, teardown),
        cmocka_unit_test_setup_teardown(test_sums_must_be_on_and_arguments_are_checked, setup, teardown),
        cmocka_unit_test(test_split_impulse_depth_0_stops_landings_from_hopping),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
