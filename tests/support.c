// Shared test helpers: a headless GL context, paths, a capturing logger, and the solver
// tests' scenes built alike on the GPU and in the CPU reference. See support.h.
#include "tests/support.h"

#include <epoxy/gl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "engine/gl/screenshot.h"

static void capture(void *user, eng_log_level level, const char *message)
{
    support_log *log = user;
    log->count++;
    if (level == ENG_LOG_ERROR) log->error_count++;
    size_t room = sizeof log->text - log->len;
    int n = snprintf(log->text + log->len, room, "%s: %s\n", eng_log_level_name(level), message);
    if (n > 0) log->len += (size_t)n < room ? (size_t)n : room - 1;
}

eng_logger support_capture_logger(support_log *log)
{
    support_log_clear(log);
    eng_logger l = { capture, log, ENG_LOG_DEBUG };
    return l;
}

void support_log_clear(support_log *log)
{
    log->text[0] = 0;
    log->len = 0;
    log->count = 0;
    log->error_count = 0;
}

bool support_log_contains(const support_log *log, const char *needle)
{
    return strstr(log->text, needle) != NULL;
}

static bool has_shaders(const char *root)
{
    char p[1100];
    struct stat st;
    snprintf(p, sizeof p, "%s/shaders", root);
    return stat(p, &st) == 0 && S_ISDIR(st.st_mode);
}

const char *support_source_dir(char *out, size_t size)
{
#ifdef SEICHE_SOURCE_DIR
    // The checkout the build was configured in (unless it has moved since).
    if (has_shaders(SEICHE_SOURCE_DIR)) {
        snprintf(out, size, "%s", SEICHE_SOURCE_DIR);
        return out;
    }
#endif
    if (has_shaders(".")) {
        snprintf(out, size, ".");
        return out;
    }
    char exe[1024];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) {
        exe[n] = 0;
        // Strip the program name and two directories: <repo>/build/bin/test_x.
        for (int i = 0; i < 3; i++) {
            char *slash = strrchr(exe, '/');
            if (!slash) break;
            *slash = 0;
        }
        if (exe[0] && has_shaders(exe)) {
            snprintf(out, size, "%s", exe);
            return out;
        }
    }
    snprintf(out, size, ".");
    return out;
}

const char *support_source_path(const char *rel, char *out, size_t size)
{
    char root[1024];
    support_source_dir(root, sizeof root);
    snprintf(out, size, "%s/%s", root, rel);
    return out;
}

const char *support_bin_path(const char *name, char *out, size_t size)
{
    char exe[1024];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    char *slash = n > 0 ? (exe[n] = 0, strrchr(exe, '/')) : NULL;
    if (slash) {
        *slash = 0;
        snprintf(out, size, "%s/%s", exe, name);
    } else {
        char rel[256];
        snprintf(rel, sizeof rel, "build/bin/%s", name);
        support_source_path(rel, out, size);
    }
    return out;
}

eng_context *support_headless_context(int width, int height)
{
    eng_context_def def = eng_default_context_def();
    def.mode = ENG_CONTEXT_HEADLESS;
    def.width = width;
    def.height = height;
    def.vsync = false;
    char err[512];
    eng_context_status st;
    eng_context *ctx = eng_context_create(&def, &st, err, (int)sizeof err);
    if (!ctx) fail_msg("no headless GL 4.3 context (status %d): %s", (int)st, err);
    return ctx;
}

const char *support_gl_renderer(void)
{
    static char renderer[512];
    static bool known = false;
    if (known) return renderer;
    eng_context_def def = eng_default_context_def();
    def.mode = ENG_CONTEXT_HEADLESS;
    def.width = def.height = 16;
    def.logger.min_level = ENG_LOG_ERROR + 1; // quiet: a failure is the test's to report
    char err[512];
    eng_context_status st;
    eng_context *ctx = eng_context_create(&def, &st, err, (int)sizeof err);
    if (ctx) {
        snprintf(renderer, sizeof renderer, "%s", eng_context_renderer(ctx));
        eng_context_destroy(ctx);
    }
    known = true;
    return renderer;
}

bool support_gl_is_mesa(void)
{
    const char *r = support_gl_renderer();
    return strstr(r, "Mesa") || strstr(r, "llvmpipe");
}

void support_skip_unless_mesa(const char *what)
{
    if (support_gl_is_mesa()) return;
    const char *r = support_gl_renderer();
    print_message("SKIPPED: %s needs Mesa (MESA_GL_VERSION_OVERRIDE); this GL is %s\n", what,
                  *r ? r : "(none: no headless context)");
    skip();
}

void support_skip_unless_on_path(const char *program)
{
    const char *path = getenv("PATH");
    const char *p = path ? path : "";
    while (*p) {
        const char *end = strchr(p, ':');
        size_t len = end ? (size_t)(end - p) : strlen(p);
        char file[1024];
        // An empty entry is the current directory, as for the shell.
        snprintf(file, sizeof file, "%.*s/%s", len ? (int)len : 1, len ? p : ".", program);
        struct stat st;
        if (stat(file, &st) == 0 && S_ISREG(st.st_mode) && access(file, X_OK) == 0) return;
        p = end ? end + 1 : p + len;
    }
    print_message("SKIPPED: needs %s on the PATH, which has none (PATH=%s)\n", program, path ? path : "");
    skip();
}

