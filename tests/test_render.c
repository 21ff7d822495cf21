// The renderer, headless at 160x120 on whatever GL the machine has (llvmpipe in CI): a
// known scene's pixels are where and what they should be, particle impostors (the spheres
// mode) drawn from an SSBO + indirect buffer land at the projected place with correct
// depth, screenshots are real PNG files, meshes and the GPU timer behave.
#include "tests/support.h"

#include <epoxy/gl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine/render/camera.h"
#include "engine/gl/gpu_timer.h"
#include "engine/render/mesh.h"
#include "engine/render/renderer.h"
#include "engine/render/scene.h"
#include "engine/gl/screenshot.h"

#define W 160
#define H 120

typedef struct fixture {
    eng_context *ctx;
    support_log log;
    eng_renderer *r;
    eng_mesh_store *meshes;
    eng_scene *scene;
} fixture;

static int setup(void **state)
{
    static fixture f;
    memset(&f, 0, sizeof f);
    f.ctx = support_headless_context(W, H);
    eng_renderer_def rd = eng_default_renderer_def();
    char dir[1024], err[2048];
    rd.shader_dir = support_source_path("shaders", dir, sizeof dir);
    rd.logger = support_capture_logger(&f.log);
    // These tests pin the sphere impostors; the surface mode has tests/test_surface.c.
    rd.fluid.mode = ENG_FLUID_SPHERES;
    f.r = eng_renderer_create(&rd, err, sizeof err);
    if (!f.r) fail_msg("renderer: %s", err);
    eng_mesh_store_def md = eng_default_mesh_store_def();
    md.logger = rd.logger;
    f.meshes = eng_mesh_store_create(&md);
    eng_scene_def sd = eng_default_scene_def();
    sd.logger = rd.logger;
    f.scene = eng_scene_create(&sd);
    *state = &f;
    return f.meshes && f.scene ? 0 : -1;
}

static int teardown(void **state)
{
    fixture *f = *state;
    eng_scene_destroy(f->scene);
    eng_mesh_store_destroy(f->meshes);
    eng_renderer_destroy(f->r);
    eng_context_destroy(f->ctx);
    return 0;
}

static eng_camera make_camera(float ex, float ey, float ez, float tx, float ty, float tz)
{
    eng_camera cam;
    eng_camera_def def = eng_default_camera_def();
    def.position[0] = ex, def.position[1] = ey, def.position[2] = ez;
    def.target[0] = tx, def.target[1] = ty, def.target[2] = tz;
    char err[256];
    if (!eng_camera_init(&cam, &def, err, sizeof err)) fail_msg("camera: %s", err);
    return cam;
}

// Pixel (from the top-left) where a world point lands.
static void project(const eng_camera *cam, float x, float y, float z, int *px, int *py)
{
    mat4 view, proj;
    eng_camera_view(cam, view);
    eng_camera_projection(cam, (float)W / (float)H, proj);
    vec4 p = { x, y, z, 1.0f }, v, c;
    glm_mat4_mulv(view, p, v);
    glm_mat4_mulv(proj, v, c);
    *px = (int)floorf((c[0] / c[3] * 0.5f + 0.5f) * (float)W);
    *py = (int)floorf((0.5f - c[1] / c[3] * 0.5f) * (float)H);
}

static eng_node_id add_node(fixture *f, eng_mesh_id mesh, float x, float y, float z, float r, float g, float b)
{
    eng_node_def d = eng_default_node_def();
    d.mesh = mesh;
    d.local.translation[0] = x, d.local.translation[1] = y, d.local.translation[2] = z;
    d.color[0] = r, d.color[1] = g, d.color[2] = b;
    eng_node_id id = eng_node_create(f->scene, &d);
    assert_true(eng_node_is_valid(f->scene, id));
    return id;
}

static void print_pixel(const char *what, int x, int y, const int c[3])
{
    print_message("%-22s (%3d,%3d) = %3d %3d %3d\n", what, x, y, c[0], c[1], c[2]);
}

