// What the fuzzers of tests/fuzz/ found in the fluid API (and what was found while writing
// them), each pinned as a plain test (the fuzzers' inputs are in tests/fuzz/regressions/,
// replayed by the harnesses). Headless on
// llvmpipe; run by tests/run.sh with the strict GL mode on, so a missing barrier fails.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

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

static pbf_world *fine_world(uint32_t capacity)
{
    pbf_world_def d = pbf_default_world_def();
    d.params.particle_radius = 0.0006f; // spacing 1.2 mm
    d.params.kernel_radius = 0.0024f;
    d.params.max_speed = 100.0f; // the nozzles below are that fast
    d.max_neighbours = pbf_suggest_max_neighbours(&d.params);
    d.capacity = capacity;
    for (int k = 0; k < 3; k++) d.domain_max[k] = 1.5f; // room for a nozzle of 0.68 m
    char err[512];
    pbf_world *w = pbf_world_create(&d, err, sizeof err);
    if (!w) print_error("%s\n", err);
    assert_non_null(w);
    return w;
}

// Found writing fuzz_pbf_api: a 10 m nozzle (in range) on 1.2 mm particles made a disc of
// 2.2e8 points: 3.9 s and 1.8 GB to add the emitter. Now at most PBF_MAX_EMITTER_POINTS.
static void nozzle_of_too_many_points_is_refused(void **state)
{
    (void)state;
    pbf_world *w = fine_world(1000);
    pbf_emitter_def e = pbf_default_emitter_def();
    e.position[0] = e.position[1] = e.position[2] = 0.05f;
    e.radius = 10.0f;
    e.speed = 100.0f;
    pbf_emitter_id id;
    assert_int_equal(pbf_world_add_emitter(w, &e, &id), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "pbf_emitter_def.radius 10 m holds more than 1048576 particles"));
    pbf_world_destroy(w);
}

// Found writing fuzz_pbf_api: a nozzle of nearly PBF_MAX_EMITTER_POINTS points at its
// highest rate for a 1 s step owes 8e10 particles, which overflowed an int (signed overflow
// and a float-to-int conversion out of range: undefined behaviour). It fills the capacity.
static void long_step_of_a_wide_fast_nozzle_fills_the_capacity(void **state)
{
    (void)state;
    pbf_world *w = fine_world(1000);
    pbf_emitter_def e = pbf_default_emitter_def();
    e.position[0] = e.position[1] = e.position[2] = 0.75f;
    e.radius = 0.68f;
    e.speed = 100.0f;
    e.rate = pbf_emitter_max_rate(w, e.speed, e.radius);
    pbf_emitter_id id;
    assert_int_equal(pbf_world_add_emitter(w, &e, &id), PBF_OK);
    assert_int_equal(pbf_world_step(w, 1.0f), PBF_OK);
    assert_int_equal(pbf_world_particle_count(w), 1000);
    pbf_world_destroy(w);
}

// fuzz_pbf_api, regressions/grid_scan_past_max_work_group_count: 1 mm particles in a 1 m
// domain needed 128M grid cells when the grid was dense, and the scan's first level
// dispatched 125,000 work groups where llvmpipe (and GL's minimum) allows 65535. The grid is
// hashed now (buckets in proportion to the capacity), so that world is made and steps; more
// than 65535 x 128 particles is still refused when GL_MAX_COMPUTE_WORK_GROUP_COUNT is that
// small (NVIDIA's is 2^31 - 1).
static void grid_or_capacity_beyond_one_dispatch_is_refused(void **state)
{
    (void)state;
    GLint groups = 0;
    glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &groups);
    pbf_world_def d = pbf_default_world_def();
    d.params.particle_radius = 0.001f;
    d.params.kernel_radius = 0.004f;
    d.max_neighbours = pbf_suggest_max_neighbours(&d.params);
    d.capacity = 1000;
    char err[512] = "";
    pbf_world *w = pbf_world_create(&d, err, sizeof err);
    assert_non_null(w);
    float pos[3] = { 0.5f, 0.5f, 0.5f };
    assert_int_equal(pbf_world_add_particles(w, pos, NULL, 1), PBF_OK);
    assert_int_equal(pbf_world_step(w, 1.0f / 60.0f), PBF_OK);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    pbf_world_destroy(w);
    d = pbf_default_world_def();
    if ((double)groups * 128.0 < 67108864.0) {
        d.capacity = (uint32_t)groups * 128u + 1u;
        assert_null(pbf_world_create(&d, err, sizeof err));
        print_message("%s\n", err);
        assert_non_null(strstr(err, "GL_MAX_COMPUTE_WORK_GROUP_COUNT"));
    }
}

