// GL context creation: GLFW window or headless EGL. See context.h.
#include "engine/gl/context.h"
#include "engine/gl/gl_strict.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <GLFW/glfw3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct eng_context {
    eng_context_mode mode;
    int width, height;
    eng_logger logger;
    GLFWwindow *window;
    EGLDisplay egl_display;
    EGLContext egl_context;
    GLuint fbo, color_rb, depth_rb;
    bool close_requested;
    bool debug;          // KHR_debug output on, driver errors fail the run
    bool gl_ready;       // created and current: GL calls are safe
    uint32_t seen_perf[64]; // performance-warning ids already printed
    int seen_perf_count;
    char platform[32];
    char renderer[256];
};

eng_context_def eng_default_context_def(void)
{
    eng_context_def d;
    memset(&d, 0, sizeof d);
    d.mode = ENG_CONTEXT_WINDOW;
    d.width = 1280;
    d.height = 720;
    d.title = "Seiche";
    d.vsync = true;
#ifdef SEICHE_DEBUG
    d.debug = true;
#else
    d.debug = false;
#endif
    d.logger = eng_default_logger();
    return d;
}

// Driver messages: errors and undefined behaviour fail the run (eng_gl_fail: exit status 5),
// except out-of-memory and shader compiler messages, which the calls that allocate and the
// shader builder (pbf_glsl, with file:line) report themselves; performance
// warnings are printed once per message id; the rest go to the logger.
static void GLAPIENTRY debug_cb(GLenum source, GLenum type, GLuint id, GLenum severity,
                                GLsizei length, const GLchar *message, const void *user)
{
    (void)length;
    eng_context *ctx = (eng_context *)user;
    bool handled = strstr(message, "out of memory") || strstr(message, "OUT_OF_MEMORY") ||
                   source == GL_DEBUG_SOURCE_SHADER_COMPILER;
    if ((type == GL_DEBUG_TYPE_ERROR || type == GL_DEBUG_TYPE_UNDEFINED_BEHAVIOR) && !handled) {
        eng_gl_fail("GL %s reported by the driver: %s", type == GL_DEBUG_TYPE_ERROR ? "error" : "undefined behaviour",
                    message);
        return;
    }
    if (type == GL_DEBUG_TYPE_PERFORMANCE) {
        for (int i = 0; i < ctx->seen_perf_count; i++)
            if (ctx->seen_perf[i] == id) return;
        if (ctx->seen_perf_count < (int)(sizeof ctx->seen_perf / sizeof ctx->seen_perf[0]))
            ctx->seen_perf[ctx->seen_perf_count++] = id;
        eng_log(&ctx->logger, ENG_LOG_WARN, "GL performance: %s", message);
        return;
    }
    eng_log_level lvl = severity == GL_DEBUG_SEVERITY_HIGH ? ENG_LOG_ERROR
                      : severity == GL_DEBUG_SEVERITY_MEDIUM ? ENG_LOG_WARN
                      : ENG_LOG_DEBUG;
    if (type == GL_DEBUG_TYPE_ERROR) lvl = ENG_LOG_ERROR;
    eng_log(&ctx->logger, lvl, "GL: %s", message);
}

static eng_gl_proc egl_proc(const char *name) { return (eng_gl_proc)eglGetProcAddress(name); }
static eng_gl_proc glfw_proc(const char *name) { return (eng_gl_proc)glfwGetProcAddress(name); }

static bool env_is_1(const char *name)
{
    const char *v = getenv(name);
    return v && strcmp(v, "1") == 0;
}

static void fail(eng_context *ctx, char *err, int err_size, const char *fmt, const char *a)
{
    char msg[512];
    snprintf(msg, sizeof msg, fmt, a);
    if (err && err_size > 0) snprintf(err, (size_t)err_size, "%s", msg);
    eng_log(&ctx->logger, ENG_LOG_ERROR, "%s", msg);
}

