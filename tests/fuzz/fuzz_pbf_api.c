// libFuzzer harness: the fluid module's C API (fluid/pbf.h) on a real GL context.
//
// One headless EGL context (engine/gl/context.h, Mesa's llvmpipe here) is made once, with
// KHR_debug on and the strict GL mode (SEICHE_GL_STRICT, engine/gl/gl_strict.h): a GL error
// or a synchronisation hazard our calls cause aborts the input like a crash. One small world
// (2048 particles, a 1 m box) is made once too and reset after every input; an input may
// also make a second world from a fuzzer-made pbf_world_def and use that.
//
// Each input is a sequence of calls with fuzzer-chosen arguments: NaN, infinities, huge,
// tiny and negative numbers, NULL pointers, null, stale and made-up ids, capacities at and
// past their limits, tiny and huge radii and domains, odd dt, nested calls from the substep
// hook. Every call must return PBF_OK or an error (with a message in pbf_world_last_error),
// never crash, hang, leak or touch memory it does not own. Inputs stay cheap: at most 6
// steps, 4 iterations x 4 substeps, 3 sweeps of the coarse level, 2048 particles (4096 in a fuzzer-made world, and no
// world needing more than 64 MiB).
// Build and run: make fuzz (docs/testing.md).
#include "tests/fuzz/fuzz_gl.h"
#include "fluid/pbf.h"
#include "fluid/pbf_internal.h"
#include "tests/fuzz/fuzz_input.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_IDS 96
#define MAX_STEPS 6
#define MAX_OPS 48

static eng_context *ctx;
static pbf_world *base;
static pbf_world_def base_def;

typedef struct state {
    pbf_world *w;      // the world calls go to: base or `own`
    pbf_world *own;    // a world made by this input, destroyed at its end
    pbf_collider_id colliders[MAX_IDS];
    int collider_count;
    pbf_emitter_id emitters[MAX_IDS];
    int emitter_count;
    pbf_sink_id sinks[MAX_IDS];
    int sink_count;
    int steps;
    int hook_depth;
    fuzz_input *in;
} state;

static void quiet_log(void *user, int level, const char *message)
{
    (void)user;
    if (level < 0 || level > 3 || !message || !message[0]) abort();
}

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    ctx = fuzz_gl_context("fuzz_pbf_api");
    base = fuzz_gl_base_world("fuzz_pbf_api", quiet_log, &base_def);
    return 0;
}

// ---- checks -----------------------------------------------------------------------------

static pbf_result check(state *s, pbf_world *w, pbf_result r, const char *fn)
{
    (void)s;
    if ((int)r < PBF_OK || r > PBF_ERR_OUT_OF_MEMORY) {
        fprintf(stderr, "%s returned %d, not a pbf_result\n", fn, (int)r);
        abort();
    }
    if (r != PBF_OK && w && !pbf_world_last_error(w)[0]) {
        fprintf(stderr, "%s failed (%d) without a message\n", fn, (int)r);
        abort();
    }
    return r;
}

// ---- argument makers ----------------------------------------------------------------------

// A position: inside the world's 1 m box most of the time (so calls get past the checks).
static float coord(fuzz_input *in)
{
    uint8_t how = fuzz_u8(in);
    if (how < 160) return (float)how / 160.0f;
    return fuzz_float(in);
}

static void vec(fuzz_input *in, float *v, int n)
{
    for (int k = 0; k < n; k++) v[k] = coord(in);
}

// A small positive size most of the time.
static float size_value(fuzz_input *in)
{
    uint8_t how = fuzz_u8(in);
    if (how < 128) return 0.01f + (float)how / 256.0f;
    return fuzz_float(in);
}

static void unit_quat(fuzz_input *in, float q[4])
{
    uint8_t how = fuzz_u8(in);
    q[0] = q[1] = q[2] = 0.0f;
    q[3] = 1.0f;
    if (how < 128) return;
    if (how < 192) { // a rotation about an axis
        float a = (float)fuzz_u8(in) * 0.05f;
        int axis = fuzz_u8(in) % 3;
        q[axis] = sinf(a);
        q[3] = cosf(a);
        return;
    }
    for (int k = 0; k < 4; k++) q[k] = fuzz_float(in);
}