static void known_scene_puts_lit_box_sphere_ground_and_sky_in_place(void **state)
{
    fixture *f = *state;
    eng_mesh_id box = eng_mesh_create_box(f->meshes, (const float[]){ 0.5f, 0.5f, 0.5f });
    eng_mesh_id sphere = eng_mesh_create_sphere(f->meshes, 0.5f);
    assert_true(eng_mesh_is_valid(f->meshes, box) && eng_mesh_is_valid(f->meshes, sphere));
    eng_node_id nb = add_node(f, box, -0.9f, 0.5f, 0.0f, 0.85f, 0.12f, 0.10f);
    eng_node_id ns = add_node(f, sphere, 0.9f, 0.5f, 0.0f, 0.15f, 0.75f, 0.20f);
    eng_camera cam = make_camera(0.0f, 2.0f, 5.0f, 0.0f, 0.4f, 0.0f);

    support_log_clear(&f->log);
    eng_renderer_begin(f->r, f->ctx, &cam);
    eng_renderer_draw_scene(f->r, f->scene, f->meshes);
    eng_renderer_end(f->r);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    assert_int_equal(f->log.error_count, 0);

    int x, y, c[3];
    // The box: its front face centre, lit red (not black, not washed out).
    project(&cam, -0.9f, 0.5f, 0.5f, &x, &y);
    support_pixel(f->ctx, x, y, c);
    print_pixel("box front centre", x, y, c);
    assert_true(c[0] > 90 && c[0] > 2 * c[1] && c[0] > 2 * c[2]);
    // Its top face gets more of the light than its front: brighter red.
    int top[3], tx, ty;
    project(&cam, -0.9f, 1.0f, 0.0f, &tx, &ty);
    support_pixel(f->ctx, tx, ty, top);
    print_pixel("box top centre", tx, ty, top);
    assert_true(top[0] > c[0] + 10 && top[0] > 2 * top[1]);
    // The sphere: green at its centre.
    project(&cam, 0.9f, 0.5f, 0.0f, &x, &y);
    support_pixel(f->ctx, x, y, c);
    print_pixel("sphere centre", x, y, c);
    assert_true(c[1] > 90 && c[1] > 2 * c[0] && c[1] > 2 * c[2]);
    // Sky at the top: the clear colour, pale blue.
    support_pixel(f->ctx, W / 2, 2, c);
    print_pixel("top (sky)", W / 2, 2, c);
    assert_true(abs(c[0] - 158) <= 6 && abs(c[1] - 194) <= 6 && abs(c[2] - 230) <= 6);
    // Ground at the bottom: lit grey, clearly not sky.
    support_pixel(f->ctx, W / 2, H - 3, c);
    print_pixel("bottom (ground)", W / 2, H - 3, c);
    assert_true(c[0] > 90 && abs(c[0] - c[1]) < 16 && abs(c[1] - c[2]) < 24 && c[2] < 200);

    char err[512];
    const char *png = "/tmp/seiche_test_render_scene.png";
    assert_true(eng_screenshot_write_png(f->ctx, png, err, sizeof err));

    // A hidden node is not drawn: the box's pixel turns into ground/sky.
    assert_true(eng_node_set_visible(f->scene, nb, false));
    eng_renderer_begin(f->r, f->ctx, &cam);
    eng_renderer_draw_scene(f->r, f->scene, f->meshes);
    eng_renderer_end(f->r);
    project(&cam, -0.9f, 0.5f, 0.5f, &x, &y);
    support_pixel(f->ctx, x, y, c);
    assert_false(c[0] > 2 * c[1]);
    eng_node_destroy(f->scene, nb);
    eng_node_destroy(f->scene, ns);
    eng_mesh_destroy(f->meshes, box);
    eng_mesh_destroy(f->meshes, sphere);
}

