// fluid/pbf.h refuses misuse instead of crashing: every function given a NULL world or a
// NULL pointer where it needs one returns an error (or 0 / NULL / false where it returns a
// value), and the world's message names the argument. Also sizes that would overflow, and
// a step started from inside a step.
#include "tests/support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/egl.h>

#include "fluid/pbf.h"

typedef struct fixture {
    eng_context *ctx;
    pbf_world *world;
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    if (!f) return -1;
    f->ctx = support_headless_context(32, 32);
    pbf_world_def d = pbf_default_world_def();
    d.params.particle_radius = 0.02f;
    d.params.kernel_radius = 0.08f;
    d.max_neighbours = pbf_suggest_max_neighbours(&d.params);
    d.capacity = 2048;
    char err[512];
    f->world = pbf_world_create(&d, err, sizeof err);
    if (!f->world) return -1;
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    pbf_world_destroy(f->world);
    eng_context_destroy(f->ctx);
    free(f);
    return 0;
}

static void null_world_is_refused_by_every_function(void **state)
{
    (void)state;
    const float v3[3] = { 0.1f, 0.1f, 0.1f }, q[4] = { 0, 0, 0, 1 };
    float out3[3], out3b[3];
    pbf_block_def b = pbf_default_block_def();
    pbf_emitter_def e = pbf_default_emitter_def();
    pbf_collider_def c = pbf_default_collider_def();
    pbf_params p = pbf_default_params();
    pbf_emitter_id eid = { 0 };
    pbf_sink_id sid = { 0 };
    pbf_collider_id cid = { 0 };
    pbf_collider_report rep;
    pbf_step_stats st[2];
    float buf[8];
    assert_int_equal(pbf_world_set_params(NULL, &p), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_set_container(NULL, v3, v3, false), PBF_ERR_INVALID_ARG);
    pbf_world_remove_container(NULL);
    assert_int_equal(pbf_world_add_block(NULL, &b, NULL), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_add_particles(NULL, buf, NULL, 1), PBF_ERR_INVALID_ARG);
    pbf_world_clear(NULL);
    assert_true(pbf_emitter_max_rate(NULL, 1.0f, 0.05f) == 0.0f);
    assert_int_equal(pbf_world_add_emitter(NULL, &e, &eid), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_set_emitter(NULL, eid, &e), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_remove_emitter(NULL, eid), PBF_ERR_INVALID_ARG);
    assert_false(pbf_emitter_is_valid(NULL, eid));
    assert_int_equal(pbf_world_add_sink(NULL, v3, v3, &sid), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_remove_sink(NULL, sid), PBF_ERR_INVALID_ARG);
    assert_false(pbf_sink_is_valid(NULL, sid));
    assert_int_equal(pbf_world_particle_count(NULL), 0);
    assert_int_equal(pbf_world_capacity(NULL), 0);
    assert_true(pbf_world_particle_mass(NULL) == 0.0f);
    assert_int_equal(pbf_world_step(NULL, 0.01f), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_step_with(NULL, 0.01f, NULL, NULL), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_add_collider(NULL, &c, &cid), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_remove_collider(NULL, cid), PBF_ERR_INVALID_ARG);
    assert_false(pbf_collider_is_valid(NULL, cid));
    assert_int_equal(pbf_world_set_collider_pose(NULL, cid, v3, q, NULL, NULL, NULL), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_collider_force(NULL, cid, out3, out3b), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_collider_report(NULL, cid, 1, false, &rep), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_set_collider_strength(NULL, cid, 1.0f), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_poll_stats(NULL, st, 2, false), 0);
    pbf_gpu_buffers g = pbf_world_gpu_buffers(NULL);
    assert_int_equal(g.positions, 0);
    assert_int_equal(pbf_world_read_particles(NULL, buf, NULL, NULL, 2), 0);
    assert_true(pbf_world_state_hash(NULL) == 0);
    assert_null(pbf_world_params(NULL));
    assert_non_null(pbf_world_last_error(NULL));
    pbf_world_destroy(NULL);
    assert_null(pbf_world_create(NULL, NULL, 0));
    char err[128];
    assert_null(pbf_world_create(NULL, err, sizeof err));
    assert_non_null(strstr(err, "def"));
}