static float dt_value(fuzz_input *in)
{
    static const float table[] = { 1.0f / 60.0f, 1.0f / 120.0f, 0.004f, 0.0f, -0.016f, 1.0f, 1.0000001f, 0.5f,
                                   1e-45f, 1e-38f, 1e-30f, 1e-12f, 1e-6f, 2.0f, 1e30f, NAN, INFINITY, -INFINITY };
    uint8_t how = fuzz_u8(in);
    if (how < 200) return table[how % (sizeof table / sizeof table[0])];
    return fuzz_float(in);
}

static pbf_collider_id pick_collider(state *s)
{
    uint8_t how = fuzz_u8(s->in);
    if (s->collider_count > 0 && how < 200) return s->colliders[how % s->collider_count];
    pbf_collider_id id = { (uint16_t)fuzz_u8(s->in), (uint16_t)fuzz_u8(s->in) };
    if (how == 255) id.index1 = 0xffff;
    return id;
}

static pbf_emitter_id pick_emitter(state *s)
{
    uint8_t how = fuzz_u8(s->in);
    if (s->emitter_count > 0 && how < 200) return s->emitters[how % s->emitter_count];
    pbf_emitter_id id = { (uint16_t)fuzz_u8(s->in), (uint16_t)fuzz_u8(s->in) };
    if (how == 255) id.index1 = 0xffff;
    return id;
}

static pbf_sink_id pick_sink(state *s)
{
    uint8_t how = fuzz_u8(s->in);
    if (s->sink_count > 0 && how < 200) return s->sinks[how % s->sink_count];
    pbf_sink_id id = { (uint16_t)fuzz_u8(s->in), (uint16_t)fuzz_u8(s->in) };
    if (how == 255) id.index1 = 0xffff;
    return id;
}

// Parameters with one or more fields changed; kept cheap when they are valid.
static pbf_params params_value(state *s)
{
    pbf_params p = *pbf_world_params(s->w);
    int changes = 1 + fuzz_u8(s->in) % 3;
    for (int i = 0; i < changes; i++) {
        int count = 0;
        const pbf_param_info *table = pbf_param_table(&count);
        uint8_t which = fuzz_u8(s->in);
        if (which % (count + 1) == (unsigned)count) {
            p.gravity[fuzz_u8(s->in) % 3] = fuzz_float(s->in);
            continue;
        }
        const pbf_param_info *info = &table[which % count];
        char *field = (char *)&p + info->offset;
        if (info->is_int) {
            int v = (int)(int8_t)fuzz_u8(s->in);
            if (fuzz_u8(s->in) == 255) v = (int)fuzz_u32(s->in);
            memcpy(field, &v, sizeof v);
        } else {
            // Mostly within the documented range, else anything.
            float v = fuzz_u8(s->in) < 160 ? (float)(info->min + (info->max - info->min) * fuzz_u8(s->in) / 255.0)
                                           : fuzz_float(s->in);
            memcpy(field, &v, sizeof v);
        }
    }
    if (fuzz_u8(s->in) > 224) { // other particles, the kernel at 4 radii: tiny to huge
        static const float radii[] = { 0.0005f, 0.00051f, 0.0006f, 0.001f, 0.005f, 0.05f, 0.2f, 1.0f };
        p.particle_radius = radii[fuzz_u8(s->in) % 8];
        p.kernel_radius = 4.0f * p.particle_radius;
    }
    if (pbf_params_validate(&p, NULL, 0) == PBF_OK) {
        if (p.iterations > 4) p.iterations = 1 + p.iterations % 4;
        if (p.substeps > 4) p.substeps = 1 + p.substeps % 4;
        // The coarse level's sweeps are 2 dispatches each per substep: a few are enough to
        // exercise it (with 43, one input made 5,500 dispatches and held 3.5 GB in ASan's
        // quarantine of llvmpipe's per-dispatch allocations).
        if (p.level_sweeps > 3) p.level_sweeps = 1 + p.level_sweeps % 3;
    }
    return p;
}

// ---- the calls --------------------------------------------------------------------------------

static void op(state *s);

// The substep hook runs one more call (a nested step, edit or pose), at most two deep.
static void hook(void *user, pbf_world *world, int substep, float dt)
{
    state *s = user;
    if (world != s->w || substep < 0 || !(dt > 0.0f)) abort();
    if (s->hook_depth >= 2 || s->in->size == 0) return;
    s->hook_depth++;
    op(s);
    s->hook_depth--;
}

