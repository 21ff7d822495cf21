// The water's particle passes by compute shaders (eng_fluid_look.splat = compute). See
// render_internal.h, shaders/render/splat.comp and docs/architecture.md, "Rendering".
//
// Per pass: splat.comp, one invocation per particle, merges every texel its sphere covers
// into R32UI images with atomics (min of the depth's bits, fixed-point sums of the
// thickness); then splat_resolve.comp turns those into the float textures the raster
// passes write (surf.depth, surf.thick, surf.tint; the shadow map's front and thick) and
// resets the images for the next frame. The images are reset once when they are made.
// Synchronisation: the particle buffers' barrier is eng_renderer_end's (storage and
// command: the splats read the indirect command as a storage block); the scene's depth
// the splats test against was written as a framebuffer attachment by an earlier command,
// which GL orders before later texture fetches; between the splat and the resolve, and
// after the resolve (image atomics of the next frame, texture fetches of the smoothing,
// composite and lit passes, and the raster path's framebuffer clears should the look
// switch back), glMemoryBarrier with the bits for each.
#include "engine/render/render_internal.h"

#include <stdio.h>
#include <string.h>

#include "fluid/pbf_glsl.h"
#include "shaders/render/render_shared.glsl"

pbf_glsl_source eng_render_sources(void);

static bool build(eng_renderer *r, splat_prog *sp, const char *file, const char *defines, const char *label,
                  char *err, size_t err_size)
{
    const eng_renderer_def *d = &r->def;
    pbf_glsl_stage stage = { GL_COMPUTE_SHADER, file };
    char msg[4096];
    pbf_glsl_source src = eng_render_sources();
    if (d->shader_dir) src.dir = d->shader_dir;
    GLuint p = sp->prog = pbf_glsl_build_from(&src, &stage, 1, defines, msg, sizeof msg);
    if (!p) {
        eng_log(&d->logger, ENG_LOG_ERROR, "renderer: %s", msg);
        if (err && err_size > 0) snprintf(err, err_size, "%s", msg);
        return false;
    }
    eng_render_label(GL_PROGRAM, p, label);
    sp->radius = glGetUniformLocation(p, "u_radius");
    sp->count = glGetUniformLocation(p, "u_count");
    sp->fill = glGetUniformLocation(p, "u_fill");
    sp->size = glGetUniformLocation(p, "u_size");
    sp->view = glGetUniformLocation(p, "u_view");
    sp->proj = glGetUniformLocation(p, "u_proj");
    sp->light_near = glGetUniformLocation(p, "u_light_near");
    sp->store = glGetUniformLocation(p, "u_store");
    sp->groups = glGetUniformLocation(p, "u_groups");
    sp->spray_speed = glGetUniformLocation(p, "u_spray_speed");
    sp->spray_density = glGetUniformLocation(p, "u_spray_density");
    sp->particle_mass = glGetUniformLocation(p, "u_particle_mass");
    sp->inv_rest_density = glGetUniformLocation(p, "u_inv_rest_density");
    sp->stage = glGetUniformLocation(p, "u_stage");
    return true;
}

bool eng_splat_create(eng_renderer *r, char *err, size_t err_size)
{
    return build(r, &r->splat_depth, "render/splat.comp", "#define SPLAT_DEPTH 1\n", "render/splat_depth", err,
                 err_size) &&
           build(r, &r->splat_thick, "render/splat.comp", "#define SPLAT_THICK 1\n", "render/splat_thickness", err,
                 err_size) &&
           build(r, &r->splat_light, "render/splat.comp", "#define SPLAT_LIGHT 1\n", "render/splat_shadow", err,
                 err_size) &&
           build(r, &r->resolve_surface, "render/splat_resolve.comp", "#define RESOLVE_SURFACE 1\n",
                 "render/splat_resolve_surface", err, err_size) &&
           build(r, &r->resolve_light, "render/splat_resolve.comp", "#define RESOLVE_LIGHT 1\n",
                 "render/splat_resolve_shadow", err, err_size) &&
           build(r, &r->splat_nearest, "render/splat.comp", "#define SPLAT_NEAREST 1\n", "render/splat_nearest", err,
                 err_size) &&
           build(r, &r->splat_id, "render/splat.comp", "#define SPLAT_ID 1\n", "render/splat_id", err, err_size) &&
           build(r, &r->resolve_spheres, "render/splat_resolve.comp", "#define RESOLVE_SPHERES 1\n",
                 "render/splat_reset_spheres", err, err_size) &&
           build(r, &r->spray_count, "render/spray_cull.comp", "#define CULL_COUNT 1\n", "render/spray_count", err,
                 err_size) &&
           build(r, &r->spray_scan, "render/spray_cull.comp", "#define CULL_SCAN 1\n", "render/spray_scan", err,
                 err_size) &&
           build(r, &r->spray_write, "render/spray_cull.comp", "#define CULL_WRITE 1\n", "render/spray_write", err,
                 err_size);
}

