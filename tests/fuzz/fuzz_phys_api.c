// libFuzzer harness: the rigid-body module's C API (fluid/bullet/phys.h), Bullet underneath, no GL.
//
// An engine developer reaches Bullet through this wrapper, so every call with every argument must
// return PHYS_OK or an error with a message (in phys_world_last_error, and in the log), never crash,
// hang, leak, touch memory it does not own, or hit undefined behaviour (UBSan, float-cast-overflow
// included). Each input runs in a world made once and emptied after it, or in one of its own from a
// fuzzer-made phys_world_def (a refused def must leave no world), as a sequence of calls: shapes of every kind (hulls and meshes from fuzzer-made
// points, compounds of mixed parts), bodies from fuzzer-made defs (enum fields with values no
// enumerator has, NaN, infinities, huge and tiny numbers), poses, velocities, forces, joints, the
// drag constraint, ray casts, contact reports and sums, steps with odd dt; ids live, destroyed,
// null, made up and from a second world. A body the wrapper accepted and stepped must keep a finite
// pose. Inputs stay cheap: at most 64 calls and 12 steps.
// Build and run: make fuzz (docs/testing.md).
#include "fluid/bullet/phys.h"
#include "tests/fuzz/fuzz_input.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_IDS 24
#define MAX_OPS 64
#define MAX_STEPS 12

typedef struct state {
    phys_world *w, *other;
    phys_shape_id shapes[MAX_IDS];
    int shape_count;
    phys_body_id bodies[MAX_IDS];
    int body_count;
    phys_joint_id joints[MAX_IDS];
    int joint_count;
    phys_constraint_id drags[MAX_IDS];
    int drag_count;
    int steps;
    fuzz_input *in;
} state;

static int verbose = -1; // FUZZ_PHYS_VERBOSE=1: each call, its result and the vectors made, on stderr

static void checked_log(void *user, phys_log_level level, const char *message)
{
    (void)user;
    if ((int)level < PHYS_LOG_ERROR || (int)level > PHYS_LOG_INFO || !message || !message[0]) {
        fprintf(stderr, "log callback: level %d, message %s\n", (int)level, message ? message : "NULL");
        abort();
    }
}


static phys_result check(const state *s, phys_result r, const char *fn)
{
    if (verbose < 0) verbose = getenv("FUZZ_PHYS_VERBOSE") != NULL;
    if (verbose) fprintf(stderr, "%s -> %s %s\n", fn, phys_result_string(r), r ? phys_world_last_error(s->w) : "");
    if ((int)r < PHYS_OK || (int)r > PHYS_ERR_INTERNAL) {
        fprintf(stderr, "%s returned %d, not a phys_result\n", fn, (int)r);
        abort();
    }
    if (r == PHYS_ERR_INTERNAL) { // "a bug": Bullet or the wrapper failed
        fprintf(stderr, "%s: internal error: %s\n", fn, phys_world_last_error(s->w));
        abort();
    }
    if (r != PHYS_OK && !phys_world_last_error(s->w)[0]) {
        fprintf(stderr, "%s failed (%d) without a message\n", fn, (int)r);
        abort();
    }
    return r;
}
#define CALL(s, expr) check((s), (expr), #expr)

// ---- argument makers ------------------------------------------------------------------------

// Mostly a place within a few metres, else any float.
static float coord(fuzz_input *in)
{
    uint8_t how = fuzz_u8(in);
    if (how < 160) return ((float)how - 80.0f) / 20.0f;
    return fuzz_float(in);
}

static phys_vec3 vec(fuzz_input *in)
{
    phys_vec3 v;
    v.x = coord(in);
    v.y = coord(in);
    v.z = coord(in);
    if (verbose > 0) fprintf(stderr, "  vec (%.9g, %.9g, %.9g)\n", (double)v.x, (double)v.y, (double)v.z);
    return v;
}

// Mostly a small positive size, else any float.
static float size_value(fuzz_input *in)
{
    uint8_t how = fuzz_u8(in);
    float v = how < 128 ? 0.02f + (float)how / 128.0f : fuzz_float(in);
    if (verbose > 0) fprintf(stderr, "  size %.9g\n", (double)v);
    return v;
}

