// libFuzzer harness: the coupling's C API (fluid/bullet/coupling.h) between a real fluid world on a
// headless GL context (llvmpipe here, the strict GL mode on) and a Bullet world.
//
// An engine developer who couples Bullet bodies to the water calls these with bodies of every
// kind and shape, in any order: bodies added, removed, teleported, destroyed in the phys_world
// behind the coupling's back, coupled steps with odd dt, settings from cpl_def_set and raw fields.
// Every call must return CPL_OK or an error with a message in cpl_last_error, a refused
// cpl_create a message in err; nothing may crash, leak, touch memory it does not own or cause a
// GL error or hazard. The fluid world (2048 particles) and the Bullet world are made once and
// emptied after each input; a coupling is made per input. Inputs stay cheap: at most 32 calls
// and 3 coupled steps.
// Build and run: make fuzz (docs/testing.md).
#include "tests/fuzz/fuzz_gl.h"
#include "fluid/bullet/coupling.h"
#include "tests/fuzz/fuzz_input.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_BODIES 16
#define MAX_OPS 32
#define MAX_STEPS 3

static eng_context *ctx;
static pbf_world *fluid;
static pbf_world_def fluid_def;
static phys_world *phys;

typedef struct state {
    cpl_coupling *c;
    phys_body_id bodies[MAX_BODIES];
    phys_shape_id shapes[MAX_BODIES];
    int body_count, shape_count, steps;
    fuzz_input *in;
} state;

static void quiet_log(void *user, int level, const char *message)
{
    (void)user;
    if (level < 0 || level > 3 || !message || !message[0]) abort();
}

static void cpl_log(void *user, const char *message)
{
    (void)user;
    if (!message || !message[0]) abort();
}

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    ctx = fuzz_gl_context("fuzz_cpl_api");
    fluid = fuzz_gl_base_world("fuzz_cpl_api", quiet_log, &fluid_def);
    phys_world_def d = phys_default_world_def();
    if (phys_world_create(&d, &phys) != PHYS_OK) abort();
    return 0;
}

static cpl_result check(const state *s, cpl_result r, const char *fn)
{
    if ((int)r < CPL_OK || (int)r > CPL_ERR_OUT_OF_MEMORY) {
        fprintf(stderr, "%s returned %d, not a cpl_result\n", fn, (int)r);
        abort();
    }
    if (r != CPL_OK && !cpl_last_error(s->c)[0]) {
        fprintf(stderr, "%s failed (%d) without a message\n", fn, (int)r);
        abort();
    }
    return r;
}
#define CALL(s, expr) check((s), (expr), #expr)

// ---- argument makers ------------------------------------------------------------------------

// Mostly inside the fluid's 1 m domain, else any float.
static float coord(fuzz_input *in)
{
    uint8_t how = fuzz_u8(in);
    if (how < 200) return (float)how / 200.0f;
    return fuzz_float(in);
}

static phys_vec3 vec(fuzz_input *in) { return (phys_vec3){ coord(in), coord(in), coord(in) }; }

static phys_quat quat(fuzz_input *in)
{
    uint8_t how = fuzz_u8(in);
    if (how < 160) return (phys_quat){ 0, 0, 0, 1 };
    if (how < 230) {
        float a = (float)fuzz_u8(in) * 0.05f;
        return (phys_quat){ sinf(a), 0, 0, cosf(a) };
    }
    return (phys_quat){ fuzz_float(in), fuzz_float(in), fuzz_float(in), fuzz_float(in) };
}

static float dt_value(fuzz_input *in)
{
    static const float table[] = { 1.0f / 60.0f, 1.0f / 120.0f, 0.004f, 0.0f, -0.016f, 1.0f, 1.0000001f,
                                   1e-7f, 3.2e-6f, 1e-45f, 2.0f, NAN, INFINITY };
    uint8_t how = fuzz_u8(in);
    if (how < 220) return table[how % (sizeof table / sizeof table[0])];
    return fuzz_float(in);
}

static phys_body_id pick_body(state *s)
{
    uint8_t how = fuzz_u8(s->in);
    if (s->body_count > 0 && how < 220) return s->bodies[how % s->body_count];
    if (how < 240) return (phys_body_id){ 0, 0, 0 };
    return (phys_body_id){ fuzz_u8(s->in), (uint16_t)fuzz_u8(s->in), (uint16_t)fuzz_u8(s->in) };
}

