// The screen-space water surface (van der Laan, Green & Sainz 2009; Green, GDC 2010; the
// narrow-range filter of Truong & Yuksel 2018). See render_internal.h and
// docs/architecture.md, "Rendering".
//
// After the opaque scene is drawn into the renderer's own target (scene_color +
// scene_depth, the context's size), at `resolution` times that size:
//   0. the scene's depth is copied (blit, nearest) into fluid_ds, so the particles are
//      depth-tested against the scene
//   1. thickness: every particle adds the ray's chord through it (additive, tested
//      against fluid_ds, not writing it)                       -> thick
//   2. depth: sphere impostors, the nearest wins (writes fluid_ds)  -> depth (eye depth, m)
//   3. smoothing along y, then x: the narrow-range filter on the depth, a Gaussian on the
//      thickness                                  -> smooth[0], smooth_thick[0] -> [1], [1]
//   4. composite, full size, into the context's framebuffer: scene colour and depth where
//      there is no water in front, else the shaded water and its depth.
//   5. spray: fast particles with few neighbours, soft white discs blended over it (the
//      fluid's velocity buffer gives speed and density; nothing without it). A compute
//      pass lists them first (spray_cull.comp, splat.c) and only those are drawn.
// With the look's splat = compute, passes 1 and 2 are splat.c's instead (the same textures).
// Passes 1, 2 and 5 draw the particles from the fluid's buffers (eng_render_bind_fluid).
// Every pass writes framebuffer attachments that a later pass samples once that
// framebuffer is no longer bound: GL orders framebuffer writes before later texture
// fetches, so no glMemoryBarrier is needed between them (barriers cover image stores,
// storage buffers and the like: the particle buffers' barrier is in eng_renderer_end).
// No texture is ever sampled while attached to the bound framebuffer.
#include "engine/render/render_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "shaders/render/render_shared.glsl"

bool eng_surface_create(eng_renderer *r, char *err, size_t err_size)
{
    r->smooth_prog = eng_render_build(&r->def, "render/fullscreen.vert", "render/smooth.frag", NULL, "render/smooth",
                                      err, err_size);
    if (!r->smooth_prog) return false;
    r->composite_prog = eng_render_build(&r->def, "render/fullscreen.vert", "render/composite.frag", NULL,
                                         "render/composite", err, err_size);
    if (!r->composite_prog) return false;
    GLuint p = r->smooth_prog;
    r->smooth_step = glGetUniformLocation(p, "u_step");
    r->smooth_world_radius = glGetUniformLocation(p, "u_world_radius");
    r->smooth_px_per_m = glGetUniformLocation(p, "u_px_per_m");
    r->smooth_max_px = glGetUniformLocation(p, "u_max_px");
    r->smooth_range = glGetUniformLocation(p, "u_range");
    p = r->composite_prog;
    r->comp_fluid_size = glGetUniformLocation(p, "u_fluid_size");
    r->comp_layer = glGetUniformLocation(p, "u_layer");
    r->comp_absorption = glGetUniformLocation(p, "u_absorption");
    r->comp_scatter = glGetUniformLocation(p, "u_scatter");
    r->comp_refraction = glGetUniformLocation(p, "u_refraction");
    r->comp_reflection = glGetUniformLocation(p, "u_reflection");
    r->comp_specular = glGetUniformLocation(p, "u_specular");
    r->comp_shininess = glGetUniformLocation(p, "u_shininess");
    r->comp_view_mode = glGetUniformLocation(p, "u_view_mode");
    return true;
}