// Checks the current context for GL 4.3 and compute shaders; fills the renderer string.
static eng_context_status check_compute(eng_context *ctx, char *err, int err_size)
{
    const char *ren = (const char *)glGetString(GL_RENDERER);
    const char *ver = (const char *)glGetString(GL_VERSION);
    snprintf(ctx->renderer, sizeof ctx->renderer, "%s (%s)", ren ? ren : "?", ver ? ver : "?");
    int gl = epoxy_gl_version();
    bool compute = gl >= 43 || epoxy_has_gl_extension("GL_ARB_compute_shader");
    if (gl < 43 || !compute) {
        char found[400];
        snprintf(found, sizeof found, "Seiche needs OpenGL 4.3 core with compute shaders; found OpenGL %d.%d%s on %s",
                 gl / 10, gl % 10, compute ? "" : " without compute shaders", ctx->renderer);
        fail(ctx, err, err_size, "%s", found);
        return ENG_CONTEXT_NO_COMPUTE;
    }
    return ENG_CONTEXT_OK;
}

bool eng_display_available(void)
{
    const char *d = getenv("DISPLAY");
    const char *w = getenv("WAYLAND_DISPLAY");
    if ((!d || !*d) && (!w || !*w)) return false;
    if (!glfwInit()) return false;
    glfwTerminate();
    return true;
}

static eng_context_status create_window(eng_context *ctx, const eng_context_def *def,
                                        char *err, int err_size)
{
    if (!glfwInit()) {
        fail(ctx, err, err_size, "%s", "cannot open a window: no display (set DISPLAY, or use --headless)");
        return ENG_CONTEXT_NO_DISPLAY;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    glfwWindowHint(GLFW_OPENGL_DEBUG_CONTEXT, ctx->debug ? GLFW_TRUE : GLFW_FALSE);
    glfwWindowHint(GLFW_SAMPLES, 4);
    ctx->window = glfwCreateWindow(def->width, def->height, def->title ? def->title : "Seiche", NULL, NULL);
    if (!ctx->window) {
        // Find out what the machine does offer, for the message.
        glfwDefaultWindowHints();
        glfwWindowHint(GLFW_VISIBLE, GLFW_FALSE);
        GLFWwindow *probe = glfwCreateWindow(64, 64, "probe", NULL, NULL);
        if (!probe) {
            fail(ctx, err, err_size, "%s", "cannot create any OpenGL context on this display");
            glfwTerminate();
            return ENG_CONTEXT_NO_GL;
        }
        glfwMakeContextCurrent(probe);
        eng_context_status st = check_compute(ctx, err, err_size);
        if (st == ENG_CONTEXT_OK) {
            fail(ctx, err, err_size, "%s", "the display offers no OpenGL 4.3 core context");
            st = ENG_CONTEXT_NO_COMPUTE;
        }
        glfwDestroyWindow(probe);
        glfwTerminate();
        return st;
    }
    glfwMakeContextCurrent(ctx->window);
    glfwSwapInterval(def->vsync ? 1 : 0);
    snprintf(ctx->platform, sizeof ctx->platform, "glfw");
    return check_compute(ctx, err, err_size);
}

static EGLDisplay egl_open(eng_context *ctx)
{
    const char *want = getenv("SEICHE_EGL_PLATFORM"); // "device" or "surfaceless"
    bool try_device = !want || strcmp(want, "device") == 0;
    bool try_surfaceless = !want || strcmp(want, "surfaceless") == 0;
    if (try_device && epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_platform_device")) {
        EGLDeviceEXT devs[16];
        EGLint n = 0;
        if (eglQueryDevicesEXT(16, devs, &n) && n > 0) {
            for (EGLint i = 0; i < n; i++) {
                EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, devs[i], NULL);
                EGLint maj, min;
                if (d != EGL_NO_DISPLAY && eglInitialize(d, &maj, &min)) {
                    snprintf(ctx->platform, sizeof ctx->platform, "egl-device");
                    return d;
                }
            }
        }
    }
    if (try_surfaceless && epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
        EGLint maj, min;
        if (d != EGL_NO_DISPLAY && eglInitialize(d, &maj, &min)) {
            snprintf(ctx->platform, sizeof ctx->platform, "egl-surfaceless");
            return d;
        }
    }
    return EGL_NO_DISPLAY;
}

