// The renderer: defs and checks, the frame (queued draws, then the passes in order), scene
// meshes and sphere impostors. The shadow map is in shadow.c, the water surface in
// surface.c. See renderer.h.
#include "engine/render/render_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <stdlib.h>

#include "fluid/pbf_glsl.h"
#include "shaders/render/render_shared.glsl"

// ---- GL helpers (shared with shadow.c and surface.c) -------------------------------

void eng_render_label(GLenum kind, GLuint name, const char *label)
{
    if (name) glObjectLabel(kind, name, -1, label);
}

GLuint eng_render_build(const eng_renderer_def *d, const char *vert, const char *frag, const char *defines,
                        const char *label, char *err, size_t err_size)
{
    pbf_glsl_stage stages[2] = { { GL_VERTEX_SHADER, vert }, { GL_FRAGMENT_SHADER, frag } };
    char msg[4096];
    pbf_glsl_source src = eng_render_sources();
    if (d->shader_dir) src.dir = d->shader_dir;
    GLuint prog = pbf_glsl_build_from(&src, stages, 2, defines, msg, sizeof msg);
    if (!prog) {
        eng_log(&d->logger, ENG_LOG_ERROR, "renderer: %s", msg);
        if (err && err_size > 0) snprintf(err, err_size, "%s", msg);
        return 0;
    }
    eng_render_label(GL_PROGRAM, prog, label);
    return prog;
}

GLuint eng_render_texture(GLenum internal_format, int w, int h, GLenum filter, const char *label)
{
    GLuint t = 0;
    GLint prev = 0; // the active unit's texture: a lit pass may be reading it
    glGetIntegerv(GL_TEXTURE_BINDING_2D, &prev);
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexStorage2D(GL_TEXTURE_2D, 1, internal_format, w, h);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, (GLint)filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, (GLint)filter);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glBindTexture(GL_TEXTURE_2D, (GLuint)prev);
    eng_render_label(GL_TEXTURE, t, label);
    return t;
}

GLuint eng_render_framebuffer(const GLuint *colors, int color_count, GLuint depth, const char *label)
{
    GLuint fb = 0;
    GLenum bufs[4];
    glGenFramebuffers(1, &fb);
    glBindFramebuffer(GL_FRAMEBUFFER, fb);
    for (int i = 0; i < color_count; i++) {
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + (GLenum)i, GL_TEXTURE_2D, colors[i], 0);
        bufs[i] = GL_COLOR_ATTACHMENT0 + (GLenum)i;
    }
    if (depth) glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
    if (color_count > 0) glDrawBuffers(color_count, bufs);
    else glDrawBuffer(GL_NONE);
    glReadBuffer(color_count > 0 ? GL_COLOR_ATTACHMENT0 : GL_NONE);
    GLenum st = glCheckFramebufferStatus(GL_FRAMEBUFFER);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    if (st != GL_FRAMEBUFFER_COMPLETE) {
        glDeleteFramebuffers(1, &fb);
        return 0;
    }
    eng_render_label(GL_FRAMEBUFFER, fb, label);
    return fb;
}

int eng_render_timer_begin(eng_renderer *r, const char *name)
{
    int t = eng_gpu_timer_begin(r->timer, name);
    if (r->flush_timestamps) glFlush();
    return t;
}

void eng_render_timer_end(eng_renderer *r, int section)
{
    if (section < 0) return;
    eng_gpu_timer_end(r->timer, section);
    if (r->flush_timestamps) glFlush();
}

// ---- creation ----------------------------------------------------------------------

static void mesh_locations(mesh_prog *m)
{
    GLuint p = m->prog;
    m->model = glGetUniformLocation(p, "u_model");
    m->normal_model = glGetUniformLocation(p, "u_normal_model");
    m->color = glGetUniformLocation(p, "u_color");
    m->specular = glGetUniformLocation(p, "u_specular");
    m->shininess = glGetUniformLocation(p, "u_shininess");
    m->checker_cell = glGetUniformLocation(p, "u_checker_cell");
}