static void free_targets(surface_targets *s)
{
    GLuint fbos[] = { s->scene_fbo, s->depth_fbo, s->thick_fbo, s->smooth_fbo[0], s->smooth_fbo[1] };
    GLuint tex[] = { s->scene_color, s->scene_depth, s->fluid_ds,        s->depth,          s->thick,
                     s->smooth[0],   s->smooth[1],   s->smooth_thick[0], s->smooth_thick[1], s->tint,
                     s->depth_bits,  s->thick_bits };
    for (size_t i = 0; i < sizeof fbos / sizeof fbos[0]; i++)
        if (fbos[i]) glDeleteFramebuffers(1, &fbos[i]);
    for (size_t i = 0; i < sizeof tex / sizeof tex[0]; i++)
        if (tex[i]) glDeleteTextures(1, &tex[i]);
    memset(s, 0, sizeof *s);
}

void eng_surface_destroy(eng_renderer *r)
{
    if (r->smooth_prog) glDeleteProgram(r->smooth_prog);
    if (r->composite_prog) glDeleteProgram(r->composite_prog);
    free_targets(&r->surf);
}

bool eng_surface_targets(eng_renderer *r, int w, int h)
{
    surface_targets *s = &r->surf;
    float k = r->def.fluid.resolution;
    int fw = (int)lroundf((float)w * k), fh = (int)lroundf((float)h * k);
    if (fw < 1) fw = 1;
    if (fh < 1) fh = 1;
    if (s->scene_fbo && s->width == w && s->height == h && s->fw == fw && s->fh == fh) return true;
    free_targets(s);
    s->width = w, s->height = h, s->fw = fw, s->fh = fh;
    s->scene_color = eng_render_texture(GL_RGBA8, w, h, GL_LINEAR, "eng.surface.scene_color");
    s->scene_depth = eng_render_texture(GL_DEPTH_COMPONENT32F, w, h, GL_NEAREST, "eng.surface.scene_depth");
    s->fluid_ds = eng_render_texture(GL_DEPTH_COMPONENT32F, fw, fh, GL_NEAREST, "eng.surface.fluid_depth_test");
    s->depth = eng_render_texture(GL_R32F, fw, fh, GL_NEAREST, "eng.surface.depth");
    s->thick = eng_render_texture(GL_R16F, fw, fh, GL_LINEAR, "eng.surface.thickness");
    s->smooth[0] = eng_render_texture(GL_R32F, fw, fh, GL_NEAREST, "eng.surface.smooth_y");
    s->smooth[1] = eng_render_texture(GL_R32F, fw, fh, GL_NEAREST, "eng.surface.smoothed");
    s->smooth_thick[0] = eng_render_texture(GL_R16F, fw, fh, GL_LINEAR, "eng.surface.thickness_y");
    s->smooth_thick[1] = eng_render_texture(GL_R16F, fw, fh, GL_LINEAR, "eng.surface.thickness_smoothed");
    s->scene_fbo = eng_render_framebuffer(&s->scene_color, 1, s->scene_depth, "eng.surface.scene_fbo");
    s->depth_fbo = eng_render_framebuffer(&s->depth, 1, s->fluid_ds, "eng.surface.depth_fbo");
    s->tint = eng_render_texture(GL_RGBA16F, fw, fh, GL_LINEAR, "eng.surface.tint");
    const GLuint thick_tint[2] = { s->thick, s->tint };
    s->thick_fbo = eng_render_framebuffer(thick_tint, 2, s->fluid_ds, "eng.surface.thickness_fbo");
    for (int i = 0; i < 2; i++) {
        const GLuint both[2] = { s->smooth[i], s->smooth_thick[i] };
        s->smooth_fbo[i] = eng_render_framebuffer(both, 2, 0, i == 0 ? "eng.surface.smooth_y_fbo" : "eng.surface.smoothed_fbo");
    }
    if (!s->scene_fbo || !s->depth_fbo || !s->thick_fbo || !s->smooth_fbo[0] || !s->smooth_fbo[1]) {
        eng_log(&r->def.logger, ENG_LOG_ERROR,
                "renderer: the surface targets (%dx%d, water %dx%d) could not be made; drawing spheres", w, h, fw, fh);
        free_targets(s);
        return false;
    }
    return true;
}

