// Tints (seiche.colour): a particle's colour lives on the GPU in the w of its position and
// stays with the particle however the solver sorts it; emitters pour tinted water; the
// renderer draws the tint in both modes (the surface with its particle passes drawn either
// way). Headless on llvmpipe, small scenes.
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
#include "engine/render/camera.h"
#include "engine/render/renderer.h"
#include "fluid/pbf.h"
#include "tests/support.h"

#define W 160
#define H 120

static eng_context *ctx;

static int setup(void **state)
{
    (void)state;
    ctx = support_headless_context(W, H);
    return ctx ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    eng_context_destroy(ctx);
    return 0;
}

static pbf_world *make_world(uint32_t capacity)
{
    pbf_world_def d = pbf_default_world_def();
    d.params.particle_radius = 0.025f;
    d.params.kernel_radius = 0.1f;
    d.max_neighbours = pbf_suggest_max_neighbours(&d.params);
    d.capacity = capacity;
    const float lo[3] = { -1.0f, 0.0f, -0.5f }, hi[3] = { 1.0f, 2.0f, 0.5f };
    memcpy(d.domain_min, lo, sizeof lo);
    memcpy(d.domain_max, hi, sizeof hi);
    char err[512];
    pbf_world *w = pbf_world_create(&d, err, sizeof err);
    if (!w) print_error("%s\n", err);
    assert_non_null(w);
    assert_int_equal(pbf_world_set_container(w, lo, hi, false), PBF_OK);
    return w;
}

static const float red[3] = { 1.0f, 0.0f, 0.0f }, blue[3] = { 0.0f, 0.0f, 1.0f }, green[3] = { 0.0f, 1.0f, 0.0f };

static bool same_rgb(const float a[3], const float b[3])
{
    return fabsf(a[0] - b[0]) < 1e-6f && fabsf(a[1] - b[1]) < 1e-6f && fabsf(a[2] - b[2]) < 1e-6f;
}

static void tint_code_round_trips_every_level(void **state)
{
    (void)state;
    for (int v = 0; v < 256; v++) {
        float rgb[3] = { (float)v / 255.0f, (float)(255 - v) / 255.0f, (float)((v * 7) % 256) / 255.0f }, back[3];
        float w = pbf_tint_encode(rgb);
        assert_true(w <= -1.0f && w >= -16777216.0f);
        assert_true(pbf_tint_decode(w, back));
        assert_true(same_rgb(rgb, back));
    }
    // Black and white are tints too; the height parameter [0, 1] is not.
    float back[3];
    assert_true(pbf_tint_decode(pbf_tint_encode((const float[]){ 0, 0, 0 }), back));
    assert_true(pbf_tint_decode(pbf_tint_encode((const float[]){ 1, 1, 1 }), back));
    assert_true(back[0] == 1.0f && back[1] == 1.0f && back[2] == 1.0f);
    assert_false(pbf_tint_decode(0.0f, NULL));
    assert_false(pbf_tint_decode(0.5f, NULL));
    assert_false(pbf_tint_decode(1.0f, NULL));
    assert_false(pbf_tint_decode(NAN, NULL));
}

// Reads every particle; counts those of each tint, and checks particle `id` against `want`.
typedef struct tint_count { uint32_t red, blue, green, plain, n; } tint_count;
static tint_count count_tints(pbf_world *w, float *pos, uint32_t *ids, uint32_t max)
{
    tint_count c = { 0 };
    c.n = pbf_world_read_particles(w, pos, NULL, ids, max);
    for (uint32_t i = 0; i < c.n; i++) {
        float rgb[3];
        if (!pbf_tint_decode(pos[4 * i + 3], rgb)) c.plain++;
        else if (same_rgb(rgb, red)) c.red++;
        else if (same_rgb(rgb, blue)) c.blue++;
        else if (same_rgb(rgb, green)) c.green++;
    }
    return c;
}