// A particle program of vertex shader `vert` (particles.vert, or fullscreen.vert for the
// sphere modes' compute path) and fragment shader `frag`, with its uniforms' locations.
static bool build_particle_prog(eng_renderer *r, particle_prog *pp, const char *vert, const char *frag,
                                const char *defines, const char *label, char *err, size_t err_size)
{
    GLuint p = pp->prog = eng_render_build(&r->def, vert, frag, defines, label, err, err_size);
    if (!p) return false;
    pp->radius = glGetUniformLocation(p, "u_radius");
    pp->count = glGetUniformLocation(p, "u_count");
    pp->fill = glGetUniformLocation(p, "u_fill");
    pp->light_view = glGetUniformLocation(p, "u_light_view");
    pp->light_proj = glGetUniformLocation(p, "u_light_proj");
    pp->light_near = glGetUniformLocation(p, "u_light_near");
    pp->color_mode = glGetUniformLocation(p, "u_color_mode");
    pp->color_range = glGetUniformLocation(p, "u_color_range");
    pp->particle_mass = glGetUniformLocation(p, "u_particle_mass");
    pp->inv_rest_density = glGetUniformLocation(p, "u_inv_rest_density");
    pp->color_low = glGetUniformLocation(p, "u_color_low");
    pp->color_mid = glGetUniformLocation(p, "u_color_mid");
    pp->color_high = glGetUniformLocation(p, "u_color_high");
    pp->specular = glGetUniformLocation(p, "u_specular");
    pp->shininess = glGetUniformLocation(p, "u_shininess");
    pp->spray = glGetUniformLocation(p, "u_spray");
    return true;
}

static bool build_particles(eng_renderer *r, particle_prog *pp, const char *frag, const char *defines,
                            const char *label, char *err, size_t err_size)
{
    return build_particle_prog(r, pp, "render/particles.vert", frag, defines, label, err, err_size);
}

static bool build_programs(eng_renderer *r, char *err, size_t err_size)
{
    const eng_renderer_def *d = &r->def;
    r->mesh.prog = eng_render_build(d, "render/mesh.vert", "render/mesh.frag", NULL, "render/mesh", err, err_size);
    if (!r->mesh.prog) return false;
    mesh_locations(&r->mesh);
    r->mesh_shadow.prog = eng_render_build(d, "render/mesh.vert", "render/depth_only.frag", "#define SHADOW_PASS 1\n",
                                           "render/mesh_shadow", err, err_size);
    if (!r->mesh_shadow.prog) return false;
    mesh_locations(&r->mesh_shadow);
    return build_particles(r, &r->spheres, "render/particles.frag",
                           "#define COLOR_MODES 1\n#define NEAR_QUAD 1\n", "render/particles",
                           err, err_size) &&
           build_particles(r, &r->fluid_depth, "render/fluid_depth.frag", "#define NEAR_QUAD 1\n",
                           "render/fluid_depth", err, err_size) &&
           build_particles(r, &r->fluid_thick, "render/fluid_thickness.frag", "#define TINT 1\n",
                           "render/fluid_thickness", err, err_size) &&
           build_particles(r, &r->fluid_shadow, "render/shadow_fluid.frag", "#define LIGHT_PASS 1\n",
                           "render/shadow_fluid", err, err_size) &&
           build_particles(r, &r->fluid_spray, "render/spray.frag", "#define SPRAY 1\n", "render/spray", err,
                           err_size) &&
           build_particle_prog(r, &r->spheres_lit, "render/fullscreen.vert", "render/spheres.frag",
                               "#define COLOR_MODES 1\n", "render/spheres_lit", err, err_size);
}

