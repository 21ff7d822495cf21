// The water surface and the shadows, headless at 256x192 (llvmpipe in CI): a fixed scene
// (a jittered block of water, a one-particle-thin sheet, a red box half in the water, a
// green ball in the air) is rendered and
//  - compared with stored references (tests/fixtures/surface_*.png; a tolerance that
//    passes llvmpipe's run-to-run and build-to-build noise, not a broken pass), and
//  - checked for what each pass must do, so that a failure says which one broke: the
//    water is there and blue, a thin sheet is lighter than the bulk, the smoothed depth
//    has far less high-frequency energy than the raw splats yet the same shape and a
//    floating cluster stays its own layer, a splat is a sphere's front (not a flat quad),
//    the water reflects the sky, the normals face up on top and towards the eye in
//    front, the water's depth is written
//    (a body in front hides it, depth reads back as the water's), bodies cast shadows,
//    the water casts a tinted one, fast drops show as spray.
// SEICHE_UPDATE_REFERENCES=1 rewrites the reference images (look at them before committing).
#include "tests/support.h"

#include <epoxy/gl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image.h>

#include "engine/gl/gpu_timer.h"
#include "engine/gl/screenshot.h"
#include "engine/render/camera.h"
#include "engine/render/mesh.h"
#include "engine/render/renderer.h"
#include "engine/render/scene.h"

#define W 256
#define H 192
#define RADIUS 0.02f
static const float ONE[3] = { 2.0f, 0.5f, 2.0f };

// The block of water: a lattice of spacing 2 r, jittered (the smoothing has work to do).
#define BX0 -0.70f
#define BX1 0.10f
#define BY1 0.30f
#define BZ0 -0.30f
#define BZ1 0.30f
// The thin sheet: one layer of particles standing at z = SZ, in x [SX0, SX1], y [SY0, SY1].
#define SX0 0.30f
#define SX1 0.75f
#define SY0 0.25f
#define SY1 0.65f
#define SZ -0.10f
// Spray: DROPS drops in a row at y DY, z DZ from x DX0, 3 m/s, at half the rest density.
#define DROPS 6
#define DX0 -0.10f
#define DY 0.62f
#define DZ 0.25f
// A floating 3x3x3 cluster above the block, a layer of its own in front of its top.
#define CX -0.58f
#define CY 0.45f
#define CZ 0.18f

typedef struct fixture {
    eng_context *ctx;
    support_log log;
    eng_renderer *r;
    eng_mesh_store *meshes;
    eng_scene *scene;
    eng_camera cam;
    GLuint ssbo, vel, cmd;
    int count;
    GLuint one_ssbo, one_cmd; // a single particle at ONE (the splats' shape)
    char fixtures[1024];
} fixture;

static unsigned rng_state = 12345u;
static float jitter(void)
{
    rng_state = rng_state * 1664525u + 1013904223u;
    return ((float)(rng_state >> 8) / 16777216.0f - 0.5f) * 0.6f * RADIUS; // +-0.3 r
}

static int make_particles(float *p, int max)
{
    int n = 0;
    const float s = 2.0f * RADIUS;
    for (float y = RADIUS; y < BY1; y += s)
        for (float z = BZ0 + RADIUS; z < BZ1; z += s)
            for (float x = BX0 + RADIUS; x < BX1; x += s)
                if (n < max) {
                    p[4 * n + 0] = x + jitter();
                    p[4 * n + 1] = y + jitter();
                    p[4 * n + 2] = z + jitter();
                    p[4 * n + 3] = y / BY1;
                    n++;
                }
    for (float y = SY0; y < SY1; y += s)
        for (float x = SX0; x < SX1; x += s)
            if (n < max) {
                p[4 * n + 0] = x, p[4 * n + 1] = y, p[4 * n + 2] = SZ, p[4 * n + 3] = 1.0f;
                n++;
            }
    for (int k = 0; k < 27 && n < max; k++, n++) {
        p[4 * n + 0] = CX + (float)(k % 3 - 1) * s;
        p[4 * n + 1] = CY + (float)(k / 3 % 3 - 1) * s;
        p[4 * n + 2] = CZ + (float)(k / 9 - 1) * s;
        p[4 * n + 3] = 0.5f;
    }
    for (int k = 0; k < DROPS && n < max; k++, n++)
        p[4 * n + 0] = DX0 + 0.06f * (float)k, p[4 * n + 1] = DY, p[4 * n + 2] = DZ, p[4 * n + 3] = 1.0f;
    return n;
}

static void add_node(fixture *f, eng_mesh_id mesh, float x, float y, float z, float r, float g, float b)
{
    eng_node_def d = eng_default_node_def();
    d.mesh = mesh;
    d.local.translation[0] = x, d.local.translation[1] = y, d.local.translation[2] = z;
    d.color[0] = r, d.color[1] = g, d.color[2] = b;
    assert_true(eng_node_is_valid(f->scene, eng_node_create(f->scene, &d)));
}

static eng_camera camera(const float eye[3], const float target[3], float fov_deg)
{
    eng_camera_def cd = eng_default_camera_def();
    cd.fov_y = fov_deg * 3.14159265f / 180.0f;
    memcpy(cd.position, eye, 3 * sizeof(float));
    memcpy(cd.target, target, 3 * sizeof(float));
    eng_camera cam;
    char err[256];
    if (!eng_camera_init(&cam, &cd, err, sizeof err)) fail_msg("camera: %s", err);
    return cam;
}

