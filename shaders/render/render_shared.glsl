// Constants shared by the renderer's C code (engine/renderer.c includes this file) and its
// GLSL. Only #define lines and comments here, so that it compiles as both.
#ifndef SEICHE_RENDER_SHARED
#define SEICHE_RENDER_SHARED

// Uniform block binding of the per-frame block (camera, light, sky; see frame.glsl).
#define ENG_RENDER_FRAME_UBO_BINDING 0
// Shader storage binding the particle pass reads positions from (vec4 per particle).
#define ENG_RENDER_PARTICLE_SSBO_BINDING 0

// Vertex attribute locations of eng_mesh_gpu meshes.
#define ENG_RENDER_ATTRIB_POSITION 0
#define ENG_RENDER_ATTRIB_NORMAL 1

#endif