eng_renderer *eng_renderer_create(const eng_renderer_def *def, char *err, size_t err_size)
{
    if (err && err_size > 0) err[0] = 0;
    if (!eng_render_check_def(def, err, err_size)) return NULL;
    GLint vertex_ssbos = 0;
    glGetIntegerv(GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS, &vertex_ssbos);
    if (vertex_ssbos < 2) {
        char msg[160];
        snprintf(msg, sizeof msg, "renderer: GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS is %d; particle impostors need 2",
                 (int)vertex_ssbos);
        eng_log(&def->logger, ENG_LOG_ERROR, "%s", msg);
        if (err && err_size > 0) snprintf(err, err_size, "%s", msg);
        return NULL;
    }
    eng_renderer *r = calloc(1, sizeof *r);
    if (!r) return NULL;
    r->def = *def;
    r->t_frame = -1;
    const char *renderer = (const char *)glGetString(GL_RENDERER);
    r->flush_timestamps = renderer && strstr(renderer, "llvmpipe");

    if (!build_programs(r, err, err_size) || !eng_splat_create(r, err, err_size) || !eng_shadow_create(r, err, err_size) ||
        !eng_surface_create(r, err, err_size)) {
        eng_renderer_destroy(r);
        return NULL;
    }
    glGenVertexArrays(1, &r->empty_vao);
    glBindVertexArray(r->empty_vao);
    eng_render_label(GL_VERTEX_ARRAY, r->empty_vao, "eng.empty_vao");
    glBindVertexArray(0);

    glGenBuffers(1, &r->frame_ubo);
    glBindBuffer(GL_UNIFORM_BUFFER, r->frame_ubo);
    glBufferData(GL_UNIFORM_BUFFER, sizeof(eng_frame_block), NULL, GL_DYNAMIC_DRAW);
    eng_render_label(GL_BUFFER, r->frame_ubo, "eng.frame_ubo");
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
    GLuint progs[] = { r->mesh.prog,        r->mesh_shadow.prog,  r->spheres.prog,     r->fluid_depth.prog,
                       r->fluid_thick.prog, r->fluid_shadow.prog, r->fluid_spray.prog, r->spheres_lit.prog };
    for (size_t i = 0; i < sizeof progs / sizeof progs[0]; i++)
        if (progs[i]) glDeleteProgram(progs[i]);
    eng_surface_destroy(r);
    eng_splat_destroy(r);
    eng_shadow_destroy(r);
    if (r->empty_vao) glDeleteVertexArrays(1, &r->empty_vao);
    if (r->frame_ubo) glDeleteBuffers(1, &r->frame_ubo);
    eng_mesh_store_destroy(r->own_meshes);
    eng_gpu_timer_destroy(r->timer);
    free(r->meshes);
    free(r);
}

eng_gpu_timer *eng_renderer_gpu_timer(eng_renderer *r) { return r->timer; }

bool eng_renderer_set_light(eng_renderer *r, const eng_light *light)
{
    if (!eng_render_check_light(&r->def.logger, NULL, 0, "light", light)) return false;
    r->def.light = *light;
    return true;
}

bool eng_renderer_set_sky(eng_renderer *r, const float sky_color[3])
{
    if (!eng_render_check_rgb(&r->def.logger, NULL, 0, "sky_color", sky_color, 1.0f)) return false;
    memcpy(r->def.sky_color, sky_color, sizeof r->def.sky_color);
    return true;
}

bool eng_renderer_set_fluid_look(eng_renderer *r, const eng_fluid_look *look)
{
    if (!look) {
        eng_log(&r->def.logger, ENG_LOG_ERROR, "eng_renderer_set_fluid_look: look must not be NULL");
        return false;
    }
    if (!eng_render_check_look(&r->def.logger, NULL, 0, "eng_fluid_look", look)) return false;
    r->def.fluid = *look;
    return true;
}

eng_fluid_look eng_renderer_fluid_look(const eng_renderer *r) { return r->def.fluid; }

bool eng_renderer_set_fluid_mode(eng_renderer *r, eng_fluid_mode mode)
{
    if ((int)mode < 0 || mode >= ENG_FLUID_MODE_COUNT) {
        eng_log(&r->def.logger, ENG_LOG_ERROR, "eng_renderer_set_fluid_mode: mode must be 0..%d (%s) (got %d)",
                ENG_FLUID_MODE_COUNT - 1, eng_fluid_mode_names(), (int)mode);
        return false;
    }
    r->def.fluid.mode = mode;
    return true;
}

eng_fluid_mode eng_renderer_fluid_mode(const eng_renderer *r) { return r->def.fluid.mode; }