static eng_context_status create_headless(eng_context *ctx, const eng_context_def *def,
                                          char *err, int err_size)
{
    EGLDisplay d = egl_open(ctx);
    if (d == EGL_NO_DISPLAY) {
        fail(ctx, err, err_size, "%s", "headless: no EGL display (neither the device nor the surfaceless platform)");
        return ENG_CONTEXT_NO_GL;
    }
    ctx->egl_display = d;
    if (!eglBindAPI(EGL_OPENGL_API)) {
        fail(ctx, err, err_size, "%s", "headless: this EGL cannot bind desktop OpenGL");
        return ENG_CONTEXT_NO_GL;
    }
    EGLConfig cfg = NULL;
    EGLint ncfg = 0;
    const EGLint cfg_attr[] = { EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_SURFACE_TYPE, 0, EGL_NONE };
    if (!eglChooseConfig(d, cfg_attr, &cfg, 1, &ncfg) || ncfg < 1) {
        const EGLint any[] = { EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE };
        if (!eglChooseConfig(d, any, &cfg, 1, &ncfg) || ncfg < 1) cfg = NULL;
    }
    const EGLint ctx_attr[] = {
        EGL_CONTEXT_MAJOR_VERSION, 4,
        EGL_CONTEXT_MINOR_VERSION, 3,
        EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
        EGL_CONTEXT_OPENGL_DEBUG, ctx->debug ? EGL_TRUE : EGL_FALSE,
        EGL_NONE,
    };
    ctx->egl_context = eglCreateContext(d, cfg, EGL_NO_CONTEXT, ctx_attr);
    if (ctx->egl_context == EGL_NO_CONTEXT) {
        // Find out what is offered, for the message.
        EGLContext probe = eglCreateContext(d, cfg, EGL_NO_CONTEXT, (const EGLint[]){ EGL_NONE });
        if (probe == EGL_NO_CONTEXT || !eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, probe)) {
            fail(ctx, err, err_size, "%s", "headless: EGL cannot create any OpenGL context");
            return ENG_CONTEXT_NO_GL;
        }
        eng_context_status st = check_compute(ctx, err, err_size);
        if (st == ENG_CONTEXT_OK) {
            fail(ctx, err, err_size, "%s", "headless: EGL offers no OpenGL 4.3 core context");
            st = ENG_CONTEXT_NO_COMPUTE;
        }
        eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(d, probe);
        return st;
    }
    if (!eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, ctx->egl_context)) {
        fail(ctx, err, err_size, "%s", "headless: eglMakeCurrent without a surface failed (EGL_KHR_surfaceless_context missing?)");
        return ENG_CONTEXT_NO_GL;
    }
    eng_context_status st = check_compute(ctx, err, err_size);
    if (st != ENG_CONTEXT_OK) return st;
    glGenFramebuffers(1, &ctx->fbo);
    glGenRenderbuffers(1, &ctx->color_rb);
    glGenRenderbuffers(1, &ctx->depth_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, ctx->color_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, def->width, def->height);
    glBindRenderbuffer(GL_RENDERBUFFER, ctx->depth_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, def->width, def->height);
    glBindFramebuffer(GL_FRAMEBUFFER, ctx->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, ctx->color_rb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, ctx->depth_rb);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        fail(ctx, err, err_size, "%s", "headless: the offscreen framebuffer is incomplete");
        return ENG_CONTEXT_NO_GL;
    }
    return ENG_CONTEXT_OK;
}

