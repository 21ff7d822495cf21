// seiche-embed: the smallest host of the fluid module. It makes its own GL context (here
// with EGL through the engine's helper, but any current GL 4.3 context will do), creates
// a fluid world, drops a block of water in a box, steps it, and reads the metrics back
// late. No Lua, no window, no Bullet: this is what another engine links.
#include <stdio.h>

#include "engine/gl/context.h"
#include "fluid/pbf.h"

int main(void)
{
    eng_context_def cd = eng_default_context_def();
    cd.mode = ENG_CONTEXT_HEADLESS;
    cd.width = cd.height = 64;
    char err[1024];
    eng_context_status st;
    eng_context *ctx = eng_context_create(&cd, &st, err, sizeof err);
    if (!ctx) return 3;

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
        eng_context_destroy(ctx);
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
        return 2;
    }
    printf("seiche-embed: %u particles on %s\n", added, eng_context_renderer(ctx));
    for (int frame = 0; frame < 60; frame++) {
        pbf_world_step(w, 1.0f / 60.0f);
        // A host draws here from pbf_world_gpu_buffers(w): no download.
        pbf_step_stats stats[8];
        int n = pbf_world_poll_stats(w, stats, 8, frame == 59);
        for (int i = 0; i < n; i++)
            if (stats[i].step % 20 == 19 || frame == 59)
                printf("step %3llu: rho_avg %.1f rho_max %.1f kg/m^3, %.2f ms GPU\n",
                       (unsigned long long)stats[i].step, (double)stats[i].density_avg,
                       (double)stats[i].density_max, stats[i].step_ms);
    }
    pbf_world_destroy(w);
    eng_context_destroy(ctx);
    return 0;
}