bool eng_renderer_set_shadow_bounds(eng_renderer *r, const float lo[3], const float hi[3])
{
    for (int k = 0; k < 3; k++)
        if (!(isfinite(lo[k]) && isfinite(hi[k]) && lo[k] < hi[k])) {
            eng_log(&r->def.logger, ENG_LOG_ERROR,
                    "eng_renderer_set_shadow_bounds: lo[%d] must be < hi[%d], both finite m (got %g, %g)", k, k,
                    (double)lo[k], (double)hi[k]);
            return false;
        }
    memcpy(r->shadow.lo, lo, sizeof r->shadow.lo);
    memcpy(r->shadow.hi, hi, sizeof r->shadow.hi);
    r->shadow.has_bounds = true;
    return true;
}

eng_surface_textures eng_renderer_surface_textures(const eng_renderer *r)
{
    eng_surface_textures t;
    memset(&t, 0, sizeof t);
    const surface_targets *s = &r->surf;
    if (!s->drawn) return t;
    t.depth = s->depth;
    t.smoothed = r->def.fluid.smoothing > 0.0f ? s->smooth[1] : s->depth;
    t.thickness = r->def.fluid.smoothing > 0.0f ? s->smooth_thick[1] : s->thick;
    t.width = s->fw;
    t.height = s->fh;
    return t;
}

// ---- a frame: the queue ------------------------------------------------------------

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
    r->width = w;
    r->height = h;
    r->aspect = (float)w / (float)h;
    r->warned_stale_mesh = false;
    r->scene_count = r->mesh_count = r->fluid_count = 0;
    if (!r->shadow.has_bounds) {
        float lo[3], hi[3];
        for (int k = 0; k < 3; k++) lo[k] = cam->target[k] - 4.0f, hi[k] = cam->target[k] + 4.0f;
        eng_renderer_set_shadow_bounds(r, lo, hi);
    }
}

void eng_renderer_draw_mesh(eng_renderer *r, const eng_mesh_store *meshes, eng_mesh_id mesh, mat4 model,
                            const float color[3])
{
    if (!in_frame(r, "eng_renderer_draw_mesh")) return;
    if (!eng_mesh_get_gpu(meshes, mesh)) {
        eng_log(&r->def.logger, ENG_LOG_ERROR, "eng_renderer_draw_mesh: attempt to use a destroyed mesh (index %u)",
                (unsigned)mesh.index1);
        return;
    }
    if (r->mesh_count == r->mesh_cap) {
        int cap = r->mesh_cap ? 2 * r->mesh_cap : 64;
        queued_mesh *m = realloc(r->meshes, (size_t)cap * sizeof *m);
        if (!m) {
            eng_log(&r->def.logger, ENG_LOG_ERROR, "eng_renderer_draw_mesh: out of memory");
            return;
        }
        r->meshes = m;
        r->mesh_cap = cap;
    }
    queued_mesh *q = &r->meshes[r->mesh_count++];
    q->meshes = meshes;
    q->mesh = mesh;
    glm_mat4_copy(model, q->model);
    memcpy(q->color, color, sizeof q->color);
}

void eng_renderer_draw_scene(eng_renderer *r, eng_scene *scene, const eng_mesh_store *meshes)
{
    if (!in_frame(r, "eng_renderer_draw_scene")) return;
    if (!scene || !meshes) {
        eng_log(&r->def.logger, ENG_LOG_ERROR, "eng_renderer_draw_scene: %s must not be NULL", !scene ? "scene" : "meshes");
        return;
    }
    if (r->scene_count == MAX_SCENES) {
        eng_log(&r->def.logger, ENG_LOG_ERROR, "eng_renderer_draw_scene: at most %d scenes a frame", MAX_SCENES);
        return;
    }
    r->scenes[r->scene_count++] = (queued_scene){ scene, meshes };
}