static void tint_follows_each_particle_as_the_blocks_mix(void **state)
{
    (void)state;
    pbf_world *w = make_world(8192);
    pbf_block_def b = pbf_default_block_def();
    const float lmin[3] = { -1.0f, 0.0f, -0.5f }, lmax[3] = { -0.6f, 0.6f, 0.5f };
    const float rmin[3] = { 0.6f, 0.0f, -0.5f }, rmax[3] = { 1.0f, 0.6f, 0.5f };
    memcpy(b.min, lmin, sizeof lmin), memcpy(b.max, lmax, sizeof lmax);
    uint32_t nl = 0, nr = 0;
    assert_int_equal(pbf_world_add_block(w, &b, &nl), PBF_OK);
    memcpy(b.min, rmin, sizeof rmin), memcpy(b.max, rmax, sizeof rmax);
    assert_int_equal(pbf_world_add_block(w, &b, &nr), PBF_OK);
    assert_int_equal(pbf_world_tint_box(w, lmin, lmax, red), PBF_OK);
    assert_int_equal(pbf_world_tint_box(w, rmin, rmax, blue), PBF_OK);
    uint32_t n = nl + nr;
    float *pos = malloc((size_t)n * 16);
    uint32_t *ids = malloc((size_t)n * 4);
    assert_non_null(pos), assert_non_null(ids);
    tint_count c = count_tints(w, pos, ids, n);
    assert_int_equal(c.red, nl);
    assert_int_equal(c.blue, nr);
    // Two dam breaks run into each other; every step sorts the particles into cell order.
    for (int s = 0; s < 90; s++) assert_int_equal(pbf_world_step(w, 1.0f / 60.0f), PBF_OK);
    c = count_tints(w, pos, ids, n);
    assert_int_equal(c.n, n);
    uint32_t moved = 0, crossed = 0;
    for (uint32_t i = 0; i < n; i++) {
        float rgb[3];
        assert_true(pbf_tint_decode(pos[4 * i + 3], rgb));
        // ids follow the order of adding: the left block's first.
        assert_true(same_rgb(rgb, ids[i] < nl ? red : blue));
        float x = pos[4 * i];
        moved += ids[i] < nl ? x > lmax[0] : x < rmin[0];
        crossed += ids[i] < nl ? x > 0.0f : x < 0.0f;
    }
    print_message("after 90 steps: %u red, %u blue; %u left their block, %u crossed the middle\n", c.red, c.blue, moved,
                  crossed);
    assert_true(moved > n / 3); // 1800 of 3840 at the defaults: enough to see the tint travel
    // Untinting gives back the height parameter.
    const float all_min[3] = { -1, 0, -0.5f }, all_max[3] = { 1, 2, 0.5f };
    assert_int_equal(pbf_world_tint_box(w, all_min, all_max, NULL), PBF_OK);
    c = count_tints(w, pos, ids, n);
    assert_int_equal(c.plain, n);
    for (uint32_t i = 0; i < n; i++) assert_true(fabsf(pos[4 * i + 3] - pos[4 * i + 1] / 2.0f) < 1e-5f);
    free(pos);
    free(ids);
    pbf_world_destroy(w);
}

static void emitter_pours_its_tint_until_it_is_cleared(void **state)
{
    (void)state;
    pbf_world *w = make_world(8192);
    pbf_emitter_def e = pbf_default_emitter_def();
    e.position[0] = 0.0f, e.position[1] = 1.0f, e.position[2] = 0.0f;
    e.direction[0] = 0.0f, e.direction[1] = -1.0f, e.direction[2] = 0.0f;
    e.speed = 1.0f, e.radius = 0.1f;
    e.rate = pbf_emitter_max_rate(w, e.speed, e.radius);
    pbf_emitter_id id;
    assert_int_equal(pbf_world_add_emitter(w, &e, &id), PBF_OK);
    assert_int_equal(pbf_world_set_emitter_tint(w, id, green), PBF_OK);
    // set_emitter keeps the tint.
    e.speed = 1.5f;
    assert_int_equal(pbf_world_set_emitter(w, id, &e), PBF_OK);
    for (int s = 0; s < 20; s++) assert_int_equal(pbf_world_step(w, 1.0f / 60.0f), PBF_OK);
    uint32_t max = 8192;
    float *pos = malloc((size_t)max * 16);
    uint32_t *ids = malloc((size_t)max * 4);
    tint_count c = count_tints(w, pos, ids, max);
    assert_true(c.n > 50);
    assert_int_equal(c.green, c.n);
    uint32_t first = c.n;
    assert_int_equal(pbf_world_set_emitter_tint(w, id, NULL), PBF_OK);
    for (int s = 0; s < 10; s++) assert_int_equal(pbf_world_step(w, 1.0f / 60.0f), PBF_OK);
    c = count_tints(w, pos, ids, max);
    assert_int_equal(c.green, first);
    assert_true(c.plain > 0);
    assert_int_equal(c.green + c.plain, c.n);
    // Bad input is named.
    assert_int_equal(pbf_world_set_emitter_tint(w, id, (const float[]){ 0, 2, 0 }), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "rgb[1] must be in [0, 1] (got 2)"));
    const float lo[3] = { 0, 0, 0 }, hi[3] = { 1, NAN, 1 };
    assert_int_equal(pbf_world_tint_box(w, lo, hi, red), PBF_ERR_INVALID_ARG);
    assert_non_null(strstr(pbf_world_last_error(w), "pbf_world_tint_box: the box must be finite"));
    assert_int_equal(pbf_world_remove_emitter(w, id), PBF_OK);
    assert_int_equal(pbf_world_set_emitter_tint(w, id, red), PBF_ERR_STALE_ID);
    free(pos);
    free(ids);
    pbf_world_destroy(w);
}