void support_pixel(const eng_context *ctx, int x, int y, int rgb[3])
{
    int w, h;
    eng_context_size(ctx, &w, &h);
    assert_true(x >= 0 && x < w && y >= 0 && y < h);
    unsigned char *px = malloc((size_t)w * (size_t)h * 4);
    assert_non_null(px);
    char err[256];
    if (!eng_read_pixels(ctx, px, w, h, err, sizeof err)) {
        free(px);
        fail_msg("eng_read_pixels: %s", err);
    }
    const unsigned char *p = px + ((size_t)y * (size_t)w + (size_t)x) * 4;
    rgb[0] = p[0];
    rgb[1] = p[1];
    rgb[2] = p[2];
    free(px);
}

int support_gpu_setup(void **state)
{
    support_gpu *f = calloc(1, sizeof *f);
    if (!f) return -1;
    f->ctx = support_headless_context(32, 32);
    if (!f->ctx) {
        free(f);
        return -1;
    }
    const char *env = getenv("SEICHE_SHADER_DIR");
    if (env && *env) snprintf(f->shader_dir, sizeof f->shader_dir, "%s", env);
    else support_source_path("shaders", f->shader_dir, sizeof f->shader_dir);
    support_source_path("tests/fixtures", f->fixtures_dir, sizeof f->fixtures_dir);
    *state = f;
    return 0;
}

int support_gpu_teardown(void **state)
{
    support_gpu *f = *state;
    if (f) eng_context_destroy(f->ctx);
    free(f);
    return 0;
}

// ---- the solver tests' scenes ---------------------------------------------------------

support_scene support_dam_break(void)
{
    support_scene s;
    memset(&s, 0, sizeof s);
    s.params = pbf_default_params();
    s.capacity = 2048;
    const float dmin[3] = { -0.05f, -0.05f, -0.05f }, dmax[3] = { 0.55f, 0.6f, 0.3f };
    const float bmin[3] = { 0.0f, 0.0f, 0.0f }, bmax[3] = { 0.5f, 0.5f, 0.26f };
    memcpy(s.domain_min, dmin, sizeof dmin);
    memcpy(s.domain_max, dmax, sizeof dmax);
    s.container = true;
    memcpy(s.box_min, bmin, sizeof bmin);
    memcpy(s.box_max, bmax, sizeof bmax);
    s.closed_top = false;
    s.block = pbf_default_block_def();
    // The block stands 3 mm (0.12 spacing) off the walls. Placed right against them its
    // wall layer starts exactly in balance (the wall model is calibrated to the lattice),
    // C = max(rho / rho0 - 1, 0) then flips on rounding noise, and the two sides part ways
    // for reasons that say nothing about the implementation.
    const float lo[3] = { 0.003f, 0.003f, 0.003f }, hi[3] = { 0.253f, 0.253f, 0.253f };
    memcpy(s.block.min, lo, sizeof lo);
    memcpy(s.block.max, hi, sizeof hi);
    return s;
}

pbf_world *support_gpu_world(const support_gpu *f, const support_scene *s)
{
    pbf_world_def def = pbf_default_world_def();
    def.params = s->params;
    def.capacity = s->capacity;
    def.max_neighbours = pbf_suggest_max_neighbours(&s->params);
    memcpy(def.domain_min, s->domain_min, sizeof def.domain_min);
    memcpy(def.domain_max, s->domain_max, sizeof def.domain_max);
    def.shader_dir = f->shader_dir;
    char err[1024];
    pbf_world *w = pbf_world_create(&def, err, sizeof err);
    if (!w) fail_msg("pbf_world_create: %s", err);
    if (s->container) assert_int_equal(pbf_world_set_container(w, s->box_min, s->box_max, s->closed_top), PBF_OK);
    if (s->block.max[0] > s->block.min[0]) assert_int_equal(pbf_world_add_block(w, &s->block, NULL), PBF_OK);
    if (s->extra) assert_int_equal(pbf_world_add_particles(w, s->positions, s->velocities, s->extra), PBF_OK);
    return w;
}

pbf_cpu_world *support_cpu_world(const support_scene *s)
{
    char err[1024];
    pbf_cpu_world *w = pbf_cpu_world_create(&s->params, s->capacity, s->domain_min, s->domain_max, err, sizeof err);
    if (!w) fail_msg("pbf_cpu_world_create: %s", err);
    if (s->container)
        assert_int_equal(pbf_cpu_world_set_container(w, s->box_min, s->box_max, s->closed_top), PBF_OK);
    if (s->block.max[0] > s->block.min[0]) assert_int_equal(pbf_cpu_world_add_block(w, &s->block, NULL), PBF_OK);
    if (s->extra)
        assert_int_equal(pbf_cpu_world_add_particles(w, s->positions, s->velocities, s->extra), PBF_OK);
    return w;
}

double support_max_deviation(const float *a, const float *b, uint32_t n)
{
    double worst = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) {
            double d = (double)a[4 * i + k] - (double)b[4 * i + k];
            d2 += d * d;
        }
        if (!(d2 <= worst * worst)) worst = sqrt(d2); // NaN counts as the worst
    }
    return worst;
}

void support_assert_mentions(const char *message, const char *const *needles)
{
    for (; *needles; needles++)
        if (!strstr(message, *needles)) fail_msg("message \"%s\" does not mention \"%s\"", message, *needles);
}

double support_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

void support_capture_warning(void *user, int level, const char *message)
{
    support_warnings *c = user;
    if (level != 2) return;
    c->warnings++;
    snprintf(c->last, sizeof c->last, "%s", message);
}