static phys_quat quat(fuzz_input *in)
{
    phys_quat q = { 0, 0, 0, 1 };
    uint8_t how = fuzz_u8(in);
    if (how < 128) return q;
    if (how < 200) {
        float a = (float)fuzz_u8(in) * 0.05f;
        float *axis[3] = { &q.x, &q.y, &q.z };
        *axis[fuzz_u8(in) % 3] = sinf(a);
        q.w = cosf(a);
        return q;
    }
    q.x = fuzz_float(in);
    q.y = fuzz_float(in);
    q.z = fuzz_float(in);
    q.w = fuzz_float(in);
    return q;
}

// An enum field's value: mostly valid, sometimes one no enumerator has (read back as an int by
// the wrapper, so any bits are allowed).
static int enum_value(fuzz_input *in, int lo, int hi)
{
    uint8_t how = fuzz_u8(in);
    if (how < 224) return lo + how % (hi - lo + 1);
    return (int)fuzz_u32(in);
}

static float dt_value(fuzz_input *in)
{
    static const float table[] = { 1.0f / 60.0f, 1.0f / 240.0f, 0.004f, 0.0f, -0.016f, 1.0f, 10.0f, 10.000001f,
                                   1e-7f, 9.9e-8f, 1e-45f, 1e-30f, 0.5f, 1e30f, NAN, INFINITY, -INFINITY };
    uint8_t how = fuzz_u8(in);
    if (how < 200) return table[how % (sizeof table / sizeof table[0])];
    return fuzz_float(in);
}

// Ids: mostly one this input made (maybe destroyed since), else null, made up, or the other
// world's.
#define PICK(s, list, count, type)                                                                  \
    do {                                                                                            \
        uint8_t how_ = fuzz_u8((s)->in);                                                           \
        memset(&picked, 0, sizeof picked);                                                         \
        if ((count) > 0 && how_ < 208) picked = (list)[how_ % (count)];                            \
        else if (how_ < 232) { /* null */ }                                                        \
        else {                                                                                      \
            picked.index1 = fuzz_u8((s)->in);                                                      \
            picked.world0 = fuzz_u8((s)->in);                                                      \
            picked.generation = fuzz_u8((s)->in);                                                  \
        }                                                                                           \
    } while (0)

static phys_shape_id pick_shape(state *s)
{
    phys_shape_id picked;
    PICK(s, s->shapes, s->shape_count, phys_shape_id);
    return picked;
}

static phys_body_id pick_body(state *s)
{
    phys_body_id picked;
    PICK(s, s->bodies, s->body_count, phys_body_id);
    return picked;
}

static phys_joint_id pick_joint(state *s)
{
    phys_joint_id picked;
    PICK(s, s->joints, s->joint_count, phys_joint_id);
    return picked;
}

static phys_constraint_id pick_drag(state *s)
{
    phys_constraint_id picked;
    PICK(s, s->drags, s->drag_count, phys_constraint_id);
    return picked;
}

// Points for hulls and meshes: corners of a small box with noise, the same point repeated, points
// on a plane or a line, or any floats.
static void points(fuzz_input *in, phys_vec3 *p, uint32_t n)
{
    uint8_t kind = fuzz_u8(in) % 4;
    for (uint32_t i = 0; i < n; i++) {
        switch (kind) {
        case 0:
            p[i].x = (i & 1 ? 0.5f : -0.5f) + (float)(int8_t)fuzz_u8(in) * 1e-3f;
            p[i].y = (i & 2 ? 0.5f : -0.5f) + (float)(int8_t)fuzz_u8(in) * 1e-3f;
            p[i].z = (i & 4 ? 0.5f : -0.5f) + (float)(int8_t)fuzz_u8(in) * 1e-3f;
            break;
        case 1: p[i] = (phys_vec3){ 1, 2, 3 }; break;
        case 2: p[i] = (phys_vec3){ coord(in), coord(in), fuzz_u8(in) < 128 ? 0.0f : 1e-7f }; break;
        default: p[i] = vec(in); break;
        }
    }
}

// ---- the calls ------------------------------------------------------------------------------

// Keeps a new shape's id; one that does not fit is destroyed at once (the base world is emptied
// from these lists).
static void keep_shape(state *s, phys_result r, phys_shape_id id)
{
    if (r != PHYS_OK) return;
    if (s->shape_count < MAX_IDS) s->shapes[s->shape_count++] = id;
    else CALL(s, phys_shape_destroy(s->w, id));
}