// Two tinted blocks, drawn: the red one red, the blue one blue, in both fluid modes (the
// renderer decodes the tint in GLSL: this checks it reads what pbf_tint_encode wrote).
static void both_modes_draw_the_tints(void **state)
{
    (void)state;
    pbf_world *w = make_world(8192);
    pbf_block_def b = pbf_default_block_def();
    const float lmin[3] = { -0.8f, 0.0f, -0.2f }, lmax[3] = { -0.2f, 0.5f, 0.2f };
    const float rmin[3] = { 0.2f, 0.0f, -0.2f }, rmax[3] = { 0.8f, 0.5f, 0.2f };
    memcpy(b.min, lmin, sizeof lmin), memcpy(b.max, lmax, sizeof lmax);
    assert_int_equal(pbf_world_add_block(w, &b, NULL), PBF_OK);
    memcpy(b.min, rmin, sizeof rmin), memcpy(b.max, rmax, sizeof rmax);
    assert_int_equal(pbf_world_add_block(w, &b, NULL), PBF_OK);
    assert_int_equal(pbf_world_tint_box(w, lmin, lmax, red), PBF_OK);
    assert_int_equal(pbf_world_tint_box(w, rmin, rmax, blue), PBF_OK);
    assert_int_equal(pbf_world_step(w, 1.0f / 60.0f), PBF_OK);

    eng_camera cam;
    eng_camera_def cd = eng_default_camera_def();
    cd.position[0] = 0.0f, cd.position[1] = 0.6f, cd.position[2] = 2.2f;
    cd.target[0] = 0.0f, cd.target[1] = 0.25f, cd.target[2] = 0.0f;
    char err[2048];
    assert_true(eng_camera_init(&cam, &cd, err, sizeof err));
    // spheres; the surface; the surface with its particle passes as compute splats
    static const char *const names[3] = { "spheres", "surface", "surface, compute splats" };
    for (int mode = 0; mode < 3; mode++) {
        eng_renderer_def rd = eng_default_renderer_def();
        char dir[1024];
        rd.shader_dir = support_source_path("shaders", dir, sizeof dir);
        rd.fluid.mode = mode == 0 ? ENG_FLUID_SPHERES : ENG_FLUID_SURFACE;
        rd.fluid.splat = mode == 2 ? ENG_FLUID_SPLAT_COMPUTE : ENG_FLUID_SPLAT_RASTER;
        eng_renderer *r = eng_renderer_create(&rd, err, sizeof err);
        if (!r) fail_msg("renderer: %s", err);
        eng_renderer_begin(r, ctx, &cam);
        eng_fluid_draw fd = eng_fluid_draw_of(w, NULL);
        eng_renderer_draw_fluid(r, &fd);
        eng_renderer_end(r);
        assert_int_equal(glGetError(), GL_NO_ERROR);
        // Sum the pixels of each half of the image's middle band.
        long left[3] = { 0 }, right[3] = { 0 };
        for (int y = H / 3; y < 2 * H / 3; y += 2)
            for (int x = 8; x < W - 8; x += 2) {
                int c[3];
                support_pixel(ctx, x, y, c);
                long *s = x < W / 2 ? left : right;
                for (int k = 0; k < 3; k++) s[k] += c[k];
            }
        print_message("%s: left %ld %ld %ld, right %ld %ld %ld\n", names[mode], left[0], left[1], left[2], right[0],
                      right[1], right[2]);
        assert_true(left[0] > left[2] * 5 / 4);
        assert_true(right[2] > right[0] * 5 / 4);
        eng_renderer_destroy(r);
    }
    pbf_world_destroy(w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(tint_code_round_trips_every_level),
        cmocka_unit_test(tint_follows_each_particle_as_the_blocks_mix),
        cmocka_unit_test(emitter_pours_its_tint_until_it_is_cleared),
        cmocka_unit_test(both_modes_draw_the_tints),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
