// Shared helpers for the cmocka tests: a headless GL context, the shader and fixture
// directories, a logger that captures messages so tests can assert on them, and the
// solver tests' scenes, built the same way on the GPU and in the CPU reference.
//
// Include after the cmocka prerequisites (<stdarg.h>, <stddef.h>, <stdint.h>, <setjmp.h>)
// and <cmocka.h>, or on its own: this header includes them itself.
#ifndef SEICHE_TESTS_SUPPORT_H
#define SEICHE_TESTS_SUPPORT_H

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "engine/gl/context.h"
#include "engine/core/log.h"
#include "fluid/pbf.h"
#include "fluid/pbf_cpu.h"

/// Messages captured by support_capture_logger(); `text` holds "level: message\n" lines.
typedef struct support_log {
    char text[16384];
    size_t len;
    int count;       ///< messages received (also those that no longer fit)
    int error_count; ///< of which at ENG_LOG_ERROR
} support_log;

/// A logger that appends every message (DEBUG and up) to `log` instead of stderr.
eng_logger support_capture_logger(support_log *log);
void support_log_clear(support_log *log);
/// True when some captured message contains `needle`.
bool support_log_contains(const support_log *log, const char *needle);

/// The repository root: SEICHE_SOURCE_DIR when the build defines it (and it holds
/// shaders/), else the current directory when it holds shaders/, else two levels above
/// the test program (build/bin/test_x -> repo). Written into `out`; returns `out`.
const char *support_source_dir(char *out, size_t size);
/// "<root>/<rel>", e.g. support_source_path("shaders", buf, sizeof buf).
const char *support_source_path(const char *rel, char *out, size_t size);

/// "<dir of this test program>/<name>": the runner and the other programs built with the
/// test (build/bin/seiche, or build/sanitize/bin/seiche for the sanitizer build).
const char *support_bin_path(const char *name, char *out, size_t size);

/// A headless context of the given size; the test fails (with the reason) when none can
/// be made. Destroy with eng_context_destroy.
eng_context *support_headless_context(int width, int height);

/// The fixture of the GPU tests: one headless context for the group, the shader directory
/// ($SEICHE_SHADER_DIR, else <repo>/shaders) and the fixtures directory (<repo>/tests/fixtures).
typedef struct support_gpu {
    eng_context *ctx;
    char shader_dir[1024];
    char fixtures_dir[1024];
} support_gpu;
/// cmocka group setup and teardown: *state becomes a support_gpu.
int support_gpu_setup(void **state);
int support_gpu_teardown(void **state);

/// The GL of this machine, "GL_RENDERER (GL_VERSION)", read once from a headless context
/// made and destroyed for it (so call it while no context of the test is current), then
/// cached. "" when no context can be made.
const char *support_gl_renderer(void);
/// True when that GL is Mesa's: its renderer or version string names Mesa or llvmpipe.
/// Only Mesa honours MESA_GL_VERSION_OVERRIDE.
bool support_gl_is_mesa(void);
/// Skips the running test (cmocka skip(), counted as skipped) with the reason printed,
/// unless the GL is Mesa's. `what` says what the test needs Mesa for.
void support_skip_unless_mesa(const char *what);
/// Skips the running test with the reason printed unless `program` is an executable file
/// in a directory of $PATH (as `command -v` finds it).
void support_skip_unless_on_path(const char *program);

/// Reads back the pixel at (x, y), counted from the top-left corner, of the current
/// framebuffer of `ctx` into rgb[0..2] (0..255).
void support_pixel(const eng_context *ctx, int x, int y, int rgb[3]);

// ---- the solver tests' scenes (test_solver, test_solver_colliders, test_mirror) ---------

/// A scene built identically on the GPU (support_gpu_world) and in the CPU reference
/// (support_cpu_world): parameters, capacity, domain (m), a container, a block and extra
/// particles, added in that order.
typedef struct support_scene {
    pbf_params params;
    uint32_t capacity;
    float domain_min[3], domain_max[3];
    bool container;
    float box_min[3], box_max[3];
    bool closed_top;
    pbf_block_def block;    ///< none when block.max[0] <= block.min[0]
    const float *positions; ///< extra particles (xyz triples) after the block, or NULL
    const float *velocities;
    uint32_t extra;
} support_scene;

/// A dam break: a 0.25 m cube of water (10^3 particles at the default 2.5 cm spacing) in
/// the corner of an open 0.5 x 0.5 x 0.25 m tank, default parameters.
support_scene support_dam_break(void);
/// The scene on the GPU (shaders from f->shader_dir) and in the CPU reference; the test
/// fails when either refuses it.
pbf_world *support_gpu_world(const support_gpu *f, const support_scene *s);
pbf_cpu_world *support_cpu_world(const support_scene *s);
/// Largest distance between corresponding particles of two xyzw arrays (m or m/s); NaN
/// counts as the worst.
double support_max_deviation(const float *a, const float *b, uint32_t n);
/// Fails unless `message` contains every string of the NULL-terminated `needles`.
void support_assert_mentions(const char *message, const char *const *needles);
/// Seconds on the monotonic clock (for timing a call within a test).
double support_seconds(void);

/// The warnings (level 2) a world logs: how many, and the last one's text. Pass
/// support_capture_warning as pbf_world_def.log with a support_warnings as log_user.
typedef struct support_warnings {
    int warnings;
    char last[512];
} support_warnings;
void support_capture_warning(void *user, int level, const char *message);

#endif