static int setup(void **state)
{
    static fixture f;
    memset(&f, 0, sizeof f);
    f.ctx = support_headless_context(W, H);
    eng_renderer_def rd = eng_default_renderer_def();
    char dir[1024], err[2048];
    // $SEICHE_SHADER_DIR when set (tools/surface_mutations.sh breaks passes on purpose).
    const char *env = getenv("SEICHE_SHADER_DIR");
    rd.shader_dir = env && env[0] ? env : support_source_path("shaders", dir, sizeof dir);
    support_source_path("tests/fixtures", f.fixtures, sizeof f.fixtures);
    rd.logger = support_capture_logger(&f.log);
    rd.shadow_size = 512;
    f.r = eng_renderer_create(&rd, err, sizeof err);
    if (!f.r) fail_msg("renderer: %s", err);
    const float lo[3] = { -1.0f, 0.0f, -0.6f }, hi[3] = { 1.0f, 0.8f, 0.6f };
    assert_true(eng_renderer_set_shadow_bounds(f.r, lo, hi));
    eng_mesh_store_def md = eng_default_mesh_store_def();
    md.logger = rd.logger;
    f.meshes = eng_mesh_store_create(&md);
    eng_scene_def sd = eng_default_scene_def();
    sd.logger = rd.logger;
    f.scene = eng_scene_create(&sd);
    if (!f.meshes || !f.scene) return -1;
    // A red box standing half in the water, a green ball in the air in front of the sheet.
    add_node(&f, eng_mesh_create_box(f.meshes, (const float[]){ 0.12f, 0.2f, 0.12f }), -0.15f, 0.2f, 0.0f, 0.85f,
             0.12f, 0.10f);
    add_node(&f, eng_mesh_create_sphere(f.meshes, 0.07f), 0.75f, 0.55f, 0.35f, 0.15f, 0.75f, 0.20f);

    f.cam = camera((const float[]){ 0.05f, 0.8f, 1.35f }, (const float[]){ 0.05f, 0.22f, 0.0f }, 60.0f);

    static float p[4 * 8192];
    f.count = make_particles(p, 8192);
    glGenBuffers(1, &f.ssbo);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, f.ssbo);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)f.count * 16, p, GL_STATIC_DRAW);
    // Velocities: still water at rest density (volume = mass / rho0); the drops (last) fly.
    for (int i = 0; i < f.count; i++) p[4 * i] = p[4 * i + 1] = p[4 * i + 2] = 0.0f, p[4 * i + 3] = 0.064f / 1000.0f;
    for (int i = f.count - DROPS; i < f.count; i++) p[4 * i] = 3.0f, p[4 * i + 3] = 2.0f * 0.064f / 1000.0f;
    glGenBuffers(1, &f.vel);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, f.vel);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)f.count * 16, p, GL_STATIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    const GLuint command[4] = { 4, (GLuint)f.count, 0, 0 };
    glGenBuffers(1, &f.cmd);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, f.cmd);
    glBufferData(GL_DRAW_INDIRECT_BUFFER, sizeof command, command, GL_STATIC_DRAW);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    const float one[4] = { ONE[0], ONE[1], ONE[2], 0.5f };
    const GLuint one_command[4] = { 4, 1, 0, 0 };
    glGenBuffers(1, &f.one_ssbo);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, f.one_ssbo);
    glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof one, one, GL_STATIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    glGenBuffers(1, &f.one_cmd);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, f.one_cmd);
    glBufferData(GL_DRAW_INDIRECT_BUFFER, sizeof one_command, one_command, GL_STATIC_DRAW);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    *state = &f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    glDeleteBuffers(1, &f->ssbo);
    glDeleteBuffers(1, &f->vel);
    glDeleteBuffers(1, &f->cmd);
    glDeleteBuffers(1, &f->one_ssbo);
    glDeleteBuffers(1, &f->one_cmd);
    eng_scene_destroy(f->scene);
    eng_mesh_store_destroy(f->meshes);
    eng_renderer_destroy(f->r);
    eng_context_destroy(f->ctx);
    return 0;
}

enum { DRY, WET, ONE_PARTICLE, WET_TWICE };

// Renders the scene from `cam` with `look` and no water (DRY), the water (WET), the one
// particle alone, or the water queued as two fluids (WET_TWICE: the renderer's passes over
// several fluids), and reads it back (rows from the top) when `rgba` is given.
// A camera 1.2 radii from the particle at ONE (off the axis), its near plane inside that,
// so that the sphere covers most of the frame and its near side stays beyond the plane.
static eng_camera near_camera(void)
{
    eng_camera_def cd = eng_default_camera_def();
    const float eye[3] = { ONE[0] + 0.3f * RADIUS, ONE[1] + 0.2f * RADIUS, ONE[2] + 1.15f * RADIUS };
    memcpy(cd.position, eye, sizeof eye);
    memcpy(cd.target, ONE, sizeof eye);
    cd.near_plane = 0.1f * RADIUS;
    eng_camera cam;
    char err[256];
    if (!eng_camera_init(&cam, &cd, err, sizeof err)) fail_msg("camera: %s", err);
    return cam;
}

static void render_from(fixture *f, const eng_camera *cam, const eng_fluid_look *look, int water, unsigned char *rgba)
{
    assert_true(eng_renderer_set_fluid_look(f->r, look));
    support_log_clear(&f->log);
    eng_renderer_begin(f->r, f->ctx, cam);
    if (water != ONE_PARTICLE) eng_renderer_draw_scene(f->r, f->scene, f->meshes);
    if (water != DRY) {
        eng_fluid_draw d = eng_default_fluid_draw();
        bool block = water != ONE_PARTICLE;
        d.positions = block ? f->ssbo : f->one_ssbo;
        d.velocities = block ? f->vel : 0;
        d.draw_indirect = block ? f->cmd : f->one_cmd;
        d.radius = RADIUS;
        d.particle_mass = 0.064f;
        d.rest_density = 1000.0f;
        eng_renderer_draw_fluid(f->r, &d);
        if (water == WET_TWICE) eng_renderer_draw_fluid(f->r, &d);
    }
    eng_renderer_end(f->r);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    assert_int_equal(f->log.error_count, 0);
    if (rgba) assert_true(eng_read_pixels(f->ctx, rgba, W, H, NULL, 0));
}

static void render(fixture *f, const eng_fluid_look *look, bool water, unsigned char *rgba)
{
    render_from(f, &f->cam, look, water ? WET : DRY, rgba);
}

// Pixel (from the top-left) where a world point lands, and its window depth.
static void project(const eng_camera *cam, float x, float y, float z, int *px, int *py, float *depth)
{
    mat4 view, proj;
    eng_camera_view(cam, view);
    eng_camera_projection(cam, (float)W / (float)H, proj);
    vec4 p = { x, y, z, 1.0f }, v, c;
    glm_mat4_mulv(view, p, v);
    glm_mat4_mulv(proj, v, c);
    *px = (int)floorf((c[0] / c[3] * 0.5f + 0.5f) * (float)W);
    *py = (int)floorf((0.5f - c[1] / c[3] * 0.5f) * (float)H);
    if (depth) *depth = c[2] / c[3] * 0.5f + 0.5f;
}

