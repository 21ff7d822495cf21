// What the GL harnesses (fuzz_pbf_api, fuzz_lua_script) share: one headless GL 4.3 context
// under the strict GL mode with KHR_debug, where any hazard or driver error aborts (so
// libFuzzer keeps the input), and a base fluid world of 2048 particles that stays quiet.
// Header only.
#ifndef SEICHE_FUZZ_GL_H
#define SEICHE_FUZZ_GL_H

#include <stdio.h>
#include <stdlib.h>

#include "engine/gl/context.h"
#include "engine/gl/gl_strict.h"
#include "fluid/pbf.h"
#include "fluid/pbf_internal.h"

static void fuzz_gl_abort(void *user, const char *message)
{
    fprintf(stderr, "%s: GL strict mode / driver: %s\n", (const char *)user, message);
    abort();
}

/// The context (exits with a message when there is none), strict mode on, handler set.
static inline eng_context *fuzz_gl_context(const char *harness)
{
    setenv("SEICHE_GL_STRICT", "1", 0);
    eng_context_def def = eng_default_context_def();
    def.mode = ENG_CONTEXT_HEADLESS;
    def.width = 64;
    def.height = 64;
    def.vsync = false;
    def.debug = true;
    char err[512];
    eng_context_status st;
    eng_context *ctx = eng_context_create(&def, &st, err, (int)sizeof err);
    if (!ctx) {
        fprintf(stderr, "%s: no headless GL 4.3 context: %s\n", harness, err);
        exit(1);
    }
    eng_gl_strict_set_handler(fuzz_gl_abort, (void *)harness, NULL, NULL);
    return ctx;
}

/// The base world (capacity 2048, `log` for its messages); exits with a message on failure.
static inline pbf_world *fuzz_gl_base_world(const char *harness, pbf_log_fn *log, pbf_world_def *def_out)
{
    pbf_world_def d = pbf_default_world_def();
    d.capacity = 2048;
    d.log = log;
    char err[512];
    pbf_world *w = pbf_world_create(&d, err, sizeof err);
    if (!w) {
        fprintf(stderr, "%s: the base world: %s\n", harness, err);
        exit(1);
    }
    if (def_out) *def_out = d;
    return w;
}

/// The base world back as it was: no particles, colliders, emitters, sinks or container,
/// the `first` parameters, and every step's statistics read. The slots are read from the
/// world (fluid/pbf_internal.h) so that ids an input did not keep are removed too.
static inline void fuzz_gl_reset_base(pbf_world *base, const pbf_params *first)
{
    pbf_world_poll_stats(base, NULL, 0, true);
    for (int i = 0; i < PBF_MAX_COLLIDERS; i++)
        if (base->slots[i].used)
            pbf_world_remove_collider(base, (pbf_collider_id){ (uint16_t)(i + 1), base->slots[i].generation });
    for (int i = 0; i < PBF_MAX_EMITTERS; i++)
        if (base->emitters[i].used)
            pbf_world_remove_emitter(base, (pbf_emitter_id){ (uint16_t)(i + 1), base->emitters[i].generation });
    for (int i = 0; i < PBF_MAX_SINKS; i++)
        if (base->sinks[i].used) pbf_world_remove_sink(base, (pbf_sink_id){ (uint16_t)(i + 1), base->sinks[i].generation });
    pbf_world_remove_container(base);
    pbf_world_clear(base); // first: a new particle_radius waits for an empty world
    if (pbf_world_set_params(base, first) != PBF_OK) abort();
}

#endif
