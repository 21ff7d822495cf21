// The renderer: sky, a ground plane with a subtle checker, every visible node of an
// eng_scene Phong-lit with its colour (one directional light + ambient + specular), the
// light's shadow map (bodies, walls and the water), and the fluid drawn straight from its
// GPU buffers in one of four modes (eng_fluid_mode): a screen-space water surface (the
// default), or lit sphere impostors coloured by initial height, density or speed.
//
// A frame:
//   eng_renderer_begin(r, ctx, &cam);
//   eng_renderer_draw_scene(r, scene, meshes);           // queued
//   eng_renderer_draw_fluid(r, &fluid);                  // queued (or draw_particles)
//   eng_renderer_end(r);                                 // draws; then eng_context_present(ctx)
//
// The draw calls queue what they are given and eng_renderer_end draws it all, because the
// shadow map needs every caster before the first lit pixel, and the water needs the
// opaque scene behind it. The passes, in order (docs/architecture.md, "Rendering"):
//   shadow             opaque casters' depth from the light; the water's nearest distance
//                      from the light and its thickness along the light rays
//   scene              ground and meshes (into the renderer's own target in surface mode)
//   surface_thickness  water thickness along each view ray (additive)
//   surface_depth      the particles' eye depth (sphere impostors, nearest wins)
//   surface_smooth     the narrow-range filter on that depth, a Gaussian on the thickness
//   surface_composite  refraction, absorption, Fresnel reflection, highlight, shadow; the
//                      water's depth written, so that what is drawn later sorts with it
//   surface_spray      fast drops with few neighbours as soft white discs over it
//   particles          (sphere modes) lit impostors into the context's framebuffer
// No pass reads anything back to the CPU. Each is timed with the renderer's eng_gpu_timer
// under the names above, and "frame" for all of it.
//
// It draws into eng_context_framebuffer(ctx) at the context size, colour and depth.
// Shaders are embedded in the library (eng_render_sources) or, for shader development,
// read from eng_renderer_def.shader_dir ("<repo>/shaders"): render/*.vert, render/*.frag
// and their headers.
#ifndef ENG_RENDERER_H
#define ENG_RENDERER_H

#include <cglm/cglm.h>
#include <epoxy/gl.h>
#include <stdbool.h>
#include <stddef.h>

#include "engine/render/camera.h"
#include "engine/gl/context.h"
#include "engine/gl/gpu_timer.h"
#include "engine/core/log.h"
#include "fluid/pbf.h"
#include "fluid/pbf_glsl.h"
#include "engine/render/mesh.h"
#include "engine/render/scene.h"

typedef struct eng_light {
    float direction[3]; ///< from the scene towards the light, world space (normalised on use; non-zero)
    float color[3];     ///< light colour times intensity, each 0..4
    float ambient[3];   ///< ambient light, each 0..1
} eng_light;

/// The renderer's shader sources (shaders/render/*), embedded at build time.
pbf_glsl_source eng_render_sources(void);

/// How the fluid is drawn.
typedef enum eng_fluid_mode {
    ENG_FLUID_SURFACE = 0, ///< a smooth, refracting, absorbing water surface (screen space)
    ENG_FLUID_SPHERES,     ///< lit spheres coloured by initial height (eng_particle_style)
    ENG_FLUID_DENSITY,     ///< spheres coloured by density: blue below rho0, white at it, red above
    ENG_FLUID_SPEED,       ///< spheres coloured by speed: dark blue (still) to red (fast)
    ENG_FLUID_MODE_COUNT
} eng_fluid_mode;

/// "surface", "spheres", "density", "speed"; NULL for a value out of range.
const char *eng_fluid_mode_name(eng_fluid_mode mode);
/// The mode of that name; false (and `mode` unchanged) for any other text.
bool eng_fluid_mode_parse(const char *name, eng_fluid_mode *mode);
/// "surface|spheres|density|speed", for usage and error messages.
const char *eng_fluid_mode_names(void);