static void op_add_collider(state *s)
{
    fuzz_input *in = s->in;
    pbf_collider_def d = pbf_default_collider_def();
    uint8_t type = fuzz_u8(in);
    d.type = (pbf_collider_type)(type < 250 ? type % 7 : (int)(int8_t)type);
    for (int k = 0; k < 4; k++) d.size[k] = size_value(in);
    if (d.type == PBF_SHAPE_PLANE && fuzz_bool(in)) {
        d.size[0] = 0.0f;
        d.size[1] = 1.0f;
        d.size[2] = 0.0f;
        d.size[3] = coord(in);
    }
    vec(in, d.position, 3);
    unit_quat(in, d.rotation);
    d.two_way = fuzz_bool(in);
    float planes[4 * 8];
    float *grid = NULL;
    if (d.type == PBF_SHAPE_CONVEX_HULL) {
        // A box as 6 planes, or fuzzer planes; plane_count up to what the array holds, or a
        // count out of range (checked before the planes are read).
        static const float box[6][4] = { { 1, 0, 0, 0.1f }, { -1, 0, 0, 0.1f }, { 0, 1, 0, 0.1f },
                                         { 0, -1, 0, 0.1f }, { 0, 0, 1, 0.1f }, { 0, 0, -1, 0.1f } };
        memcpy(planes, box, sizeof box);
        uint8_t how = fuzz_u8(in);
        d.plane_count = how < 200 ? 4 + how % 5 : how == 255 ? PBF_MAX_HULL_PLANES + 1 : how % 4;
        if (fuzz_bool(in))
            for (int k = 0; k < 4 * 8; k++) planes[k] = fuzz_float(in);
        d.planes = fuzz_u8(in) == 0 ? NULL : planes;
    }
    if (d.type == PBF_SHAPE_SDF) {
        // Small grids only (values must hold dims[0] * dims[1] * dims[2] samples); dims out of
        // range are refused before values is read.
        uint32_t dims[3];
        for (int k = 0; k < 3; k++) {
            uint8_t how = fuzz_u8(in);
            dims[k] = how < 200 ? 2 + how % 7 : how < 230 ? how % 2 : 1024u + how;
        }
        memcpy(d.grid.dims, dims, sizeof dims);
        size_t n = 1;
        bool valid_dims = true;
        for (int k = 0; k < 3; k++) {
            valid_dims &= dims[k] >= 2 && dims[k] <= 1023;
            n *= valid_dims ? dims[k] : 1;
        }
        grid = malloc(n * sizeof *grid);
        for (size_t i = 0; i < n; i++) grid[i] = (float)i * 0.01f - 0.05f;
        if (fuzz_u8(in) > 240) grid[fuzz_u8(in) % n] = fuzz_float(in);
        d.grid.values = fuzz_u8(in) == 0 ? NULL : grid;
        vec(in, d.grid.origin, 3);
        d.grid.cell = size_value(in);
    }
    pbf_collider_id id = { 0, 0 };
    uint8_t nulls = fuzz_u8(in);
    pbf_result r = check(s, s->w, pbf_world_add_collider(s->w, nulls == 1 ? NULL : &d, nulls == 2 ? NULL : &id),
                         "pbf_world_add_collider");
    if (r == PBF_OK && nulls != 2) {
        if (!pbf_collider_is_valid(s->w, id)) abort();
        if (s->collider_count < MAX_IDS) s->colliders[s->collider_count++] = id;
    }
    free(grid);
}

static void op_emitter(state *s)
{
    fuzz_input *in = s->in;
    pbf_emitter_def d = pbf_default_emitter_def();
    vec(in, d.position, 3);
    if (fuzz_bool(in)) vec(in, d.direction, 3);
    if (fuzz_bool(in)) d.speed = fuzz_float(in);
    if (fuzz_bool(in)) d.radius = fuzz_float(in);
    if (fuzz_bool(in)) {
        float max = pbf_emitter_max_rate(s->w, d.speed, d.radius);
        d.rate = fuzz_bool(in) ? max * (float)fuzz_u8(in) / 255.0f : fuzz_float(in);
    }
    d.enabled = fuzz_u8(in) != 0;
    uint8_t what = fuzz_u8(in) % 3;
    uint8_t nulls = fuzz_u8(in);
    if (what == 0) {
        pbf_emitter_id id = { 0, 0 };
        pbf_result r = check(s, s->w, pbf_world_add_emitter(s->w, nulls == 1 ? NULL : &d, nulls == 2 ? NULL : &id),
                             "pbf_world_add_emitter");
        if (r == PBF_OK && nulls != 2 && s->emitter_count < MAX_IDS) s->emitters[s->emitter_count++] = id;
    } else if (what == 1) {
        check(s, s->w, pbf_world_set_emitter(s->w, pick_emitter(s), nulls == 1 ? NULL : &d), "pbf_world_set_emitter");
    } else {
        check(s, s->w, pbf_world_remove_emitter(s->w, pick_emitter(s)), "pbf_world_remove_emitter");
    }
}

