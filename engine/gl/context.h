// The GL context: a GLFW window (X11, works under Xvfb) or a headless EGL context
// (Mesa's surfaceless platform, or the EGL device platform that NVIDIA's driver offers).
// Both are OpenGL 4.3+ core with compute shaders, reached through libepoxy; creation
// fails with ENG_CONTEXT_NO_COMPUTE, and a message saying what was found, otherwise.
#ifndef ENG_CONTEXT_H
#define ENG_CONTEXT_H

#include <stdbool.h>

#include "engine/core/log.h"

typedef struct eng_context eng_context;
struct GLFWwindow;

typedef enum eng_context_mode {
    ENG_CONTEXT_WINDOW = 0, ///< a GLFW window; needs a display
    ENG_CONTEXT_HEADLESS,   ///< EGL without a window; renders to an offscreen framebuffer
} eng_context_mode;

typedef enum eng_context_status {
    ENG_CONTEXT_OK = 0,
    ENG_CONTEXT_NO_DISPLAY,  ///< window mode asked for, but no display could be opened
    ENG_CONTEXT_NO_GL,       ///< no OpenGL context could be created at all
    ENG_CONTEXT_NO_COMPUTE,  ///< a context, but not GL 4.3 with compute shaders
    ENG_CONTEXT_BAD_ARGUMENT,
} eng_context_status;

typedef struct eng_context_def {
    eng_context_mode mode;
    int width, height;     ///< framebuffer size in pixels, 16..16384
    const char *title;     ///< window title
    bool vsync;            ///< window mode only
    bool debug;            ///< a debug context with KHR_debug messages sent to the logger
    eng_logger logger;
} eng_context_def;

eng_context_def eng_default_context_def(void);

/// Creates the context and makes it current. On failure returns NULL and, if `status`
/// is not NULL, the reason; the message has gone to the logger and to `err`.
eng_context *eng_context_create(const eng_context_def *def, eng_context_status *status,
                                char *err, int err_size);
void eng_context_destroy(eng_context *ctx);

/// True when a display is reachable (DISPLAY or WAYLAND_DISPLAY set and a window opens).
bool eng_display_available(void);

bool eng_context_is_headless(const eng_context *ctx);
void eng_context_size(const eng_context *ctx, int *width, int *height);
/// The framebuffer the scene is drawn into: 0 for a window, an offscreen FBO headless.
unsigned eng_context_framebuffer(const eng_context *ctx);
/// Presents the frame (window) and polls events; headless it only finishes nothing.
void eng_context_present(eng_context *ctx);
void eng_context_poll(eng_context *ctx);
bool eng_context_should_close(const eng_context *ctx);
void eng_context_request_close(eng_context *ctx);
/// The GLFW window, or NULL headless (for input handling).
struct GLFWwindow *eng_context_window(const eng_context *ctx);
const eng_logger *eng_context_logger(const eng_context *ctx);
/// "GL_RENDERER (GL_VERSION)", e.g. "llvmpipe (LLVM 15.0.6, 256 bits) (4.5 (Core Profile) Mesa 22.3.6)"
const char *eng_context_renderer(const eng_context *ctx);
/// Which platform gave the context: "glfw-x11", "egl-device", "egl-surfaceless".
const char *eng_context_platform(const eng_context *ctx);

#endif