/// Debug views of the surface mode: what the composite shows where the water is.
typedef enum eng_fluid_view {
    ENG_FLUID_VIEW_SHADED = 0, ///< the water
    ENG_FLUID_VIEW_DEPTH,      ///< smoothed eye depth, grey, repeating every metre
    ENG_FLUID_VIEW_NORMALS,    ///< world normal * 0.5 + 0.5
    ENG_FLUID_VIEW_THICKNESS,  ///< 1 - exp(-2 thickness/m), grey
    ENG_FLUID_VIEW_COUNT
} eng_fluid_view;

/// How the water's particle passes (the surface's depth and thickness, the water in the
/// shadow map) are drawn: through the raster pipeline (sphere impostors), or by a compute
/// shader that walks each sphere's texels and merges with atomics (the same images to
/// rounding; for GPUs with little raster hardware). The spheres modes and the spray always
/// use the raster pipeline. Compute is the default: on llvmpipe it drew a 200k-particle
/// surface frame in 0.6 of the time (docs/performance.md).
typedef enum eng_fluid_splat {
    ENG_FLUID_SPLAT_RASTER = 0, ///< sphere impostors, depth test and blending
    ENG_FLUID_SPLAT_COMPUTE,    ///< splat.comp and splat_resolve.comp
    ENG_FLUID_SPLAT_COUNT
} eng_fluid_splat;

/// How the fluid looks, and the shadows: the settings `seiche.render{...}` changes (its Lua
/// binding reads eng_renderer_fluid_look, sets the fields the table names, and applies
/// the whole with eng_renderer_set_fluid_look, which checks every field).
typedef struct eng_fluid_look {
    eng_fluid_mode mode;
    float absorption[3];    ///< surface: Beer-Lambert absorption of the water, 1/m per channel, each 0..100;
                            ///< also tints the light under water in the shadow map
    float scatter[3];       ///< surface: colour the bulk sends back (lit by ambient + light), each 0..1
    float refraction;       ///< surface: strength of the refraction offset, 0..4 (1: about water's)
    float reflection;       ///< surface: Fresnel reflectance at normal incidence F0, 0..1 (water 0.02)
    float specular;         ///< surface: strength of the sun's highlight, 0..8
    float shininess;        ///< surface: its Blinn-Phong exponent, 1..8192
    float smoothing;        ///< surface: smoothing radius in particle radii, 0..16 (0: none)
    float spray;            ///< surface: opacity of spray drawn over the water, 0..1 (0: none):
                            ///< drops faster than spray_speed with few neighbours (needs velocities)
    float spray_speed;      ///< surface: m/s where spray starts (full at twice that), (0, 1000]
    float resolution;       ///< surface: size of the water's textures against the target, 0.25..1
    float density_range[2]; ///< density mode: rho/rho0 at the blue and the red end, 0 < [0] < [1] <= 10
    float speed_max;        ///< speed mode: m/s at the red end, (0, 1000]
    bool shadows;           ///< the light's shadow map (bodies, walls, ground and water)
    eng_fluid_view view;    ///< surface: a debug view instead of the shaded water
    eng_fluid_splat splat;  ///< surface, shadows and sphere modes: how the particle passes are drawn
} eng_fluid_look;

/// Surface mode, water absorbing (3, 1, 0.45)/m, half-resolution surface textures,
/// smoothing over 6 particle radii, spray from 1.5 m/s at 0.6 opacity, density map 0.9..1.1 rho0, speed map 0..2 m/s, shadows,
/// compute splats.
eng_fluid_look eng_default_fluid_look(void);