static void bind_texture(GLuint unit, GLuint tex)
{
    glActiveTexture(GL_TEXTURE0 + unit);
    glBindTexture(GL_TEXTURE_2D, tex);
    glActiveTexture(GL_TEXTURE0);
}

// Draws every queued fluid with particle program `p` into the bound framebuffer.
static void draw_fluids(eng_renderer *r, const particle_prog *p)
{
    glUseProgram(p->prog);
    glBindVertexArray(r->empty_vao);
    for (int i = 0; i < r->fluid_count; i++) {
        eng_render_bind_fluid(p, &r->fluids[i]);
        eng_render_draw_fluid_instances(&r->fluids[i]);
    }
    glBindVertexArray(0);
}

static void pass_thickness(eng_renderer *r)
{
    surface_targets *s = &r->surf;
    int t = eng_render_timer_begin(r, "surface_thickness");
    glBindFramebuffer(GL_READ_FRAMEBUFFER, s->scene_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, s->thick_fbo);
    glBlitFramebuffer(0, 0, s->width, s->height, 0, 0, s->fw, s->fh, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, s->thick_fbo);
    glViewport(0, 0, s->fw, s->fh);
    const float zero[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
    glClearBufferfv(GL_COLOR, 0, zero);
    glClearBufferfv(GL_COLOR, 1, zero);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_ONE, GL_ONE);
    draw_fluids(r, &r->fluid_thick);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    eng_render_timer_end(r, t);
}