// Particle buffers as the fluid would leave them: vec4 positions and an indirect command.
static void make_particle_buffers(const float *vec4s, int n, int instances, GLuint *ssbo, GLuint *cmd)
{
    glGenBuffers(1, ssbo);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, *ssbo);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)((size_t)n * 4 * sizeof(float)), vec4s, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    const GLuint command[4] = { 4, (GLuint)instances, 0, 0 }; // count, instanceCount, first, baseInstance
    glGenBuffers(1, cmd);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, *cmd);
    glBufferData(GL_DRAW_INDIRECT_BUFFER, sizeof command, command, GL_DYNAMIC_DRAW);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
}

static void particle_impostors_appear_where_projected_with_gradient_colours(void **state)
{
    fixture *f = *state;
    eng_camera cam = make_camera(0.0f, 1.5f, 4.0f, 0.0f, 0.6f, 0.0f);
    const float radius = 0.25f;
    // Three particles in the air, colour parameters 0, 0.5, 1; a fourth beyond instanceCount.
    const float p[] = {
        -1.0f, 1.0f, 0.0f, 0.0f, //
        0.0f, 1.0f, 0.0f, 0.5f,  //
        1.0f, 1.0f, 0.0f, 1.0f,  //
        0.0f, 2.0f, 0.0f, 0.5f,  //
    };
    GLuint ssbo, cmd;
    make_particle_buffers(p, 4, 3, &ssbo, &cmd);
    // The same view without particles, for comparison.
    unsigned char *bg = malloc(W * H * 4);
    assert_non_null(bg);
    eng_renderer_begin(f->r, f->ctx, &cam);
    eng_renderer_end(f->r);
    assert_true(eng_read_pixels(f->ctx, bg, W, H, NULL, 0));

    support_log_clear(&f->log);
    eng_renderer_begin(f->r, f->ctx, &cam);
    eng_renderer_draw_particles(f->r, &cam, ssbo, cmd, radius, NULL);
    eng_renderer_end(f->r);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    assert_int_equal(f->log.error_count, 0);

    int x, y, c[3];
    int col[3][3];
    for (int i = 0; i < 3; i++) {
        project(&cam, p[i * 4], p[i * 4 + 1], p[i * 4 + 2], &x, &y);
        support_pixel(f->ctx, x, y, col[i]);
        print_pixel(i == 0 ? "particle w=0" : i == 1 ? "particle w=0.5" : "particle w=1", x, y, col[i]);
    }
    // Deep blue, then cyan, then near white: blue dominates the first, and the gradient
    // brightens along w.
    assert_true(col[0][2] > col[0][0] + 60 && col[0][2] > col[0][1]);
    assert_true(col[1][1] > col[0][1] + 40 && col[1][2] > col[1][0] + 60);
    assert_true(col[2][0] > col[1][0] + 60 && col[2][0] > 120 && col[2][2] > 150);
    // Just outside the disc (1.3 radii to the side of the middle one) the background is
    // untouched; so is the place of the fourth particle, past instanceCount = 3.
    const float away[2][3] = { { 1.3f * radius, 1.0f, 0.0f }, { 0.0f, 2.0f, 0.0f } };
    for (int i = 0; i < 2; i++) {
        project(&cam, away[i][0], away[i][1], away[i][2], &x, &y);
        support_pixel(f->ctx, x, y, c);
        const unsigned char *b = bg + ((size_t)y * W + (size_t)x) * 4;
        print_pixel(i == 0 ? "beside the disc" : "4th (not drawn)", x, y, c);
        assert_true(abs(c[0] - b[0]) <= 2 && abs(c[1] - b[1]) <= 2 && abs(c[2] - b[2]) <= 2);
    }
    free(bg);
    char err[512];
    assert_true(eng_screenshot_write_png(f->ctx, "/tmp/seiche_test_render_particles.png", err, sizeof err));
    glDeleteBuffers(1, &ssbo);
    glDeleteBuffers(1, &cmd);
}