// A hull's points: mostly 4 to cap of them, sometimes too few, or a count past the limit (refused
// before any point is read), or no array.
static void make_hull_part(fuzz_input *in, phys_convex_hull *h, phys_vec3 *buf, uint32_t cap)
{
    uint8_t n = fuzz_u8(in);
    h->point_count = n < 240 ? 4 + n % (cap - 3) : n < 254 ? n % 4 : 65537u + n;
    h->points = fuzz_u8(in) == 255 ? NULL : buf;
    points(in, buf, h->point_count <= cap ? h->point_count : cap);
}

static void create_shape(state *s)
{
    fuzz_input *in = s->in;
    phys_shape_id id;
    phys_result r;
    switch (fuzz_u8(in) % 8) {
    case 0: {
        phys_plane p = { vec(in), coord(in) };
        if (fuzz_bool(in)) p.normal = (phys_vec3){ 0, 1, 0 };
        r = CALL(s, phys_shape_create_plane(s->w, &p, &id));
        break;
    }
    case 1: {
        phys_box b = { { size_value(in), size_value(in), size_value(in) } };
        r = CALL(s, phys_shape_create_box(s->w, &b, &id));
        break;
    }
    case 2: {
        phys_sphere sp = { size_value(in) };
        r = CALL(s, phys_shape_create_sphere(s->w, &sp, &id));
        break;
    }
    case 3: {
        phys_capsule c = { size_value(in), size_value(in) };
        r = CALL(s, phys_shape_create_capsule(s->w, &c, &id));
        break;
    }
    case 4: {
        phys_cylinder c = { size_value(in), size_value(in) };
        r = CALL(s, phys_shape_create_cylinder(s->w, &c, &id));
        break;
    }
    case 5: {
        phys_vec3 buf[40];
        phys_convex_hull h;
        make_hull_part(in, &h, buf, 40);
        phys_hull_info info;
        char msg[96];
        phys_result m = phys_convex_hull_measure(&h, &info, msg, fuzz_bool(in) ? sizeof msg : 0);
        r = CALL(s, phys_shape_create_convex_hull(s->w, &h, &id));
        if (m != r) { // the world-free measure and the world must agree
            fprintf(stderr, "phys_convex_hull_measure gave %d, the world %d\n", (int)m, (int)r);
            abort();
        }
        break;
    }
    case 6: {
        phys_vec3 v[12];
        uint32_t idx[24];
        phys_triangle_mesh m;
        m.vertex_count = 3 + fuzz_u8(in) % 10;
        m.triangle_count = fuzz_u8(in) % 9;
        points(in, v, m.vertex_count);
        for (uint32_t i = 0; i < m.triangle_count * 3; i++) {
            uint8_t k = fuzz_u8(in);
            idx[i] = k < 250 ? k % m.vertex_count : (k == 255 ? 0xffffffffu : m.vertex_count);
        }
        m.vertices = fuzz_u8(in) == 255 ? NULL : v;
        m.indices = fuzz_u8(in) == 255 ? NULL : idx;
        r = CALL(s, phys_shape_create_triangle_mesh(s->w, &m, &id));
        break;
    }
    default: {
        phys_compound_part parts[6];
        phys_vec3 bufs[6][12];
        phys_compound c = { parts, 1 + fuzz_u8(in) % 6 };
        memset(parts, 0, sizeof parts);
        for (uint32_t i = 0; i < c.part_count; i++) {
            int type = enum_value(in, PHYS_SHAPE_PLANE, PHYS_SHAPE_COMPOUND);
            memcpy(&parts[i].type, &type, sizeof type);
            switch (type) {
            case PHYS_SHAPE_BOX: parts[i].box = (phys_box){ { size_value(in), size_value(in), size_value(in) } }; break;
            case PHYS_SHAPE_SPHERE: parts[i].sphere.radius = size_value(in); break;
            case PHYS_SHAPE_CAPSULE: parts[i].capsule = (phys_capsule){ size_value(in), size_value(in) }; break;
            case PHYS_SHAPE_CYLINDER: parts[i].cylinder = (phys_cylinder){ size_value(in), size_value(in) }; break;
            case PHYS_SHAPE_CONVEX_HULL: make_hull_part(in, &parts[i].hull, bufs[i], 12); break;
            default: break;
            }
            parts[i].position = vec(in);
            parts[i].rotation = quat(in);
            if (verbose > 0)
                fprintf(stderr, "  part %u type %d rotation (%.9g, %.9g, %.9g, %.9g)\n", i, type, (double)parts[i].rotation.x,
                        (double)parts[i].rotation.y, (double)parts[i].rotation.z, (double)parts[i].rotation.w);
        }
        if (fuzz_u8(in) == 255) c.part_count = fuzz_bool(in) ? 0 : PHYS_MAX_COMPOUND_PARTS + 1;
        if (c.part_count > 6 && c.part_count != PHYS_MAX_COMPOUND_PARTS + 1) c.part_count = 6;
        if (c.part_count == PHYS_MAX_COMPOUND_PARTS + 1) c.part_count = 0; // keep to the array
        r = CALL(s, phys_shape_create_compound(s->w, &c, &id));
        break;
    }
    }
    keep_shape(s, r, id);
}