// Mean colour over a square of side 2 h + 1 around (x, y).
static void mean_rgb(const unsigned char *rgba, int x, int y, int h, double out[3])
{
    out[0] = out[1] = out[2] = 0.0;
    int n = 0;
    for (int j = y - h; j <= y + h; j++)
        for (int i = x - h; i <= x + h; i++) {
            assert_true(i >= 0 && i < W && j >= 0 && j < H);
            for (int k = 0; k < 3; k++) out[k] += rgba[((size_t)j * W + (size_t)i) * 4 + (size_t)k];
            n++;
        }
    for (int k = 0; k < 3; k++) out[k] /= n;
}

static double luma(const double c[3]) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

static void print_rgb(const char *what, int x, int y, const double c[3])
{
    print_message("%-30s (%3d,%3d) = %5.1f %5.1f %5.1f\n", what, x, y, c[0], c[1], c[2]);
}

// The mean difference of two W x H RGBA frames in levels per channel, and how many pixels
// differ by more than `far_levels` in some channel.
static double frame_difference(const unsigned char *a, const unsigned char *b, int far_levels, long *far)
{
    double sum = 0.0;
    *far = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        int worst = 0;
        for (int k = 0; k < 3; k++) {
            int d = abs((int)a[i * 4 + (size_t)k] - (int)b[i * 4 + (size_t)k]);
            sum += d;
            worst = d > worst ? d : worst;
        }
        *far += worst > far_levels;
    }
    return sum / (3.0 * W * H);
}

// Compares with tests/fixtures/<name> (or rewrites it under SEICHE_UPDATE_REFERENCES=1):
// a mean difference of at most 0.5 levels per channel and at most 0.25 % of pixels (120)
// differing by more than 24 in some channel. llvmpipe renders these bit for bit alike
// whatever its thread count or vector width; the margin is for other Mesa builds. A
// missing opaque shadow moves 0.75 % of the pixels.
static void compare_reference(fixture *f, const char *name, const unsigned char *rgba)
{
    char path[1200];
    snprintf(path, sizeof path, "%s/%s", f->fixtures, name);
    const char *update = getenv("SEICHE_UPDATE_REFERENCES");
    if (update && strcmp(update, "1") == 0) {
        char err[512];
        assert_true(eng_screenshot_write_png(f->ctx, path, err, sizeof err));
        print_message("wrote %s\n", path);
        return;
    }
    int w = 0, h = 0, ch = 0;
    unsigned char *ref = stbi_load(path, &w, &h, &ch, 4);
    if (!ref) fail_msg("cannot read the reference %s (SEICHE_UPDATE_REFERENCES=1 makes it)", path);
    assert_int_equal(w, W);
    assert_int_equal(h, H);
    long far;
    double mean = frame_difference(rgba, ref, 24, &far), frac = (double)far / (double)(W * H);
    stbi_image_free(ref);
    print_message("%s: mean difference %.3f levels, %.3f %% of pixels off by more than 24\n", name, mean, 100.0 * frac);
    if (mean > 0.5 || frac > 0.0025) {
        char out[1200];
        snprintf(out, sizeof out, "/tmp/seiche_test_surface_%s", name);
        eng_screenshot_write_png(f->ctx, out, NULL, 0);
        fail_msg("%s differs from the reference (this frame: %s)", name, out);
    }
}

static void surface_matches_the_reference_image(void **state)
{
    fixture *f = *state;
    static unsigned char rgba[W * H * 4];
    eng_fluid_look look = eng_default_fluid_look();
    render(f, &look, true, rgba);
    compare_reference(f, "surface_shaded.png", rgba);
    // Rendering again gives the same image (no state carried between frames).
    static unsigned char again[W * H * 4];
    render(f, &look, true, again);
    long differ = 0;
    for (size_t i = 0; i < sizeof again; i++) differ += again[i] != rgba[i];
    assert_int_equal(differ, 0);
}

static void sphere_modes_match_their_reference_images(void **state)
{
    fixture *f = *state;
    static unsigned char rgba[W * H * 4];
    eng_fluid_look look = eng_default_fluid_look();
    look.mode = ENG_FLUID_SPHERES;
    render(f, &look, true, rgba);
    compare_reference(f, "surface_spheres.png", rgba);
    // Still water at rest density: the density map is white; the speed map its slowest colour.
    int x, y;
    project(&f->cam, -0.3f, 0.15f, BZ1, &x, &y, NULL);
    double c[3];
    look.mode = ENG_FLUID_DENSITY;
    render(f, &look, true, rgba);
    mean_rgb(rgba, x, y, 2, c);
    print_rgb("density map, block front", x, y, c);
    assert_true(c[0] > 120 && fabs(c[0] - c[2]) < 40 && fabs(c[1] - c[2]) < 40);
    look.mode = ENG_FLUID_SPEED;
    render(f, &look, true, rgba);
    mean_rgb(rgba, x, y, 2, c);
    print_rgb("speed map, block front", x, y, c);
    assert_true(c[2] > c[0] + 30 && c[2] > c[1]);
}

static void water_is_drawn_blue_where_the_block_is(void **state)
{
    fixture *f = *state;
    static unsigned char dry[W * H * 4], wet[W * H * 4];
    eng_fluid_look look = eng_default_fluid_look();
    render(f, &look, false, dry);
    render(f, &look, true, wet);
    // Over the block's front face (a grid of points), nearly every pixel changed.
    int changed = 0, total = 0;
    for (float x = BX0 + 0.08f; x < BX1 - 0.06f; x += 0.04f)
        for (float y = 0.04f; y < BY1 - 0.06f; y += 0.04f) {
            if (x > -0.30f && x < 0.0f) continue; // the box stands there
            int px, py;
            project(&f->cam, x, y, BZ1, &px, &py, NULL);
            const unsigned char *a = dry + ((size_t)py * W + (size_t)px) * 4, *b = wet + ((size_t)py * W + (size_t)px) * 4;
            int d = abs(a[0] - b[0]) + abs(a[1] - b[1]) + abs(a[2] - b[2]);
            changed += d > 30;
            total++;
        }
    print_message("block front: %d of %d pixels changed by the water\n", changed, total);
    assert_true(total > 20 && changed >= total * 9 / 10);
    int x, y;
    double c[3];
    project(&f->cam, -0.5f, 0.12f, BZ1, &x, &y, NULL);
    mean_rgb(wet, x, y, 2, c);
    print_rgb("block front (bulk)", x, y, c);
    assert_true(c[2] > c[0] + 50 && c[2] > 60); // blue: the red end absorbed
}