// 2.1M particles hash into 2^23 buckets: clearing them one per thread needs 65537 work
// groups of 128, past GL's minimum of 65535 (llvmpipe's limit), so the clear strides.
static void bucket_clear_of_a_large_world_fits_one_dispatch(void **state)
{
    (void)state;
    pbf_world_def d = pbf_default_world_def();
    d.capacity = 2100000;
    char err[512] = "";
    pbf_world *w = pbf_world_create(&d, err, sizeof err);
    assert_non_null(w);
    float pos[6] = { 0.5f, 0.5f, 0.5f, 0.52f, 0.5f, 0.5f };
    assert_int_equal(pbf_world_add_particles(w, pos, NULL, 2), PBF_OK);
    assert_int_equal(pbf_world_step(w, 1.0f / 60.0f), PBF_OK);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    float out[8];
    assert_int_equal(pbf_world_read_particles(w, out, NULL, NULL, 2), 2);
    assert_true(out[1] < 0.5f && out[1] > 0.49f); // fell, by about g dt^2
    assert_true(out[5] < 0.5f && out[5] > 0.49f);
    pbf_world_destroy(w);
}

// fuzz_pbf_api, regressions/memory_of_a_def_whose_domain_is_not_finite: pbf_world_def_memory
// takes any def, unchecked; with the coarse level on, its layout divided a NaN domain into
// cells and converted the NaN to an integer (undefined behaviour, which the sanitizers'
// build stops on). The level's cells are now not counted where its layout cannot be made,
// and the world refuses the same def naming the domain.
static void memory_of_a_def_whose_domain_is_not_finite_is_defined(void **state)
{
    (void)state;
    pbf_world_def def = pbf_default_world_def();
    def.params.level_sweeps = 20;
    uint64_t with_level = pbf_world_def_memory(&def);
    def.params.level_sweeps = 0;
    uint64_t without = pbf_world_def_memory(&def);
    assert_true(with_level > without); // a finite domain: the level's cells counted
    const float bad[] = { NAN, INFINITY, -INFINITY };
    for (int k = 0; k < 3; k++) {
        def = pbf_default_world_def();
        def.domain_max[1] = bad[k];
        uint64_t plain = pbf_world_def_memory(&def);
        def.params.level_sweeps = 20;
        assert_int_equal(pbf_world_def_memory(&def), plain);
        char err[256];
        assert_null(pbf_world_create(&def, err, sizeof err));
        assert_non_null(strstr(err, "domain_max[1]"));
    }
    def = pbf_default_world_def();
    def.params.kernel_radius = NAN;
    uint64_t plain = pbf_world_def_memory(&def);
    def.params.level_sweeps = 20;
    assert_int_equal(pbf_world_def_memory(&def), plain);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(clear_right_after_adding_particles_is_ordered_after_the_append),
        cmocka_unit_test(denormal_dt_is_refused),
        cmocka_unit_test(nozzle_of_too_many_points_is_refused),
        cmocka_unit_test(long_step_of_a_wide_fast_nozzle_fills_the_capacity),
        cmocka_unit_test(grid_or_capacity_beyond_one_dispatch_is_refused),
        cmocka_unit_test(bucket_clear_of_a_large_world_fits_one_dispatch),
        cmocka_unit_test(memory_of_a_def_whose_domain_is_not_finite_is_defined),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
