// Forward renderer: scene meshes, ground, particle impostors. See renderer.h.
#include "engine/render/renderer.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

#include "fluid/pbf_glsl.h"
#include "shaders/render/render_shared.glsl"

// Mirror of the std140 block `Frame` in shaders/render/frame.glsl.
typedef struct eng_frame_block {
    float view[16];
    float proj[16];
    float inv_view[16];
    float camera_pos[4];
    float light_dir[4];
    float light_color[4];
    float ambient[4];
    float sky_color[4];
    float fog[4];
} eng_frame_block;
_Static_assert(sizeof(eng_frame_block) == 3 * 64 + 6 * 16, "eng_frame_block must match the std140 block Frame");

typedef struct mesh_pass {
    GLuint prog;
    GLint model, normal_model, color, specular, shininess, checker_cell;
} mesh_pass;

typedef struct particle_pass {
    GLuint prog;
    GLuint vao; // empty: the vertex shader reads the SSBO
    GLint radius, count, color_low, color_mid, color_high, specular, shininess;
} particle_pass;

struct eng_renderer {
    eng_renderer_def def;
    mesh_pass mesh;
    particle_pass particles;
    GLuint frame_ubo;
    eng_mesh_store *own_meshes; // the ground plane
    eng_mesh_id ground;
    eng_gpu_timer *timer;
    // Per frame.
    bool in_frame;
    eng_context *ctx;
    eng_camera cam;
    float aspect;
    int t_frame;
    bool warned_stale_mesh;
};

eng_renderer_def eng_default_renderer_def(void)
{
    eng_renderer_def d;
    memset(&d, 0, sizeof d);
    d.shader_dir = NULL;
    d.logger = eng_default_logger();
    d.sky_color[0] = 0.62f, d.sky_color[1] = 0.76f, d.sky_color[2] = 0.90f;
    d.light.direction[0] = 0.35f, d.light.direction[1] = 0.85f, d.light.direction[2] = 0.40f;
    d.light.color[0] = 0.95f, d.light.color[1] = 0.92f, d.light.color[2] = 0.85f;
    d.light.ambient[0] = 0.28f, d.light.ambient[1] = 0.30f, d.light.ambient[2] = 0.34f;
    d.specular = 0.25f;
    d.shininess = 32.0f;
    d.ground = true;
    d.ground_height = 0.0f;
    d.ground_size = 200.0f;
    d.ground_cell = 1.0f;
    d.ground_color[0] = 0.58f, d.ground_color[1] = 0.58f, d.ground_color[2] = 0.56f;
    d.fog_start = 40.0f;
    d.fog_end = 100.0f;
    return d;
}

eng_particle_style eng_default_particle_style(void)
{
    eng_particle_style s = {
        .color_low = { 0.04f, 0.22f, 0.62f },
        .color_mid = { 0.10f, 0.66f, 0.86f },
        .color_high = { 0.86f, 0.96f, 1.00f },
        .specular = 0.6f,
        .shininess = 64.0f,
    };
    return s;
}

// ---- input checks ------------------------------------------------------------------

static bool fail(const eng_logger *log, char *err, size_t err_size, const char *fmt, const char *field, double got)
{
    char msg[256];
    snprintf(msg, sizeof msg, fmt, field, got);
    eng_log(log, ENG_LOG_ERROR, "%s", msg);
    if (err && err_size > 0) snprintf(err, err_size, "%s", msg);
    return false;
}

static bool check_rgb(const eng_logger *log, char *err, size_t err_size, const char *field, const float c[3], float hi)
{
    for (int k = 0; k < 3; k++) {
        if (!(c[k] >= 0.0f && c[k] <= hi)) {
            char f[96];
            snprintf(f, sizeof f, "%.80s[%d]", field, k);
            return fail(log, err, err_size, hi > 1.0f ? "%s must be 0..4 (got %g)" : "%s must be 0..1 (got %g)", f,
                        (double)c[k]);
        }
    }
    return true;
}

static bool check_light(const eng_logger *log, char *err, size_t err_size, const char *field, const eng_light *l)
{
    const float *d = l->direction;
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    char f[96];
    snprintf(f, sizeof f, "%s.direction", field);
    if (!(len > 1e-6f) || !isfinite(len))
        return fail(log, err, err_size, "%s must be a finite non-zero vector (got length %g)", f, (double)len);
    snprintf(f, sizeof f, "%s.color", field);
    if (!check_rgb(log, err, err_size, f, l->color, 4.0f)) return false;
    snprintf(f, sizeof f, "%s.ambient", field);
    return check_rgb(log, err, err_size, f, l->ambient, 1.0f);
}