static void a_thin_sheet_is_lighter_and_clearer_than_the_bulk(void **state)
{
    fixture *f = *state;
    static unsigned char dry[W * H * 4], wet[W * H * 4];
    eng_fluid_look look = eng_default_fluid_look();
    render(f, &look, false, dry);
    render(f, &look, true, wet);
    int sx, sy, bx, by;
    project(&f->cam, 0.5f * (SX0 + SX1), 0.5f * (SY0 + SY1), SZ, &sx, &sy, NULL);
    project(&f->cam, -0.5f, 0.12f, BZ1, &bx, &by, NULL);
    double sheet[3], bulk[3], behind_sheet[3], behind_bulk[3];
    mean_rgb(wet, sx, sy, 2, sheet);
    mean_rgb(wet, bx, by, 2, bulk);
    mean_rgb(dry, sx, sy, 2, behind_sheet);
    mean_rgb(dry, bx, by, 2, behind_bulk);
    print_rgb("sheet", sx, sy, sheet);
    print_rgb("behind the sheet", sx, sy, behind_sheet);
    print_rgb("bulk", bx, by, bulk);
    print_rgb("behind the bulk", bx, by, behind_bulk);
    assert_true(luma(sheet) > luma(bulk) + 30);
    // The sheet keeps most of what is behind it; the bulk keeps little of its red.
    assert_true(sheet[0] > 0.6 * behind_sheet[0]);
    assert_true(bulk[0] < 0.4 * behind_bulk[0]);
}

// Mean squared discrete Laplacian of `z` over the pixels where it and its 4 neighbours
// hold water no further than `layer` apart (inside one surface).
static double laplacian_energy(const float *z, int w, int h, float layer, int *count)
{
    double sum = 0.0;
    int n = 0;
    for (int y = 1; y < h - 1; y++)
        for (int x = 1; x < w - 1; x++) {
            float c = z[y * w + x], l = z[y * w + x - 1], r = z[y * w + x + 1], u = z[(y - 1) * w + x],
                  d = z[(y + 1) * w + x];
            if (c <= 0 || l <= 0 || r <= 0 || u <= 0 || d <= 0) continue;
            if (fabsf(l - c) > layer || fabsf(r - c) > layer || fabsf(u - c) > layer || fabsf(d - c) > layer) continue;
            double lap = (double)(l + r + u + d - 4.0f * c);
            sum += lap * lap;
            n++;
        }
    *count = n;
    return n ? sum / n : 0.0;
}

static float *read_r32f(GLuint tex, int w, int h)
{
    float *buf = malloc((size_t)w * h * sizeof(float));
    assert_non_null(buf);
    glBindTexture(GL_TEXTURE_2D, tex);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_RED, GL_FLOAT, buf);
    glBindTexture(GL_TEXTURE_2D, 0);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    return buf;
}

static void smoothing_removes_the_bumps_of_the_spheres_and_keeps_the_shape(void **state)
{
    fixture *f = *state;
    eng_fluid_look look = eng_default_fluid_look();
    render(f, &look, true, NULL);
    eng_surface_textures t = eng_renderer_surface_textures(f->r);
    assert_true(t.depth && t.smoothed && t.thickness && t.smoothed != t.depth);
    assert_int_equal(t.width, W / 2);
    assert_int_equal(t.height, H / 2);
    float *raw = read_r32f(t.depth, t.width, t.height), *smooth = read_r32f(t.smoothed, t.width, t.height);
    int n_raw, n_smooth;
    double e_raw = laplacian_energy(raw, t.width, t.height, 2.0f * RADIUS, &n_raw);
    double e_smooth = laplacian_energy(smooth, t.width, t.height, 2.0f * RADIUS, &n_smooth);
    // The same water, the same outline: every texel with water before has water after,
    // and the depth moved by less than a particle radius on average.
    int water = 0, lost = 0, gained = 0;
    double moved = 0.0;
    for (int i = 0; i < t.width * t.height; i++) {
        lost += raw[i] > 0 && smooth[i] <= 0;
        gained += raw[i] <= 0 && smooth[i] > 0;
        if (raw[i] > 0 && smooth[i] > 0) {
            water++;
            moved += fabs((double)smooth[i] - raw[i]);
        }
    }
    moved /= water > 0 ? water : 1;
    // The cluster floats well in front of the block's top: smoothing keeps it a layer of
    // its own (the narrow range), not pulled back towards the water around it.
    int cx, cy;
    project(&f->cam, CX, CY, CZ, &cx, &cy, NULL);
    size_t ci = (size_t)(t.height - 1 - cy / 2) * (size_t)t.width + (size_t)(cx / 2);
    print_message("cluster centre: raw %.4f m, smoothed %.4f m\n", raw[ci], smooth[ci]);
    assert_true(raw[ci] > 0.0f && fabsf(smooth[ci] - raw[ci]) < 0.5f * RADIUS);
    print_message("Laplacian energy: raw %.3g m^2 (%d texels), smoothed %.3g m^2 (%d texels), ratio %.3f; "
                  "%d texels of water, mean move %.4f m\n",
                  e_raw, n_raw, e_smooth, n_smooth, e_smooth / e_raw, water, moved);
    assert_true(water > t.width * t.height / 8);
    assert_int_equal(lost, 0);
    assert_int_equal(gained, 0);
    assert_true(n_raw > water / 4 && n_smooth > n_raw);
    assert_true(e_smooth < 0.25 * e_raw);
    assert_true(moved < 1.5f * RADIUS);
    free(raw);
    free(smooth);
}

