// Inside the renderer: the state renderer.c, shadow.c, surface.c and splat.c share. Not for use
// outside engine/render/.
//
//   render_def.c  defaults and the checks of defs, looks and styles
//   renderer.c  the frame (queue, then the passes in order), meshes and
//               sphere impostors
//   shadow.c    the light's view and the shadow map (opaque casters, the water's front and
//               thickness)
//   surface.c   the screen-space water: targets, thickness, depth, smoothing, composite
//   splat.c     the water's particle passes (surface thickness and depth, the shadow's
//               water, the sphere modes' nearest particle) by compute shaders, when the
//               look's splat is compute; the spray's cull
#ifndef ENG_RENDER_INTERNAL_H
#define ENG_RENDER_INTERNAL_H

#include "engine/render/renderer.h"

#define MAX_FLUIDS 4
#define MAX_SCENES 8

// Mirror of the std140 block `Frame` in shaders/render/frame.glsl.
typedef struct eng_frame_block {
    float view[16];
    float proj[16];
    float inv_view[16];
    float light_viewproj[16];
    float camera_pos[4];
    float light_dir[4];
    float light_color[4];
    float ambient[4];
    float sky_color[4];
    float fog[4];
    float ground_color[4];
    float shadow[4];
    float water_light[4];
    float viewport[4];
} eng_frame_block;
_Static_assert(sizeof(eng_frame_block) == 4 * 64 + 10 * 16, "eng_frame_block must match the std140 block Frame");

typedef struct mesh_prog {
    GLuint prog;
    GLint model, normal_model, color, specular, shininess, checker_cell;
} mesh_prog;

// One program over particles.vert; a location is -1 where that program has no such uniform.
typedef struct particle_prog {
    GLuint prog;
    GLint radius, count, fill, light_view, light_proj, light_near;
    GLint color_mode, color_range, particle_mass, inv_rest_density, color_low, color_mid, color_high;
    GLint specular, shininess;
    GLint spray;
} particle_prog;

// One compute program of the splats (splat.comp, splat_resolve.comp); -1 where it has no
// such uniform.
typedef struct splat_prog {
    GLuint prog;
    GLint radius, count, fill, size, view, proj, light_near, store;
    GLint groups, spray_speed, spray_density, particle_mass, inv_rest_density; // spray_cull.comp
    GLint stage;                                                                 // splat.comp
} splat_prog;

typedef struct queued_mesh {
    const eng_mesh_store *meshes;
    eng_mesh_id mesh;
    mat4 model;
    float color[3];
} queued_mesh;

typedef struct queued_scene {
    eng_scene *scene;
    const eng_mesh_store *meshes;
} queued_scene;

typedef struct queued_fluid {
    eng_fluid_draw d;
    eng_particle_style style;
    GLint count; // particles the buffers hold (the smaller of the two)
} queued_fluid;

typedef struct shadow_map {
    int size;
    GLuint fbo, depth, front, thick;
    bool has_bounds;
    float lo[3], hi[3];
    mat4 view, proj, viewproj;
    float near_plane, range; // m
    GLuint bits;             // compute splats: R32UI, 2 layers (front code, thickness)
} shadow_map;

typedef struct surface_targets {
    int width, height;   // the scene target (the context's size)
    int fw, fh;          // the water's textures
    GLuint scene_fbo, scene_color, scene_depth;
    GLuint fluid_ds;     // D32F at the water's size: the scene's depth, then the particles'
    GLuint depth_fbo, depth;   // raw eye depth (R32F) + fluid_ds
    GLuint thick_fbo, thick;   // thickness (R16F) + fluid_ds (tested only)
    GLuint tint;               // the tinted share (RGBA16F), thick_fbo's second target
    GLuint smooth_fbo[2], smooth[2], smooth_thick[2]; // [0] along y, [1] then along x
    GLuint depth_bits;   // compute splats: R32UI, the nearest eye depth's bits
    GLuint thick_bits;   // compute splats: R32UI, 5 layers (thickness, tinted rgb and a)
    bool drawn;          // the latest frame drew the surface
} surface_targets;

struct eng_renderer {
    eng_renderer_def def;
    mesh_prog mesh, mesh_shadow;
    particle_prog spheres, fluid_depth, fluid_thick, fluid_shadow, fluid_spray;
    particle_prog spheres_lit; // the sphere modes from compute splats (fullscreen.vert, spheres.frag)
    splat_prog splat_depth, splat_thick, splat_light, resolve_surface, resolve_light;
    splat_prog splat_nearest, splat_id, resolve_spheres;
    splat_prog spray_count, spray_scan, spray_write;
    GLuint spray_list, spray_cmd, spray_groups; // the spray pass's draw (spray_cull.comp)
    GLint spray_capacity;                       // drops spray_list holds
    GLuint splat_big;                           // splat.comp's list of large spheres
    GLint splat_big_capacity;                   // particles it holds
    GLuint sphere_ids, sphere_nearest;          // the sphere modes' splats: R32UI at the frame's size
    int sphere_w, sphere_h;
    GLuint smooth_prog, composite_prog;
    GLint smooth_step, smooth_world_radius, smooth_px_per_m, smooth_max_px, smooth_range;
    GLint comp_fluid_size, comp_layer, comp_absorption, comp_scatter, comp_refraction, comp_reflection,
        comp_specular, comp_shininess, comp_view_mode;
    GLuint empty_vao; // attribute-less draws (impostors, full-screen triangles)
    GLuint frame_ubo;
    eng_mesh_store *own_meshes; // the ground plane
    eng_mesh_id ground;
    eng_gpu_timer *timer;
    bool flush_timestamps; // llvmpipe records a timestamp only when its commands are flushed
    shadow_map shadow;
    surface_targets surf;
    bool warned_no_velocities;
    // Per frame.
    bool in_frame;
    eng_context *ctx;
    eng_camera cam;
    int width, height;
    float aspect;
    int t_frame;
    bool warned_stale_mesh;
    queued_scene scenes[MAX_SCENES];
    int scene_count;
    queued_mesh *meshes;
    int mesh_count, mesh_cap;
    queued_fluid fluids[MAX_FLUIDS];
    int fluid_count;
};

