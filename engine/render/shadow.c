// The light's shadow map. See render_internal.h.
//
// An orthographic view along the light direction covers the shadow bounds (a sphere
// around the box, so that any light direction fits). One pass, one framebuffer of three
// textures at shadow_size^2:
//   depth  D32F   the opaque casters (scene nodes and queued meshes; the ground only
//                 receives), slope-scaled polygon offset against acne
//   front  R32F   the nearest water from the light, m past the near plane (MIN blending)
//   thick  R16F   the water crossed along each light ray, m (additive)
// The water is drawn after the casters, depth-tested against them and not writing depth.
// Receivers (frame.glsl, light_visibility) take 3x3 PCF of the depth and the Beer-Lambert
// transmittance of min(their depth past the water's front, the thickness).
// Synchronisation: the three textures are written as framebuffer attachments and sampled
// by later draws after the framebuffer is unbound; GL orders that without a barrier. The
// particle buffers' barrier (storage + command) is issued once in eng_renderer_end.
#include "engine/render/render_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "shaders/render/render_shared.glsl"

static const float far_away = (float)ENG_RENDER_SPLAT_FAR; // the front's clear value: no water on that ray

bool eng_shadow_create(eng_renderer *r, char *err, size_t err_size)
{
    shadow_map *s = &r->shadow;
    s->size = r->def.shadow_size;
    s->depth = eng_render_texture(GL_DEPTH_COMPONENT32F, s->size, s->size, GL_LINEAR, "eng.shadow.depth");
    s->front = eng_render_texture(GL_R32F, s->size, s->size, GL_LINEAR, "eng.shadow.front");
    s->thick = eng_render_texture(GL_R16F, s->size, s->size, GL_LINEAR, "eng.shadow.thickness");
    // Outside the map: lit, no water.
    const float one[4] = { 1.0f, 1.0f, 1.0f, 1.0f }, far4[4] = { far_away, far_away, far_away, far_away },
                zero[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
    const GLuint tex[3] = { s->depth, s->front, s->thick };
    const float *border[3] = { one, far4, zero };
    for (int i = 0; i < 3; i++) {
        glBindTexture(GL_TEXTURE_2D, tex[i]);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
        glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, border[i]);
    }
    glBindTexture(GL_TEXTURE_2D, s->depth);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    glBindTexture(GL_TEXTURE_2D, 0);
    const GLuint colors[2] = { s->front, s->thick };
    s->fbo = eng_render_framebuffer(colors, 2, s->depth, "eng.shadow.fbo");
    if (!s->fbo) {
        const char *msg = "renderer: the shadow map's framebuffer is incomplete (D32F + R32F + R16F)";
        eng_log(&r->def.logger, ENG_LOG_ERROR, "%s", msg);
        if (err && err_size > 0) snprintf(err, err_size, "%s", msg);
        return false;
    }
    glm_mat4_identity(s->view);
    glm_mat4_identity(s->proj);
    glm_mat4_identity(s->viewproj);
    s->range = 1.0f;
    return true;
}

void eng_shadow_destroy(eng_renderer *r)
{
    shadow_map *s = &r->shadow;
    if (s->fbo) glDeleteFramebuffers(1, &s->fbo);
    GLuint tex[4] = { s->depth, s->front, s->thick, s->bits };
    for (int i = 0; i < 4; i++)
        if (tex[i]) glDeleteTextures(1, &tex[i]);
}

void eng_shadow_prepare(eng_renderer *r)
{
    shadow_map *s = &r->shadow;
    vec3 center, half, l;
    for (int k = 0; k < 3; k++) {
        center[k] = 0.5f * (s->lo[k] + s->hi[k]);
        half[k] = 0.5f * (s->hi[k] - s->lo[k]);
        l[k] = r->def.light.direction[k];
    }
    glm_vec3_normalize(l);
    float radius = glm_vec3_norm(half) * 1.02f;
    vec3 eye, up = { 0.0f, 1.0f, 0.0f };
    if (fabsf(l[1]) > 0.99f) up[1] = 0.0f, up[2] = 1.0f;
    glm_vec3_scale(l, 2.0f * radius, eye);
    glm_vec3_add(center, eye, eye);
    glm_lookat(eye, center, up, s->view);
    s->near_plane = radius;
    s->range = 2.0f * radius;
    glm_ortho(-radius, radius, -radius, radius, s->near_plane, s->near_plane + s->range, s->proj);
    glm_mat4_mul(s->proj, s->view, s->viewproj);
}