typedef struct eng_renderer_def {
    const char *shader_dir;  ///< NULL: the embedded shaders; else a directory holding render/
    eng_logger logger;
    float sky_color[3];      ///< clear and fog colour, each 0..1
    eng_light light;
    float specular;          ///< highlight strength on scene meshes, 0..1
    float shininess;         ///< Phong exponent of scene meshes, 1..1024
    bool ground;             ///< draw the ground plane
    float ground_height;     ///< y of the ground plane, m
    float ground_size;       ///< side of the square ground plane, m, > 0
    float ground_cell;       ///< checker cell size, m, > 0
    float ground_color[3];   ///< albedo, each 0..1
    float fog_start;         ///< distance where fog begins, m, >= 0
    float fog_end;           ///< distance where only sky remains, m, > fog_start
    eng_fluid_look fluid;    ///< see eng_fluid_look
    int shadow_size;         ///< shadow map side in texels, 64..8192
} eng_renderer_def;

/// shader_dir NULL (embedded), a light from above-front-right, pale blue sky, a 200 m grey ground
/// at y = 0 with 1 m checker cells, fog from 40 m to 100 m, eng_default_fluid_look(), a
/// 2048-texel shadow map.
eng_renderer_def eng_default_renderer_def(void);

/// How particle impostors look in the spheres mode. The colour parameter (w of each vec4)
/// runs through low (0) -> mid (0.5) -> high (1).
typedef struct eng_particle_style {
    float color_low[3];  ///< each 0..1
    float color_mid[3];
    float color_high[3];
    float specular;      ///< 0..1
    float shininess;     ///< 1..1024
} eng_particle_style;

/// Water: deep blue -> cyan -> near white, a sharp highlight.
eng_particle_style eng_default_particle_style(void);

/// A fluid to draw, straight from its GPU buffers (pbf_world_gpu_buffers gives them).
typedef struct eng_fluid_draw {
    GLuint positions;       ///< SSBO, a vec4 per particle: xyz m, w colour parameter 0..1 (required)
    GLuint velocities;      ///< SSBO, a vec4 per particle: xyz m/s, w the particle's volume m^3
                            ///< (mass / density; the fluid's velocity buffer). 0: none; the
                            ///< density and speed modes then colour by height (with a warning)
    GLuint draw_indirect;   ///< DrawArraysIndirectCommand {count 4, instanceCount N, 0, 0},
                            ///< written on the GPU (required)
    float radius;           ///< particle radius, m, > 0
    float particle_mass;    ///< kg, > 0 with velocities: density = mass / volume
                            ///< (pbf_derive_constants(params).mass)
    float rest_density;     ///< rho0, kg/m^3, > 0 with velocities (the density map's white)
    const eng_particle_style *style; ///< spheres mode colours; NULL: eng_default_particle_style()
} eng_fluid_draw;

/// All zero but radius 0.02 m, mass 0.064 kg (its water cube), rest density 1000 kg/m^3.
eng_fluid_draw eng_default_fluid_draw(void);

/// The draw of a Seiche fluid world (pbf_world_gpu_buffers, its radius, particle mass and
/// rest density) with the spheres mode's `style` (may be NULL). Ask again after every step:
/// the buffers swap. A NULL world gives eng_default_fluid_draw() (no buffers: refused).
eng_fluid_draw eng_fluid_draw_of(const pbf_world *world, const eng_particle_style *style);

typedef struct eng_renderer eng_renderer;

/// Builds the shader programs. NULL on failure, with the reason ("shaders/render/x.frag:12:
/// error: ...", or the def field that is out of range) in `err` (may be NULL) and the log.
eng_renderer *eng_renderer_create(const eng_renderer_def *def, char *err, size_t err_size);
void eng_renderer_destroy(eng_renderer *r);

/// Starts a frame with the camera `cam` into the context's framebuffer at its size.
void eng_renderer_begin(eng_renderer *r, eng_context *ctx, const eng_camera *cam);
/// Queues every node that has a valid mesh and is visible (with all its ancestors); the
/// nodes are read at eng_renderer_end (at most 8 scenes a frame).
void eng_renderer_draw_scene(eng_renderer *r, eng_scene *scene, const eng_mesh_store *meshes);
/// Queues one mesh with a model matrix (object -> world) and a colour (rgb 0..1).
void eng_renderer_draw_mesh(eng_renderer *r, const eng_mesh_store *meshes, eng_mesh_id mesh,
                            mat4 model, const float color[3]);