// ---- the calls ------------------------------------------------------------------------------

// A body of any kind, of one of the shapes the coupling takes (a small one, in the domain mostly).
static void make_body(state *s)
{
    fuzz_input *in = s->in;
    if (s->body_count >= MAX_BODIES || s->shape_count >= MAX_BODIES) return;
    phys_shape_id shape;
    phys_result r;
    int kind = fuzz_u8(in) % 8;
    float size = 0.02f + (float)(fuzz_u8(in) % 64) / 512.0f;
    static const phys_vec3 tetra[4] = { { 0, 0, 0 }, { 0.1f, 0, 0 }, { 0, 0.1f, 0 }, { 0, 0, 0.1f } };
    static const uint32_t tris[12] = { 0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3 };
    switch (kind) {
    case 0: r = phys_shape_create_sphere(phys, &(phys_sphere){ size }, &shape); break;
    case 1: r = phys_shape_create_box(phys, &(phys_box){ { size, size * 0.5f, size } }, &shape); break;
    case 2: r = phys_shape_create_capsule(phys, &(phys_capsule){ size * 0.5f, size }, &shape); break;
    case 3: r = phys_shape_create_cylinder(phys, &(phys_cylinder){ size, size * 0.5f }, &shape); break;
    case 4: r = phys_shape_create_convex_hull(phys, &(phys_convex_hull){ tetra, 4 }, &shape); break;
    case 5: {
        phys_compound_part parts[2];
        memset(parts, 0, sizeof parts);
        for (int i = 0; i < 2; i++) {
            parts[i].type = PHYS_SHAPE_BOX;
            parts[i].box.half_extents = (phys_vec3){ size, size * 0.3f, size * 0.3f };
            parts[i].position = (phys_vec3){ 0, i ? size : -size, 0 };
            parts[i].rotation = (phys_quat){ 0, 0, 0, 1 };
        }
        r = phys_shape_create_compound(phys, &(phys_compound){ parts, 2 }, &shape);
        break;
    }
    case 6:
        r = phys_shape_create_triangle_mesh(phys, &(phys_triangle_mesh){ tetra, 4, tris, 4 }, &shape);
        break;
    default: {
        // A mesh from the input, its corners on a coarse grid so that repeated, collinear and
        // degenerate triangles come often (the distance grid's bake: coupling_mesh.c).
        phys_vec3 v[24];
        uint32_t idx[3 * 32];
        uint32_t nv = 3 + fuzz_u8(in) % 22, nt = 1 + fuzz_u8(in) % 32;
        for (uint32_t i = 0; i < nv; i++)
            v[i] = (phys_vec3){ (float)(fuzz_u8(in) % 16) / 64.0f, (float)(fuzz_u8(in) % 16) / 64.0f,
                                (float)(fuzz_u8(in) % 16) / 64.0f };
        for (uint32_t i = 0; i < 3 * nt; i++) idx[i] = fuzz_u8(in) % nv;
        r = phys_shape_create_triangle_mesh(phys, &(phys_triangle_mesh){ v, nv, idx, nt }, &shape);
        break;
    }
    }
    if (r != PHYS_OK) return;
    s->shapes[s->shape_count++] = shape;
    phys_body_def d = phys_default_body_def();
    d.shape = shape;
    d.type = kind >= 6 || fuzz_u8(in) > 200 ? (fuzz_bool(in) ? PHYS_BODY_STATIC : PHYS_BODY_KINEMATIC) : PHYS_BODY_DYNAMIC;
    d.position = vec(in);
    d.orientation = quat(in);
    d.density = fuzz_u8(in) < 128 ? 500.0f : 100.0f + 20.0f * (float)fuzz_u8(in);
    phys_body_id id;
    if (phys_body_create(phys, &d, &id) == PHYS_OK) s->bodies[s->body_count++] = id;
}

