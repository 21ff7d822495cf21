// Which bodies the coupling takes (fluid/bullet/coupling.h): bad input rejected with the field
// named, a compound paddle wheel on an axle, and a compound beyond the collider limit refused.
#include "tests/coupling_fixture.h"

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

// A step too short for Bullet (1e-7 s a substep, up to max_substeps of them) is refused
// before either world moves, so they stay in lockstep; a fluid world destroyed before the
// coupling is said so by every call, and cpl_destroy then frees only the coupling.
static void a_step_too_short_or_a_fluid_world_gone_is_refused(void **state)
{
    scene s;
    scene_def sd = default_scene_def();
    scene_create(*state, &s, &sd);
    float half[3] = { 0.05f, 0.05f, 0.05f }, at[3] = { 0.2f, 0.2f, 0.2f };
    add_box(&s, PHYS_BODY_DYNAMIC, half, at, 500.0f, NULL);
    assert_int_equal(cpl_step(s.cpl, 2e-6f), CPL_ERR_INVALID_ARG);
    assert_contains(cpl_last_error(s.cpl), "cpl_step: dt must be in [3.2e-06, 1] s");
    assert_int_equal(cpl_step_count(s.cpl), 0);
    pbf_step_stats st[4];
    assert_int_equal(pbf_world_poll_stats(s.fluid, st, 4, true), 0); // the fluid did not step either
    assert_int_equal(cpl_step(s.cpl, 1.0f / 60.0f), CPL_OK);
    cpl_def got;
    assert_int_equal(cpl_get_def(s.cpl, NULL), CPL_ERR_INVALID_ARG);
    assert_contains(cpl_last_error(s.cpl), "cpl_get_def: out must not be NULL");
    assert_int_equal(cpl_get_def(s.cpl, &got), CPL_OK);
    pbf_world_destroy(s.fluid);
    assert_int_equal(cpl_step(s.cpl, 1.0f / 60.0f), CPL_ERR_FLUID);
    assert_contains(cpl_last_error(s.cpl), "cpl_step: the fluid world (cpl_def.fluid) was destroyed before the coupling");
    cpl_destroy(s.cpl); // read the freed world before 0.19.3 (AddressSanitizer: make sanitize)
    phys_world_destroy(s.phys);
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
        cmocka_unit_test(bad_input_is_rejected_with_the_field_named),
        cmocka_unit_test(a_step_too_short_or_a_fluid_world_gone_is_refused),
        cmocka_unit_test(paddle_wheel_under_a_stream_turns_the_way_the_water_pushes),
        cmocka_unit_test(paddle_wheel_without_water_stays_still),
        cmocka_unit_test(compound_beyond_the_collider_limit_is_refused),
    };
    const char *filter = getenv("SEICHE_TEST_FILTER"); // e.g. "*750*"
    if (filter && *filter) cmocka_set_test_filter(filter);
    return cmocka_run_group_tests(tests, setup, teardown);
}