static void depth_splats_are_spheres_not_flat_quads(void **state)
{
    fixture *f = *state;
    // One particle 0.3 m in front of the eye: the splat's eye depth is the sphere's front,
    // r nearer than its centre, and falls off away from the middle as a sphere does.
    const float eye[3] = { ONE[0], ONE[1], ONE[2] + 0.3f };
    eng_camera cam = camera(eye, ONE, 60.0f);
    eng_fluid_look look = eng_default_fluid_look();
    render_from(f, &cam, &look, ONE_PARTICLE, NULL);
    eng_surface_textures t = eng_renderer_surface_textures(f->r);
    float *raw = read_r32f(t.depth, t.width, t.height);
    // Texels per metre at 0.3 m: half the height times the projection's y scale over 0.3.
    mat4 proj;
    eng_camera_projection(&cam, (float)W / (float)H, proj);
    float texels_per_m = 0.5f * (float)t.height * proj[1][1] / 0.3f;
    int off = (int)lroundf(0.7f * RADIUS * texels_per_m);
    size_t mid = (size_t)(t.height / 2) * (size_t)t.width + (size_t)(t.width / 2);
    float d = (float)off / texels_per_m / RADIUS; // the offset in radii
    float centre = raw[mid], side = raw[mid + (size_t)off];
    float want_side = 0.3f - RADIUS * sqrtf(1.0f - d * d);
    print_message("splat: centre %.5f m (sphere front %.5f), %d texels (%.2f r) aside %.5f m (sphere %.5f)\n", centre,
                  0.3f - RADIUS, off, (double)d, side, want_side);
    assert_true(fabsf(centre - (0.3f - RADIUS)) < 0.15f * RADIUS);
    assert_true(fabsf(side - want_side) < 0.15f * RADIUS && side > centre + 0.15f * RADIUS);
    free(raw);
}

static void reflection_mirrors_the_sky_on_top_of_the_water(void **state)
{
    fixture *f = *state;
    // With a reflectance of 1 the top of the block is a mirror: the sky over it, bright and
    // blue-white; with water's 0.02 the same pixels show mostly the dark bulk below.
    static unsigned char mirror[W * H * 4], water[W * H * 4];
    eng_fluid_look look = eng_default_fluid_look();
    render(f, &look, true, water);
    look.reflection = 1.0f;
    render(f, &look, true, mirror);
    int x, y;
    double m[3], w[3];
    project(&f->cam, -0.5f, BY1, -0.22f, &x, &y, NULL);
    mean_rgb(mirror, x, y, 1, m);
    mean_rgb(water, x, y, 1, w);
    print_rgb("top of the block, mirror", x, y, m);
    print_rgb("top of the block, water", x, y, w);
    assert_true(m[2] > 190 && m[2] > m[0] + 60 && m[2] > w[2] + 50);
}

static void normals_face_up_on_top_and_towards_the_eye_in_front(void **state)
{
    fixture *f = *state;
    static unsigned char rgba[W * H * 4];
    eng_fluid_look look = eng_default_fluid_look();
    look.view = ENG_FLUID_VIEW_NORMALS; // rgb = world normal * 0.5 + 0.5
    render(f, &look, true, rgba);
    eng_screenshot_write_png(f->ctx, "/tmp/seiche_test_surface_normals.png", NULL, 0);
    int x, y;
    double top[3], front[3];
    project(&f->cam, -0.5f, BY1, -0.22f, &x, &y, NULL);
    mean_rgb(rgba, x, y, 1, top);
    print_rgb("normal, top of the block", x, y, top);
    project(&f->cam, -0.5f, 0.12f, BZ1, &x, &y, NULL);
    mean_rgb(rgba, x, y, 1, front);
    print_rgb("normal, front of the block", x, y, front);
    // Top: +y (green high); front: +z (blue high, green near the middle).
    assert_true(top[1] > 0.85 * 255 && top[1] > top[2]);
    assert_true(front[2] > 0.8 * 255 && front[1] < 0.75 * 255);
}

static void the_water_writes_its_depth_and_bodies_in_front_hide_it(void **state)
{
    fixture *f = *state;
    static unsigned char rgba[W * H * 4];
    eng_fluid_look look = eng_default_fluid_look();
    render(f, &look, true, rgba);
    // The depth buffer holds the sheet's depth, not the ground far behind it.
    int x, y;
    float expect, ground;
    const float sx = 0.5f * (SX0 + SX1), sy = 0.5f * (SY0 + SY1);
    project(&f->cam, sx, sy, SZ + RADIUS, &x, &y, &expect);
    float got = 0.0f;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, eng_context_framebuffer(f->ctx));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glReadPixels(x, H - 1 - y, 1, 1, GL_DEPTH_COMPONENT, GL_FLOAT, &got);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    // Where the eye ray through that pixel meets the ground.
    float t = f->cam.position[1] / (f->cam.position[1] - sy);
    project(&f->cam, f->cam.position[0] + t * (sx - f->cam.position[0]), 0.0f,
            f->cam.position[2] + t * (SZ - f->cam.position[2]), &x, &y, &ground);
    print_message("depth at the sheet: %.5f (its face projects to %.5f; the ground behind %.5f)\n", got, expect,
                  ground);
    assert_true(fabsf(got - expect) < 0.2f * (ground - expect));
    // The red box stands in the water: above the water it is red, in front of the water
    // line too (the box's front is nearer than the water behind it).
    double c[3];
    project(&f->cam, -0.15f, 0.36f, 0.12f, &x, &y, NULL);
    mean_rgb(rgba, x, y, 1, c);
    print_rgb("box above the water", x, y, c);
    assert_true(c[0] > 2 * c[1] && c[0] > 2 * c[2]);
    // The green ball hangs in front of the sheet: green, not water.
    project(&f->cam, 0.75f, 0.55f, 0.42f, &x, &y, NULL);
    mean_rgb(rgba, x, y, 1, c);
    print_rgb("ball in front of the sheet", x, y, c);
    assert_true(c[1] > 1.5 * c[0] && c[1] > 1.3 * c[2]);
}

static void bodies_cast_shadows_and_the_water_a_tinted_one(void **state)
{
    fixture *f = *state;
    static unsigned char lit[W * H * 4], unlit[W * H * 4];
    eng_fluid_look look = eng_default_fluid_look();
    render(f, &look, true, lit);
    look.shadows = false;
    render(f, &look, true, unlit);
    // Where the light from (0.35, 0.85, 0.40) puts the ball's and the sheet's shadows on the ground.
    const float l[3] = { 0.35f, 0.85f, 0.40f };
    float t = 0.55f / l[1];
    int x, y;
    double in[3], out[3];
    project(&f->cam, 0.75f - l[0] * t, 0.0f, 0.35f - l[2] * t, &x, &y, NULL);
    mean_rgb(lit, x, y, 1, in);
    mean_rgb(unlit, x, y, 1, out);
    print_rgb("ground in the ball's shadow", x, y, in);
    print_rgb("the same without shadows", x, y, out);
    assert_true(luma(in) < 0.75 * luma(out));
    float ys = 0.5f * (SY0 + SY1);
    t = ys / l[1];
    project(&f->cam, 0.5f * (SX0 + SX1) - l[0] * t, 0.0f, SZ - l[2] * t, &x, &y, NULL);
    mean_rgb(lit, x, y, 1, in);
    mean_rgb(unlit, x, y, 1, out);
    print_rgb("ground under the sheet's shadow", x, y, in);
    print_rgb("the same without shadows", x, y, out);
    // Light through a thin sheet of water: a little darker, and bluer (red absorbed most).
    assert_true(luma(in) < luma(out) - 3);
    assert_true(in[2] / in[0] > 1.03 * out[2] / out[0]);
    assert_true(luma(in) > 0.6 * luma(out)); // not an opaque shadow
}