eng_context *eng_context_create(const eng_context_def *def, eng_context_status *status,
                                char *err, int err_size)
{
    eng_context_status st_local;
    if (!status) status = &st_local;
    if (err && err_size > 0) err[0] = 0;
    eng_context *ctx = calloc(1, sizeof *ctx);
    if (!ctx) {
        *status = ENG_CONTEXT_NO_GL;
        return NULL;
    }
    ctx->logger = def->logger;
    ctx->mode = def->mode;
    ctx->width = def->width;
    ctx->height = def->height;
    // Debug output in debug builds (def->debug), and whenever SEICHE_GL_DEBUG=1 or the
    // strict mode is asked for (the test suite runs so).
    ctx->debug = def->debug || env_is_1("SEICHE_GL_DEBUG") || eng_gl_strict_requested();
    if (def->width < 16 || def->width > 16384 || def->height < 16 || def->height > 16384) {
        char msg[128];
        snprintf(msg, sizeof msg, "%dx%d", def->width, def->height);
        fail(ctx, err, err_size, "eng_context_def.width/height must be 16..16384 (got %s)", msg);
        *status = ENG_CONTEXT_BAD_ARGUMENT;
        free(ctx);
        return NULL;
    }
    *status = def->mode == ENG_CONTEXT_WINDOW ? create_window(ctx, def, err, err_size)
                                              : create_headless(ctx, def, err, err_size);
    if (*status != ENG_CONTEXT_OK) {
        eng_context_destroy(ctx);
        return NULL;
    }
    ctx->gl_ready = true;
    if (ctx->debug && epoxy_has_gl_extension("GL_KHR_debug")) {
        glEnable(GL_DEBUG_OUTPUT);
        glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
        glDebugMessageCallback(debug_cb, ctx);
    }
    if (eng_gl_strict_requested()) {
        char msg[256];
        if (!eng_gl_strict_install(ctx->window ? glfw_proc : egl_proc, msg, sizeof msg)) {
            fail(ctx, err, err_size, "%s", msg);
            *status = ENG_CONTEXT_NO_GL;
            eng_context_destroy(ctx);
            return NULL;
        }
        eng_log(&ctx->logger, ENG_LOG_INFO, "GL strict mode on (SEICHE_GL_STRICT=1)");
    }
    eng_log(&ctx->logger, ENG_LOG_DEBUG, "GL context: %s via %s", ctx->renderer, ctx->platform);
    return ctx;
}

void eng_context_destroy(eng_context *ctx)
{
    if (!ctx) return;
    bool current = ctx->gl_ready;
    if (current && ctx->debug && epoxy_has_gl_extension("GL_KHR_debug")) glDebugMessageCallback(NULL, NULL);
    if (current) eng_gl_strict_uninstall();
    if (ctx->fbo) {
        glDeleteFramebuffers(1, &ctx->fbo);
        glDeleteRenderbuffers(1, &ctx->color_rb);
        glDeleteRenderbuffers(1, &ctx->depth_rb);
    }
    if (ctx->window) {
        glfwDestroyWindow(ctx->window);
        glfwTerminate();
    }
    if (ctx->egl_display) {
        eglMakeCurrent(ctx->egl_display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        if (ctx->egl_context) eglDestroyContext(ctx->egl_display, ctx->egl_context);
        eglTerminate(ctx->egl_display);
    }
    free(ctx);
}

bool eng_context_is_headless(const eng_context *ctx) { return ctx->mode == ENG_CONTEXT_HEADLESS; }

void eng_context_size(const eng_context *ctx, int *width, int *height)
{
    if (ctx->window) {
        glfwGetFramebufferSize(ctx->window, width, height);
    } else {
        *width = ctx->width;
        *height = ctx->height;
    }
}

unsigned eng_context_framebuffer(const eng_context *ctx) { return ctx->fbo; }

void eng_context_present(eng_context *ctx)
{
    if (ctx->window) glfwSwapBuffers(ctx->window);
}

void eng_context_poll(eng_context *ctx)
{
    if (ctx->window) glfwPollEvents();
}

bool eng_context_should_close(const eng_context *ctx)
{
    return ctx->close_requested || (ctx->window && glfwWindowShouldClose(ctx->window));
}

void eng_context_request_close(eng_context *ctx) { ctx->close_requested = true; }
struct GLFWwindow *eng_context_window(const eng_context *ctx) { return ctx->window; }
const eng_logger *eng_context_logger(const eng_context *ctx) { return &ctx->logger; }
const char *eng_context_renderer(const eng_context *ctx) { return ctx->renderer; }
const char *eng_context_platform(const eng_context *ctx) { return ctx->platform; }