static void op_sink(state *s)
{
    fuzz_input *in = s->in;
    if (fuzz_bool(in)) {
        float lo[3], hi[3];
        vec(in, lo, 3);
        vec(in, hi, 3);
        pbf_sink_id id = { 0, 0 };
        uint8_t nulls = fuzz_u8(in);
        pbf_result r = check(s, s->w, pbf_world_add_sink(s->w, nulls == 1 ? NULL : lo, nulls == 2 ? NULL : hi,
                                                         nulls == 3 ? NULL : &id), "pbf_world_add_sink");
        if (r == PBF_OK && nulls != 3 && s->sink_count < MAX_IDS) s->sinks[s->sink_count++] = id;
    } else {
        check(s, s->w, pbf_world_remove_sink(s->w, pick_sink(s)), "pbf_world_remove_sink");
    }
}

static void op_pose(state *s)
{
    fuzz_input *in = s->in;
    float p[3], q[4], v[3], av[3], c[3];
    vec(in, p, 3);
    unit_quat(in, q);
    for (int k = 0; k < 3; k++) {
        v[k] = fuzz_u8(in) < 200 ? 0.1f * (float)(int8_t)fuzz_u8(in) : fuzz_float(in);
        av[k] = fuzz_u8(in) < 200 ? 0.1f * (float)(int8_t)fuzz_u8(in) : fuzz_float(in);
    }
    vec(in, c, 3);
    uint8_t nulls = fuzz_u8(in);
    check(s, s->w, pbf_world_set_collider_pose(s->w, pick_collider(s), nulls & 1 ? NULL : p, nulls & 2 ? NULL : q,
                                               nulls & 4 ? NULL : v, nulls & 8 ? NULL : av, nulls & 16 ? NULL : c),
          "pbf_world_set_collider_pose");
}

static void op_create_world(state *s)
{
    fuzz_input *in = s->in;
    if (s->own) { // back to the base world
        pbf_world_destroy(s->own);
        s->own = NULL;
        s->w = base;
        s->collider_count = s->emitter_count = s->sink_count = 0;
        return;
    }
    pbf_world_def def = pbf_default_world_def();
    def.capacity = 1024;
    def.log = fuzz_bool(in) ? quiet_log : NULL;
    uint8_t how = fuzz_u8(in);
    if (how & 1) def.capacity = fuzz_u8(in) < 200 ? 1 + fuzz_u32(in) % 4096 : fuzz_u32(in);
    if (how & 2) def.max_neighbours = fuzz_u32(in) % 600;
    if (how & 4) def.grid_cells_per_kernel = fuzz_u8(in) % 6;
    if (how & 8)
        for (int k = 0; k < 3; k++) {
            def.domain_min[k] = fuzz_float(in);
            def.domain_max[k] = fuzz_float(in);
        }
    if (how & 16) {
        s->w = base; // params_value reads the current world's
        def.params = params_value(s);
        s->w = s->own ? s->own : base;
    }
    if (how & 32) def.shader_dir = fuzz_bool(in) ? "" : "/nonexistent/shaders";
    char err_buf[256];
    size_t err_size = fuzz_u8(in) % 4 == 0 ? 0 : sizeof err_buf;
    char *err = fuzz_u8(in) == 0 ? NULL : err_buf;
    // Cheap worlds only: as a host would, ask first what one needs.
    if (def.capacity > 4096 && def.capacity <= (1u << 26)) return;
    if (pbf_world_def_memory(&def) > (64u << 20)) return;
    pbf_world *w = pbf_world_create(fuzz_u8(in) == 0 ? NULL : &def, err, err_size);
    if (!w) {
        if (err && err_size && !err[0]) {
            fprintf(stderr, "pbf_world_create failed without a message\n");
            abort();
        }
        return;
    }
    s->own = s->w = w;
    s->collider_count = s->emitter_count = s->sink_count = 0;
}