static void create_body(state *s)
{
    fuzz_input *in = s->in;
    phys_body_def d = phys_default_body_def();
    int type = enum_value(in, PHYS_BODY_STATIC, PHYS_BODY_DYNAMIC);
    memcpy(&d.type, &type, sizeof type);
    d.shape = pick_shape(s);
    d.position = vec(in);
    d.orientation = quat(in);
    uint8_t fields = fuzz_u8(in);
    if (fields & 1) d.linear_velocity = vec(in);
    if (fields & 2) d.angular_velocity = vec(in);
    if (fields & 4) d.mass = fuzz_float(in);
    if (fields & 8) d.density = fuzz_float(in);
    if (fields & 16) d.friction = fuzz_float(in);
    if (fields & 32) d.restitution = fuzz_float(in);
    if (fields & 64) {
        d.linear_damping = fuzz_float(in);
        d.angular_damping = fuzz_float(in);
    }
    d.allow_sleep = fuzz_bool(in);
    if (verbose > 0)
        fprintf(stderr, "  body type %d mass %.9g density %.9g friction %.9g restitution %.9g damping %.9g %.9g\n",
                type, (double)d.mass, (double)d.density, (double)d.friction, (double)d.restitution,
                (double)d.linear_damping, (double)d.angular_damping);
    phys_body_id id;
    if (CALL(s, phys_body_create(s->w, &d, &id)) != PHYS_OK) return;
    if (s->body_count < MAX_IDS) s->bodies[s->body_count++] = id;
    else CALL(s, phys_body_destroy(s->w, id));
}

