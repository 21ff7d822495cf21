// seiche-embed: the smallest host of the fluid module, built the way another engine would
// build it: `cc main.c $(pkg-config --cflags --libs seiche-fluid)` against an installed
// Seiche (make install), nothing of Seiche's engine. It makes its own headless GL 4.3
// context with EGL (through libepoxy, which the fluid uses too; any current GL 4.3 context
// will do), creates a fluid world, drops a block of water in a box, steps it, and reads
// the metrics back late. No Lua, no window, no Bullet. docs/embedding.md walks through it.
#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <stdio.h>
#include <string.h>

#include "fluid/pbf.h"

// A headless EGL display: Mesa's surfaceless platform, else the first EGL device (NVIDIA).
static EGLDisplay headless_display(void)
{
    EGLDisplay d = EGL_NO_DISPLAY;
    if (epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_MESA_platform_surfaceless"))
        d = eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    if (d == EGL_NO_DISPLAY && epoxy_has_egl_extension(EGL_NO_DISPLAY, "EGL_EXT_device_enumeration")) {
        EGLDeviceEXT dev[4];
        EGLint n = 0;
        if (eglQueryDevicesEXT(4, dev, &n) && n > 0)
            d = eglGetPlatformDisplayEXT(EGL_PLATFORM_DEVICE_EXT, dev[0], NULL);
    }
    return d;
}

static int make_context(void)
{
    EGLDisplay d = headless_display();
    if (d == EGL_NO_DISPLAY || !eglInitialize(d, NULL, NULL)) return 0;
    if (!eglBindAPI(EGL_OPENGL_API)) return 0;
    const EGLint cfg_attr[] = { EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE };
    EGLConfig cfg;
    EGLint n = 0;
    if (!eglChooseConfig(d, cfg_attr, &cfg, 1, &n)) n = 0;
    const EGLint ctx_attr[] = { EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 3,
                                EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE };
    EGLContext c = eglCreateContext(d, n > 0 ? cfg : EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, ctx_attr);
    return c != EGL_NO_CONTEXT && eglMakeCurrent(d, EGL_NO_SURFACE, EGL_NO_SURFACE, c);
}

int main(void)
{
    if (!make_context()) {
        fprintf(stderr, "seiche-embed: no headless OpenGL 4.3 context (EGL surfaceless or device platform)\n");
        return 3;
    }
    char err[1024];
    pbf_world_def def = pbf_default_world_def();
    def.params.particle_radius = 0.02f;
    def.params.kernel_radius = 0.08f;
    def.max_neighbours = pbf_suggest_max_neighbours(&def.params);
    def.capacity = 4096;
    const float lo[3] = { 0, 0, 0 }, hi[3] = { 0.6f, 0.6f, 0.3f };
    for (int k = 0; k < 3; k++) {
        def.domain_min[k] = lo[k];
        def.domain_max[k] = hi[k];
    }
    pbf_world *w = pbf_world_create(&def, err, sizeof err);
    if (!w) {
        fprintf(stderr, "seiche-embed: %s\n", err);
        return 2;
    }
    pbf_world_set_container(w, lo, hi, false);
    pbf_block_def block = pbf_default_block_def();
    block.max[0] = 0.24f;
    block.max[1] = 0.4f;
    block.max[2] = 0.3f;
    uint32_t added = 0;
    if (pbf_world_add_block(w, &block, &added) != PBF_OK) {
        fprintf(stderr, "seiche-embed: %s\n", pbf_world_last_error(w));
        pbf_world_destroy(w);
        return 2;
    }
    printf("seiche-embed: Seiche %s, %u particles on %s\n", pbf_version(), added,
           (const char *)glGetString(GL_RENDERER));
    for (int frame = 0; frame < 60; frame++) {
        pbf_world_step(w, 1.0f / 60.0f);
        // A host draws here from pbf_world_gpu_buffers(w), after the barrier of its use
        // (pbf.h): no download.
        pbf_step_stats stats[8];
        int n = pbf_world_poll_stats(w, stats, 8, frame == 59);
        for (int i = 0; i < n; i++)
            if (stats[i].step % 20 == 19 || frame == 59)
                printf("step %3llu: rho_avg %.1f rho_max %.1f kg/m^3, %.2f ms GPU\n",
                       (unsigned long long)stats[i].step, (double)stats[i].density_avg,
                       (double)stats[i].density_max, stats[i].step_ms);
    }
    pbf_world_destroy(w);
    return 0;
}