// The sphere modes' images (splat.c, "the sphere modes") deleted and forgotten.
static void drop_sphere_images(eng_renderer *r)
{
    GLuint texs[2] = { r->sphere_ids, r->sphere_nearest };
    for (int i = 0; i < 2; i++)
        if (texs[i]) glDeleteTextures(1, &texs[i]);
    r->sphere_ids = r->sphere_nearest = 0;
    r->sphere_w = r->sphere_h = 0;
}

void eng_splat_destroy(eng_renderer *r)
{
    splat_prog *all[] = { &r->splat_depth,   &r->splat_thick, &r->splat_light, &r->resolve_surface,
                          &r->resolve_light, &r->splat_nearest, &r->splat_id, &r->resolve_spheres,
                          &r->spray_count,   &r->spray_scan,  &r->spray_write };
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        if (all[i]->prog) glDeleteProgram(all[i]->prog);
    GLuint bufs[4] = { r->spray_list, r->spray_cmd, r->spray_groups, r->splat_big };
    for (int i = 0; i < 4; i++)
        if (bufs[i]) glDeleteBuffers(1, &bufs[i]);
    drop_sphere_images(r);
}

// A GL-only storage buffer of `size` bytes (no CPU access); 0 if GL could not make it.
static GLuint gpu_buffer(GLsizeiptr size, const char *label)
{
    GLuint b = 0;
    GLint64 got = 0;
    glGenBuffers(1, &b);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, b);
    glBufferData(GL_SHADER_STORAGE_BUFFER, size, NULL, GL_DYNAMIC_COPY);
    glGetBufferParameteri64v(GL_SHADER_STORAGE_BUFFER, GL_BUFFER_SIZE, &got);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
    if (got != size) {
        while (glGetError() != GL_NO_ERROR) {} // the GL_OUT_OF_MEMORY this leaves is reported by the caller
        glDeleteBuffers(1, &b);
        return 0;
    }
    eng_render_label(GL_BUFFER, b, label);
    return b;
}

// Work groups of 64 the spray cull and the splats use: enough for every particle the
// buffers hold, at most 65535 (a grid-stride loop covers the rest).
static GLuint particle_groups(GLint count)
{
    GLuint groups = ((GLuint)(count > 0 ? count : 1) + 63u) / 64u;
    return groups < 65535u ? groups : 65535u;
}

bool eng_spray_cull(eng_renderer *r, const queued_fluid *f)
{
    if (f->count <= 0) return false; // buffers that hold no particle: nothing to list
    if (!r->spray_cmd) {
        r->spray_cmd = gpu_buffer(4 * sizeof(GLuint), "eng.spray.command");
        r->spray_groups = gpu_buffer(65535 * sizeof(GLuint), "eng.spray.groups");
    }
    if (f->count > r->spray_capacity) {
        if (r->spray_list) glDeleteBuffers(1, &r->spray_list);
        r->spray_list = gpu_buffer((GLsizeiptr)f->count * 2 * (GLsizeiptr)sizeof(GLuint), "eng.spray.list");
        r->spray_capacity = r->spray_list ? f->count : 0;
    }
    if (!r->spray_cmd || !r->spray_groups || !r->spray_list) {
        eng_log(&r->def.logger, ENG_LOG_ERROR, "renderer: the spray's buffers (%d drops) could not be made", f->count);
        return false;
    }
    const eng_fluid_look *k = &r->def.fluid;
    GLuint groups = particle_groups(f->count);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_VELOCITY_SSBO_BINDING, f->d.velocities);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_DRAW_SSBO_BINDING, f->d.draw_indirect);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_SPRAY_GROUPS_BINDING, r->spray_groups);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_SPRAY_CMD_BINDING, r->spray_cmd);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_SPRAY_LIST_BINDING, r->spray_list);
    const splat_prog *passes[3] = { &r->spray_count, &r->spray_scan, &r->spray_write };
    for (int i = 0; i < 3; i++) {
        const splat_prog *p = passes[i];
        glUseProgram(p->prog);
        glUniform1ui(p->groups, groups);
        glUniform1i(p->count, f->count);
        glUniform1f(p->spray_speed, k->spray_speed);
        glUniform1f(p->spray_density, 0.7f);
        glUniform1f(p->particle_mass, f->d.particle_mass);
        glUniform1f(p->inv_rest_density, 1.0f / f->d.rest_density);
        glDispatchCompute(i == 1 ? 1u : groups, 1, 1);
        // counts -> the scan -> offsets -> the list; the last for the draw (storage + command)
        glMemoryBarrier(i < 2 ? GL_SHADER_STORAGE_BARRIER_BIT : GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    }
    return true;
}