// Every function with a NULL world: an error, 0, NULL or false, never a crash.
static void op_null_world(state *s)
{
    float v[4] = { 0, 0, 0, 1 };
    pbf_collider_id cid = { 1, 1 };
    pbf_emitter_id eid = { 1, 1 };
    pbf_sink_id sid = { 1, 1 };
    pbf_params p = pbf_default_params();
    pbf_block_def b = pbf_default_block_def();
    pbf_collider_def cd = pbf_default_collider_def();
    pbf_emitter_def ed = pbf_default_emitter_def();
    pbf_collider_report rep;
    pbf_step_stats st;
    (void)s;
    if (pbf_world_step(NULL, 0.01f) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_step_with(NULL, 0.01f, hook, NULL) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_set_params(NULL, &p) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_set_container(NULL, v, v, true) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_add_block(NULL, &b, NULL) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_add_particles(NULL, v, v, 1) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_add_emitter(NULL, &ed, &eid) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_set_emitter(NULL, eid, &ed) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_remove_emitter(NULL, eid) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_add_sink(NULL, v, v, &sid) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_remove_sink(NULL, sid) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_add_collider(NULL, &cd, &cid) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_remove_collider(NULL, cid) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_set_collider_pose(NULL, cid, v, v, v, v, v) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_collider_force(NULL, cid, v, v) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_collider_report(NULL, cid, 1, false, &rep) != PBF_ERR_INVALID_ARG) abort();
    if (pbf_world_poll_stats(NULL, &st, 1, false) != 0) abort();
    if (pbf_world_read_particles(NULL, v, v, NULL, 1) != 0) abort();
    if (pbf_world_state_hash(NULL) != 0) abort();
    if (pbf_world_particle_count(NULL) || pbf_world_capacity(NULL) || pbf_world_particle_mass(NULL) != 0.0f) abort();
    if (pbf_world_params(NULL) || !pbf_world_last_error(NULL)[0]) abort();
    if (pbf_collider_is_valid(NULL, cid) || pbf_emitter_is_valid(NULL, eid) || pbf_sink_is_valid(NULL, sid)) abort();
    if (pbf_emitter_max_rate(NULL, 1.0f, 0.1f) != 0.0f) abort();
    if (pbf_world_gpu_buffers(NULL).positions != 0) abort();
    pbf_world_clear(NULL);
    pbf_world_remove_container(NULL);
    pbf_world_destroy(NULL);
}

