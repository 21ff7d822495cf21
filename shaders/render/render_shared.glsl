// Constants shared by the renderer's C code (engine/render/*.c include this file) and its
// GLSL. Only #define lines and comments here, so that it compiles as both.
#ifndef SEICHE_RENDER_SHARED
#define SEICHE_RENDER_SHARED

// Uniform block binding of the per-frame block (camera, light, sky, shadow; frame.glsl).
#define ENG_RENDER_FRAME_UBO_BINDING 0
// Shader storage bindings the particle passes read: positions (vec4 per particle: xyz m,
// w colour parameter) and velocities (vec4: xyz m/s, w the particle's volume m^3).
#define ENG_RENDER_PARTICLE_SSBO_BINDING 0
#define ENG_RENDER_VELOCITY_SSBO_BINDING 1
// The compute splats (splat.comp) also read the fluid's indirect draw command, whose
// instanceCount is the particle count now.
#define ENG_RENDER_DRAW_SSBO_BINDING 2
// The spray pass's own draw (spray_cull.comp): the list of drops, their indirect command,
// and the per-work-group counts and offsets of the cull.
#define ENG_RENDER_SPRAY_LIST_BINDING 3
#define ENG_RENDER_SPRAY_CMD_BINDING 4
#define ENG_RENDER_SPRAY_GROUPS_BINDING 5
// The compute splats' list of spheres too large for one invocation (splat.comp).
#define ENG_RENDER_SPLAT_BIG_BINDING 6

// Vertex attribute locations of eng_mesh_gpu meshes.
#define ENG_RENDER_ATTRIB_POSITION 0
#define ENG_RENDER_ATTRIB_NORMAL 1

// Texture units. The shadow map's three textures stay bound for the whole frame (every
// lit pass reads them); the surface passes use the units after them.
#define ENG_RENDER_TEX_SHADOW 0        // opaque depth from the light (sampler2DShadow)
#define ENG_RENDER_TEX_SHADOW_FRONT 1  // R32F: distance from the light to the first water, m
#define ENG_RENDER_TEX_SHADOW_THICK 2  // R16F: water thickness along the light ray, m
#define ENG_RENDER_TEX_SCENE_COLOR 3   // the opaque scene behind the water (RGBA8)
#define ENG_RENDER_TEX_SCENE_DEPTH 4   // its depth (D32F, window depth 0..1)
#define ENG_RENDER_TEX_FLUID_DEPTH 5   // eye depth of the water, m (R32F, 0 = no water)
#define ENG_RENDER_TEX_FLUID_THICK 6   // water thickness along the view ray, m (R16F)
#define ENG_RENDER_TEX_FLUID_TINT 7    // RGBA16F: tinted particles' colour times thickness
                                       // (rgb) and their thickness (a), m: unsmoothed
#define ENG_RENDER_TEX_SPLAT_TEST 8    // the compute splats' depth test (window depth 0..1)

// Image units of the compute splats (splat.comp, splat_resolve.comp): the integer images
// they merge into, and the float textures the resolve writes.
#define ENG_RENDER_IMG_SPLAT 0
#define ENG_RENDER_IMG_SPLAT_LAYERS 1
#define ENG_RENDER_IMG_OUT0 2
#define ENG_RENDER_IMG_OUT1 3
#define ENG_RENDER_IMG_OUT2 4
// Fixed point of the splats' sums: units per metre of thickness (2^20: a texel holds up to
// 4096 m, to a micrometre).
#define ENG_RENDER_SPLAT_SCALE 1048576.0
// A sphere covering more texels than this is splatted by a whole work group (splat.comp).
#define ENG_RENDER_SPLAT_BIG 256
// The shadow map's front where no water is: m past the light's near plane.
#define ENG_RENDER_SPLAT_FAR 1e30

// Colour modes of the sphere impostors (eng_fluid_mode's sphere modes).
#define ENG_RENDER_COLOR_HEIGHT 0  // the w of each position (initial height, or a tint: w <= -1)
#define ENG_RENDER_COLOR_DENSITY 1 // particle_mass / velocity.w against rho0
#define ENG_RENDER_COLOR_SPEED 2   // |velocity.xyz|

// Debug views of the surface composite (eng_fluid_look.debug_view).
#define ENG_RENDER_VIEW_SHADED 0
#define ENG_RENDER_VIEW_DEPTH 1     // smoothed eye depth, grey
#define ENG_RENDER_VIEW_NORMALS 2   // world normal * 0.5 + 0.5
#define ENG_RENDER_VIEW_THICKNESS 3 // thickness, grey

#endif