static bool check_buffer(const eng_logger *log, const char *fn, const char *field, GLuint b, GLenum target,
                         GLint64 *size)
{
    if (!b || !glIsBuffer(b)) {
        eng_log(log, ENG_LOG_ERROR, "%s: %s must be a GL buffer (got %u)", fn, field, b);
        return false;
    }
    glBindBuffer(target, b);
    glGetBufferParameteri64v(target, GL_BUFFER_SIZE, size);
    glBindBuffer(target, 0);
    return true;
}

// `legacy`: called as eng_renderer_draw_particles, whose arguments have other names.
static void queue_fluid(eng_renderer *r, const char *fn, const eng_fluid_draw *d, bool legacy)
{
    const eng_logger *log = &r->def.logger;
    if (!(d->radius > 0.0f && isfinite(d->radius))) {
        eng_log(log, ENG_LOG_ERROR, "%s: radius must be > 0 m (got %g)", fn, (double)d->radius);
        return;
    }
    GLint64 size = 0, vel_size = 0, cmd_size = 0;
    if (!check_buffer(log, fn, legacy ? "positions_ssbo" : "positions", d->positions, GL_SHADER_STORAGE_BUFFER,
                      &size) ||
        !check_buffer(log, fn, legacy ? "draw_indirect_buffer" : "draw_indirect", d->draw_indirect,
                      GL_DRAW_INDIRECT_BUFFER, &cmd_size))
        return;
    if (d->velocities) {
        if (!check_buffer(log, fn, "velocities", d->velocities, GL_SHADER_STORAGE_BUFFER, &vel_size)) return;
        if (!(d->particle_mass > 0.0f && isfinite(d->particle_mass))) {
            eng_log(log, ENG_LOG_ERROR, "%s: particle_mass must be > 0 kg with velocities (got %g)", fn,
                    (double)d->particle_mass);
            return;
        }
        if (!(d->rest_density > 0.0f && isfinite(d->rest_density))) {
            eng_log(log, ENG_LOG_ERROR, "%s: rest_density must be > 0 kg/m^3 with velocities (got %g)", fn,
                    (double)d->rest_density);
            return;
        }
    }
    if (cmd_size < 16) {
        eng_log(log, ENG_LOG_ERROR, "%s: draw_indirect%s must hold a 16-byte DrawArraysIndirectCommand (has %lld bytes)",
                fn, legacy ? "_buffer" : "", (long long)cmd_size);
        return;
    }
    eng_particle_style style = d->style ? *d->style : eng_default_particle_style();
    if (d->style && !eng_render_check_style(log, &style)) return;
    if (r->fluid_count == MAX_FLUIDS) {
        eng_log(log, ENG_LOG_ERROR, "%s: at most %d fluids a frame", fn, MAX_FLUIDS);
        return;
    }
    queued_fluid *f = &r->fluids[r->fluid_count++];
    f->d = *d;
    f->d.style = NULL;
    f->style = style;
    GLint64 n = size / 16;
    if (d->velocities && vel_size / 16 < n) n = vel_size / 16;
    f->count = (GLint)(n > 0x7fffffff ? 0x7fffffff : n);
}

void eng_renderer_draw_fluid(eng_renderer *r, const eng_fluid_draw *fluid)
{
    if (!in_frame(r, "eng_renderer_draw_fluid")) return;
    if (!fluid) {
        eng_log(&r->def.logger, ENG_LOG_ERROR, "eng_renderer_draw_fluid: fluid must not be NULL");
        return;
    }
    queue_fluid(r, "eng_renderer_draw_fluid", fluid, false);
}

void eng_renderer_draw_particles(eng_renderer *r, const eng_camera *cam, GLuint positions_ssbo,
                                 GLuint draw_indirect_buffer, float radius, const eng_particle_style *style)
{
    const char *fn = "eng_renderer_draw_particles";
    if (!in_frame(r, fn)) return;
    if (cam && memcmp(cam, &r->cam, sizeof *cam) != 0) {
        eng_log(&r->def.logger, ENG_LOG_ERROR,
                "%s: cam must be NULL or the frame's camera (everything is drawn with the camera given to "
                "eng_renderer_begin)", fn);
        return;
    }
    eng_fluid_draw d = eng_default_fluid_draw();
    d.positions = positions_ssbo;
    d.draw_indirect = draw_indirect_buffer;
    d.radius = radius;
    d.style = style;
    queue_fluid(r, fn, &d, true);
}