static void body_calls(state *s)
{
    fuzz_input *in = s->in;
    phys_body_id b = pick_body(s);
    phys_vec3 v, p;
    phys_quat q;
    float f;
    bool flag;
    void *user;
    phys_body_type type;
    phys_mass_data m;
    phys_shape_desc d;
    bool wake = fuzz_bool(in);
    switch (fuzz_u8(in) % 25) {
    case 0: CALL(s, phys_body_destroy(s->w, b)); break;
    case 1: CALL(s, phys_body_set_pose(s->w, b, vec(in), quat(in))); break;
    case 2: CALL(s, phys_body_get_pose(s->w, b, fuzz_u8(in) == 255 ? NULL : &p, &q)); break;
    case 3: CALL(s, phys_body_set_kinematic_target(s->w, b, vec(in), quat(in))); break;
    case 4: CALL(s, phys_body_set_linear_velocity(s->w, b, vec(in))); break;
    case 5: CALL(s, phys_body_set_angular_velocity(s->w, b, vec(in))); break;
    case 6: CALL(s, phys_body_get_linear_velocity(s->w, b, &v)); break;
    case 7: CALL(s, phys_body_get_angular_velocity(s->w, b, fuzz_u8(in) == 255 ? NULL : &v)); break;
    case 8: CALL(s, phys_body_get_extent(s->w, b, &v)); break;
    case 9: CALL(s, phys_body_get_velocity_at_point(s->w, b, vec(in), &v)); break;
    case 10: CALL(s, phys_body_apply_force(s->w, b, vec(in), wake)); break;
    case 11: CALL(s, phys_body_apply_force_at_point(s->w, b, vec(in), vec(in), wake)); break;
    case 12: CALL(s, phys_body_apply_torque(s->w, b, vec(in), wake)); break;
    case 13: CALL(s, phys_body_apply_impulse(s->w, b, vec(in), wake)); break;
    case 14: CALL(s, phys_body_apply_impulse_at_point(s->w, b, vec(in), vec(in), wake)); break;
    case 15: CALL(s, phys_body_apply_angular_impulse(s->w, b, vec(in), wake)); break;
    case 16: CALL(s, phys_body_get_mass_data(s->w, b, &m)); break;
    case 17: CALL(s, phys_body_set_linear_factor(s->w, b, vec(in))); break;
    case 18: CALL(s, phys_body_set_angular_factor(s->w, b, vec(in))); break;
    case 19:
        CALL(s, phys_body_get_linear_factor(s->w, b, &v));
        CALL(s, phys_body_get_angular_factor(s->w, b, &v));
        break;
    case 20:
        CALL(s, phys_body_set_sleep_enabled(s->w, b, fuzz_bool(in)));
        CALL(s, phys_body_wake(s->w, b));
        CALL(s, phys_body_is_awake(s->w, b, &flag));
        break;
    case 21:
        CALL(s, phys_body_set_user_data(s->w, b, s));
        CALL(s, phys_body_get_user_data(s->w, b, &user));
        break;
    case 22:
        CALL(s, phys_body_get_type(s->w, b, &type));
        CALL(s, phys_body_get_shape(s->w, b, &d));
        break;
    case 23:
        CALL(s, phys_body_set_held_force(s->w, b, vec(in), vec(in)));
        CALL(s, phys_body_get_held_force(s->w, b, fuzz_bool(in) ? &v : NULL, fuzz_bool(in) ? &p : NULL));
        break;
    default:
        (void)f;
        (void)phys_body_is_valid(s->w, b);
        (void)phys_body_is_valid(s->other, b);
        break;
    }
}

static void joint_calls(state *s)
{
    fuzz_input *in = s->in;
    phys_joint_id id;
    phys_result r = PHYS_ERR_INVALID_ARG;
    float f;
    phys_vec3 a, b;
    phys_joint_type type;
    switch (fuzz_u8(in) % 10) {
    case 0: {
        phys_hinge_joint_def d = phys_default_hinge_joint_def();
        d.body_a = pick_body(s);
        d.body_b = pick_body(s);
        d.pivot = vec(in);
        d.axis = vec(in);
        d.enable_limit = fuzz_bool(in);
        d.lower_angle = coord(in);
        d.upper_angle = coord(in);
        d.enable_motor = fuzz_bool(in);
        d.motor_speed = coord(in);
        d.max_motor_torque = fuzz_float(in);
        d.collide_connected = fuzz_bool(in);
        r = CALL(s, phys_joint_create_hinge(s->w, &d, &id));
        break;
    }
    case 1: {
        phys_slider_joint_def d = phys_default_slider_joint_def();
        d.body_a = pick_body(s);
        d.body_b = pick_body(s);
        d.anchor = vec(in);
        d.axis = vec(in);
        d.enable_limit = fuzz_bool(in);
        d.lower_translation = coord(in);
        d.upper_translation = coord(in);
        d.enable_motor = fuzz_bool(in);
        d.motor_speed = coord(in);
        d.max_motor_force = fuzz_float(in);
        r = CALL(s, phys_joint_create_slider(s->w, &d, &id));
        break;
    }
    case 2: {
        phys_fixed_joint_def d = phys_default_fixed_joint_def();
        d.body_a = pick_body(s);
        d.body_b = pick_body(s);
        d.collide_connected = fuzz_bool(in);
        r = CALL(s, phys_joint_create_fixed(s->w, &d, &id));
        break;
    }
    case 3: {
        phys_point_joint_def d = phys_default_point_joint_def();
        d.body_a = pick_body(s);
        d.body_b = pick_body(s);
        d.pivot = vec(in);
        r = CALL(s, phys_joint_create_point(s->w, &d, &id));
        break;
    }
    case 4: CALL(s, phys_joint_set_motor(s->w, pick_joint(s), fuzz_bool(in), coord(in), fuzz_float(in))); break;
    case 5: CALL(s, phys_joint_set_limits(s->w, pick_joint(s), fuzz_bool(in), coord(in), coord(in))); break;
    case 6:
        CALL(s, phys_joint_get_angle(s->w, pick_joint(s), &f));
        CALL(s, phys_joint_get_position(s->w, pick_joint(s), &f));
        break;
    case 7:
        CALL(s, phys_joint_get_applied_impulse(s->w, pick_joint(s), fuzz_bool(in) ? &a : NULL,
                                               fuzz_bool(in) ? &b : NULL));
        CALL(s, phys_joint_get_type(s->w, pick_joint(s), &type));
        break;
    case 8: CALL(s, phys_joint_destroy(s->w, pick_joint(s))); break;
    default: {
        phys_point_constraint_def d = phys_default_point_constraint_def();
        d.body = pick_body(s);
        d.pivot = vec(in);
        if (fuzz_bool(in)) d.max_force = fuzz_float(in);
        if (fuzz_bool(in)) d.error_reduction = fuzz_float(in);
        phys_constraint_id c;
        uint8_t what = fuzz_u8(in) % 3;
        if (what == 0) {
            if (CALL(s, phys_point_constraint_create(s->w, &d, &c)) == PHYS_OK) {
                if (s->drag_count < MAX_IDS) s->drags[s->drag_count++] = c;
                else CALL(s, phys_constraint_destroy(s->w, c));
            }
        } else if (what == 1) {
            CALL(s, phys_point_constraint_set_pivot(s->w, pick_drag(s), vec(in)));
        } else {
            CALL(s, phys_constraint_destroy(s->w, pick_drag(s)));
        }
        return;
    }
    }
    if (r != PHYS_OK) return;
    if (s->joint_count < MAX_IDS) s->joints[s->joint_count++] = id;
    else CALL(s, phys_joint_destroy(s->w, id));
}