static void fast_lonely_drops_show_as_spray(void **state)
{
    fixture *f = *state;
    static unsigned char spray[W * H * 4], none[W * H * 4];
    eng_fluid_look look = eng_default_fluid_look();
    render(f, &look, true, spray);
    look.spray = 0.0f;
    render(f, &look, true, none);
    double sum = 0.0;
    for (int k = 0; k < DROPS; k++) {
        int x, y;
        double a[3], b[3];
        project(&f->cam, DX0 + 0.06f * (float)k, DY, DZ, &x, &y, NULL);
        mean_rgb(spray, x, y, 0, a);
        mean_rgb(none, x, y, 0, b);
        if (k == 0) print_rgb("drop with spray", x, y, a), print_rgb("drop without", x, y, b);
        sum += luma(a) - luma(b);
    }
    print_message("spray brightens the drops by %.1f levels on average\n", sum / DROPS);
    assert_true(sum / DROPS > 25.0);
}

// True when texel i has a neighbour (of the 8) whose depth differs from its own by more than
// jump in either image: the texel lies on the edge of a nearer sphere's disc.
static bool on_a_depth_edge(const float *d0, const float *d1, int w, int h, int i, double jump)
{
    int x = i % w, y = i / w;
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            int u = x + dx, v = y + dy;
            if ((dx == 0 && dy == 0) || u < 0 || v < 0 || u >= w || v >= h) continue;
            int j = v * w + u;
            if (fabs((double)d0[j] - d0[i]) > jump || fabs((double)d1[j] - d1[i]) > jump) return true;
        }
    return false;
}

// The compute splats (look.splat = compute) make the textures the raster passes make: the
// same water in the same texels at the same depth, the same thickness to the fixed point's
// and R16F's rounding, and so the same frame (the surface and the water's shadow).
static void compute_splats_draw_what_the_raster_passes_draw(void **state)
{
    fixture *f = *state;
    static unsigned char raster[W * H * 4], compute[W * H * 4];
    eng_fluid_look look = eng_default_fluid_look();
    look.smoothing = 0.0f; // the raw splats: depth and thickness as the passes wrote them
    look.splat = ENG_FLUID_SPLAT_RASTER;
    render(f, &look, true, raster);
    eng_surface_textures t = eng_renderer_surface_textures(f->r);
    float *depth_r = read_r32f(t.depth, t.width, t.height), *thick_r = read_r32f(t.thickness, t.width, t.height);
    look.splat = ENG_FLUID_SPLAT_COMPUTE;
    render(f, &look, true, compute);
    eng_gpu_timer *timer = eng_renderer_gpu_timer(f->r);
    eng_gpu_timer_wait(timer);
    assert_true(eng_gpu_timer_ms(timer, "surface_resolve") >= 0.0); // the compute path ran
    t = eng_renderer_surface_textures(f->r);
    float *depth_c = read_r32f(t.depth, t.width, t.height), *thick_c = read_r32f(t.thickness, t.width, t.height);
    int water = 0, only_one = 0, differ = 0, inside = 0;
    double worst_depth = 0.0, worst_thick = 0.0, thick_sum = 0.0;
    for (int i = 0; i < t.width * t.height; i++) {
        bool a = depth_r[i] > 0.0f, b = depth_c[i] > 0.0f;
        only_one += a != b;
        if (a && b) {
            water++;
            double d = fabs((double)depth_c[i] - depth_r[i]);
            worst_depth = fmax(worst_depth, d);
            if (d > 1e-4) {
                differ++;
                inside += !on_a_depth_edge(depth_r, depth_c, t.width, t.height, i, 0.5 * d);
            }
        }
        worst_thick = fmax(worst_thick, fabs((double)thick_c[i] - thick_r[i]));
        thick_sum += thick_r[i];
    }
    print_message("compute splats: %d texels of water, %d with water in one only, %d at depths more than 0.1 mm "
                  "apart (at most %.2e m; %d of them off a sphere's edge), thickness within %.2e m (mean %.3f m)\n",
                  water, only_one, differ, worst_depth, inside, worst_thick, thick_sum / (t.width * t.height));
    assert_true(water > t.width * t.height / 10);
    assert_true(only_one <= water / 500); // a texel centre on a silhouette may fall either way
    // Where a nearer sphere's disc ends in front of a farther one, a texel centre on that edge
    // falls inside or outside it by rounding: the raster path's sprite corners are snapped to
    // the rasteriser's subpixel grid, the compute path measures from the exact centre. Such a
    // texel shows the next sphere behind, cm farther (8 of 2042 texels on llvmpipe, 30 of
    // 2043 by up to 3.7 cm on an NVIDIA H200). Every such texel sits on a depth edge; a texel
    // inside a disc that differs means a sphere drawn at another depth, or not at all.
    assert_true(inside == 0);
    assert_true(differ <= water / 25);
    assert_true(worst_thick < 2e-3 * 8.0); // R16F's step at the thickest texels (< 8 m)
    free(depth_r), free(thick_r), free(depth_c), free(thick_c);
    long far;
    double mean = frame_difference(raster, compute, 8, &far);
    print_message("frames: mean difference %.4f levels, %ld pixels off by more than 8\n", mean, far);
    assert_true(mean < 0.1 && far <= W * H / 1000);
    // A particle the eye almost touches (1.2 radii from its centre, off the axis) covers
    // most of the frame: the compute splat walks it all, as the raster quad draws it.
    eng_camera near_cam = near_camera();
    look = eng_default_fluid_look();
    look.splat = ENG_FLUID_SPLAT_RASTER;
    render_from(f, &near_cam, &look, ONE_PARTICLE, raster);
    look.splat = ENG_FLUID_SPLAT_COMPUTE;
    render_from(f, &near_cam, &look, ONE_PARTICLE, compute);
    mean = frame_difference(raster, compute, 8, &far);
    static unsigned char dry[W * H * 4];
    render_from(f, &near_cam, &look, DRY, dry);
    long shows;
    frame_difference(raster, dry, 8, &shows);
    print_message("a particle 1.2 radii from the eye: %ld of %d pixels show it; the two paths differ by %.4f levels "
                  "(%ld pixels by more than 8)\n", shows, W * H, mean, far);
    assert_true(shows > W * H / 2);
    assert_true(mean < 0.1 && far <= W * H / 1000);
    // Two fluids a frame (the same water queued twice: twice the thickness, twice the spray):
    // each fluid's splat, large-sphere list and spray cull in turn, as the raster passes
    // draw each in turn.
    look = eng_default_fluid_look();
    look.splat = ENG_FLUID_SPLAT_RASTER;
    render_from(f, &f->cam, &look, WET_TWICE, raster);
    look.splat = ENG_FLUID_SPLAT_COMPUTE;
    render_from(f, &f->cam, &look, WET_TWICE, compute);
    mean = frame_difference(raster, compute, 8, &far);
    static unsigned char once[W * H * 4];
    render_from(f, &f->cam, &look, WET, once);
    long thicker;
    frame_difference(compute, once, 8, &thicker);
    print_message("two fluids: the paths differ by %.4f levels (%ld pixels by more than 8); %ld pixels differ from one "
                  "fluid's frame\n", mean, far, thicker);
    assert_true(mean < 0.1 && far <= W * H / 1000);
    assert_true(thicker > W * H / 50); // the second fluid was drawn
    // The shipped look (compute splats) and the raster passes against the same reference.
    look = eng_default_fluid_look();
    assert_int_equal(look.splat, ENG_FLUID_SPLAT_COMPUTE);
    look.splat = ENG_FLUID_SPLAT_RASTER;
    render(f, &look, true, raster);
    compare_reference(f, "surface_shaded.png", raster);
}

