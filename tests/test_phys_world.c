// The Bullet wrapper's world as a whole (fluid/bullet/phys.h): bad input rejected naming the field,
// stale and foreign ids, a world destroyed with live objects, and bit-identical reruns.

#include <malloc.h>
#include <pthread.h>

#include "tests/phys_fixture.h"

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

// Bullet keeps 1/mass and 1/inertia in floats: a sphere of density 9.6e-38 kg/m^3 (fuzz_phys_api's
// find: a mass of 1.8e-41 kg, a denormal) came out of its first step as NaN. Bodies under
// PHYS_MIN_MASS are refused, as a mass or from a density, and so is one too small to turn.
static void test_mass_under_the_limit_is_refused_and_the_limit_steps(void **state) {
    fixture *f = *state;
    phys_body_def def = phys_default_body_def();
    phys_sphere sphere = {0.0356f};
    assert_ok(phys_shape_create_sphere(f->world, &sphere, &def.shape));
    def.density = 9.62378154e-38f;
    phys_body_id id = {0, 0, 0};
    assert_int_equal(phys_body_create(f->world, &def, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_body_def.density 9.62378e-38 times the sphere volume");
    assert_contains(phys_world_last_error(f->world), "it must be in [PHYS_MIN_MASS = 1e-06, PHYS_MAX_MASS = 1e+06 kg]");
    def.mass = 1e-9f;
    assert_int_equal(phys_body_create(f->world, &def, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world),
                    "phys_body_def.mass must be 0 (from the density) or at least PHYS_MIN_MASS = 1e-06 kg (got 1e-09)");
    phys_sphere speck = {1e-20f};  // 1 kg: inertia 4e-41 kg m^2, whose inverse is no float
    phys_body_def tiny = phys_default_body_def();
    assert_ok(phys_shape_create_sphere(f->world, &speck, &tiny.shape));
    tiny.mass = 1;
    assert_int_equal(phys_body_create(f->world, &tiny, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "too small to invert in a float: make the shape larger");
    assert_int_equal(phys_world_get_body_count(f->world), 0);

    // At the limit a body falls, spins and stays finite.
    def.mass = PHYS_MIN_MASS;
    def.angular_velocity = v3(0, 3, 0);
    assert_ok(phys_body_create(f->world, &def, &id));
    run(f->world, 1.0f / 60.0f, 30);
    phys_vec3 p;
    phys_quat q;
    assert_ok(phys_body_get_pose(f->world, id, &p, &q));
    assert_near(p.y, -9.81 / 3600.0 * 30 * 31 / 2, 1e-3);  // 30 steps of free fall (symplectic Euler)
    assert_true(isfinite(q.x) && isfinite(q.y) && isfinite(q.w));
}

// Bullet lets a body of about 1.5e7 kg fall straight through a static floor (1e7 rests): the
// wrapper refuses bodies over PHYS_MAX_MASS, given as a mass or as a density, and one at the
// limit rests on a static box as a light one does.
static void test_mass_over_the_limit_is_refused_and_the_limit_rests(void **state) {
    fixture *f = *state;
    phys_body_def def = phys_default_body_def();
    def.shape = make_box(f->world, 0.05f, 0.05f, 0.05f);
    def.mass = 2.0f * PHYS_MAX_MASS;
    phys_body_id id = {0, 0, 0};
    assert_int_equal(phys_body_create(f->world, &def, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_body_def.mass must be at most PHYS_MAX_MASS = 1e+06 kg (got 2e+06)");
    def.mass = 0;
    def.density = 2.0e9f;  // 0.001 m^3: 2e6 kg
    assert_int_equal(phys_body_create(f->world, &def, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "gives mass 2e+06 kg; it must be in [PHYS_MIN_MASS = 1e-06, PHYS_MAX_MASS = 1e+06 kg]");
    assert_int_equal(phys_world_get_body_count(f->world), 0);

    phys_body_def floor = phys_default_body_def();
    floor.type = PHYS_BODY_STATIC;
    floor.shape = make_box(f->world, 1, 0.025f, 1);
    floor.position = v3(0, -0.025f, 0);
    phys_body_id floor_id = {0, 0, 0};
    assert_ok(phys_body_create(f->world, &floor, &floor_id));
    def.density = 1000;
    def.mass = PHYS_MAX_MASS;
    def.position = v3(0, 0.3f, 0);
    phys_body_id heavy = {0, 0, 0}, light = {0, 0, 0};
    assert_ok(phys_body_create(f->world, &def, &heavy));
    def.mass = 1;
    def.position = v3(0.5f, 0.3f, 0);
    assert_ok(phys_body_create(f->world, &def, &light));
    run(f->world, 1.0f / 60.0f, 90);
    assert_near(position_of(f->world, heavy).y, 0.05, 0.002);
    assert_near(position_of(f->world, light).y, 0.05, 0.002);
}

// A C caller may store any int in an enum field: refused by value, with no undefined
// behaviour on the C++ side (UBSan, make sanitize, reported the load of 7 before 0.19.3).
static void test_enum_out_of_range_is_refused_naming_the_value(void **state) {
    fixture *f = *state;
    phys_body_def def = phys_default_body_def();
    def.shape = make_sphere(f->world, 1);
    int seven = 7;
    memcpy(&def.type, &seven, sizeof seven);
    phys_body_id id = {0, 0, 0};
    assert_int_equal(phys_body_create(f->world, &def, &id), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), "phys_body_def.type must be PHYS_BODY_STATIC, PHYS_BODY_KINEMATIC or PHYS_BODY_DYNAMIC (got 7)");
    phys_compound_part part;
    memset(&part, 0, sizeof part);
    part.rotation.w = 1;
    int seventy_seven = 77;
    memcpy(&part.type, &seventy_seven, sizeof seventy_seven);
    phys_compound c;
    memset(&c, 0, sizeof c);
    c.parts = &part;
    c.part_count = 1;
    phys_shape_id shape = {0, 0, 0};
    assert_int_equal(phys_shape_create_compound(f->world, &c, &shape), PHYS_ERR_INVALID_ARG);
    assert_contains(phys_world_last_error(f->world), ".type must be PHYS_SHAPE_BOX");
    assert_contains(phys_world_last_error(f->world), "(got 77)");
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
        cmocka_unit_test_setup_teardown(test_negative_mass_is_rejected_naming_the_field, setup, teardown),
        cmocka_unit_test_setup_teardown(test_mass_over_the_limit_is_refused_and_the_limit_rests, setup, teardown),
        cmocka_unit_test_setup_teardown(test_mass_under_the_limit_is_refused_and_the_limit_steps, setup, teardown),
        cmocka_unit_test_setup_teardown(test_enum_out_of_range_is_refused_naming_the_value, setup, teardown),
        cmocka_unit_test_setup_teardown(test_zero_size_box_is_rejected_naming_the_field, setup, teardown),
        cmocka_unit_test_setup_teardown(test_nan_pose_is_rejected_naming_the_field, setup, teardown),
        cmocka_unit_test_setup_teardown(test_stale_id_is_rejected_after_destroy, setup, teardown),
        cmocka_unit_test_setup_teardown(test_id_from_another_world_is_rejected, setup, teardown),
        cmocka_unit_test_setup_teardown(test_triangle_mesh_on_dynamic_body_is_rejected, setup, teardown),
        cmocka_unit_test_setup_teardown(test_static_body_velocity_is_rejected, setup, teardown),
        cmocka_unit_test(test_invalid_world_def_is_reported_through_the_log),
        cmocka_unit_test(test_destroying_world_with_live_objects_frees_everything),
        cmocka_unit_test(test_same_scene_gives_bit_identical_state),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