GLuint eng_render_uint_layers(int w, int h, int layers, const char *label)
{
    GLuint t = 0;
    GLint prev = 0;
    glGetIntegerv(GL_TEXTURE_BINDING_2D_ARRAY, &prev);
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D_ARRAY, t);
    glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_R32UI, w, h, layers);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glBindTexture(GL_TEXTURE_2D_ARRAY, (GLuint)prev);
    eng_render_label(GL_TEXTURE, t, label);
    return t;
}

// A resolve program over w x h texels (its images bound): stores the textures and resets
// the integer images (`store` 1) or only resets them (0), then the barrier `after`.
static void resolve(const splat_prog *p, int w, int h, int store, GLbitfield after)
{
    glUseProgram(p->prog);
    glUniform2i(p->size, w, h);
    glUniform1i(p->store, store);
    glDispatchCompute((GLuint)(w + 7) / 8, (GLuint)(h + 7) / 8, 1);
    glMemoryBarrier(after);
}

// After a resolve that stored: the next frame's atomics, the later passes' texture
// fetches, and the raster path's framebuffer clears should the look switch back.
#define AFTER_RESOLVE (GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT | GL_FRAMEBUFFER_BARRIER_BIT)

// Work groups of the dispatch over the large spheres (each loops over the list).
#define LARGE_GROUPS 512u

// The list of large spheres, as long as the largest queued fluid; false (logged) if it
// could not be made.
static bool large_list(eng_renderer *r)
{
    GLint most = 0;
    for (int i = 0; i < r->fluid_count; i++) most = r->fluids[i].count > most ? r->fluids[i].count : most;
    if (most <= r->splat_big_capacity) return true;
    if (r->splat_big) glDeleteBuffers(1, &r->splat_big);
    r->splat_big = gpu_buffer(((GLsizeiptr)most + 1) * (GLsizeiptr)sizeof(GLuint), "eng.splat.large");
    r->splat_big_capacity = r->splat_big ? most : 0;
    if (!r->splat_big)
        eng_log(&r->def.logger, ENG_LOG_ERROR, "renderer: the compute splats' list (%d particles) could not be made", most);
    return r->splat_big != 0;
}

// Splat program `sp` in use, with the view, projection and target size.
static void splat_begin(const splat_prog *sp, const float *view, const float *proj, int w, int h)
{
    glUseProgram(sp->prog);
    glUniformMatrix4fv(sp->view, 1, GL_FALSE, view);
    glUniformMatrix4fv(sp->proj, 1, GL_FALSE, proj);
    glUniform2i(sp->size, w, h);
    glUniform1f(sp->fill, 6.0f / 3.14159265f); // as eng_render_bind_fluid
}

// Fluid `f` through the splat program in use (its images and test texture bound, the large
// list made): the list emptied, every particle (the large spheres listed), then the listed
// ones a work group each.
static void splat_fluid(eng_renderer *r, const splat_prog *sp, const queued_fluid *f)
{
    glUniform1f(sp->radius, f->d.radius);
    glUniform1i(sp->count, f->count);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_PARTICLE_SSBO_BINDING, f->d.positions);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_DRAW_SSBO_BINDING, f->d.draw_indirect);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ENG_RENDER_SPLAT_BIG_BINDING, r->splat_big);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT); // the last large dispatch read the list
    glUniform1i(sp->stage, 2);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUniform1i(sp->stage, 0);
    glDispatchCompute(particle_groups(f->count), 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT); // the list (the images take atomics only)
    glUniform1i(sp->stage, 1);
    glDispatchCompute(LARGE_GROUPS, 1, 1);
}

// Every queued fluid through splat program `sp` (splat_fluid).
static void splat_fluids(eng_renderer *r, const splat_prog *sp, const float *view, const float *proj, int w, int h)
{
    splat_begin(sp, view, proj, w, h);
    for (int i = 0; i < r->fluid_count; i++) splat_fluid(r, sp, &r->fluids[i]);
}