static bool check_def(const eng_renderer_def *d, char *err, size_t err_size)
{
    const eng_logger *log = &d->logger;
    if (d->shader_dir && !d->shader_dir[0]) {
        const char *msg = "eng_renderer_def.shader_dir must be NULL (the embedded shaders) or name the shader "
                          "directory (got \"\")";
        eng_log(log, ENG_LOG_ERROR, "%s", msg);
        if (err && err_size > 0) snprintf(err, err_size, "%s", msg);
        return false;
    }
    if (!check_rgb(log, err, err_size, "eng_renderer_def.sky_color", d->sky_color, 1.0f)) return false;
    if (!check_light(log, err, err_size, "eng_renderer_def.light", &d->light)) return false;
    if (!(d->specular >= 0.0f && d->specular <= 1.0f))
        return fail(log, err, err_size, "%s must be 0..1 (got %g)", "eng_renderer_def.specular", (double)d->specular);
    if (!(d->shininess >= 1.0f && d->shininess <= 1024.0f))
        return fail(log, err, err_size, "%s must be 1..1024 (got %g)", "eng_renderer_def.shininess",
                    (double)d->shininess);
    if (!isfinite(d->ground_height))
        return fail(log, err, err_size, "%s must be finite m (got %g)", "eng_renderer_def.ground_height",
                    (double)d->ground_height);
    if (!(d->ground_size > 0.0f && isfinite(d->ground_size)))
        return fail(log, err, err_size, "%s must be > 0 m (got %g)", "eng_renderer_def.ground_size",
                    (double)d->ground_size);
    if (!(d->ground_cell > 0.0f && isfinite(d->ground_cell)))
        return fail(log, err, err_size, "%s must be > 0 m (got %g)", "eng_renderer_def.ground_cell",
                    (double)d->ground_cell);
    if (!check_rgb(log, err, err_size, "eng_renderer_def.ground_color", d->ground_color, 1.0f)) return false;
    if (!(d->fog_start >= 0.0f && isfinite(d->fog_start)))
        return fail(log, err, err_size, "%s must be >= 0 m (got %g)", "eng_renderer_def.fog_start",
                    (double)d->fog_start);
    if (!(d->fog_end > d->fog_start && isfinite(d->fog_end)))
        return fail(log, err, err_size, "%s must be > fog_start (m) (got %g)", "eng_renderer_def.fog_end",
                    (double)d->fog_end);
    return true;
}

static bool check_style(const eng_logger *log, const eng_particle_style *s)
{
    if (!check_rgb(log, NULL, 0, "eng_particle_style.color_low", s->color_low, 1.0f)) return false;
    if (!check_rgb(log, NULL, 0, "eng_particle_style.color_mid", s->color_mid, 1.0f)) return false;
    if (!check_rgb(log, NULL, 0, "eng_particle_style.color_high", s->color_high, 1.0f)) return false;
    if (!(s->specular >= 0.0f && s->specular <= 1.0f))
        return fail(log, NULL, 0, "%s must be 0..1 (got %g)", "eng_particle_style.specular", (double)s->specular);
    if (!(s->shininess >= 1.0f && s->shininess <= 1024.0f))
        return fail(log, NULL, 0, "%s must be 1..1024 (got %g)", "eng_particle_style.shininess", (double)s->shininess);
    return true;
}

// ---- creation ----------------------------------------------------------------------

static GLuint build(const eng_renderer_def *d, const char *vert, const char *frag, char *err, size_t err_size)
{
    pbf_glsl_stage stages[2] = { { GL_VERTEX_SHADER, vert }, { GL_FRAGMENT_SHADER, frag } };
    char msg[4096];
    pbf_glsl_source src = eng_render_sources();
    if (d->shader_dir) src.dir = d->shader_dir;
    GLuint prog = pbf_glsl_build_from(&src, stages, 2, NULL, msg, sizeof msg);
    if (!prog) {
        eng_log(&d->logger, ENG_LOG_ERROR, "renderer: %s", msg);
        if (err && err_size > 0) snprintf(err, err_size, "%s", msg);
    }
    return prog;
}

