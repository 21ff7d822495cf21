// The Bullet wrapper's shapes (fluid/bullet/phys.h): ray casts, mass from density, convex hulls
// and triangle meshes, compounds and motion factors, and shapes in use.

#include "tests/phys_fixture.h"

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

// The world-axis size of a body at its pose (the coupling's height along gravity).
static void test_extent_follows_the_pose(void **state) {
    fixture *f = *state;
    phys_world *w = f->world;
    phys_body_id box = make_body(w, PHYS_BODY_DYNAMIC, make_box(w, 0.3f, 0.1f, 0.2f), v3(0, 5, 0));
    phys_vec3 e;
    assert_ok(phys_body_get_extent(w, box, &e));
    assert_near(e.x, 0.6, 1e-4);
    assert_near(e.y, 0.2, 1e-4);
    assert_near(e.z, 0.4, 1e-4);
    // A quarter turn about z swaps x and y.
    const float s = 0.70710678f;
    assert_ok(phys_body_set_pose(w, box, v3(0, 5, 0), (phys_quat){0, 0, s, s}));
    assert_ok(phys_body_get_extent(w, box, &e));
    assert_near(e.x, 0.2, 1e-4);
    assert_near(e.y, 0.6, 1e-4);
    phys_body_id ball = make_body(w, PHYS_BODY_DYNAMIC, make_sphere(w, 0.25f), v3(3, 5, 0));
    assert_ok(phys_body_get_extent(w, ball, &e));
    assert_near(e.y, 0.5, 1e-4);
    assert_int_equal(phys_body_get_extent(w, ball, NULL), PHYS_ERR_INVALID_ARG);
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

// A hull measured without a world is the hull the world builds; bad clouds get the world's reasons.
static void test_convex_hull_is_measured_without_a_world(void **state) {
    fixture *f = *state;
    phys_vec3 pts[9];
    for (int i = 0; i < 8; ++i) pts[i] = v3(i & 1 ? 0.5f : -0.5f, i & 2 ? 1.0f : -1.0f, i & 4 ? 0.5f : -0.5f);
    pts[8] = v3(0.1f, 0.2f, 0);  // inside
    phys_convex_hull hull = {pts, 9};
    phys_hull_info info;
    char msg[256] = "stale";
    assert_ok(phys_convex_hull_measure(&hull, &info, msg, sizeof msg));
    assert_string_equal(msg, "");
    assert_int_equal(info.vertex_count, 8);
    assert_int_equal(info.plane_count, 6);
    assert_near(info.volume, 2.0, 1e-5);
    phys_shape_id shape;
    assert_ok(phys_shape_create_convex_hull(f->world, &hull, &shape));
    phys_shape_desc d;
    assert_ok(phys_shape_get_desc(f->world, shape, &d));
    assert_int_equal(d.hull.point_count, info.vertex_count);
    assert_int_equal(d.hull.plane_count, info.plane_count);
    assert_near(d.volume, info.volume, 1e-6);

    const phys_hull_info untouched = {77, 78, 79.0f};
    info = untouched;
    phys_vec3 flat[4] = {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {1, 0, 1}};
    phys_convex_hull bad = {flat, 4};
    assert_int_equal(phys_convex_hull_measure(&bad, &info, msg, sizeof msg), PHYS_ERR_INVALID_ARG);
    assert_contains(msg, "phys_convex_hull_measure: phys_convex_hull.points must span a volume");
    pts[2].y = NAN;
    assert_int_equal(phys_convex_hull_measure(&hull, &info, msg, sizeof msg), PHYS_ERR_INVALID_ARG);
    assert_contains(msg, "phys_convex_hull.points[2].y must be finite (got nan)");
    bad.point_count = 3;
    assert_int_equal(phys_convex_hull_measure(&bad, &info, msg, sizeof msg), PHYS_ERR_INVALID_ARG);
    assert_contains(msg, "phys_convex_hull.point_count must be in [4, 65536] (got 3)");
    bad.points = NULL;
    bad.point_count = 4;
    assert_int_equal(phys_convex_hull_measure(&bad, &info, msg, sizeof msg), PHYS_ERR_INVALID_ARG);
    assert_contains(msg, "phys_convex_hull.points must not be NULL");
    assert_int_equal(phys_convex_hull_measure(&hull, NULL, msg, sizeof msg), PHYS_ERR_INVALID_ARG);
    assert_contains(msg, "out must not be NULL");
    assert_memory_equal(&info, &untouched, sizeof info);
    char tiny[8];  // cut, terminated
    assert_int_equal(phys_convex_hull_measure(&bad, &info, tiny, sizeof tiny), PHYS_ERR_INVALID_ARG);
    assert_int_equal(strlen(tiny), sizeof tiny - 1);
    assert_int_equal(phys_convex_hull_measure(&bad, &info, NULL, 0), PHYS_ERR_INVALID_ARG);  // no message asked
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

// ---- shapes in use --------------------------------------------------------------------

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

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_ray_cast_hits_nearest_body_at_right_distance, setup, teardown),
        cmocka_unit_test_setup_teardown(test_density_times_volume_gives_mass, setup, teardown),
        cmocka_unit_test_setup_teardown(test_explicit_mass_wins_over_density, setup, teardown),
        cmocka_unit_test_setup_teardown(test_extent_follows_the_pose, setup, teardown),
        cmocka_unit_test_setup_teardown(test_convex_hull_query_returns_points_and_planes, setup, teardown),
        cmocka_unit_test_setup_teardown(test_degenerate_convex_hull_is_rejected, setup, teardown),
        cmocka_unit_test_setup_teardown(test_convex_hull_is_measured_without_a_world, setup, teardown),
        cmocka_unit_test_setup_teardown(test_triangle_mesh_query_returns_vertices_and_indices, setup, teardown),
        cmocka_unit_test_setup_teardown(test_shape_in_use_cannot_be_destroyed, setup, teardown),
        cmocka_unit_test_setup_teardown(test_compound_mass_and_inertia_come_from_density, setup, teardown),
        cmocka_unit_test_setup_teardown(test_compound_desc_round_trips_children_and_frame, setup, teardown),
        cmocka_unit_test_setup_teardown(test_compound_rests_on_a_plane, setup, teardown),
        cmocka_unit_test_setup_teardown(test_angular_factor_keeps_rotation_to_one_axis, setup, teardown),
        cmocka_unit_test_setup_teardown(test_bad_compound_and_factors_are_rejected_naming_the_field, setup, teardown),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