static void bind_maps(const shadow_map *s, bool bind)
{
    const GLuint units[3] = { ENG_RENDER_TEX_SHADOW, ENG_RENDER_TEX_SHADOW_FRONT, ENG_RENDER_TEX_SHADOW_THICK };
    const GLuint tex[3] = { s->depth, s->front, s->thick };
    for (int i = 0; i < 3; i++) {
        glActiveTexture(GL_TEXTURE0 + units[i]);
        glBindTexture(GL_TEXTURE_2D, bind ? tex[i] : 0);
    }
    glActiveTexture(GL_TEXTURE0);
}

void eng_shadow_render(eng_renderer *r)
{
    shadow_map *s = &r->shadow;
    bind_maps(s, false); // never sampled while they are attachments
    if (!r->def.fluid.shadows) {
        bind_maps(s, true); // still complete textures for the samplers that skip them
        return;
    }
    int t = eng_render_timer_begin(r, "shadow");
    glBindFramebuffer(GL_FRAMEBUFFER, s->fbo);
    glViewport(0, 0, s->size, s->size);
    const GLenum none[2] = { GL_NONE, GL_NONE }, both[2] = { GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1 };
    glDrawBuffers(2, both);
    const float depth_one = 1.0f, front_clear[4] = { far_away, 0.0f, 0.0f, 0.0f }, zero[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
    glDepthMask(GL_TRUE);
    glClearBufferfv(GL_DEPTH, 0, &depth_one);
    glClearBufferfv(GL_COLOR, 0, front_clear);
    glClearBufferfv(GL_COLOR, 1, zero);

    // Opaque casters: depth only.
    glDrawBuffers(2, none);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(2.0f, 4.0f);
    glUseProgram(r->mesh_shadow.prog);
    eng_render_draw_queued_meshes(r, &r->mesh_shadow);
    glDisable(GL_POLYGON_OFFSET_FILL);

    // The water: nearest distance (MIN) and thickness (ADD), behind no caster; by compute
    // splats where the look asks for them (the raster draw below if their images could not
    // be made, logged).
    bool splatted = false;
    if (r->fluid_count > 0 && r->def.fluid.splat == ENG_FLUID_SPLAT_COMPUTE) {
        glBindFramebuffer(GL_FRAMEBUFFER, 0); // the casters' depth is sampled: attached to nothing bound
        splatted = eng_splat_shadow(r);
        if (!splatted) glBindFramebuffer(GL_FRAMEBUFFER, s->fbo);
    }
    if (r->fluid_count > 0 && !splatted) {
        glDrawBuffers(2, both);
        glDepthMask(GL_FALSE);
        glEnablei(GL_BLEND, 0);
        glEnablei(GL_BLEND, 1);
        glBlendEquationi(0, GL_MIN);
        glBlendEquationi(1, GL_FUNC_ADD);
        glBlendFunci(0, GL_ONE, GL_ONE);
        glBlendFunci(1, GL_ONE, GL_ONE);
        const particle_prog *p = &r->fluid_shadow;
        glUseProgram(p->prog);
        glUniformMatrix4fv(p->light_view, 1, GL_FALSE, (const float *)s->view);
        glUniformMatrix4fv(p->light_proj, 1, GL_FALSE, (const float *)s->proj);
        glUniform1f(p->light_near, s->near_plane);
        glBindVertexArray(r->empty_vao);
        for (int i = 0; i < r->fluid_count; i++) {
            eng_render_bind_fluid(p, &r->fluids[i]);
            eng_render_draw_fluid_instances(&r->fluids[i]);
        }
        glBindVertexArray(0);
        glDisablei(GL_BLEND, 0);
        glDisablei(GL_BLEND, 1);
        glBlendEquation(GL_FUNC_ADD);
        glDepthMask(GL_TRUE);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    eng_render_timer_end(r, t);
    bind_maps(s, true);
}