eng_renderer *eng_renderer_create(const eng_renderer_def *def, char *err, size_t err_size)
{
    if (err && err_size > 0) err[0] = 0;
    if (!check_def(def, err, err_size)) return NULL;
    GLint vertex_ssbos = 0;
    glGetIntegerv(GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS, &vertex_ssbos);
    if (vertex_ssbos < 1) {
        fail(&def->logger, err, err_size, "%s: GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS is %g; particle impostors need 1",
             "renderer", (double)vertex_ssbos);
        return NULL;
    }
    eng_renderer *r = calloc(1, sizeof *r);
    if (!r) return NULL;
    r->def = *def;
    r->t_frame = -1;

    r->mesh.prog = build(def, "render/mesh.vert", "render/mesh.frag", err, err_size);
    if (r->mesh.prog) r->particles.prog = build(def, "render/particles.vert", "render/particles.frag", err, err_size);
    if (!r->mesh.prog || !r->particles.prog) {
        eng_renderer_destroy(r);
        return NULL;
    }
    GLuint p = r->mesh.prog;
    r->mesh.model = glGetUniformLocation(p, "u_model");
    r->mesh.normal_model = glGetUniformLocation(p, "u_normal_model");
    r->mesh.color = glGetUniformLocation(p, "u_color");
    r->mesh.specular = glGetUniformLocation(p, "u_specular");
    r->mesh.shininess = glGetUniformLocation(p, "u_shininess");
    r->mesh.checker_cell = glGetUniformLocation(p, "u_checker_cell");
    p = r->particles.prog;
    r->particles.radius = glGetUniformLocation(p, "u_radius");
    r->particles.count = glGetUniformLocation(p, "u_count");
    r->particles.color_low = glGetUniformLocation(p, "u_color_low");
    r->particles.color_mid = glGetUniformLocation(p, "u_color_mid");
    r->particles.color_high = glGetUniformLocation(p, "u_color_high");
    r->particles.specular = glGetUniformLocation(p, "u_specular");
    r->particles.shininess = glGetUniformLocation(p, "u_shininess");
    glGenVertexArrays(1, &r->particles.vao);
    glBindVertexArray(r->particles.vao);
    glObjectLabel(GL_VERTEX_ARRAY, r->particles.vao, -1, "eng.particles_vao");
    glBindVertexArray(0);

    glGenBuffers(1, &r->frame_ubo);
    glBindBuffer(GL_UNIFORM_BUFFER, r->frame_ubo);
    glBufferData(GL_UNIFORM_BUFFER, sizeof(eng_frame_block), NULL, GL_DYNAMIC_DRAW);
    glObjectLabel(GL_BUFFER, r->frame_ubo, -1, "eng.frame_ubo");
    glBindBuffer(GL_UNIFORM_BUFFER, 0);

    eng_mesh_store_def md = eng_default_mesh_store_def();
    md.max_meshes = 4;
    md.logger = def->logger;
    r->own_meshes = eng_mesh_store_create(&md);
    if (r->own_meshes) r->ground = eng_mesh_create_plane(r->own_meshes, def->ground_size, def->ground_size);

    eng_gpu_timer_def td = eng_default_gpu_timer_def();
    td.max_sections = 16;
    td.logger = def->logger;
    r->timer = eng_gpu_timer_create(&td);
    if (!r->own_meshes || !eng_mesh_is_valid(r->own_meshes, r->ground) || !r->timer) {
        if (err && err_size > 0) snprintf(err, err_size, "renderer: out of memory");
        eng_renderer_destroy(r);
        return NULL;
    }
    return r;
}

void eng_renderer_destroy(eng_renderer *r)
{
    if (!r) return;
    if (r->mesh.prog) glDeleteProgram(r->mesh.prog);
    if (r->particles.prog) glDeleteProgram(r->particles.prog);
    if (r->particles.vao) glDeleteVertexArrays(1, &r->particles.vao);
    if (r->frame_ubo) glDeleteBuffers(1, &r->frame_ubo);
    eng_mesh_store_destroy(r->own_meshes);
    eng_gpu_timer_destroy(r->timer);
    free(r);
}

eng_gpu_timer *eng_renderer_gpu_timer(eng_renderer *r) { return r->timer; }

bool eng_renderer_set_light(eng_renderer *r, const eng_light *light)
{
    if (!check_light(&r->def.logger, NULL, 0, "light", light)) return false;
    r->def.light = *light;
    return true;
}

bool eng_renderer_set_sky(eng_renderer *r, const float sky_color[3])
{
    if (!check_rgb(&r->def.logger, NULL, 0, "sky_color", sky_color, 1.0f)) return false;
    memcpy(r->def.sky_color, sky_color, sizeof r->def.sky_color);
    return true;
}

// ---- a frame -----------------------------------------------------------------------