static void null_pointers_are_refused_naming_the_argument(void **state)
{
    fixture *f = *state;
    pbf_world *w = f->world;
    const float v3[3] = { 0.1f, 0.1f, 0.1f };
    float out3[3];
    pbf_emitter_def e = pbf_default_emitter_def();
    pbf_emitter_id eid = { 0 };
    pbf_collider_id cid = { 0 };
    char err[256];
    assert_int_equal(pbf_world_set_params(w, NULL), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "params"));
    assert_int_equal(pbf_world_set_container(w, NULL, v3, false), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "min"));
    assert_int_equal(pbf_world_set_container(w, v3, NULL, false), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "max"));
    assert_int_equal(pbf_world_add_block(w, NULL, NULL), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "block"));
    assert_int_equal(pbf_world_add_emitter(w, NULL, &eid), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_add_emitter(w, &e, NULL), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_set_emitter(w, eid, NULL), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_add_sink(w, NULL, v3, NULL), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_add_sink(w, v3, NULL, NULL), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_add_collider(w, NULL, &cid), PBF_ERR_INVALID_ARG);
    // Without the id an object could never be removed: refused, no slot taken.
    pbf_collider_def box = pbf_default_collider_def();
    assert_int_equal(pbf_world_add_collider(w, &box, NULL), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "pbf_world_add_collider: out must not be NULL"));
    const float lo3[3] = { 0.0f, 0.0f, 0.0f };
    assert_int_equal(pbf_world_add_sink(w, lo3, v3, NULL), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "pbf_world_add_sink: out must not be NULL"));
    assert_int_equal(pbf_world_set_params(w, NULL), PBF_ERR_INVALID_ARG); // a message the next must replace
    assert_int_equal(pbf_world_region_stats(w, lo3, v3, NULL), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "pbf_world_region_stats: out must not be NULL"));
    assert_int_equal(pbf_world_set_collider_pose(w, cid, NULL, NULL, NULL, NULL, NULL), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_collider_force(w, cid, NULL, NULL), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_collider_report(w, cid, 1, false, NULL), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_poll_stats(w, NULL, 4, false), 0);
    (void)out3;
    // The parameter helpers.
    assert_int_equal(pbf_params_validate(NULL, err, sizeof err), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_params_validate(NULL, NULL, 0), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_params_set(NULL, "iterations", 3, err, sizeof err), PBF_ERR_INVALID_ARG);
    pbf_params p = pbf_default_params();
    assert_int_equal(pbf_params_set(&p, NULL, 3, err, sizeof err), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_params_set(&p, "iterations", 3, NULL, 0), PBF_OK);
    assert_null(pbf_param_find(NULL));
    assert_int_equal(pbf_suggest_max_neighbours(NULL), 0);
    assert_true(pbf_world_def_memory(NULL) == 0);
    assert_non_null(pbf_param_table(NULL));
    // Values that do not fit.
    assert_true(pbf_emitter_max_rate(w, 1e30f, 1e30f) >= 0.0f);
    assert_true(pbf_emitter_max_rate(w, NAN, 0.05f) == 0.0f);
}

static void again_from_hook(void *user, pbf_world *w, int substep, float dt)
{
    (void)substep;
    (void)dt;
    pbf_result *r = user;
    *r = pbf_world_step(w, 0.01f);
}

static void step_from_inside_a_step_is_refused(void **state)
{
    fixture *f = *state;
    pbf_result inner = PBF_OK;
    assert_int_equal(pbf_world_step_with(f->world, 0.01f, again_from_hook, &inner), PBF_OK);
    assert_int_equal(inner, PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(f->world), "inside"));
    // And the world still steps afterwards.
    assert_int_equal(pbf_world_step(f->world, 0.01f), PBF_OK);
}