static void op(state *s)
{
    fuzz_input *in = s->in;
    pbf_world *w = s->w;
    switch (fuzz_u8(in) % 20) {
    case 0: { // a block
        pbf_block_def b = pbf_default_block_def();
        vec(in, b.min, 3);
        for (int k = 0; k < 3; k++) b.max[k] = b.min[k] + (fuzz_u8(in) < 200 ? 0.02f + 0.002f * fuzz_u8(in) : coord(in));
        if (fuzz_bool(in)) vec(in, b.velocity, 3);
        uint32_t added = 0;
        uint8_t nulls = fuzz_u8(in);
        check(s, w, pbf_world_add_block(w, nulls == 1 ? NULL : &b, nulls == 2 ? NULL : &added), "pbf_world_add_block");
        break;
    }
    case 1: { // particles
        float pos[3 * 64], vel[3 * 64];
        uint32_t n = fuzz_u8(in) % 65;
        for (uint32_t i = 0; i < 3 * n; i++) {
            pos[i] = coord(in);
            vel[i] = fuzz_u8(in) < 220 ? 0.0f : fuzz_float(in);
        }
        uint8_t nulls = fuzz_u8(in);
        // A count past the arrays only with a NULL array (refused before it is read) or
        // past the capacity (refused before too).
        uint32_t count = nulls == 3 ? fuzz_u32(in) | 0x10000000u : n;
        check(s, w, pbf_world_add_particles(w, nulls == 1 || nulls == 3 ? NULL : pos, nulls == 2 ? NULL : vel,
                                            nulls == 3 && fuzz_bool(in) ? count : n), "pbf_world_add_particles");
        break;
    }
    case 2:
    case 3: { // a step, with the hook or without
        if (s->steps >= MAX_STEPS) break;
        s->steps++;
        float dt = dt_value(in);
        if (fuzz_bool(in)) check(s, w, pbf_world_step(w, dt), "pbf_world_step");
        else check(s, w, pbf_world_step_with(w, dt, fuzz_bool(in) ? hook : NULL, s), "pbf_world_step_with");
        break;
    }
    case 4: { // parameters
        pbf_params p = params_value(s);
        check(s, w, pbf_world_set_params(w, fuzz_u8(in) == 0 ? NULL : &p), "pbf_world_set_params");
        break;
    }
    case 5: { // the container
        if (fuzz_u8(in) < 40) {
            pbf_world_remove_container(w);
            break;
        }
        float lo[3], hi[3];
        vec(in, lo, 3);
        vec(in, hi, 3);
        uint8_t nulls = fuzz_u8(in);
        check(s, w, pbf_world_set_container(w, nulls == 1 ? NULL : lo, nulls == 2 ? NULL : hi, fuzz_bool(in)),
              "pbf_world_set_container");
        break;
    }
    case 6: op_add_collider(s); break;
    case 7: check(s, w, pbf_world_remove_collider(w, pick_collider(s)), "pbf_world_remove_collider"); break;
    case 8: op_pose(s); break;
    case 9: { // forces
        float f[3], t[3];
        pbf_collider_id id = pick_collider(s);
        uint8_t nulls = fuzz_u8(in);
        if (fuzz_bool(in)) {
            check(s, w, pbf_world_collider_force(w, id, nulls & 1 ? NULL : f, nulls & 2 ? NULL : t),
                  "pbf_world_collider_force");
        } else {
            pbf_collider_report rep;
            int back = (int)(int8_t)fuzz_u8(in);
            check(s, w, pbf_world_collider_report(w, id, back, fuzz_bool(in), nulls & 1 ? NULL : &rep),
                  "pbf_world_collider_report");
        }
        break;
    }
    case 10: op_emitter(s); break;
    case 11: op_sink(s); break;
    case 12: { // statistics
        pbf_step_stats st[8];
        int max = (int)(int8_t)fuzz_u8(in) % 9;
        bool null_out = fuzz_u8(in) == 0;
        int n = pbf_world_poll_stats(w, null_out ? NULL : st, null_out ? max : max < 0 ? 0 : max, fuzz_bool(in));
        if (n < 0 || (!null_out && n > (max < 0 ? 0 : max))) {
            fprintf(stderr, "pbf_world_poll_stats returned %d for max %d\n", n, max);
            abort();
        }
        break;
    }
    case 13: { // reading back
        static float pos[4 * 4096], vel[4 * 4096];
        static uint32_t ids[4096];
        uint32_t max = fuzz_u8(in) < 200 ? fuzz_u32(in) % 4097 : 4096;
        uint8_t nulls = fuzz_u8(in);
        uint32_t n = pbf_world_read_particles(w, nulls & 1 ? NULL : pos, nulls & 2 ? NULL : vel, nulls & 4 ? NULL : ids,
                                              max);
        if (n > max || n > pbf_world_capacity(w)) abort();
        break;
    }
    case 14: { // queries
        (void)pbf_world_state_hash(w);
        pbf_gpu_buffers b = pbf_world_gpu_buffers(w);
        if (b.count > pbf_world_capacity(w) || pbf_world_particle_count(w) > pbf_world_capacity(w)) abort();
        float rate = pbf_emitter_max_rate(w, fuzz_float(in), fuzz_float(in));
        if (!(rate >= 0.0f)) abort();
        (void)pbf_collider_is_valid(w, pick_collider(s));
        (void)pbf_emitter_is_valid(w, pick_emitter(s));
        (void)pbf_sink_is_valid(w, pick_sink(s));
        (void)pbf_world_particle_mass(w);
        break;
    }
    case 15: pbf_world_clear(w); break;
    case 16: // not from the hook: that would destroy the world being stepped (a host's bug)
        if (s->hook_depth == 0) op_create_world(s);
        break;
    case 17: op_null_world(s); break;
    default: { // a burst of steps of a normal dt, so the GPU side runs with what was added
        for (int k = 0; k < 2 && s->steps < MAX_STEPS; k++, s->steps++)
            check(s, w, pbf_world_step(w, 1.0f / 60.0f), "pbf_world_step");
        break;
    }
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = { data, size };
    state s;
    memset(&s, 0, sizeof s);
    s.w = base;
    s.in = &in;
    for (int i = 0; i < MAX_OPS && in.size > 0; i++) op(&s);
    if (s.own) pbf_world_destroy(s.own);
    fuzz_gl_reset_base(base, &base_def.params);
    return 0;
}
