// Looking inside the GPU step, for tests that compare it with the CPU reference stage by
// stage (tests/test_mirror.c): the stage hook, and a storage binding's buffer read back.
#include "fluid/pbf_internal.h"

#include <epoxy/gl.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

void pbf_world_set_stage_hook(pbf_world *w, pbf_stage_hook_fn *fn, void *user)
{
    w->stage_hook = fn;
    w->stage_hook_user = user;
}

// The buffer at storage binding `binding` as the passes see it now.
static GLuint binding_buffer(const pbf_world *w, int binding)
{
    switch (binding) {
    case PBF_B_POS: return w->pos[w->cur_pos];
    case PBF_B_VEL: return w->vel[w->cur_vel];
    case PBF_B_PRED: return w->pred[w->cur_pred];
    case PBF_B_ID: return w->ids[w->cur_ids];
    case PBF_B_POS_OUT: return w->pos[w->cur_pos ^ 1];
    case PBF_B_VEL_OUT: return w->vel[w->cur_vel ^ 1];
    case PBF_B_PRED_OUT: return w->pred[w->cur_pred ^ 1];
    case PBF_B_ID_OUT: return w->ids[w->cur_ids ^ 1];
    case PBF_B_CELL: return w->cell_of;
    case PBF_B_CELL_START: return w->cell_start;
    case PBF_B_CELL_FILL: return w->cell_fill;
    case PBF_B_SORTED: return w->sorted;
    case PBF_B_ORDER: return w->order;
    case PBF_B_LAMBDA: return w->lambda;
    case PBF_B_OMEGA: return w->omega;
    case PBF_B_TENSION: return w->tension;
    case PBF_B_COLLIDERS: return w->colliders;
    case PBF_B_FORCES: return w->forces; // the step's accumulators come first
    case PBF_B_NB_LIST: return w->nb_list;
    case PBF_B_NB_COUNT: return w->nb_count;
    case PBF_B_STATE: return w->state;
    case PBF_B_COLLIDER_DATA: return w->collider_data;
    case PBF_B_LEVEL: return w->level;
    default: return 0;
    }
}

// The neighbour lists are interleaved on the GPU (entry k of particle i at k * capacity + i,
// shaders/fluid/common.glsl nb_index); they come back a row of max_neighbours per particle,
// the CPU reference's layout: `bytes` covers the rows of the first bytes / (4 max) particles.
static pbf_result read_lists(pbf_world *w, size_t bytes, uint32_t *out)
{
    size_t max = w->max_neighbours, cap = w->capacity, n = bytes / 4 / max;
    if (n * max * 4 != bytes || n > cap)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_read_binding: %zu bytes of the neighbour lists is not whole "
                        "rows of %zu entries for at most %zu particles", bytes, max, cap);
    size_t words = (max - 1) * cap + n;
    uint32_t *all = malloc(words * 4);
    if (!all) return pbf_fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_world_read_binding: out of memory (%zu bytes)", words * 4);
    if (!pbf_download(w, w->nb_list, 0, (GLsizeiptr)(words * 4), all)) {
        free(all);
        return pbf_fail(w, PBF_ERR_GL, "pbf_world_read_binding: no read-back buffer of %zu bytes (out of memory?)", words * 4);
    }
    for (size_t i = 0; i < n; i++)
        for (size_t k = 0; k < max; k++) out[i * max + k] = all[k * cap + i];
    free(all);
    return PBF_OK;
}

pbf_result pbf_world_read_binding(pbf_world *w, int binding, size_t bytes, void *out)
{
    GLuint buf = binding_buffer(w, binding);
    if (!buf) return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_read_binding: binding %d has no buffer to read", binding);
    if (bytes == 0) return PBF_OK;
    glBindBuffer(GL_COPY_READ_BUFFER, buf);
    GLint64 size = 0;
    glGetBufferParameteri64v(GL_COPY_READ_BUFFER, GL_BUFFER_SIZE, &size);
    if ((uint64_t)bytes > (uint64_t)size)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_read_binding: %zu bytes asked of binding %d, which holds %lld",
                        bytes, binding, (long long)size);
    if (binding == PBF_B_NB_LIST) return read_lists(w, bytes, out);
    // Through the read-back buffer, after the barrier shader writes need (pbf_download).
    if (!pbf_download(w, buf, 0, (GLsizeiptr)bytes, out))
        return pbf_fail(w, PBF_ERR_GL, "pbf_world_read_binding: no read-back buffer of %zu bytes (out of memory?)", bytes);
    return PBF_OK;
}