static void destroy_from_hook(void *user, pbf_world *w, int substep, float dt)
{
    (void)user;
    (void)substep;
    (void)dt;
    pbf_world_destroy(w); // the step goes on with it: ignored
    pbf_world_clear(w);
}

// pbf_world_destroy and pbf_world_clear return nothing: inside a hook they are ignored and say
// so (the step went on with a freed world before 0.19.3).
static void destroy_and_clear_from_a_hook_are_ignored(void **state)
{
    fixture *f = *state;
    uint64_t serial = pbf_world_serial(f->world);
    assert_true(serial != 0);
    assert_true(pbf_world_alive(f->world, serial));
    assert_false(pbf_world_alive(f->world, serial + 1));
    assert_int_equal(pbf_world_step_with(f->world, 0.01f, destroy_from_hook, NULL), PBF_OK);
    assert_non_null(strstr(pbf_world_last_error(f->world), "pbf_world_clear: called from inside a step (the substep hook): ignored"));
    assert_true(pbf_world_alive(f->world, serial));
    assert_int_equal(pbf_world_step(f->world, 0.01f), PBF_OK);
    // A world destroyed is no longer alive, and a new one never takes its serial.
    pbf_world_def d = pbf_default_world_def();
    d.capacity = 64;
    char err[256];
    pbf_world *other = pbf_world_create(&d, err, sizeof err);
    assert_non_null(other);
    uint64_t other_serial = pbf_world_serial(other);
    assert_true(other_serial > serial);
    pbf_world_destroy(other);
    assert_false(pbf_world_alive(other, other_serial));
    assert_int_equal(pbf_world_serial(other), 0);
}

// A collider's strength outside [0, 1] (or not a number) is refused naming the value; a
// removed collider's id is stale.
static void collider_strength_is_checked(void **state)
{
    fixture *f = *state;
    pbf_collider_def c = pbf_default_collider_def();
    pbf_collider_id id;
    assert_int_equal(pbf_world_add_collider(f->world, &c, &id), PBF_OK);
    assert_int_equal(pbf_world_set_collider_strength(f->world, id, 0.5f), PBF_OK);
    const float bad[] = { -0.1f, 1.5f, NAN, INFINITY };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        assert_int_equal(pbf_world_set_collider_strength(f->world, id, bad[k]), PBF_ERR_INVALID_ARG);
        assert_non_null(strstr(pbf_world_last_error(f->world), "strength must be in [0, 1] (got "));
    }
    assert_non_null(strstr(pbf_world_last_error(f->world), "(got inf)"));
    assert_int_equal(pbf_world_remove_collider(f->world, id), PBF_OK);
    assert_int_equal(pbf_world_set_collider_strength(f->world, id, 1.0f), PBF_ERR_STALE_ID);
}

// The coarse level on a domain too large for its grid is refused naming level_sweeps and
// the domain, at creation and as a change of parameters (which then leaves the world as it
// was); larger cells make it fit. A level_sweeps outside [0, 200] names the field and value.
static void coarse_level_beyond_its_grid_is_refused(void **state)
{
    fixture *f = *state;
    pbf_params p = *pbf_world_params(f->world);
    p.level_sweeps = 201;
    assert_int_equal(pbf_world_set_params(f->world, &p), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(f->world), "pbf_params.level_sweeps must be in [0, 200]"));
    assert_non_null(strstr(pbf_world_last_error(f->world), "(got 201)"));

    pbf_world_def d = pbf_default_world_def();
    d.params = *pbf_world_params(f->world); // h = 0.08 m
    d.max_neighbours = pbf_suggest_max_neighbours(&d.params);
    d.capacity = 64;
    for (int k = 0; k < 3; k++) d.domain_min[k] = -20.0f, d.domain_max[k] = 20.0f; // 500^3 cells of h
    d.params.level_sweeps = 20;
    char err[512];
    assert_null(pbf_world_create(&d, err, sizeof err));
    assert_non_null(strstr(err, "level_sweeps 20 needs a coarse grid over the domain (40 x 40 x 40 m)"));
    d.params.level_sweeps = 0;
    pbf_world *w = pbf_world_create(&d, err, sizeof err);
    assert_non_null(w);
    p = d.params;
    p.level_sweeps = 20;
    assert_int_equal(pbf_world_set_params(w, &p), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "at most 4194304"));
    assert_int_equal(pbf_world_params(w)->level_sweeps, 0);
    p.level_cell = 16.0f; // 31^3 cells of 1.28 m
    assert_int_equal(pbf_world_set_params(w, &p), PBF_OK);
    assert_int_equal(pbf_world_step(w, 0.01f), PBF_OK);
    pbf_world_destroy(w);
}