static void write_frame(eng_renderer *r, const eng_camera *cam)
{
    eng_frame_block b;
    memset(&b, 0, sizeof b);
    mat4 view, proj, inv;
    eng_camera_view(cam, view);
    eng_camera_projection(cam, r->aspect, proj);
    glm_mat4_inv(view, inv);
    memcpy(b.view, view, sizeof b.view);
    memcpy(b.proj, proj, sizeof b.proj);
    memcpy(b.inv_view, inv, sizeof b.inv_view);
    memcpy(b.camera_pos, cam->position, 3 * sizeof(float));
    const float *d = r->def.light.direction;
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++) b.light_dir[k] = d[k] / len;
    memcpy(b.light_color, r->def.light.color, 3 * sizeof(float));
    memcpy(b.ambient, r->def.light.ambient, 3 * sizeof(float));
    memcpy(b.sky_color, r->def.sky_color, 3 * sizeof(float));
    b.fog[0] = r->def.fog_start;
    b.fog[1] = r->def.fog_end;
    glBindBuffer(GL_UNIFORM_BUFFER, r->frame_ubo);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof b, &b);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    glBindBufferBase(GL_UNIFORM_BUFFER, ENG_RENDER_FRAME_UBO_BINDING, r->frame_ubo);
}

static void draw_gpu_mesh(eng_renderer *r, const eng_mesh_gpu *g, mat4 model, const float color[3],
                          float checker_cell)
{
    mat3 m3, inv;
    glm_mat4_pick3(model, m3);
    glm_mat3_inv(m3, inv);
    glm_mat3_transpose(inv);
    glUniformMatrix4fv(r->mesh.model, 1, GL_FALSE, (const float *)model);
    glUniformMatrix3fv(r->mesh.normal_model, 1, GL_FALSE, (const float *)inv);
    glUniform3fv(r->mesh.color, 1, color);
    glUniform1f(r->mesh.checker_cell, checker_cell);
    glBindVertexArray(g->vao);
    glDrawElements(GL_TRIANGLES, g->index_count, GL_UNSIGNED_INT, (const void *)0);
}

static void use_mesh_pass(eng_renderer *r)
{
    glUseProgram(r->mesh.prog);
    glUniform1f(r->mesh.specular, r->def.specular);
    glUniform1f(r->mesh.shininess, r->def.shininess);
}

static bool in_frame(eng_renderer *r, const char *fn)
{
    if (r->in_frame) return true;
    eng_log(&r->def.logger, ENG_LOG_ERROR, "%s: must be called between eng_renderer_begin and eng_renderer_end", fn);
    return false;
}