// render_def.c: checks; false with the message (naming the field) logged and in `err`
bool eng_render_check_rgb(const eng_logger *log, char *err, size_t err_size, const char *field, const float c[3],
                          float hi);
bool eng_render_check_light(const eng_logger *log, char *err, size_t err_size, const char *field, const eng_light *l);
bool eng_render_check_look(const eng_logger *log, char *err, size_t err_size, const char *field,
                           const eng_fluid_look *k);
bool eng_render_check_def(const eng_renderer_def *d, char *err, size_t err_size);
bool eng_render_check_style(const eng_logger *log, const eng_particle_style *s);

// renderer.c
GLuint eng_render_build(const eng_renderer_def *d, const char *vert, const char *frag, const char *defines,
                        const char *label, char *err, size_t err_size);
int eng_render_timer_begin(eng_renderer *r, const char *name);
void eng_render_timer_end(eng_renderer *r, int section);
void eng_render_write_frame(eng_renderer *r, int target_width, int target_height);
/// Draws every queued scene node and mesh with the program in use (mesh_prog locations).
void eng_render_draw_queued_meshes(eng_renderer *r, const mesh_prog *p);
/// Binds a queued fluid's buffers and sets the particle uniforms common to every pass.
void eng_render_bind_fluid(const particle_prog *p, const queued_fluid *f);
/// Issues the indirect draw of a bound fluid.
void eng_render_draw_fluid_instances(const queued_fluid *f);
void eng_render_label(GLenum kind, GLuint name, const char *label);
GLuint eng_render_texture(GLenum internal_format, int w, int h, GLenum filter, const char *label);
GLuint eng_render_framebuffer(const GLuint *colors, int color_count, GLuint depth, const char *label);

// shadow.c
bool eng_shadow_create(eng_renderer *r, char *err, size_t err_size);
void eng_shadow_destroy(eng_renderer *r);
/// The light's matrices from the shadow bounds and the light (before eng_render_write_frame).
void eng_shadow_prepare(eng_renderer *r);
/// The shadow pass; nothing when shadows are off. Leaves the shadow textures bound to
/// their units (ENG_RENDER_TEX_SHADOW*) for the lit passes.
void eng_shadow_render(eng_renderer *r);

// surface.c
bool eng_surface_create(eng_renderer *r, char *err, size_t err_size);
void eng_surface_destroy(eng_renderer *r);
/// Makes the targets for a w x h frame (remade when the size or resolution changed);
/// false (logged) when GL could not.
bool eng_surface_targets(eng_renderer *r, int w, int h);
/// The water passes after the opaque scene was drawn into surf.scene_fbo; ends with the
/// composite into the context's framebuffer.
void eng_surface_render(eng_renderer *r);

// splat.c: the particle passes of the surface and the shadow map by compute shaders
// (eng_fluid_look.splat = ENG_FLUID_SPLAT_COMPUTE)
bool eng_splat_create(eng_renderer *r, char *err, size_t err_size);
void eng_splat_destroy(eng_renderer *r);
/// An R32UI 2D array texture of `layers` layers (no sampling: for image atomics).
GLuint eng_render_uint_layers(int w, int h, int layers, const char *label);
/// The surface's thickness, tint and depth (surf.thick, surf.tint, surf.depth), as the
/// raster passes would write them; false (logged) if its images could not be made.
bool eng_splat_surface(eng_renderer *r);
/// The sphere modes' images at the frame's size (made or remade, then reset); false
/// (logged) if GL could not make them: the raster impostors draw instead.
bool eng_splat_spheres_targets(eng_renderer *r);
/// Fluid `f`'s nearest particle at each pixel (splat.comp SPLAT_NEAREST, then SPLAT_ID)
/// into r->sphere_ids, bound to ENG_RENDER_IMG_SPLAT for spheres.frag, with the barrier
/// for its reads. Changes the program in use.
void eng_splat_spheres_find(eng_renderer *r, const queued_fluid *f);
/// After spheres.frag drew from them: the images reset for the next fluid or frame and
/// unbound. Changes the program in use.
void eng_splat_spheres_reset(eng_renderer *r);
/// Lists the spray of fluid `f` (spray_cull.comp) into r->spray_list and its indirect
/// command r->spray_cmd, with the barriers for the draw that reads them; false (logged)
/// if the buffers could not be made.
bool eng_spray_cull(eng_renderer *r, const queued_fluid *f);
/// The water's front and thickness into the shadow map (after the casters were drawn,
/// with no framebuffer bound); false (logged) if its images could not be made.
bool eng_splat_shadow(eng_renderer *r);

#endif