// A host's buffer may hold positions no sphere can be drawn at: NaN, infinities, and finite
// ones so far away that their view-space coordinates overflow. Every path draws nothing
// for them and the rest of the water as it would without them. (splat.comp returns before
// converting such a quad's texel range to integers, undefined for a NaN; llvmpipe happens
// to clamp it to the target's edge, so here this passes without that guard too.)
static void positions_that_cannot_be_drawn_draw_nothing(void **state)
{
    fixture *f = *state;
    const float odd[7][4] = { { ONE[0], ONE[1], ONE[2], 0.5f }, { NAN, 0.2f, 0.0f, 0.5f }, { INFINITY, 0.2f, 0.0f, 0.5f },
                              { 0.0f, -INFINITY, 0.0f, 0.5f }, { 1e30f, 0.2f, 0.0f, 0.5f },
                              { 0.0f, 0.2f, 3e38f, 0.5f }, { -3e38f, -3e38f, -3e38f, 0.5f } };
    const GLuint command[4] = { 4, 7, 0, 0 };
    GLuint ssbo, cmd;
    glGenBuffers(1, &ssbo);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, ssbo);
    glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof odd, odd, GL_STATIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    glGenBuffers(1, &cmd);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, cmd);
    glBufferData(GL_DRAW_INDIRECT_BUFFER, sizeof command, command, GL_STATIC_DRAW);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    const float eye[3] = { ONE[0], ONE[1] + 0.05f, ONE[2] + 0.3f };
    eng_camera cam = camera(eye, ONE, 60.0f);
    static unsigned char alone[W * H * 4], with_odd[W * H * 4];
    const eng_fluid_mode modes[] = { ENG_FLUID_SURFACE, ENG_FLUID_SPHERES };
    const eng_fluid_splat splats[] = { ENG_FLUID_SPLAT_RASTER, ENG_FLUID_SPLAT_COMPUTE };
    for (int m = 0; m < 2; m++)
        for (int k = 0; k < 2; k++) {
            eng_fluid_look look = eng_default_fluid_look();
            look.mode = modes[m];
            look.splat = splats[k];
            render_from(f, &cam, &look, ONE_PARTICLE, alone);
            assert_true(eng_renderer_set_fluid_look(f->r, &look));
            support_log_clear(&f->log);
            eng_renderer_begin(f->r, f->ctx, &cam);
            eng_fluid_draw d = eng_default_fluid_draw();
            d.positions = ssbo;
            d.draw_indirect = cmd;
            d.radius = RADIUS;
            d.particle_mass = 0.064f;
            d.rest_density = 1000.0f;
            eng_renderer_draw_fluid(f->r, &d);
            eng_renderer_end(f->r);
            assert_int_equal(glGetError(), GL_NO_ERROR);
            assert_int_equal(f->log.error_count, 0);
            assert_true(eng_read_pixels(f->ctx, with_odd, W, H, NULL, 0));
            long far;
            double mean = frame_difference(alone, with_odd, 8, &far);
            print_message("%s, %s splats: one particle and six that cannot be drawn against it alone: %.4f levels, "
                          "%ld pixels by more than 8\n", eng_fluid_mode_name(look.mode), eng_fluid_splat_name(look.splat),
                          mean, far);
            assert_true(mean < 0.05 && far <= W * H / 1000);
        }
    glDeleteBuffers(1, &ssbo);
    glDeleteBuffers(1, &cmd);
}

// Frames the renderer has timed section `name` in (0 before its first), once every frame
// drawn so far has finished.
static long timed_frames(fixture *f, const char *name)
{
    eng_gpu_timer *t = eng_renderer_gpu_timer(f->r);
    eng_gpu_timer_wait(t);
    for (int i = 0; i < eng_gpu_timer_section_count(t); i++)
        if (strcmp(eng_gpu_timer_section(t, i, NULL), name) == 0) return eng_gpu_timer_samples(t, i);
    return 0;
}

