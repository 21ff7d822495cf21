// seiche-render-bench: GPU time of each render pass of the water, headless.
//
// N particles (--particles) fill a 1 x 1 x 1 m block (spacing (1 m^3 / N)^(1/3), jittered by
// a tenth of it, the top rippled) in the reference tank of seiche-bench (4 x 3 x 1.5 m; its
// floor and back wall drawn), seen from the front so that the water fills about a third of
// the frame. No simulation: the particles are uploaded once, so only drawing is timed. For
// each fluid mode asked (--mode) it draws warm-up frames, then measured frames, each
// waited for, and prints the median milliseconds of every pass (the renderer's GPU timer
// sections), with the size, the particle count and the GL renderer. The modes run once for
// each way of drawing the water's particle passes (the look's `splat`) that --splat names,
// one after the other in the same process (default raster,compute).
//
//   build/bin/seiche-render-bench --size 1920x1080 --particles 1000000 --frames 20
//   build/bin/seiche-render-bench --particles 1000000 --mode surface --splat raster,compute
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <epoxy/gl.h>

#include "engine/gl/context.h"
#include "engine/gl/gpu_timer.h"
#include "engine/gl/screenshot.h"
#include "engine/render/camera.h"
#include "engine/render/mesh.h"
#include "engine/render/renderer.h"
#include "engine/render/scene.h"

#include "demos/render_bench/bench_camera.h"

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static unsigned rng = 2463534242u;
static float unit_noise(void) // -0.5 .. 0.5
{
    rng ^= rng << 13;
    rng ^= rng >> 17;
    rng ^= rng << 5;
    return (float)(rng >> 8) / 16777216.0f - 0.5f;
}

// Draws `warmup` frames, then `frames` measured ones, each waited for, and prints the median
// milliseconds of every timer section under "MODE (splat SPLAT):".
static void measure(eng_renderer *r, eng_context *ctx, const eng_camera *cam, eng_scene *scene, eng_mesh_store *meshes,
                    const eng_fluid_draw *fd, int warmup, int frames, const char *mode, const char *splat)
{
    eng_gpu_timer *t = eng_renderer_gpu_timer(r);
    enum { MAX_SECTIONS = 16 };
    double *ms[MAX_SECTIONS];
    for (int i = 0; i < MAX_SECTIONS; i++) ms[i] = calloc((size_t)frames, sizeof(double));
    int got[MAX_SECTIONS] = { 0 };
    long seen[MAX_SECTIONS] = { 0 }; // samples so far: a section not drawn this frame keeps its count
    for (int f = 0; f < warmup + frames; f++) {
        eng_renderer_begin(r, ctx, cam);
        eng_renderer_draw_scene(r, scene, meshes);
        eng_renderer_draw_fluid(r, fd);
        eng_renderer_end(r);
        eng_gpu_timer_wait(t);
        if (f < warmup) {
            for (int i = 0; i < eng_gpu_timer_section_count(t) && i < MAX_SECTIONS; i++)
                seen[i] = eng_gpu_timer_samples(t, i);
            continue;
        }
        for (int i = 0; i < eng_gpu_timer_section_count(t) && i < MAX_SECTIONS; i++) {
            double x;
            eng_gpu_timer_section(t, i, &x);
            long samples = eng_gpu_timer_samples(t, i);
            if (samples > seen[i] && x >= 0.0 && got[i] < frames) ms[i][got[i]++] = x;
            seen[i] = samples;
        }
    }
    printf("%s (splat %s):\n", mode, splat);
    for (int i = 0; i < eng_gpu_timer_section_count(t) && i < MAX_SECTIONS; i++) {
        qsort(ms[i], (size_t)got[i], sizeof(double), cmp_double);
        if (got[i] > 0) printf("  %-18s %9.3f ms\n", eng_gpu_timer_section(t, i, NULL), ms[i][got[i] / 2]);
    }
    for (int i = 0; i < MAX_SECTIONS; i++) free(ms[i]);
}