static void particle_impostor_depth_is_the_sphere_surface_not_the_quad(void **state)
{
    fixture *f = *state;
    // A particle half sunk into the ground, seen from above: rays that meet its upper front
    // surface just above the ground show the particle, though the flat quad through the
    // centre would be behind the ground there; points below the ground stay hidden.
    eng_camera cam = make_camera(0.0f, 1.5f, 4.0f, 0.0f, 0.0f, 0.0f);
    const float radius = 0.5f;
    const float p[] = { 0.0f, 0.0f, 0.0f, 0.0f };
    GLuint ssbo, cmd;
    make_particle_buffers(p, 1, 1, &ssbo, &cmd);
    eng_renderer_begin(f->r, f->ctx, &cam);
    eng_renderer_draw_particles(f->r, &cam, ssbo, cmd, radius, NULL);
    eng_renderer_end(f->r);
    int x, y, c[3];
    float z_front = sqrtf(radius * radius - 0.05f * 0.05f);
    project(&cam, 0.0f, 0.05f, z_front, &x, &y);
    support_pixel(f->ctx, x, y, c);
    print_pixel("front surface y=+0.05", x, y, c);
    assert_true(c[2] > c[0] + 60); // particle blue
    z_front = sqrtf(radius * radius - 0.2f * 0.2f);
    project(&cam, 0.0f, -0.2f, z_front, &x, &y);
    support_pixel(f->ctx, x, y, c);
    print_pixel("front surface y=-0.2", x, y, c);
    assert_true(abs(c[0] - c[2]) < 30); // ground grey
    glDeleteBuffers(1, &ssbo);
    glDeleteBuffers(1, &cmd);
}

static void particle_draw_with_bad_arguments_is_refused_naming_them(void **state)
{
    fixture *f = *state;
    eng_camera cam = make_camera(0.0f, 1.5f, 4.0f, 0.0f, 0.0f, 0.0f);
    const float p[] = { 0.0f, 0.0f, 0.0f, 0.0f };
    GLuint ssbo, cmd;
    make_particle_buffers(p, 1, 1, &ssbo, &cmd);
    support_log_clear(&f->log);
    eng_renderer_draw_particles(f->r, &cam, ssbo, cmd, 0.1f, NULL); // outside a frame
    assert_true(support_log_contains(&f->log, "between eng_renderer_begin and eng_renderer_end"));
    eng_renderer_begin(f->r, f->ctx, &cam);
    eng_renderer_draw_particles(f->r, &cam, ssbo, cmd, -1.0f, NULL);
    assert_true(support_log_contains(&f->log, "radius must be > 0 m (got -1)"));
    eng_renderer_draw_particles(f->r, &cam, 0, cmd, 0.1f, NULL);
    assert_true(support_log_contains(&f->log, "positions_ssbo must be a GL buffer (got 0)"));
    eng_particle_style style = eng_default_particle_style();
    style.color_mid[1] = 2.0f;
    eng_renderer_draw_particles(f->r, &cam, ssbo, cmd, 0.1f, &style);
    assert_true(support_log_contains(&f->log, "eng_particle_style.color_mid[1] must be 0..1 (got 2)"));
    eng_renderer_end(f->r);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    glDeleteBuffers(1, &ssbo);
    glDeleteBuffers(1, &cmd);
}

static unsigned be32(const unsigned char *b)
{
    return (unsigned)b[0] << 24 | (unsigned)b[1] << 16 | (unsigned)b[2] << 8 | (unsigned)b[3];
}