// ---- a frame: the passes -----------------------------------------------------------

void eng_render_write_frame(eng_renderer *r, int target_width, int target_height)
{
    eng_frame_block b;
    memset(&b, 0, sizeof b);
    mat4 view, proj, inv;
    eng_camera_view(&r->cam, view);
    eng_camera_projection(&r->cam, r->aspect, proj);
    glm_mat4_inv(view, inv);
    memcpy(b.view, view, sizeof b.view);
    memcpy(b.proj, proj, sizeof b.proj);
    memcpy(b.inv_view, inv, sizeof b.inv_view);
    memcpy(b.light_viewproj, r->shadow.viewproj, sizeof b.light_viewproj);
    memcpy(b.camera_pos, r->cam.position, 3 * sizeof(float));
    const float *d = r->def.light.direction;
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++) b.light_dir[k] = d[k] / len;
    memcpy(b.light_color, r->def.light.color, 3 * sizeof(float));
    memcpy(b.ambient, r->def.light.ambient, 3 * sizeof(float));
    memcpy(b.sky_color, r->def.sky_color, 3 * sizeof(float));
    b.fog[0] = r->def.fog_start;
    b.fog[1] = r->def.fog_end;
    memcpy(b.ground_color, r->def.ground_color, 3 * sizeof(float));
    const shadow_map *s = &r->shadow;
    b.shadow[0] = r->def.fluid.shadows ? 1.0f : 0.0f;
    b.shadow[1] = 1.0f / (float)s->size;
    b.shadow[2] = s->range;
    // Receivers look up the map a texel and a half along their normal (no acne on slopes).
    float texel_m = 2.0f * (s->proj[0][0] > 0.0f ? 1.0f / s->proj[0][0] : 1.0f) / (float)s->size;
    b.shadow[3] = 1.5f * texel_m;
    memcpy(b.water_light, r->def.fluid.absorption, 3 * sizeof(float));
    // A receiver within one particle spacing under the water's front is the surface itself.
    b.water_light[3] = r->fluid_count > 0 ? 2.0f * r->fluids[0].d.radius : 0.0f;
    b.viewport[0] = (float)target_width;
    b.viewport[1] = (float)target_height;
    b.viewport[2] = 1.0f / (float)target_width;
    b.viewport[3] = 1.0f / (float)target_height;
    glBindBuffer(GL_UNIFORM_BUFFER, r->frame_ubo);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof b, &b);
    glBindBuffer(GL_UNIFORM_BUFFER, 0);
    glBindBufferBase(GL_UNIFORM_BUFFER, ENG_RENDER_FRAME_UBO_BINDING, r->frame_ubo);
}

static void draw_gpu_mesh(const mesh_prog *p, const eng_mesh_gpu *g, mat4 model, const float color[3],
                          float checker_cell)
{
    mat3 m3, inv;
    glm_mat4_pick3(model, m3);
    glm_mat3_inv(m3, inv);
    glm_mat3_transpose(inv);
    glUniformMatrix4fv(p->model, 1, GL_FALSE, (const float *)model);
    glUniformMatrix3fv(p->normal_model, 1, GL_FALSE, (const float *)inv);
    glUniform3fv(p->color, 1, color);
    glUniform1f(p->checker_cell, checker_cell);
    glBindVertexArray(g->vao);
    glDrawElements(GL_TRIANGLES, g->index_count, GL_UNSIGNED_INT, (const void *)0);
}