void eng_renderer_begin(eng_renderer *r, eng_context *ctx, const eng_camera *cam)
{
    if (r->in_frame) {
        eng_log(&r->def.logger, ENG_LOG_ERROR, "eng_renderer_begin: the previous frame was not ended; ending it");
        eng_renderer_end(r);
    }
    if (!ctx || !cam) {
        eng_log(&r->def.logger, ENG_LOG_ERROR, "eng_renderer_begin: %s must not be NULL", !ctx ? "ctx" : "cam");
        return;
    }
    int w, h;
    eng_context_size(ctx, &w, &h);
    if (w < 1 || h < 1) return; // a minimised window: nothing to draw into
    r->in_frame = true;
    r->ctx = ctx;
    r->cam = *cam;
    r->aspect = (float)w / (float)h;
    r->warned_stale_mesh = false;
    r->t_frame = eng_gpu_timer_begin(r->timer, "frame");

    glBindFramebuffer(GL_FRAMEBUFFER, eng_context_framebuffer(ctx));
    glViewport(0, 0, w, h);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearColor(r->def.sky_color[0], r->def.sky_color[1], r->def.sky_color[2], 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    write_frame(r, cam);

    if (r->def.ground) {
        use_mesh_pass(r);
        mat4 model;
        glm_translate_make(model, (vec3){ 0.0f, r->def.ground_height, 0.0f });
        glUniform1f(r->mesh.specular, 0.05f);
        draw_gpu_mesh(r, eng_mesh_get_gpu(r->own_meshes, r->ground), model, r->def.ground_color, r->def.ground_cell);
    }
}

void eng_renderer_draw_mesh(eng_renderer *r, const eng_mesh_store *meshes, eng_mesh_id mesh, mat4 model,
                            const float color[3])
{
    if (!in_frame(r, "eng_renderer_draw_mesh")) return;
    const eng_mesh_gpu *g = eng_mesh_get_gpu(meshes, mesh);
    if (!g) {
        eng_log(&r->def.logger, ENG_LOG_ERROR, "eng_renderer_draw_mesh: attempt to use a destroyed mesh (index %u)",
                (unsigned)mesh.index1);
        return;
    }
    use_mesh_pass(r);
    draw_gpu_mesh(r, g, model, color, 0.0f);
}

void eng_renderer_draw_scene(eng_renderer *r, eng_scene *scene, const eng_mesh_store *meshes)
{
    if (!in_frame(r, "eng_renderer_draw_scene")) return;
    int t = eng_gpu_timer_begin(r->timer, "scene");
    use_mesh_pass(r);
    eng_scene_update(scene);
    for (eng_node_id n = eng_scene_first(scene); n.index1; n = eng_scene_next(scene, n)) {
        eng_node_draw d;
        if (!eng_node_get_draw(scene, n, &d) || !d.visible || d.mesh.index1 == 0) continue;
        const eng_mesh_gpu *g = eng_mesh_get_gpu(meshes, d.mesh);
        if (!g) {
            if (!r->warned_stale_mesh)
                eng_log(&r->def.logger, ENG_LOG_WARN,
                        "eng_renderer_draw_scene: node %u refers to a destroyed mesh; not drawn",
                        (unsigned)(n.index1 - 1));
            r->warned_stale_mesh = true;
            continue;
        }
        draw_gpu_mesh(r, g, d.world, d.color, 0.0f);
    }
    glBindVertexArray(0);
    eng_gpu_timer_end(r->timer, t);
}

void eng_renderer_draw_particles(eng_renderer *r, const eng_camera *cam, GLuint positions_ssbo,
                                 GLuint draw_indirect_buffer, float radius, const eng_particle_style *style)
{
    const char *fn = "eng_renderer_draw_particles";
    if (!in_frame(r, fn)) return;
    const eng_logger *log = &r->def.logger;
    if (!(radius > 0.0f && isfinite(radius))) {
        eng_log(log, ENG_LOG_ERROR, "%s: radius must be > 0 m (got %g)", fn, (double)radius);
        return;
    }
    if (!positions_ssbo || !glIsBuffer(positions_ssbo)) {
        eng_log(log, ENG_LOG_ERROR, "%s: positions_ssbo must be a GL buffer (got %u)", fn, positions_ssbo);
        return;
    }
    if (!draw_indirect_buffer || !glIsBuffer(draw_indirect_buffer)) {
        eng_log(log, ENG_LOG_ERROR, "%s: draw_indirect_buffer must be a GL buffer (got %u)", fn, draw_indirect_buffer);
        return;
    }
    eng_particle_style def_style = eng_default_particle_style();
    if (!style) style = &def_style;
    else if (!check_style(log, style)) return;
    GLint64 size = 0, cmd_size = 0;
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, positions_ssbo);
    glGetBufferParameteri64v(GL_SHADER_STORAGE_BUFFER, GL_BUFFER_SIZE, &size);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, draw_indirect_buffer);
    glGetBufferParameteri64v(GL_DRAW_INDIRECT_BUFFER, GL_BUFFER_SIZE, &cmd_size);
    if (cmd_size < 16) {
        glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
        eng_log(log, ENG_LOG_ERROR, "%s: draw_indirect_buffer must hold a 16-byte DrawArraysIndirectCommand (has %lld bytes)",
                fn, (long long)cmd_size);
        return;
    }
    int t = eng_gpu_timer_begin(r->timer, "particles");
    // The fluid wrote both buffers from compute shaders.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    bool other_cam = cam && memcmp(cam, &r->cam, sizeof *cam) != 0;
    if (other_cam) write_frame(r, cam);
    const particle_pass *p = &r->particles;
    glUseProgram(p->prog);
    glUniform1f(p->radius, radius);
    // Instances past the end of the buffer are dropped in the vertex shader.
    glUniform1i(p->count, (GLint)(size / 16 > 0x7fffffff ? 0x7fffffff : size / 16));
    glUniform3fv(p->color_low, 1, style->color_low);
    glUniform3fv(p->color_mid, 1, style->color_mid);
    glUniform3fv(p->color_high, 1, style->color_high);
    glUniform1f(p->specular, style->specular);
    glUniform1f(p->shininess, style->shininess);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_PARTICLE_SSBO_BINDING, positions_ssbo);
    glBindVertexArray(p->vao);
    glDrawArraysIndirect(GL_TRIANGLE_STRIP, (const void *)0);
    glBindVertexArray(0);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_PARTICLE_SSBO_BINDING, 0);
    if (other_cam) write_frame(r, &r->cam);
    eng_gpu_timer_end(r->timer, t);
}

void eng_renderer_end(eng_renderer *r)
{
    if (!in_frame(r, "eng_renderer_end")) return;
    glBindVertexArray(0);
    glUseProgram(0);
    if (r->t_frame >= 0) eng_gpu_timer_end(r->timer, r->t_frame);
    r->t_frame = -1;
    eng_gpu_timer_collect(r->timer);
    r->in_frame = false;
    r->ctx = NULL;
}
