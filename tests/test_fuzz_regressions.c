// What the fuzzers of tests/fuzz/ found in the fluid API, each pinned as a plain test (the
// inputs themselves are in tests/fuzz/regressions/, replayed by the harnesses). Headless on
// llvmpipe; run by tests/run.sh with the strict GL mode on, so a missing barrier fails.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine/gl/context.h"
#include "fluid/pbf.h"
#include "tests/support.h"

static eng_context *ctx;

static int setup(void **state)
{
    (void)state;
    ctx = support_headless_context(64, 64);
    return ctx ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    eng_context_destroy(ctx);
    return 0;
}

static pbf_world *small_world(uint32_t capacity)
{
    pbf_world_def d = pbf_default_world_def();
    d.capacity = capacity;
    char err[512];
    pbf_world *w = pbf_world_create(&d, err, sizeof err);
    if (!w) print_error("%s\n", err);
    assert_non_null(w);
    return w;
}

// fuzz_pbf_api, regressions/clear_after_add_particles_without_barrier: pbf_world_clear
// uploaded the particle count right after the append's count pass had written it in a
// shader, with no GL_BUFFER_UPDATE_BARRIER_BIT between (the strict GL mode stops it).
static void clear_right_after_adding_particles_is_ordered_after_the_append(void **state)
{
    (void)state;
    pbf_world *w = small_world(256);
    float p[3 * 4] = { 0.5f, 0.5f, 0.5f, 0.55f, 0.5f, 0.5f, 0.5f, 0.55f, 0.5f, 0.5f, 0.5f, 0.55f };
    assert_int_equal(pbf_world_add_particles(w, p, NULL, 4), PBF_OK);
    pbf_world_clear(w);
    assert_int_equal(pbf_world_particle_count(w), 0);
    assert_int_equal(pbf_world_read_particles(w, NULL, NULL, NULL, 4), 0);
    assert_int_equal(pbf_world_add_particles(w, p, NULL, 4), PBF_OK);
    assert_int_equal(pbf_world_step(w, 1.0f / 60.0f), PBF_OK);
    assert_int_equal(pbf_world_read_particles(w, NULL, NULL, NULL, 4), 4);
    pbf_world_destroy(w);
}

// fuzz_pbf_api, regressions/denormal_dt_gives_zero_substeps: dt = 1e-45 s was in (0, 1],
// so it was taken, and each of 4 substeps lasted 0 s (1/dt infinite on the GPU).
static void denormal_dt_is_refused(void **state)
{
    (void)state;
    pbf_world *w = small_world(64);
    assert_int_equal(pbf_world_step(w, 1e-45f), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "dt must be in [1e-06, 1] s (got 1.4013e-45)"));
    assert_int_equal(pbf_world_step(w, 1e-7f), PBF_ERR_INVALID_ARG);
    assert_int_equal(pbf_world_step(w, PBF_MIN_DT), PBF_OK);
    pbf_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(clear_right_after_adding_particles_is_ordered_after_the_append),
        cmocka_unit_test(denormal_dt_is_refused),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
