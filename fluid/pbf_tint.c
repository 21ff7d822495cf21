// Tints: a particle's colour in the w of its position (pbf.h, "tints"), set on the GPU by
// the tint pass (shaders/fluid/tint.comp) for a box, or by an emitter as it pours.
#include "fluid/pbf_internal.h"

#include <math.h>
#include <stddef.h>

/// The most a tint code reaches: 1 + 255 * (65536 + 256 + 1) = 2^24, exact in a float.
#define TINT_LIMIT 16777216.0f

float pbf_tint_encode(const float rgb[3])
{
    uint32_t code = 0;
    for (int c = 0; c < 3; c++) {
        float v = rgb ? rgb[c] : 0.0f;
        v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f; // NaN: 0
        code = code * 256u + (uint32_t)lrintf(v * 255.0f);
    }
    return -(1.0f + (float)code);
}

bool pbf_tint_decode(float w, float rgb[3])
{
    if (!(w <= -1.0f && w >= -TINT_LIMIT)) return false;
    uint32_t code = (uint32_t)lrintf(-w - 1.0f); // exact: an integer below 2^24
    if (rgb) {
        rgb[0] = (float)((code >> 16) & 255u) / 255.0f;
        rgb[1] = (float)((code >> 8) & 255u) / 255.0f;
        rgb[2] = (float)(code & 255u) / 255.0f;
    }
    return true;
}

void pbf_tint_locate(pbf_world *w)
{
    static const char *const names[4] = { "u_box_min", "u_box_max", "u_tint", "u_untint" };
    for (int i = 0; i < 4; i++) w->u_tint[i] = glGetUniformLocation(w->programs[PROG_TINT], names[i]);
}

pbf_result pbf_world_tint_box(pbf_world *w, const float min[3], const float max[3], const float rgb[3])
{
    if (!w) return PBF_ERR_INVALID_ARG;
    if (pbf_refused_in_step(w, "pbf_world_tint_box", "")) return PBF_ERR_INVALID_ARG;
    if (!min || !max)
        return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_tint_box: %s must not be NULL", !min ? "min" : "max");
    for (int c = 0; c < 3; c++) {
        if (!isfinite(min[c]) || !isfinite(max[c]) || !(min[c] <= max[c]))
            return pbf_fail(w, PBF_ERR_INVALID_ARG,
                            "pbf_world_tint_box: the box must be finite with min[%d] <= max[%d] (got %g, %g)", c, c,
                            (double)min[c], (double)max[c]);
        if (rgb && !(rgb[c] >= 0.0f && rgb[c] <= 1.0f))
            return pbf_fail(w, PBF_ERR_INVALID_ARG, "pbf_world_tint_box: rgb[%d] must be in [0, 1] (got %g)", c,
                            (double)rgb[c]);
    }
    if (w->capacity == 0) return PBF_OK;
    pbf_bind_all(w);
    glUseProgram(w->programs[PROG_TINT]);
    glUniform3fv(w->u_tint[0], 1, min);
    glUniform3fv(w->u_tint[1], 1, max);
    glUniform1f(w->u_tint[2], pbf_tint_encode(rgb));
    glUniform1i(w->u_tint[3], rgb ? 0 : 1);
    glDispatchComputeIndirect(offsetof(pbf_gpu_state, groups_x));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    return PBF_OK;
}