static void pass_depth(eng_renderer *r)
{
    surface_targets *s = &r->surf;
    int t = eng_render_timer_begin(r, "surface_depth");
    glBindFramebuffer(GL_FRAMEBUFFER, s->depth_fbo);
    glViewport(0, 0, s->fw, s->fh);
    const float zero[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
    glClearBufferfv(GL_COLOR, 0, zero); // the depth attachment keeps the scene's depth
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    draw_fluids(r, &r->fluid_depth);
    eng_render_timer_end(r, t);
}

// Smooths the depth and the thickness; `out` receives the textures that hold them.
static void pass_smooth(eng_renderer *r, float radius, GLuint out[2])
{
    surface_targets *s = &r->surf;
    const eng_fluid_look *k = &r->def.fluid;
    out[0] = s->depth;
    out[1] = s->thick;
    if (!(k->smoothing > 0.0f)) return;
    int t = eng_render_timer_begin(r, "surface_smooth");
    mat4 proj;
    eng_camera_projection(&r->cam, r->aspect, proj);
    float world_radius = k->smoothing * radius;
    int max_px = (int)lroundf(0.06f * (float)s->fh);
    if (max_px < 2) max_px = 2;
    if (max_px > 64) max_px = 64;
    glDisable(GL_DEPTH_TEST);
    glUseProgram(r->smooth_prog);
    glUniform1f(r->smooth_world_radius, world_radius);
    glUniform1f(r->smooth_px_per_m, 0.5f * (float)s->fh * proj[1][1]);
    glUniform1i(r->smooth_max_px, max_px);
    glUniform1f(r->smooth_range, 6.0f * radius); // the narrow range: three particle spacings
    glBindVertexArray(r->empty_vao);
    glViewport(0, 0, s->fw, s->fh);
    const GLuint src[2][2] = { { s->depth, s->thick }, { s->smooth[0], s->smooth_thick[0] } };
    for (int i = 0; i < 2; i++) {
        glBindFramebuffer(GL_FRAMEBUFFER, s->smooth_fbo[i]);
        bind_texture(ENG_RENDER_TEX_FLUID_DEPTH, src[i][0]);
        bind_texture(ENG_RENDER_TEX_FLUID_THICK, src[i][1]);
        glUniform2i(r->smooth_step, i == 0 ? 0 : 1, i == 0 ? 1 : 0); // y, then x (smooth.frag)
        glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    bind_texture(ENG_RENDER_TEX_FLUID_DEPTH, 0);
    bind_texture(ENG_RENDER_TEX_FLUID_THICK, 0);
    glBindVertexArray(0);
    eng_render_timer_end(r, t);
    out[0] = s->smooth[1];
    out[1] = s->smooth_thick[1];
}

static void pass_composite(eng_renderer *r, const GLuint smoothed[2], float radius)
{
    surface_targets *s = &r->surf;
    const eng_fluid_look *k = &r->def.fluid;
    int t = eng_render_timer_begin(r, "surface_composite");
    glBindFramebuffer(GL_FRAMEBUFFER, eng_context_framebuffer(r->ctx));
    glViewport(0, 0, s->width, s->height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    bind_texture(ENG_RENDER_TEX_SCENE_COLOR, s->scene_color);
    bind_texture(ENG_RENDER_TEX_SCENE_DEPTH, s->scene_depth);
    bind_texture(ENG_RENDER_TEX_FLUID_DEPTH, smoothed[0]);
    bind_texture(ENG_RENDER_TEX_FLUID_THICK, smoothed[1]);
    bind_texture(ENG_RENDER_TEX_FLUID_TINT, s->tint);
    glUseProgram(r->composite_prog);
    glUniform2f(r->comp_fluid_size, (float)s->fw, (float)s->fh);
    glUniform1f(r->comp_layer, 6.0f * radius);
    glUniform3fv(r->comp_absorption, 1, k->absorption);
    glUniform3fv(r->comp_scatter, 1, k->scatter);
    glUniform1f(r->comp_refraction, k->refraction);
    glUniform1f(r->comp_reflection, k->reflection);
    glUniform1f(r->comp_specular, k->specular);
    glUniform1f(r->comp_shininess, k->shininess);
    glUniform1i(r->comp_view_mode, (GLint)k->view);
    glBindVertexArray(r->empty_vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glDepthFunc(GL_LESS);
    eng_render_timer_end(r, t);
}

// Spray over the composite, into the context's framebuffer: depth-tested against the
// water's and the scene's depth, not written; blended over.
static void pass_spray(eng_renderer *r)
{
    const eng_fluid_look *k = &r->def.fluid;
    bool any = false;
    for (int i = 0; i < r->fluid_count; i++) any = any || r->fluids[i].d.velocities;
    if (!(k->spray > 0.0f) || !any) return;
    int t = eng_render_timer_begin(r, "surface_spray");
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    glBlendEquation(GL_FUNC_ADD);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    const particle_prog *p = &r->fluid_spray;
    glBindVertexArray(r->empty_vao);
    for (int i = 0; i < r->fluid_count; i++) {
        const queued_fluid *f = &r->fluids[i];
        if (!f->d.velocities || !eng_spray_cull(r, f)) continue;
        // Only the drops the cull listed: instance k draws spray_list[k].
        glUseProgram(p->prog);
        glUniform1f(p->spray, k->spray);
        eng_render_bind_fluid(p, f);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_SPRAY_LIST_BINDING, r->spray_list);
        glBindBuffer(GL_DRAW_INDIRECT_BUFFER, r->spray_cmd);
        glDrawArraysIndirect(GL_TRIANGLE_STRIP, (const void *)0);
    }
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    eng_render_timer_end(r, t);
}

void eng_surface_render(eng_renderer *r)
{
    // One radius sizes the filter: the first fluid's (fluids of other sizes still draw).
    float radius = r->fluids[0].d.radius;
    // Compute splats where the look asks for them; the raster passes where it does not, or
    // (logged as an error) where their images could not be made.
    if (r->def.fluid.splat != ENG_FLUID_SPLAT_COMPUTE || !eng_splat_surface(r)) {
        pass_thickness(r);
        pass_depth(r);
    }
    GLuint smoothed[2];
    pass_smooth(r, radius, smoothed);
    pass_composite(r, smoothed, radius);
    pass_spray(r);
}
