// The strict GL mode (SEICHE_GL_STRICT=1): makes an in-order driver such as Mesa's llvmpipe
// show the ordering bugs that a real GPU driver exposes, and stops the run at the first one.
//
// It sits between Seiche and libepoxy's dispatch (the function pointers every GL call goes
// through) and, like Vulkan's synchronisation validation layer, tracks per buffer the last
// GPU write and the barriers since:
//  - every GPU clear of a buffer (glClearBuffer[Sub]Data) is held back until just before
//    the next dispatch, draw, copy, fence or readback: the order an NVIDIA driver applied
//    when it moved a small buffer to host memory. A CPU upload that follows a clear is then
//    overwritten on llvmpipe as it was on the GPU; the mode also reports it at once;
//  - a dispatch or draw that reads a buffer a shader wrote (storage block, uniform block,
//    indirect command, vertex or index data) without a glMemoryBarrier of the right bit
//    since the write is reported, naming both passes (program labels) and the buffer;
//  - a CPU upload into a buffer with a GPU clear or copy that no fence wait or glFinish has
//    covered, and a CPU upload, readback or copy of a buffer a shader wrote without
//    GL_BUFFER_UPDATE_BARRIER_BIT since, are reported the same way.
// Which storage blocks a program writes is read from its source: a block declared
// `readonly` is only read; any other is taken as written.
//
// libepoxy's dispatch is process-wide, so the mode is too: one context at a time.
// eng_context_create installs it when SEICHE_GL_STRICT=1 (docs/runner.md).
#ifndef ENG_GL_STRICT_H
#define ENG_GL_STRICT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// Exit status of a run stopped by the strict mode or by a GL error the driver reported.
#define ENG_GL_EXIT_STATUS 5

typedef void (*eng_gl_proc)(void);
typedef eng_gl_proc eng_gl_get_proc(const char *name);

/// Receives each hazard found. The default prints "seiche: GL strict: <message>" on stderr
/// and ends the process with ENG_GL_EXIT_STATUS.
typedef void eng_gl_strict_handler(void *user, const char *message);

/// Installs the mode for the current context; `get_proc` resolves the driver's functions
/// (eglGetProcAddress, glfwGetProcAddress). Installing again only keeps it installed.
/// False with a message in `err` if a function could not be resolved.
bool eng_gl_strict_install(eng_gl_get_proc *get_proc, char *err, size_t err_size);
/// Puts libepoxy's dispatch back as it was and forgets what was tracked.
void eng_gl_strict_uninstall(void);
bool eng_gl_strict_installed(void);
/// True when the environment asks for the mode (SEICHE_GL_STRICT=1).
bool eng_gl_strict_requested(void);

/// Replaces the handler (NULL: the default); returns the previous one through the pointers.
void eng_gl_strict_set_handler(eng_gl_strict_handler *handler, void *user,
                               eng_gl_strict_handler **old_handler, void **old_user);
/// Hazards found since installation.
uint64_t eng_gl_strict_hazards(void);

/// Reports a GL failure (a hazard, or a driver error seen through KHR_debug) to the
/// handler; used by the context's debug callback too.
void eng_gl_fail(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

#endif