static void world_calls(state *s)
{
    fuzz_input *in = s->in;
    switch (fuzz_u8(in) % 8) {
    case 0:
        if (s->steps < MAX_STEPS) {
            s->steps++;
            float dt = dt_value(in);
            if (verbose > 0) fprintf(stderr, "  dt %.9g\n", (double)dt);
            CALL(s, phys_world_step(s->w, dt));
        }
        break;
    case 1: CALL(s, phys_world_set_gravity(s->w, vec(in))); break;
    case 2: {
        phys_ray_hit hit;
        CALL(s, phys_world_ray_cast(s->w, vec(in), vec(in), fuzz_u8(in) == 255 ? NULL : &hit));
        break;
    }
    case 3:
    case 4: {
        // max from -5 to 8 with a buffer of 8, or anything with no buffer (refused unless 0).
        phys_contact buf[8];
        phys_contact *out = fuzz_u8(in) < 224 ? buf : NULL;
        int max = (int)(fuzz_u8(in) % 14) - 5;
        if (!out && fuzz_bool(in)) max = (int)fuzz_u32(in);
        float min_impulse = fuzz_u8(in) < 200 ? 0.0f : fuzz_float(in);
        int count = -1;
        if (fuzz_bool(in))
            CALL(s, phys_world_get_contacts(s->w, min_impulse, out, max, fuzz_u8(in) == 255 ? NULL : &count));
        else
            CALL(s, phys_world_take_contact_sums(s->w, min_impulse, out, max, fuzz_u8(in) == 255 ? NULL : &count));
        break;
    }
    case 5: CALL(s, phys_world_set_contact_sums(s->w, fuzz_bool(in))); break;
    case 6: {
        phys_shape_id id = pick_shape(s);
        float v;
        phys_shape_desc d;
        uint8_t what = fuzz_u8(in) % 3;
        if (what == 0) CALL(s, phys_shape_destroy(s->w, id));
        else if (what == 1) CALL(s, phys_shape_get_volume(s->w, id, fuzz_u8(in) == 255 ? NULL : &v));
        else CALL(s, phys_shape_get_desc(s->w, id, &d));
        (void)phys_shape_is_valid(s->w, id);
        break;
    }
    default:
        (void)phys_world_get_body_count(s->w);
        (void)phys_world_get_gravity(s->w);
        (void)phys_result_string((phys_result)(fuzz_u8(in) % 8));
        break;
    }
}