static void screenshot_is_a_png_of_the_framebuffer_size_and_bad_paths_are_named(void **state)
{
    fixture *f = *state;
    eng_camera cam = make_camera(0.0f, 2.0f, 5.0f, 0.0f, 0.4f, 0.0f);
    eng_renderer_begin(f->r, f->ctx, &cam);
    eng_renderer_end(f->r);
    const char *path = "/tmp/seiche_test_render_shot.png";
    remove(path);
    char err[512] = "";
    assert_true(eng_screenshot_write_png(f->ctx, path, err, sizeof err));
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    unsigned char head[33];
    assert_int_equal(fread(head, 1, sizeof head, fp), sizeof head);
    fseek(fp, 0, SEEK_END);
    long size = ftell(fp);
    fclose(fp);
    static const unsigned char sig[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
    assert_memory_equal(head, sig, 8);
    assert_memory_equal(head + 12, "IHDR", 4);
    assert_int_equal(be32(head + 16), W);
    assert_int_equal(be32(head + 20), H);
    assert_true(size > 100);

    const char *bad = "/tmp/seiche-no-such-dir/x/shot.png";
    assert_false(eng_screenshot_write_png(f->ctx, bad, err, sizeof err));
    print_message("bad path: %s\n", err);
    assert_non_null(strstr(err, bad));
    assert_non_null(strstr(err, "No such file or directory"));

    // Reading back with a wrong size is refused naming the sizes.
    unsigned char px[4 * 16];
    assert_false(eng_read_pixels(f->ctx, px, 4, 4, err, sizeof err));
    assert_non_null(strstr(err, "160x120"));
}

static void all_mesh_shapes_render_and_bad_shapes_are_refused_naming_the_field(void **state)
{
    fixture *f = *state;
    // A tetrahedron, given as a convex hull's triangles (counter-clockwise from outside).
    const float tet[] = { 0, 0.9f, 0, -0.45f, 0, 0.35f, 0.45f, 0, 0.35f, 0, 0, -0.45f };
    const uint32_t tet_idx[] = { 0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2 };
    eng_mesh_id m[5] = {
        eng_mesh_create_box(f->meshes, (const float[]){ 0.3f, 0.4f, 0.3f }),
        eng_mesh_create_sphere(f->meshes, 0.35f),
        eng_mesh_create_capsule(f->meshes, 0.25f, 0.25f),
        eng_mesh_create_cylinder(f->meshes, 0.3f, 0.35f),
        eng_mesh_create_triangles(f->meshes, tet, 4, tet_idx, 12),
    };
    const float colors[5][3] = { { 0.85f, 0.12f, 0.1f }, { 0.15f, 0.75f, 0.2f }, { 0.9f, 0.7f, 0.1f },
                                 { 0.6f, 0.3f, 0.8f }, { 0.95f, 0.5f, 0.2f } };
    const float ys[5] = { 0.4f, 0.35f, 0.5f, 0.35f, 0.0f };
    eng_node_id nodes[5];
    for (int i = 0; i < 5; i++) {
        assert_true(eng_mesh_is_valid(f->meshes, m[i]));
        nodes[i] = add_node(f, m[i], -2.0f + (float)i, ys[i], 0.0f, colors[i][0], colors[i][1], colors[i][2]);
    }
    // Bounds say what was built: the capsule is 2 (r + h) = 1 m tall, the hull has 12 flat vertices.
    const eng_mesh_gpu *cap = eng_mesh_get_gpu(f->meshes, m[2]);
    assert_float_equal(cap->bounds_max[1] - cap->bounds_min[1], 1.0f, 1e-4f);
    assert_int_equal(eng_mesh_get_gpu(f->meshes, m[4])->vertex_count, 12);

    eng_camera cam = make_camera(0.0f, 1.6f, 3.6f, 0.0f, 0.35f, 0.0f);
    // Particles: a small block of "water" in front, parameter varying with height.
    enum { NP = 6 * 3 * 4 };
    float p[NP * 4];
    int k = 0;
    for (int iy = 0; iy < 4; iy++)
        for (int iz = 0; iz < 3; iz++)
            for (int ix = 0; ix < 6; ix++, k++) {
                p[k * 4 + 0] = -0.55f + 0.22f * (float)ix;
                p[k * 4 + 1] = 0.1f + 0.2f * (float)iy;
                p[k * 4 + 2] = 0.9f + 0.2f * (float)iz;
                p[k * 4 + 3] = (float)iy / 3.0f;
            }
    GLuint ssbo, cmd;
    make_particle_buffers(p, NP, NP, &ssbo, &cmd);
    support_log_clear(&f->log);
    eng_renderer_begin(f->r, f->ctx, &cam);
    eng_renderer_draw_scene(f->r, f->scene, f->meshes);
    eng_renderer_draw_particles(f->r, &cam, ssbo, cmd, 0.1f, NULL);
    eng_renderer_end(f->r);
    assert_int_equal(f->log.error_count, 0);
    char err[512];
    assert_true(eng_screenshot_write_png(f->ctx, "/tmp/seiche_test_render_shapes.png", err, sizeof err));
    // The capsule's top half, above the particles: its yellow.
    int x, y, c[3];
    project(&cam, 0.0f, 0.9f, 0.25f, &x, &y);
    support_pixel(f->ctx, x, y, c);
    print_pixel("capsule top", x, y, c);
    assert_true(c[0] > 100 && c[1] > 70 && c[2] < c[1] / 2);

    // Destroying a mesh makes its nodes draw nothing, with one warning, not a crash.
    eng_mesh_destroy(f->meshes, m[0]);
    assert_false(eng_mesh_is_valid(f->meshes, m[0]));
    assert_null(eng_mesh_get_gpu(f->meshes, m[0]));
    support_log_clear(&f->log);
    eng_renderer_begin(f->r, f->ctx, &cam);
    eng_renderer_draw_scene(f->r, f->scene, f->meshes);
    eng_renderer_end(f->r);
    assert_true(support_log_contains(&f->log, "refers to a destroyed mesh"));
    assert_int_equal(glGetError(), GL_NO_ERROR);

    support_log_clear(&f->log);
    assert_int_equal(eng_mesh_create_sphere(f->meshes, -1.0f).index1, 0);
    assert_true(support_log_contains(&f->log, "eng_mesh_create_sphere: radius must be a finite length > 0 m (got -1)"));
    assert_int_equal(eng_mesh_create_box(f->meshes, (const float[]){ 1.0f, 0.0f, 1.0f }).index1, 0);
    assert_true(support_log_contains(&f->log, "half_extents[1]"));
    const uint32_t bad_idx[] = { 0, 1, 7 };
    assert_int_equal(eng_mesh_create_triangles(f->meshes, tet, 4, bad_idx, 3).index1, 0);
    assert_true(support_log_contains(&f->log, "indices[2] must be < vertex_count 4 (got 7)"));
    assert_int_equal(eng_mesh_create_triangles(f->meshes, tet, 4, tet_idx, 4).index1, 0);
    assert_true(support_log_contains(&f->log, "index_count must be a positive multiple of 3"));

    for (int i = 0; i < 5; i++) {
        eng_node_destroy(f->scene, nodes[i]);
        eng_mesh_destroy(f->meshes, m[i]);
    }
    glDeleteBuffers(1, &ssbo);
    glDeleteBuffers(1, &cmd);
}

static void gpu_timer_reports_every_section_of_a_frame(void **state)
{
    fixture *f = *state;
    support_log log;
    eng_gpu_timer_def td = eng_default_gpu_timer_def();
    td.max_sections = 40;
    td.ring_size = 4;
    td.logger = support_capture_logger(&log);
    eng_gpu_timer *t = eng_gpu_timer_create(&td);
    assert_non_null(t);
    eng_camera cam = make_camera(0.0f, 2.0f, 5.0f, 0.0f, 0.4f, 0.0f);
    char name[32];
    for (int frame = 0; frame < 6; frame++) {
        int outer = eng_gpu_timer_begin(t, "frame");
        for (int s = 0; s < 39; s++) {
            snprintf(name, sizeof name, "section_%02d", s);
            int id = eng_gpu_timer_begin(t, name);
            assert_true(id >= 0);
            if (s == 0) {
                eng_renderer_begin(f->r, f->ctx, &cam);
                eng_renderer_end(f->r);
            }
            eng_gpu_timer_end(t, id);
        }
        eng_gpu_timer_end(t, outer);
        eng_gpu_timer_collect(t); // never waits
    }
    eng_gpu_timer_wait(t);
    assert_int_equal(eng_gpu_timer_section_count(t), 40);
    double frame_ms = eng_gpu_timer_ms(t, "frame");
    double first_ms = eng_gpu_timer_ms(t, "section_00");
    print_message("frame %.3f ms, section_00 (a cleared frame) %.3f ms, dropped %ld\n", frame_ms, first_ms,
                  eng_gpu_timer_dropped(t));
    assert_true(frame_ms > 0.0 && frame_ms < 1000.0);
    assert_true(first_ms >= 0.0 && first_ms <= frame_ms);
    for (int i = 0; i < 40; i++) {
        double ms = -1.0;
        assert_non_null(eng_gpu_timer_section(t, i, &ms));
        assert_true(ms >= 0.0);
        assert_true(eng_gpu_timer_samples(t, i) > 0);
    }
    assert_true(eng_gpu_timer_ms(t, "unknown") < 0.0);
    // One more name than max_sections is refused, naming the limit; so is a stray end.
    assert_int_equal(eng_gpu_timer_begin(t, "one_too_many"), -1);
    assert_true(support_log_contains(&log, "max_sections = 40"));
    eng_gpu_timer_end(t, 3);
    assert_true(support_log_contains(&log, "still open (got 3)"));
    eng_gpu_timer_destroy(t);

    // The renderer times its own passes.
    eng_gpu_timer_wait(eng_renderer_gpu_timer(f->r));
    assert_true(eng_gpu_timer_ms(eng_renderer_gpu_timer(f->r), "frame") >= 0.0);
    assert_true(eng_gpu_timer_ms(eng_renderer_gpu_timer(f->r), "particles") >= 0.0);
}

static void renderer_reports_a_shader_error_with_file_and_line(void **state)
{
    (void)state;
    support_log log;
    eng_renderer_def rd = eng_default_renderer_def();
    rd.shader_dir = "/tmp/seiche-no-shaders-here";
    rd.logger = support_capture_logger(&log);
    char err[1024];
    eng_renderer *r = eng_renderer_create(&rd, err, sizeof err);
    assert_null(r);
    print_message("missing shaders: %s\n", err);
    assert_non_null(strstr(err, "seiche-no-shaders-here/render/mesh.vert"));
    rd = eng_default_renderer_def();
    rd.logger = support_capture_logger(&log);
    rd.light.direction[0] = rd.light.direction[1] = rd.light.direction[2] = 0.0f;
    assert_null(eng_renderer_create(&rd, err, sizeof err));
    assert_non_null(strstr(err, "eng_renderer_def.light.direction must be a finite non-zero vector"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(known_scene_puts_lit_box_sphere_ground_and_sky_in_place),
        cmocka_unit_test(particle_impostors_appear_where_projected_with_gradient_colours),
        cmocka_unit_test(particle_impostor_depth_is_the_sphere_surface_not_the_quad),
        cmocka_unit_test(particle_draw_with_bad_arguments_is_refused_naming_them),
        cmocka_unit_test(screenshot_is_a_png_of_the_framebuffer_size_and_bad_paths_are_named),
        cmocka_unit_test(all_mesh_shapes_render_and_bad_shapes_are_refused_naming_the_field),
        cmocka_unit_test(gpu_timer_reports_every_section_of_a_frame),
        cmocka_unit_test(renderer_reports_a_shader_error_with_file_and_line),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