void eng_render_draw_queued_meshes(eng_renderer *r, const mesh_prog *p)
{
    for (int i = 0; i < r->scene_count; i++) {
        eng_scene *scene = r->scenes[i].scene;
        eng_scene_update(scene);
        for (eng_node_id n = eng_scene_first(scene); n.index1; n = eng_scene_next(scene, n)) {
            eng_node_draw d;
            if (!eng_node_get_draw(scene, n, &d) || !d.visible || d.mesh.index1 == 0) continue;
            const eng_mesh_gpu *g = eng_mesh_get_gpu(r->scenes[i].meshes, d.mesh);
            if (!g) {
                if (!r->warned_stale_mesh)
                    eng_log(&r->def.logger, ENG_LOG_WARN,
                            "eng_renderer_draw_scene: node %u refers to a destroyed mesh; not drawn",
                            (unsigned)(n.index1 - 1));
                r->warned_stale_mesh = true;
                continue;
            }
            draw_gpu_mesh(p, g, d.world, d.color, 0.0f);
        }
    }
    for (int i = 0; i < r->mesh_count; i++) {
        const queued_mesh *q = &r->meshes[i];
        const eng_mesh_gpu *g = eng_mesh_get_gpu(q->meshes, q->mesh);
        if (g) draw_gpu_mesh(p, g, (vec4 *)q->model, q->color, 0.0f);
    }
    glBindVertexArray(0);
}

void eng_render_bind_fluid(const particle_prog *p, const queued_fluid *f)
{
    const float r = f->d.radius;
    glUniform1f(p->radius, r);
    glUniform1i(p->count, f->count);
    // Lattice volume over sphere volume: (2r)^3 / (4/3 pi r^3) = 6 / pi.
    glUniform1f(p->fill, 6.0f / 3.14159265f);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_PARTICLE_SSBO_BINDING, f->d.positions);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_VELOCITY_SSBO_BINDING,
                     f->d.velocities ? f->d.velocities : f->d.positions);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, f->d.draw_indirect);
}

void eng_render_draw_fluid_instances(const queued_fluid *f)
{
    (void)f;
    glDrawArraysIndirect(GL_TRIANGLE_STRIP, (const void *)0);
}

static void draw_ground(eng_renderer *r)
{
    if (!r->def.ground) return;
    mat4 model;
    glm_translate_make(model, (vec3){ 0.0f, r->def.ground_height, 0.0f });
    glUniform1f(r->mesh.specular, 0.05f);
    draw_gpu_mesh(&r->mesh, eng_mesh_get_gpu(r->own_meshes, r->ground), model, r->def.ground_color, r->def.ground_cell);
    glUniform1f(r->mesh.specular, r->def.specular);
}

