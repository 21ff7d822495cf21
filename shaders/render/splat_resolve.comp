#version 430 core
// After splat.comp: each texel's integer sums become the float textures the raster passes
// would have written, and the integer images are reset for the next frame (so nothing
// clears them separately). A texel no sphere touched is left alone: its images hold their
// reset values already, and its float textures were cleared to "no water" before the
// splats (the shadow pass's clears; splat.c's for the surface). With u_store 0 it only
// resets (the images' first use).
//   RESOLVE_SURFACE  depth bits (no hit: 0) -> the eye depth (R32F, 0: no water);
//                    layers 0..4 -> thickness (R16F) and the tinted share (RGBA16F)
//   RESOLVE_LIGHT    layer 0, the front's code (no hit: ENG_RENDER_SPLAT_FAR) -> R32F;
//                    layer 1 -> thickness (R16F)
//   RESOLVE_SPHERES  only resets, after spheres.frag read them: the nearest depth's bits
//                    and the nearest particle's index (none: all ones both)
#include "render_shared.glsl"
#include "splat_order.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

uniform ivec2 u_size;
uniform int u_store;

#ifdef RESOLVE_SURFACE
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT) uniform coherent uimage2D u_depth_bits;
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT_LAYERS) uniform coherent uimage2DArray u_thick_bits;
layout(r32f, binding = ENG_RENDER_IMG_OUT0) uniform writeonly image2D u_depth;
layout(r16f, binding = ENG_RENDER_IMG_OUT1) uniform writeonly image2D u_thick;
layout(rgba16f, binding = ENG_RENDER_IMG_OUT2) uniform writeonly image2D u_tint;
#endif
#ifdef RESOLVE_SPHERES
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT) uniform writeonly uimage2D u_ids;
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT_LAYERS) uniform writeonly uimage2D u_nearest;
#endif
#ifdef RESOLVE_LIGHT
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT) uniform coherent uimage2DArray u_bits;
layout(r32f, binding = ENG_RENDER_IMG_OUT0) uniform writeonly image2D u_front;
layout(r16f, binding = ENG_RENDER_IMG_OUT1) uniform writeonly image2D u_thick;
#endif

void main()
{
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(t, u_size))) return;
    const float k = 1.0 / ENG_RENDER_SPLAT_SCALE;
#ifdef RESOLVE_SURFACE
    if (u_store != 0) {
        uint d = imageLoad(u_depth_bits, t).r, s[5];
        s[0] = imageLoad(u_thick_bits, ivec3(t, 0)).r;
        if (d == 0xffffffffu && s[0] == 0u) return; // untouched (a tint comes with a thickness)
        imageStore(u_depth, t, vec4(d == 0xffffffffu ? 0.0 : uintBitsToFloat(d)));
        for (int i = 1; i < 5; i++) s[i] = imageLoad(u_thick_bits, ivec3(t, i)).r;
        imageStore(u_thick, t, vec4(float(s[0]) * k));
        imageStore(u_tint, t, vec4(float(s[1]), float(s[2]), float(s[3]), float(s[4])) * k);
    }
    imageStore(u_depth_bits, t, uvec4(0xffffffffu));
    for (int i = 0; i < 5; i++) imageStore(u_thick_bits, ivec3(t, i), uvec4(0u));
#endif
#ifdef RESOLVE_SPHERES
    imageStore(u_ids, t, uvec4(0xffffffffu));
    imageStore(u_nearest, t, uvec4(0xffffffffu));
#endif
#ifdef RESOLVE_LIGHT
    uint far_code = splat_order(ENG_RENDER_SPLAT_FAR);
    if (u_store != 0) {
        uint front = imageLoad(u_bits, ivec3(t, 0)).r, thick = imageLoad(u_bits, ivec3(t, 1)).r;
        if (front == far_code && thick == 0u) return; // untouched
        imageStore(u_front, t, vec4(splat_value(front)));
        imageStore(u_thick, t, vec4(float(thick) * k));
    }
    imageStore(u_bits, ivec3(t, 0), uvec4(far_code));
    imageStore(u_bits, ivec3(t, 1), uvec4(0u));
#endif
}