static int usage(void)
{
    fprintf(stderr, "usage: seiche-render-bench [--size WxH] [--particles N] [--frames N] [--warmup N]\n"
                    "                           [--mode surface,spheres,density,speed] [--resolution 0.25..1]\n"
                    "                           [--splat raster,compute] [--shaders DIR]\n"
                    "                           [--screenshot FILE.png (the last frame)]\n");
    return 2;
}

int main(int argc, char **argv)
{
    int w = 1280, h = 720, frames = 10, warmup = 3;
    long n = 100000;
    float resolution = -1.0f;
    const char *modes = "surface,spheres", *splats = "raster,compute", *shader_dir = NULL, *shot = NULL;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!v) return usage();
        char *end;
        errno = 0;
        if (strcmp(a, "--size") == 0) {
            if (sscanf(v, "%dx%d", &w, &h) != 2 || w < 16 || h < 16 || w > 16384 || h > 16384) return usage();
        } else if (strcmp(a, "--particles") == 0) {
            n = strtol(v, &end, 10);
            if (*end || errno || n < 1 || n > 64000000) return usage();
        } else if (strcmp(a, "--frames") == 0) {
            frames = (int)strtol(v, &end, 10);
            if (*end || errno || frames < 1 || frames > 100000) return usage();
        } else if (strcmp(a, "--warmup") == 0) {
            warmup = (int)strtol(v, &end, 10);
            if (*end || errno || warmup < 0 || warmup > 100000) return usage();
        } else if (strcmp(a, "--resolution") == 0) {
            resolution = strtof(v, &end);
            if (*end || errno || !(resolution >= 0.25f && resolution <= 1.0f)) return usage();
        } else if (strcmp(a, "--mode") == 0) {
            modes = v;
        } else if (strcmp(a, "--splat") == 0) {
            splats = v;
        } else if (strcmp(a, "--shaders") == 0) {
            shader_dir = v;
        } else if (strcmp(a, "--screenshot") == 0) {
            shot = v;
        } else {
            return usage();
        }
        i++;
    }
    eng_context_def cd = eng_default_context_def();
    cd.mode = ENG_CONTEXT_HEADLESS;
    cd.width = w;
    cd.height = h;
    eng_context_status st;
    char err[2048];
    eng_context *ctx = eng_context_create(&cd, &st, err, sizeof err);
    if (!ctx) return 3;
    eng_renderer_def rd = eng_default_renderer_def();
    rd.shader_dir = shader_dir;
    if (resolution > 0.0f) rd.fluid.resolution = resolution;
    eng_renderer *r = eng_renderer_create(&rd, err, sizeof err);
    if (!r) {
        fprintf(stderr, "seiche-render-bench: %s\n", err);
        return 2;
    }
    const float lo[3] = { 0.0f, 0.0f, 0.0f }, hi[3] = { 4.0f, 3.0f, 1.5f };
    eng_renderer_set_shadow_bounds(r, lo, hi);
    eng_mesh_store_def md = eng_default_mesh_store_def();
    eng_mesh_store *meshes = eng_mesh_store_create(&md);
    eng_scene_def sd = eng_default_scene_def();
    eng_scene *scene = eng_scene_create(&sd);
    const float slabs[2][6] = { { 2.0f, -0.01f, 0.75f, 2.0f, 0.01f, 0.75f }, { 2.0f, 1.5f, -0.01f, 2.0f, 1.5f, 0.01f } };
    for (int i = 0; i < 2; i++) {
        eng_node_def nd = eng_default_node_def();
        nd.mesh = eng_mesh_create_box(meshes, slabs[i] + 3);
        memcpy(nd.local.translation, slabs[i], 3 * sizeof(float));
        nd.color[0] = 0.72f, nd.color[1] = 0.74f, nd.color[2] = 0.78f;
        eng_node_create(scene, &nd);
    }

    // The block: spacing s, rippled top, jittered.
    double s = cbrt(1.0 / (double)n);
    long side = lround(1.0 / s);
    float *p = malloc((size_t)n * 4 * sizeof(float)), *v = malloc((size_t)n * 4 * sizeof(float));
    if (!p || !v) return 2;
    long k = 0;
    for (long iy = 0; k < n; iy++)
        for (long iz = 0; iz < side && k < n; iz++)
            for (long ix = 0; ix < side && k < n; ix++, k++) {
                float x = (float)((ix + 0.5) * s), y = (float)((iy + 0.5) * s), z = (float)((iz + 0.5) * s);
                y *= 1.0f + 0.08f * sinf(6.0f * x) * cosf(4.0f * z);
                p[4 * k + 0] = 0.3f + x + (float)s * 0.1f * unit_noise();
                p[4 * k + 1] = y + (float)s * 0.1f * unit_noise();
                p[4 * k + 2] = 0.25f + z + (float)s * 0.1f * unit_noise();
                p[4 * k + 3] = y;
                v[4 * k + 0] = v[4 * k + 1] = v[4 * k + 2] = 0.0f;
                v[4 * k + 3] = (float)(s * s * s); // at rest density
            }
    GLuint buf[3];
    glGenBuffers(3, buf);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buf[0]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)n * 16, p, GL_STATIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buf[1]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, (GLsizeiptr)n * 16, v, GL_STATIC_DRAW);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    const GLuint cmd[4] = { 4, (GLuint)n, 0, 0 };
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, buf[2]);
    glBufferData(GL_DRAW_INDIRECT_BUFFER, sizeof cmd, cmd, GL_STATIC_DRAW);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    free(p);
    free(v);
    eng_fluid_draw fd = eng_default_fluid_draw();
    fd.positions = buf[0];
    fd.velocities = buf[1];
    fd.draw_indirect = buf[2];
    fd.radius = (float)(0.5 * s);
    fd.particle_mass = (float)(1000.0 * s * s * s);
    fd.rest_density = 1000.0f;

    eng_camera cam;
    bench_camera(&cam, err, sizeof err); // fixed values, which the camera accepts

    printf("seiche-render-bench: %dx%d, %ld particles (radius %.2f mm), surface textures at %.2f, %s\n", w, h, n,
           1000.0 * 0.5 * s, (double)eng_renderer_fluid_look(r).resolution, eng_context_renderer(ctx));
    char splat_list[256], list[256];
    snprintf(splat_list, sizeof splat_list, "%s", splats);
    char *splat_save = NULL;
    for (char *sp = strtok_r(splat_list, ",", &splat_save); sp; sp = strtok_r(NULL, ",", &splat_save)) {
        eng_fluid_look look = eng_renderer_fluid_look(r);
        if (!eng_fluid_splat_parse(sp, &look.splat)) {
            fprintf(stderr, "seiche-render-bench: --splat: each must be raster or compute (got '%s')\n", sp);
            return 2;
        }
        eng_renderer_set_fluid_look(r, &look);
        snprintf(list, sizeof list, "%s", modes);
        char *mode_save = NULL;
        for (char *m = strtok_r(list, ",", &mode_save); m; m = strtok_r(NULL, ",", &mode_save)) {
            eng_fluid_mode mode;
            if (!eng_fluid_mode_parse(m, &mode)) {
                fprintf(stderr, "seiche-render-bench: --mode: each must be one of %s (got '%s')\n", eng_fluid_mode_names(),
                        m);
                return 2;
            }
            eng_renderer_set_fluid_mode(r, mode);
            measure(r, ctx, &cam, scene, meshes, &fd, warmup, frames, m, sp);
        }
    }
    if (shot && !eng_screenshot_write_png(ctx, shot, err, sizeof err)) fprintf(stderr, "seiche-render-bench: %s\n", err);
    glDeleteBuffers(3, buf);
    eng_scene_destroy(scene);
    eng_mesh_store_destroy(meshes);
    eng_renderer_destroy(r);
    eng_context_destroy(ctx);
    return 0;
}
