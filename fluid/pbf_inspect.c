// Looking inside the GPU step, for tests that compare it with the CPU reference stage by
// stage (tests/test_mirror.c): the stage hook, and a storage binding's buffer read back.
#include "fluid/pbf_internal.h"

#include <epoxy/gl.h>
#include <stddef.h>
#include <stdint.h>

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
    case PBF_B_NORMAL: return w->normal;
    case PBF_B_COLLIDERS: return w->colliders;
    case PBF_B_FORCES: return w->forces; // the step's accumulators come first
    case PBF_B_NB_LIST: return w->nb_list;
    case PBF_B_NB_COUNT: return w->nb_count;
    case PBF_B_STATE: return w->state;
    case PBF_B_COLLIDER_DATA: return w->collider_data;
    default: return 0;
    }
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
    // Through the read-back buffer, after the barrier shader writes need (pbf_download).
    if (!pbf_download(w, buf, 0, (GLsizeiptr)bytes, out))
        return pbf_fail(w, PBF_ERR_GL, "pbf_world_read_binding: no read-back buffer of %zu bytes (out of memory?)", bytes);
    return PBF_OK;
}
