// Forward renderer: sky clear colour, a ground plane with a subtle checker, every visible
// node of an eng_scene Phong-lit with its colour (one directional light + ambient +
// specular), and fluid particles as lit sphere impostors read straight from GPU buffers.
//
// A frame:
//   eng_renderer_begin(r, ctx, &cam);                    // target, clear, ground
//   eng_renderer_draw_scene(r, scene, meshes);
//   eng_renderer_draw_particles(r, &cam, ssbo, indirect, radius, NULL);
//   eng_renderer_end(r);                                 // then eng_context_present(ctx)
//
// It draws into eng_context_framebuffer(ctx) at the context size. Each kind of geometry
// has a pass of its own (scene meshes, particle impostors); a screen-space fluid surface
// can later be a further pass that renders the same impostors' depth into an offscreen
// target, smooths it and composites it, beside eng_renderer_draw_particles.
//
// Shaders are embedded in the library (eng_render_sources) or, for shader development,
// read from eng_renderer_def.shader_dir ("<repo>/shaders"): render/*.vert,
// render/*.frag and their headers. GPU time per pass is measured with an eng_gpu_timer
// (sections "frame", "scene", "particles").
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
} eng_renderer_def;

/// shader_dir NULL (embedded), a light from above-front-right, pale blue sky, a 200 m grey ground
/// at y = 0 with 1 m checker cells, fog from 40 m to 100 m.
eng_renderer_def eng_default_renderer_def(void);

/// How particle impostors look. The colour parameter (w of each vec4) runs through
/// low (0) -> mid (0.5) -> high (1).
typedef struct eng_particle_style {
    float color_low[3];  ///< each 0..1
    float color_mid[3];
    float color_high[3];
    float specular;      ///< 0..1
    float shininess;     ///< 1..1024
} eng_particle_style;

/// Water: deep blue -> cyan -> near white, a sharp highlight.
eng_particle_style eng_default_particle_style(void);

typedef struct eng_renderer eng_renderer;

/// Builds the shader programs. NULL on failure, with the reason ("shaders/render/x.frag:12:
/// error: ...", or the def field that is out of range) in `err` (may be NULL) and the log.
eng_renderer *eng_renderer_create(const eng_renderer_def *def, char *err, size_t err_size);
void eng_renderer_destroy(eng_renderer *r);

/// Starts a frame: binds the context's framebuffer at its size, clears to the sky colour,
/// sets the camera and light, draws the ground.
void eng_renderer_begin(eng_renderer *r, eng_context *ctx, const eng_camera *cam);
/// Draws every node that has a valid mesh and is visible (with all its ancestors).
void eng_renderer_draw_scene(eng_renderer *r, eng_scene *scene, const eng_mesh_store *meshes);
/// Draws one mesh with a model matrix (object -> world) and a colour (rgb 0..1).
void eng_renderer_draw_mesh(eng_renderer *r, const eng_mesh_store *meshes, eng_mesh_id mesh,
                            mat4 model, const float color[3]);
/// Draws particles as lit spheres of `radius` m. `positions_ssbo` holds one vec4 per
/// particle (xyz position in m, w colour parameter 0..1); `draw_indirect_buffer` holds a
/// DrawArraysIndirectCommand {count = 4, instanceCount = N, first = 0, baseInstance = 0}
/// written on the GPU. Nothing is read back. `style` NULL: eng_default_particle_style().
/// Issues the shader-storage and command barriers itself.
void eng_renderer_draw_particles(eng_renderer *r, const eng_camera *cam, GLuint positions_ssbo,
                                 GLuint draw_indirect_buffer, float radius, const eng_particle_style *style);
/// Ends the frame (GL state back to defaults, timer results collected). Does not present.
void eng_renderer_end(eng_renderer *r);

/// The renderer's GPU timer (sections "frame", "scene", "particles").
eng_gpu_timer *eng_renderer_gpu_timer(eng_renderer *r);
/// Changes the sky colour and the light from the next frame on (same ranges as the def).
bool eng_renderer_set_light(eng_renderer *r, const eng_light *light);
bool eng_renderer_set_sky(eng_renderer *r, const float sky_color[3]);

#endif