// Every body the world still has keeps a finite pose and velocity: the wrapper took its inputs,
// so what Bullet made of them must still be a place.
static void check_bodies(state *s)
{
    for (int i = 0; i < s->body_count; i++) {
        if (!phys_body_is_valid(s->w, s->bodies[i])) continue;
        phys_vec3 p, v;
        phys_quat q;
        if (phys_body_get_pose(s->w, s->bodies[i], &p, &q) != PHYS_OK ||
            phys_body_get_linear_velocity(s->w, s->bodies[i], &v) != PHYS_OK) {
            fprintf(stderr, "a live body's pose cannot be read: %s\n", phys_world_last_error(s->w));
            abort();
        }
        if (!isfinite(p.x) || !isfinite(p.y) || !isfinite(p.z) || !isfinite(q.x) || !isfinite(q.y) ||
            !isfinite(q.z) || !isfinite(q.w) || !isfinite(v.x) || !isfinite(v.y) || !isfinite(v.z)) {
            fprintf(stderr, "body %d is no longer finite after %d steps: position (%g, %g, %g), velocity (%g, %g, %g)\n",
                    i, s->steps, (double)p.x, (double)p.y, (double)p.z, (double)v.x, (double)v.y, (double)v.z);
            abort();
        }
    }
}

// A world costs about 50 ms under ASan (Bullet's pools), so one is made once and emptied after each
// input; an input that starts with a byte whose low three bits are zero makes its own world from a
// fuzzer-made def instead. The second world (for ids from elsewhere) is made once.
static phys_world *base, *other;

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    phys_world_def def = phys_default_world_def();
    def.log = checked_log;
    if (phys_world_create(&def, &base) != PHYS_OK || phys_world_create(&def, &other) != PHYS_OK) abort();
    return 0;
}

// Empties the base world for the next input: every object this input made is in the lists (one
// that did not fit was destroyed at once), and destroying a body destroys its joints.
static void empty(state *s)
{
    for (int i = 0; i < s->body_count; i++)
        if (phys_body_is_valid(s->w, s->bodies[i])) CALL(s, phys_body_destroy(s->w, s->bodies[i]));
    for (int i = 0; i < s->shape_count; i++)
        if (phys_shape_is_valid(s->w, s->shapes[i])) CALL(s, phys_shape_destroy(s->w, s->shapes[i]));
    if (phys_world_get_body_count(s->w) != 0) {
        fprintf(stderr, "%u bodies left after destroying every one made\n", phys_world_get_body_count(s->w));
        abort();
    }
    phys_world_def def = phys_default_world_def();
    CALL(s, phys_world_set_gravity(s->w, def.gravity));
    CALL(s, phys_world_set_contact_sums(s->w, false));
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = { data, size };
    state s;
    memset(&s, 0, sizeof s);
    s.in = &in;
    s.other = other;
    s.w = base;
    if (verbose < 0) verbose = getenv("FUZZ_PHYS_VERBOSE") != NULL;

    uint8_t fields = fuzz_u8(&in);
    if ((fields & 7) == 0) {
        phys_world_def def = phys_default_world_def();
        def.log = checked_log;
        if (fields & 8) def.gravity = vec(&in);
        if (fields & 16) def.solver_iterations = fuzz_u8(&in) == 255 ? (int)fuzz_u32(&in) : 1 + fuzz_u8(&in) % 20;
        if (fields & 32) def.collision_margin = fuzz_float(&in);
        if (fields & 64) def.split_impulse_depth = fuzz_float(&in);
        if (fields & 128) def.log = NULL;
        phys_world *w = (phys_world *)&s; // must be set to NULL on failure
        if (phys_world_create(&def, &w) != PHYS_OK) {
            if (w) abort();
        } else {
            s.w = w;
        }
        if (fuzz_bool(&in)) phys_world_destroy(NULL);
    }

    for (int i = 0; i < MAX_OPS && in.size > 0; i++) {
        switch (fuzz_u8(&in) % 6) {
        case 0: create_shape(&s); break;
        case 1: create_body(&s); break;
        case 2:
        case 3: body_calls(&s); break;
        case 4: joint_calls(&s); break;
        default: world_calls(&s); break;
        }
        if (s.steps) check_bodies(&s);
    }
    if (s.w == base) empty(&s);
    else phys_world_destroy(s.w);
    return 0;
}