// With no context current, GL calls do nothing: the calls that need one say so instead of
// returning OK with nothing done (or, for a read, nothing read).
static void calls_without_a_current_context_are_refused(void **state)
{
    fixture *f = *state;
    pbf_world *w = f->world;
    EGLDisplay dpy = eglGetCurrentDisplay();
    EGLContext ctx = eglGetCurrentContext();
    EGLSurface draw = eglGetCurrentSurface(EGL_DRAW), read = eglGetCurrentSurface(EGL_READ);
    assert_true(ctx != EGL_NO_CONTEXT);
    assert_true(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT));
    const char *want = "no OpenGL context is current on this thread";
    pbf_block_def b = pbf_default_block_def();
    b.min[0] = b.min[1] = b.min[2] = 0.1f;
    b.max[0] = b.max[1] = b.max[2] = 0.2f;
    const float lo[3] = { 0, 0, 0 }, hi[3] = { 1, 1, 1 }, p[3] = { 0.3f, 0.3f, 0.3f };
    float out[3];
    uint32_t got = 7;
    assert_int_equal(pbf_world_step(w, 1.0f / 60.0f), PBF_ERR_GL);
    assert_non_null(strstr(pbf_world_last_error(w), "pbf_world_step: no OpenGL context is current"));
    assert_int_equal(pbf_world_add_block(w, &b, NULL), PBF_ERR_GL);
    assert_int_equal(pbf_world_add_particles(w, p, NULL, 1), PBF_ERR_GL);
    assert_int_equal(pbf_world_set_params(w, pbf_world_params(w)), PBF_ERR_GL);
    assert_int_equal(pbf_world_set_container(w, lo, hi, false), PBF_ERR_GL);
    assert_int_equal(pbf_world_read_fields(w, lo, hi, out, NULL, NULL, 1, &got), PBF_ERR_GL);
    assert_int_equal(got, 0);
    assert_non_null(strstr(pbf_world_last_error(w), want));
    assert_int_equal(pbf_world_state_hash(w), 0);
    pbf_world_def d = pbf_default_world_def();
    char err[256] = "";
    assert_null(pbf_world_create(&d, err, sizeof err));
    assert_non_null(strstr(err, "pbf_world_create: no OpenGL context is current"));
    // Current again: the same calls work, and nothing was half done.
    assert_true(eglMakeCurrent(dpy, draw, read, ctx));
    assert_int_equal(pbf_world_add_block(w, &b, &got), PBF_OK);
    assert_true(got > 0);
    assert_int_equal(pbf_world_step(w, 1.0f / 60.0f), PBF_OK);
    pbf_world_clear(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(null_world_is_refused_by_every_function),
        cmocka_unit_test(null_pointers_are_refused_naming_the_argument),
        cmocka_unit_test(step_from_inside_a_step_is_refused),
        cmocka_unit_test(destroy_and_clear_from_a_hook_are_ignored),
        cmocka_unit_test(collider_strength_is_checked),
        cmocka_unit_test(coarse_level_beyond_its_grid_is_refused),
        cmocka_unit_test(calls_without_a_current_context_are_refused),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