// The sphere modes by compute splats (the nearest particle per pixel, splat.comp's
// SPLAT_NEAREST and SPLAT_ID, lit by the full-screen spheres.frag) draw what the raster
// impostors draw: in each colour map, with two fluids a frame, and for a particle the eye
// almost touches.
static void compute_splats_draw_the_sphere_modes_as_the_impostors_do(void **state)
{
    fixture *f = *state;
    static unsigned char raster[W * H * 4], compute[W * H * 4], dry[W * H * 4];
    const eng_fluid_mode modes[] = { ENG_FLUID_SPHERES, ENG_FLUID_DENSITY, ENG_FLUID_SPEED };
    const int waters[] = { WET, WET, WET, WET_TWICE };
    for (int k = 0; k < 4; k++) {
        eng_fluid_look look = eng_default_fluid_look();
        look.mode = modes[k % 3];
        look.splat = ENG_FLUID_SPLAT_RASTER;
        long before = timed_frames(f, "particles_splat");
        render_from(f, &f->cam, &look, waters[k], raster);
        assert_int_equal(timed_frames(f, "particles_splat"), before); // the raster path
        look.splat = ENG_FLUID_SPLAT_COMPUTE;
        render_from(f, &f->cam, &look, waters[k], compute);
        assert_true(timed_frames(f, "particles_splat") > before); // the compute path ran
        render_from(f, &f->cam, &look, DRY, dry);
        long far, shows;
        double mean = frame_difference(raster, compute, 8, &far);
        frame_difference(compute, dry, 8, &shows);
        print_message("%s%s: %ld pixels show water; the paths differ by %.4f levels (%ld pixels by more than 8)\n",
                      eng_fluid_mode_name(look.mode), waters[k] == WET_TWICE ? ", two fluids" : "", shows, mean, far);
        assert_true(shows > W * H / 20);
        // A pixel where two spheres meet at the same depth to a float's rounding may show
        // either; a silhouette pixel, a ray that grazes the sphere, either way.
        assert_true(mean < 0.1 && far <= W * H / 500);
    }
    eng_camera near_cam = near_camera();
    eng_fluid_look look = eng_default_fluid_look();
    look.mode = ENG_FLUID_SPHERES;
    look.splat = ENG_FLUID_SPLAT_RASTER;
    render_from(f, &near_cam, &look, ONE_PARTICLE, raster);
    look.splat = ENG_FLUID_SPLAT_COMPUTE;
    render_from(f, &near_cam, &look, ONE_PARTICLE, compute);
    render_from(f, &near_cam, &look, DRY, dry);
    long far, shows;
    double mean = frame_difference(raster, compute, 8, &far);
    frame_difference(compute, dry, 8, &shows);
    print_message("spheres, a particle 1.2 radii from the eye: %ld of %d pixels show it; the paths differ by %.4f "
                  "levels (%ld pixels by more than 8)\n", shows, W * H, mean, far);
    assert_true(shows > W * H / 2);
    assert_true(mean < 0.1 && far <= W * H / 1000);
}

static void every_pass_is_timed(void **state)
{
    fixture *f = *state;
    eng_fluid_look look = eng_default_fluid_look();
    for (int i = 0; i < 3; i++) render(f, &look, true, NULL);
    eng_gpu_timer *t = eng_renderer_gpu_timer(f->r);
    eng_gpu_timer_wait(t);
    static const char *const passes[] = { "shadow", "scene", "surface_thickness", "surface_depth", "surface_smooth",
                                          "surface_composite", "surface_spray", "frame" };
    for (size_t i = 0; i < sizeof passes / sizeof passes[0]; i++) {
        double ms = eng_gpu_timer_ms(t, passes[i]);
        print_message("%-18s %8.3f ms (%dx%d, %d particles, llvmpipe or whatever GL this is)\n", passes[i], ms, W, H,
                      f->count);
        assert_true(ms >= 0.0);
    }
}

static void fluid_looks_out_of_range_are_refused_naming_the_field(void **state)
{
    fixture *f = *state;
    eng_fluid_look look = eng_default_fluid_look();
    look.absorption[1] = -1.0f;
    support_log_clear(&f->log);
    assert_false(eng_renderer_set_fluid_look(f->r, &look));
    assert_true(support_log_contains(&f->log, "eng_fluid_look.absorption[1] must be 0..100 (got -1)"));
    look = eng_default_fluid_look();
    look.resolution = 2.0f;
    assert_false(eng_renderer_set_fluid_look(f->r, &look));
    assert_true(support_log_contains(&f->log, "eng_fluid_look.resolution must be 0.25..1 (got 2)"));
    assert_false(eng_renderer_set_fluid_mode(f->r, ENG_FLUID_MODE_COUNT));
    assert_true(support_log_contains(&f->log, "surface|spheres|density|speed"));
    assert_int_equal(eng_renderer_fluid_look(f->r).resolution, eng_default_fluid_look().resolution);
    eng_fluid_mode m = ENG_FLUID_SURFACE;
    assert_true(eng_fluid_mode_parse("speed", &m) && m == ENG_FLUID_SPEED);
    assert_false(eng_fluid_mode_parse("foam", &m));
    assert_string_equal(eng_fluid_mode_name(ENG_FLUID_DENSITY), "density");
    assert_null(eng_fluid_mode_name(ENG_FLUID_MODE_COUNT));
    const float lo[3] = { 0, 0, 0 }, hi[3] = { 1, 0, 1 };
    assert_false(eng_renderer_set_shadow_bounds(f->r, lo, hi));
    assert_true(support_log_contains(&f->log, "lo[1] must be < hi[1]"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(surface_matches_the_reference_image),
        cmocka_unit_test(sphere_modes_match_their_reference_images),
        cmocka_unit_test(water_is_drawn_blue_where_the_block_is),
        cmocka_unit_test(a_thin_sheet_is_lighter_and_clearer_than_the_bulk),
        cmocka_unit_test(smoothing_removes_the_bumps_of_the_spheres_and_keeps_the_shape),
        cmocka_unit_test(depth_splats_are_spheres_not_flat_quads),
        cmocka_unit_test(reflection_mirrors_the_sky_on_top_of_the_water),
        cmocka_unit_test(normals_face_up_on_top_and_towards_the_eye_in_front),
        cmocka_unit_test(the_water_writes_its_depth_and_bodies_in_front_hide_it),
        cmocka_unit_test(bodies_cast_shadows_and_the_water_a_tinted_one),
        cmocka_unit_test(fast_lonely_drops_show_as_spray),
        cmocka_unit_test(compute_splats_draw_what_the_raster_passes_draw),
        cmocka_unit_test(compute_splats_draw_the_sphere_modes_as_the_impostors_do),
        cmocka_unit_test(positions_that_cannot_be_drawn_draw_nothing),
        cmocka_unit_test(every_pass_is_timed),
        cmocka_unit_test(fluid_looks_out_of_range_are_refused_naming_the_field),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