/// Queues a fluid (at most 4 a frame), checked now; the buffers are read on the GPU at
/// eng_renderer_end, which issues the shader-storage and command barriers itself.
void eng_renderer_draw_fluid(eng_renderer *r, const eng_fluid_draw *fluid);
/// eng_renderer_draw_fluid with positions only. `cam`: NULL or the frame's camera (any
/// other is refused: everything is drawn with the camera of eng_renderer_begin).
void eng_renderer_draw_particles(eng_renderer *r, const eng_camera *cam, GLuint positions_ssbo,
                                 GLuint draw_indirect_buffer, float radius, const eng_particle_style *style);
/// Draws the frame, leaves GL state at defaults (the context's framebuffer bound, its full
/// viewport, depth test on, blending off, program 0, VAO 0, texture units 0..8, storage
/// buffer bindings 0..6 and image units 0..4 unbound)
/// and collects timer results. Does not present.
void eng_renderer_end(eng_renderer *r);

/// The renderer's GPU timer (sections named in the passes above, and "frame").
eng_gpu_timer *eng_renderer_gpu_timer(eng_renderer *r);
/// Changes the sky colour and the light from the next frame on (same ranges as the def).
bool eng_renderer_set_light(eng_renderer *r, const eng_light *light);
bool eng_renderer_set_sky(eng_renderer *r, const float sky_color[3]);

/// The fluid look from the next frame on; every field checked, nothing changed (and the
/// field named in the log: "eng_fluid_look.absorption[1] must be 0..100 (got -1)") if one
/// is out of range. For `seiche.render{...}`.
bool eng_renderer_set_fluid_look(eng_renderer *r, const eng_fluid_look *look);
/// Checks a look without a renderer (for scripts): false with "<field>.<name> must be ...
/// (got ...)" in err when a field is out of range; nothing is logged.
bool eng_fluid_look_check(const eng_fluid_look *look, const char *field, char *err, size_t err_size);
/// "shaded", "depth", "normals", "thickness"; NULL for a value out of range.
const char *eng_fluid_view_name(eng_fluid_view view);
/// The view of that name; false (and `view` unchanged) for any other text.
bool eng_fluid_view_parse(const char *name, eng_fluid_view *view);
/// "raster", "compute"; NULL for a value out of range.
const char *eng_fluid_splat_name(eng_fluid_splat splat);
/// The splat of that name; false (and `splat` unchanged) for any other text.
bool eng_fluid_splat_parse(const char *name, eng_fluid_splat *splat);
/// The current look (as set, or the def's).
eng_fluid_look eng_renderer_fluid_look(const eng_renderer *r);
/// Only the mode (the runner's --render and its `v` key); false for a value out of range.
bool eng_renderer_set_fluid_mode(eng_renderer *r, eng_fluid_mode mode);
eng_fluid_mode eng_renderer_fluid_mode(const eng_renderer *r);
/// The box the shadow map covers (world, m; each lo < hi): what casts and receives shadows
/// inside it. Until set, a box of 8 m around the first frame's camera target.
bool eng_renderer_set_shadow_bounds(eng_renderer *r, const float lo[3], const float hi[3]);

/// The surface mode's intermediate textures, as the latest frame left them (0 when that
/// frame drew no surface): for tests and debugging tools. Sizes in texels.
typedef struct eng_surface_textures {
    GLuint depth;          ///< R32F eye depth of the particles, m (0: no water)
    GLuint smoothed;       ///< R32F the same after smoothing (== depth when smoothing is 0)
    GLuint thickness;      ///< R16F water along the view ray, m, smoothed as the depth is
    int width, height;     ///< of the three above
} eng_surface_textures;
eng_surface_textures eng_renderer_surface_textures(const eng_renderer *r);

#endif