static void bind_test(GLuint tex)
{
    glActiveTexture(GL_TEXTURE0 + ENG_RENDER_TEX_SPLAT_TEST);
    glBindTexture(GL_TEXTURE_2D, tex);
    glActiveTexture(GL_TEXTURE0);
}

static void unbind_images(void)
{
    for (GLuint u = ENG_RENDER_IMG_SPLAT; u <= ENG_RENDER_IMG_OUT2; u++)
        glBindImageTexture(u, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
}

static void bind_surface_resolve(const surface_targets *s)
{
    glBindImageTexture(ENG_RENDER_IMG_SPLAT, s->depth_bits, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(ENG_RENDER_IMG_SPLAT_LAYERS, s->thick_bits, 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(ENG_RENDER_IMG_OUT0, s->depth, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindImageTexture(ENG_RENDER_IMG_OUT1, s->thick, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
    glBindImageTexture(ENG_RENDER_IMG_OUT2, s->tint, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA16F);
}

bool eng_splat_surface(eng_renderer *r)
{
    surface_targets *s = &r->surf;
    if (!large_list(r)) return false;
    if (!s->depth_bits) {
        s->depth_bits = eng_render_texture(GL_R32UI, s->fw, s->fh, GL_NEAREST, "eng.surface.splat_depth_bits");
        s->thick_bits = eng_render_uint_layers(s->fw, s->fh, 5, "eng.surface.splat_thickness_bits");
        if (!s->depth_bits || !s->thick_bits) {
            eng_log(&r->def.logger, ENG_LOG_ERROR, "renderer: the compute splats' images (%dx%d) could not be made",
                    s->fw, s->fh);
            return false;
        }
        // Their first reset (the resolve resets them after every use from then on).
        bind_surface_resolve(s);
        resolve(&r->resolve_surface, s->fw, s->fh, 0, GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    mat4 view, proj;
    eng_camera_view(&r->cam, view);
    eng_camera_projection(&r->cam, r->aspect, proj);

    // The scene's depth at the water's size (as the raster passes' depth test has it), and
    // the float textures cleared to "no water" (the resolve writes only touched texels).
    int t = eng_render_timer_begin(r, "surface_thickness");
    const float zero[4] = { 0.0f, 0.0f, 0.0f, 0.0f };
    glBindFramebuffer(GL_FRAMEBUFFER, s->depth_fbo);
    glClearBufferfv(GL_COLOR, 0, zero);
    glBindFramebuffer(GL_FRAMEBUFFER, s->thick_fbo);
    glClearBufferfv(GL_COLOR, 0, zero);
    glClearBufferfv(GL_COLOR, 1, zero);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, s->scene_fbo);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, s->thick_fbo);
    glBlitFramebuffer(0, 0, s->width, s->height, 0, 0, s->fw, s->fh, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    glBindFramebuffer(GL_FRAMEBUFFER, 0); // fluid_ds is sampled below: attached to nothing bound
    bind_test(s->fluid_ds);
    glBindImageTexture(ENG_RENDER_IMG_SPLAT, s->thick_bits, 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
    splat_fluids(r, &r->splat_thick, (const float *)view, (const float *)proj, s->fw, s->fh);
    eng_render_timer_end(r, t);

    t = eng_render_timer_begin(r, "surface_depth");
    glBindImageTexture(ENG_RENDER_IMG_SPLAT, s->depth_bits, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    splat_fluids(r, &r->splat_depth, (const float *)view, (const float *)proj, s->fw, s->fh);
    eng_render_timer_end(r, t);

    t = eng_render_timer_begin(r, "surface_resolve");
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    bind_surface_resolve(s);
    resolve(&r->resolve_surface, s->fw, s->fh, 1, AFTER_RESOLVE);
    unbind_images();
    bind_test(0);
    eng_render_timer_end(r, t);
    return true;
}

static void bind_light_resolve(const shadow_map *s)
{
    glBindImageTexture(ENG_RENDER_IMG_SPLAT, s->bits, 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
    glBindImageTexture(ENG_RENDER_IMG_OUT0, s->front, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R32F);
    glBindImageTexture(ENG_RENDER_IMG_OUT1, s->thick, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
}

bool eng_splat_shadow(eng_renderer *r)
{
    shadow_map *s = &r->shadow;
    if (!large_list(r)) return false;
    if (!s->bits) {
        s->bits = eng_render_uint_layers(s->size, s->size, 2, "eng.shadow.splat_bits");
        if (!s->bits) {
            eng_log(&r->def.logger, ENG_LOG_ERROR, "renderer: the compute splats' shadow images (%dx%d) could not be made",
                    s->size, s->size);
            return false;
        }
        bind_light_resolve(s);
        resolve(&r->resolve_light, s->size, s->size, 0, GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    }
    // The casters' depth is read as a value here, not compared.
    glBindTexture(GL_TEXTURE_2D, s->depth);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    glBindTexture(GL_TEXTURE_2D, 0);
    bind_test(s->depth);
    glBindImageTexture(ENG_RENDER_IMG_SPLAT, s->bits, 0, GL_TRUE, 0, GL_READ_WRITE, GL_R32UI);
    glUseProgram(r->splat_light.prog);
    glUniform1f(r->splat_light.light_near, s->near_plane);
    splat_fluids(r, &r->splat_light, (const float *)s->view, (const float *)s->proj, s->size, s->size);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    bind_light_resolve(s);
    resolve(&r->resolve_light, s->size, s->size, 1, AFTER_RESOLVE);
    unbind_images();
    bind_test(0);
    glBindTexture(GL_TEXTURE_2D, s->depth);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    glBindTexture(GL_TEXTURE_2D, 0);
    return true;
}

// ---- the sphere modes -------------------------------------------------------------------
// Per fluid: SPLAT_NEAREST merges each texel's nearest hit (atomicMin of the eye depth's
// bits) into sphere_nearest; SPLAT_ID, after an image barrier, merges the index of a particle
// whose hit is that nearest into sphere_ids; spheres.frag (renderer.c draw_spheres) lights
// that particle at each pixel with the scene's depth test; a reset pass then puts both
// images back to all ones. Nothing is tested against the scene here: where the nearest
// sphere is hidden, every sphere there is.

static void bind_sphere_images(const eng_renderer *r, GLenum access)
{
    glBindImageTexture(ENG_RENDER_IMG_SPLAT, r->sphere_ids, 0, GL_FALSE, 0, access, GL_R32UI);
    glBindImageTexture(ENG_RENDER_IMG_SPLAT_LAYERS, r->sphere_nearest, 0, GL_FALSE, 0, access, GL_R32UI);
}

static void reset_spheres(eng_renderer *r)
{
    bind_sphere_images(r, GL_WRITE_ONLY);
    resolve(&r->resolve_spheres, r->sphere_w, r->sphere_h, 0, GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    unbind_images();
}

bool eng_splat_spheres_targets(eng_renderer *r)
{
    if (!large_list(r)) return false;
    if (r->sphere_ids && r->sphere_w == r->width && r->sphere_h == r->height) return true;
    drop_sphere_images(r);
    r->sphere_ids = eng_render_texture(GL_R32UI, r->width, r->height, GL_NEAREST, "eng.spheres.splat_ids");
    r->sphere_nearest = eng_render_texture(GL_R32UI, r->width, r->height, GL_NEAREST, "eng.spheres.splat_nearest");
    if (!r->sphere_ids || !r->sphere_nearest) {
        eng_log(&r->def.logger, ENG_LOG_ERROR, "renderer: the compute splats' sphere images (%dx%d) could not be made",
                r->width, r->height);
        drop_sphere_images(r); // the one that was made, if any
        return false;
    }
    r->sphere_w = r->width;
    r->sphere_h = r->height;
    reset_spheres(r); // their first reset; each use resets them after
    return true;
}

void eng_splat_spheres_find(eng_renderer *r, const queued_fluid *f)
{
    mat4 view, proj;
    eng_camera_view(&r->cam, view);
    eng_camera_projection(&r->cam, r->aspect, proj);
    glBindImageTexture(ENG_RENDER_IMG_SPLAT, r->sphere_nearest, 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    splat_begin(&r->splat_nearest, (const float *)view, (const float *)proj, r->width, r->height);
    splat_fluid(r, &r->splat_nearest, f);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT); // the nearest depths, read by SPLAT_ID
    bind_sphere_images(r, GL_READ_WRITE);
    splat_begin(&r->splat_id, (const float *)view, (const float *)proj, r->width, r->height);
    splat_fluid(r, &r->splat_id, f);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT); // the indices, read by spheres.frag
    glBindImageTexture(ENG_RENDER_IMG_SPLAT_LAYERS, 0, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    glBindImageTexture(ENG_RENDER_IMG_SPLAT, r->sphere_ids, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
}

void eng_splat_spheres_reset(eng_renderer *r)
{
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT); // spheres.frag's reads before the stores
    reset_spheres(r);
}