// The opaque scene (ground, nodes, meshes) into the bound framebuffer, cleared to the sky.
static void draw_opaque(eng_renderer *r)
{
    int t = eng_render_timer_begin(r, "scene");
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glClearColor(r->def.sky_color[0], r->def.sky_color[1], r->def.sky_color[2], 1.0f);
    glClearDepth(1.0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUseProgram(r->mesh.prog);
    glUniform1f(r->mesh.specular, r->def.specular);
    glUniform1f(r->mesh.shininess, r->def.shininess);
    draw_ground(r);
    eng_render_draw_queued_meshes(r, &r->mesh);
    eng_render_timer_end(r, t);
}

// The sphere modes: per fluid, the raster impostors (particles.vert, particles.frag) or,
// with compute splats, the nearest particle per pixel found by splat.c and lit by a
// full-screen pass (spheres.frag); the same image to rounding (tests/test_surface.c).
static void draw_spheres(eng_renderer *r)
{
    int t = eng_render_timer_begin(r, "particles");
    bool compute = r->def.fluid.splat == ENG_FLUID_SPLAT_COMPUTE && eng_splat_spheres_targets(r);
    const particle_prog *p = compute ? &r->spheres_lit : &r->spheres;
    for (int i = 0; i < r->fluid_count; i++) {
        const queued_fluid *f = &r->fluids[i];
        if (compute) { // its own section too (the last fluid's, with several), inside "particles"
            int ts = eng_render_timer_begin(r, "particles_splat");
            eng_splat_spheres_find(r, f);
            eng_render_timer_end(r, ts);
        }
        glUseProgram(p->prog);
        glBindVertexArray(r->empty_vao);
        int mode = r->def.fluid.mode == ENG_FLUID_DENSITY ? ENG_RENDER_COLOR_DENSITY
                   : r->def.fluid.mode == ENG_FLUID_SPEED ? ENG_RENDER_COLOR_SPEED
                                                          : ENG_RENDER_COLOR_HEIGHT;
        if (mode != ENG_RENDER_COLOR_HEIGHT && !f->d.velocities) {
            if (!r->warned_no_velocities)
                eng_log(&r->def.logger, ENG_LOG_WARN,
                        "renderer: the %s mode needs the fluid's velocities (eng_fluid_draw.velocities); "
                        "colouring by height", eng_fluid_mode_name(r->def.fluid.mode));
            r->warned_no_velocities = true;
            mode = ENG_RENDER_COLOR_HEIGHT;
        }
        eng_render_bind_fluid(p, f);
        glUniform1i(p->color_mode, mode);
        if (mode == ENG_RENDER_COLOR_DENSITY) glUniform2fv(p->color_range, 1, r->def.fluid.density_range);
        else glUniform2f(p->color_range, 0.0f, r->def.fluid.speed_max);
        glUniform1f(p->particle_mass, f->d.particle_mass);
        glUniform1f(p->inv_rest_density, f->d.rest_density > 0.0f ? 1.0f / f->d.rest_density : 0.0f);
        glUniform3fv(p->color_low, 1, f->style.color_low);
        glUniform3fv(p->color_mid, 1, f->style.color_mid);
        glUniform3fv(p->color_high, 1, f->style.color_high);
        glUniform1f(p->specular, f->style.specular);
        glUniform1f(p->shininess, f->style.shininess);
        if (compute) {
            glDrawArrays(GL_TRIANGLES, 0, 3);
            eng_splat_spheres_reset(r);
        } else {
            eng_render_draw_fluid_instances(f);
        }
    }
    eng_render_timer_end(r, t);
}

static void reset_state(eng_renderer *r)
{
    glBindFramebuffer(GL_FRAMEBUFFER, eng_context_framebuffer(r->ctx));
    glViewport(0, 0, r->width, r->height);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_BLEND);
    glDisable(GL_CULL_FACE);
    glDisable(GL_POLYGON_OFFSET_FILL);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glBindVertexArray(0);
    glUseProgram(0);
    for (int u = 0; u <= ENG_RENDER_TEX_SPLAT_TEST; u++) {
        glActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glBindTexture(GL_TEXTURE_2D, 0);
    }
    glActiveTexture(GL_TEXTURE0);
    glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
    // The storage bindings the particle passes, the compute splats and the spray's cull use.
    for (GLuint b = ENG_RENDER_PARTICLE_SSBO_BINDING; b <= ENG_RENDER_SPLAT_BIG_BINDING; b++)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, 0);
}

void eng_renderer_end(eng_renderer *r)
{
    if (!in_frame(r, "eng_renderer_end")) return;
    r->t_frame = eng_render_timer_begin(r, "frame");
    reset_state(r);
    // The fluid wrote its buffers from compute shaders: positions and velocities are read
    // as storage blocks, the command as an indirect draw.
    if (r->fluid_count > 0) glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    bool surface = r->def.fluid.mode == ENG_FLUID_SURFACE && r->fluid_count > 0 &&
                   eng_surface_targets(r, r->width, r->height);
    eng_shadow_prepare(r);
    eng_render_write_frame(r, r->width, r->height);
    eng_shadow_render(r);

    r->surf.drawn = false;
    if (surface) {
        glBindFramebuffer(GL_FRAMEBUFFER, r->surf.scene_fbo);
        glViewport(0, 0, r->width, r->height);
        draw_opaque(r);
        eng_surface_render(r);
        r->surf.drawn = true;
    } else {
        glBindFramebuffer(GL_FRAMEBUFFER, eng_context_framebuffer(r->ctx));
        glViewport(0, 0, r->width, r->height);
        draw_opaque(r);
        if (r->fluid_count > 0) draw_spheres(r);
    }
    reset_state(r);
    eng_render_timer_end(r, r->t_frame);
    r->t_frame = -1;
    eng_gpu_timer_collect(r->timer);
    r->in_frame = false;
    r->ctx = NULL;
}