static void op(state *s)
{
    fuzz_input *in = s->in;
    phys_body_id b;
    switch (fuzz_u8(in) % 10) {
    case 0: make_body(s); break;
    case 1: {
        cpl_body_def d = cpl_default_body_def();
        d.two_way = fuzz_bool(in);
        d.measure_force = fuzz_bool(in);
        CALL(s, cpl_add_body(s->c, pick_body(s), fuzz_u8(in) < 32 ? NULL : &d));
        break;
    }
    case 2: CALL(s, cpl_remove_body(s->c, pick_body(s))); break;
    case 3: {
        b = pick_body(s);
        (void)cpl_has_body(s->c, b);
        pbf_collider_id col;
        cpl_body_stats st;
        CALL(s, cpl_body_collider(s->c, b, fuzz_u8(in) < 16 ? NULL : &col));
        CALL(s, cpl_body_get_stats(s->c, b, fuzz_u8(in) < 16 ? NULL : &st));
        break;
    }
    case 4: CALL(s, cpl_teleport_body(s->c, pick_body(s), vec(in), quat(in))); break;
    case 5:
        if (s->steps < MAX_STEPS) {
            s->steps++;
            CALL(s, cpl_step(s->c, dt_value(in)));
        }
        break;
    case 6: (void)phys_body_destroy(phys, pick_body(s)); break; // behind the coupling's back
    case 7:
        b = pick_body(s);
        (void)phys_body_set_linear_velocity(phys, b, vec(in));
        (void)phys_body_set_held_force(phys, b, vec(in), vec(in));
        (void)phys_body_apply_impulse(phys, b, vec(in), true);
        break;
    case 8: {
        cpl_def d;
        (void)cpl_body_count(s->c);
        (void)cpl_step_count(s->c);
        CALL(s, cpl_get_def(s->c, fuzz_u8(in) < 16 ? NULL : &d));
        break;
    }
    default: {
        pbf_block_def blk = pbf_default_block_def();
        for (int k = 0; k < 3; k++) {
            blk.min[k] = 0.3f;
            blk.max[k] = 0.3f + 0.05f * (float)(1 + fuzz_u8(in) % 4);
        }
        (void)pbf_world_add_block(fluid, &blk, NULL);
        break;
    }
    }
}

// A def from the table's names with fuzzer values, or raw fields, or without a world.
static cpl_def make_def(fuzz_input *in)
{
    cpl_def d = cpl_default_def();
    d.phys = phys;
    d.fluid = fluid;
    d.log = fuzz_bool(in) ? cpl_log : NULL;
    int count = 0;
    const cpl_setting_info *table = cpl_setting_table(&count);
    int changes = fuzz_u8(in) % 4;
    for (int i = 0; i < changes; i++) {
        const cpl_setting_info *info = &table[fuzz_u8(in) % count];
        char err[160] = "";
        double v = fuzz_u8(in) < 200 ? info->min + (info->max - info->min) * fuzz_u8(in) / 255.0 : fuzz_double(in);
        size_t room = fuzz_bool(in) ? sizeof err : 0;
        if (cpl_def_set(&d, info->name, v, err, room) != CPL_OK && room && !err[0]) abort(); // refused, no message
    }
    uint8_t raw = fuzz_u8(in);
    if (raw == 255) d.force_latency = (int)fuzz_u32(in);
    if (raw == 254) d.force_smoothing = fuzz_float(in);
    if (raw == 253) d.mesh_cell = fuzz_float(in);
    if (raw == 252) d.phys = NULL;
    if (raw == 251) d.fluid = NULL;
    return d;
}

static void empty_phys(state *s)
{
    for (int i = 0; i < s->body_count; i++)
        if (phys_body_is_valid(phys, s->bodies[i])) phys_body_destroy(phys, s->bodies[i]);
    for (int i = 0; i < s->shape_count; i++)
        if (phys_shape_is_valid(phys, s->shapes[i])) phys_shape_destroy(phys, s->shapes[i]);
    if (phys_world_get_body_count(phys) != 0) abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = { data, size };
    state s;
    memset(&s, 0, sizeof s);
    s.in = &in;
    cpl_def d = make_def(&in);
    char err[256] = "";
    s.c = cpl_create(&d, err, sizeof err);
    if (!s.c) {
        if (!err[0]) abort(); // refused without a message
    } else {
        for (int i = 0; i < MAX_OPS && in.size > 0; i++) op(&s);
        cpl_destroy(s.c);
    }
    empty_phys(&s);
    fuzz_gl_reset_base(fluid, &fluid_def.params);
    return 0;
}
