#version 430 core
// The water's particle passes drawn by a compute shader instead of the raster pipeline
// (eng_fluid_look.splat = compute; docs/architecture.md, "Rendering"): one invocation per
// particle walks the texels its sphere covers and merges into 32-bit integer images with
// atomics, which splat_resolve.comp then turns into the textures the raster passes write.
// The same sphere and the same tests per texel centre as particles.vert with
//   SPLAT_DEPTH  fluid_depth.frag: the nearest hit's eye depth (atomicMin of its bits; a
//                positive float's bits order as the float), tested against the scene's
//                window depth at the hit
//   SPLAT_THICK  fluid_thickness.frag: the chord times u_fill, and a tinted particle's
//                colour times chord and chord, added in fixed point (ENG_RENDER_SPLAT_SCALE
//                per metre; exact, so the sums do not depend on the order), tested at the
//                depth of the plane through the centre, as the raster quad is
//   SPLAT_LIGHT  shadow_fluid.frag: from the light (orthographic), the nearest water's
//                distance past the near plane (atomicMin of an order-keeping code) and the
//                chord, behind no opaque caster
//   SPLAT_NEAREST  the sphere modes (particles.frag), first: as SPLAT_DEPTH, untested
//                (nothing nearer than the nearest sphere can hide it: spheres.frag's depth
//                test against the scene decides)
//   SPLAT_ID     then: the index of a particle whose hit is the nearest (within 16 units in
//                the last place; the lowest such index, as the raster pass keeps the first
//                drawn), atomicMin into another image, for spheres.frag to light
// A GPU whose raster hardware is scarce (a data-centre part) draws a million point sprites
// slowly; these passes use none of it.
// A sphere that covers more than ENG_RENDER_SPLAT_BIG texels (near the eye) would keep one
// invocation looping while its neighbours idle: it is listed instead (u_stage 0), and a
// second dispatch (u_stage 1) gives each listed sphere a whole work group, its texels
// strided over the group. u_stage 2 empties the list (before each fluid's splat).
#include "render_shared.glsl"
#include "splat_order.glsl"
#include "particle_colour.glsl"

// The variants that ray-cast the sphere at each texel and keep its nearest hit.
#ifdef SPLAT_DEPTH
#define SPHERE_HIT 1
#endif
#ifdef SPLAT_NEAREST
#define SPHERE_HIT 1
#endif
#ifdef SPLAT_ID
#define SPHERE_HIT 1
#endif

layout(local_size_x = 64) in;

layout(std430, binding = ENG_RENDER_PARTICLE_SSBO_BINDING) readonly buffer Particles {
    vec4 particles[]; // xyz: position m, w: colour parameter, or a tint (w <= -1)
};
// The fluid's DrawArraysIndirectCommand {count, instanceCount, first, baseInstance}: the
// particles now in the buffers, written on the GPU (nothing is read back).
layout(std430, binding = ENG_RENDER_DRAW_SSBO_BINDING) readonly buffer Draw {
    uint draw_command[4];
};

uniform float u_radius; // m
uniform int u_count;    // particles the buffers hold
uniform float u_fill;   // the lattice's volume over the spheres'
uniform ivec2 u_size;   // texels of the target
uniform mat4 u_view;    // world -> view (the light's in SPLAT_LIGHT)
uniform mat4 u_proj;    // view -> clip
uniform int u_stage;    // 0: every particle (the large ones listed), 1: the listed ones, 2: empty the list

layout(std430, binding = ENG_RENDER_SPLAT_BIG_BINDING) buffer Big {
    uint big_count;
    uint big_list[]; // particle indices
};
// The depth the particles are tested against (window depth 0..1): the scene's at the
// water's resolution, or the shadow map's opaque casters.
layout(binding = ENG_RENDER_TEX_SPLAT_TEST) uniform sampler2D u_test_depth;

#ifdef SPLAT_DEPTH
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT) uniform coherent uimage2D u_bits;
#endif
#ifdef SPLAT_NEAREST
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT) uniform coherent uimage2D u_bits;
#endif
#ifdef SPLAT_ID
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT) uniform coherent uimage2D u_bits; // particle indices
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT_LAYERS) uniform readonly uimage2D u_nearest; // SPLAT_NEAREST's
#endif
#ifdef SPLAT_THICK
// layer 0: thickness; 1..4: tinted colour times chord (rgb) and chord (a)
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT) uniform coherent uimage2DArray u_bits;
#endif
#ifdef SPLAT_LIGHT
// layer 0: the front's code (splat_order); layer 1: thickness
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT) uniform coherent uimage2DArray u_bits;
uniform float u_light_near; // m
#endif

// Window depth (0..1) of a view-space depth z (< 0), from the projection's z and w rows.
float window_depth(float z)
{
    vec4 clip = u_proj * vec4(0.0, 0.0, z, 1.0);
    return 0.5 * clip.z / clip.w + 0.5;
}

uint fixed_point(float x) { return uint(x * ENG_RENDER_SPLAT_SCALE + 0.5); }

void splat(uint index, vec4 p)
{
    float r = u_radius, r2 = r * r;
    if (any(isnan(p.xyz)) || any(isinf(p.xyz))) return; // a diverged particle is not drawn
    vec3 c = (u_view * vec4(p.xyz, 1.0)).xyz;
    vec2 lo, hi; // the quad's corners in texels
#ifdef SPLAT_LIGHT
    float quad_depth = window_depth(c.z);
    if (quad_depth < 0.0 || quad_depth > 1.0) return; // clipped, as the raster quad
    vec2 a = (u_proj * vec4(c.xy - vec2(r * 1.02), c.z, 1.0)).xy, b = (u_proj * vec4(c.xy + vec2(r * 1.02), c.z, 1.0)).xy;
    lo = (min(a, b) * 0.5 + 0.5) * vec2(u_size);
    hi = (max(a, b) * 0.5 + 0.5) * vec2(u_size);
#else
    float d2 = dot(c, c);
    if (d2 <= r2 * 1.0001 || c.z > -0.0) return; // eye inside the sphere or behind it
    float d = sqrt(d2);
    float grow = (d / sqrt(d2 - r2)) * (d / -c.z) * 1.02;
#ifdef SPHERE_HIT
    float quad_z = -max(-c.z - r, 1e-4); // NEAR_QUAD: the quad at the sphere's nearest depth
#else
    float quad_z = c.z;
#endif
    float quad_depth = window_depth(quad_z);
    if (quad_depth < 0.0 || quad_depth > 1.0) return;
    lo = vec2(1e30), hi = vec2(-1e30);
    for (int k = 0; k < 4; k++) {
        vec2 corner = vec2((k & 1) != 0 ? 1.0 : -1.0, (k & 2) != 0 ? 1.0 : -1.0);
        vec4 q = u_proj * vec4(c.xy + corner * r * grow, c.z, 1.0);
        vec2 t = (q.xy / q.w * 0.5 + 0.5) * vec2(u_size);
        lo = min(lo, t);
        hi = max(hi, t);
    }
#endif
    // A finite position so far away that its view-space coordinates overflowed (a host's
    // buffer, not the solver's, which keeps particles in its domain): no defined quad.
    if (any(isnan(lo)) || any(isnan(hi)) || any(isinf(c))) return;
    // Texels whose centres lie inside the quad (clamped first: a sphere the eye nearly
    // touches has a quad far wider than the target, and a float too large for an int has
    // no defined conversion).
    lo = clamp(lo, vec2(-1.0), vec2(u_size) + 1.0);
    hi = clamp(hi, vec2(-1.0), vec2(u_size) + 1.0);
    ivec2 t0 = max(ivec2(ceil(lo - 0.5)), ivec2(0)), t1 = min(ivec2(floor(hi - 0.5)), u_size - 1);
    int width = t1.x - t0.x + 1, area = width * (t1.y - t0.y + 1);
    if (width <= 0 || t1.y < t0.y) return;
    if (u_stage == 0 && area > ENG_RENDER_SPLAT_BIG) {
        big_list[atomicAdd(big_count, 1u)] = index;
        return;
    }
    int first = u_stage == 0 ? 0 : int(gl_LocalInvocationID.x), step = u_stage == 0 ? 1 : int(gl_WorkGroupSize.x);
#ifdef SPLAT_THICK
    bool tinted = is_tint(p.w);
    vec3 tint = tinted ? tint_colour(p.w) : vec3(0.0);
#endif
    for (int k = first; k < area; k += step) {
        int x = t0.x + k % width, y = t0.y + k / width;
        {
            vec2 ndc = (vec2(x, y) + 0.5) / vec2(u_size) * 2.0 - 1.0;
#ifdef SPLAT_LIGHT
            float test = texelFetch(u_test_depth, ivec2(x, y), 0).r;
            vec2 v = (ndc - u_proj[3].xy) / vec2(u_proj[0][0], u_proj[1][1]); // orthographic
            vec2 e = v - c.xy;
            float h = r2 - dot(e, e);
            if (h <= 0.0 || !(quad_depth < test)) continue;
            float half_chord = sqrt(h);
            imageAtomicMin(u_bits, ivec3(x, y, 0), splat_order(-(c.z + half_chord) - u_light_near));
            imageAtomicAdd(u_bits, ivec3(x, y, 1), fixed_point(2.0 * half_chord * u_fill));
#else
            // The ray through the texel centre (perspective: x_view / -z_view from the
            // projection's first two rows).
            vec3 dir = normalize(vec3((ndc.x + u_proj[2][0]) / u_proj[0][0], (ndc.y + u_proj[2][1]) / u_proj[1][1], -1.0));
            float b = dot(dir, c);
            precise float h = b * b - (d2 - r2); // precise: the same bits in every variant
#ifdef SPHERE_HIT
            if (h < 0.0) continue;
            precise vec3 hit = dir * (b - sqrt(h));
            uint bits = floatBitsToUint(-hit.z);
#ifdef SPLAT_DEPTH
            if (!(window_depth(hit.z) < texelFetch(u_test_depth, ivec2(x, y), 0).r)) continue;
            imageAtomicMin(u_bits, ivec2(x, y), bits);
#endif
#ifdef SPLAT_NEAREST
            imageAtomicMin(u_bits, ivec2(x, y), bits);
#endif
#ifdef SPLAT_ID
            uint nearest = imageLoad(u_nearest, ivec2(x, y)).r;
            if (nearest != 0xffffffffu && bits <= nearest + 16u) imageAtomicMin(u_bits, ivec2(x, y), index);
#endif
#else
            if (h <= 0.0 || !(quad_depth < texelFetch(u_test_depth, ivec2(x, y), 0).r)) continue;
            float chord = 2.0 * sqrt(h) * u_fill;
            imageAtomicAdd(u_bits, ivec3(x, y, 0), fixed_point(chord));
            if (tinted) {
                imageAtomicAdd(u_bits, ivec3(x, y, 1), fixed_point(tint.r * chord));
                imageAtomicAdd(u_bits, ivec3(x, y, 2), fixed_point(tint.g * chord));
                imageAtomicAdd(u_bits, ivec3(x, y, 3), fixed_point(tint.b * chord));
                imageAtomicAdd(u_bits, ivec3(x, y, 4), fixed_point(chord));
            }
#endif
#endif
        }
    }
}

void main()
{
    if (u_stage == 2) {
        if (gl_GlobalInvocationID.x == 0u) big_count = 0u;
        return;
    }
    if (u_stage == 1) {
        uint count = big_count;
        for (uint b = gl_WorkGroupID.x; b < count; b += gl_NumWorkGroups.x) splat(big_list[b], particles[big_list[b]]);
        return;
    }
    uint n = min(draw_command[1], uint(max(u_count, 0)));
    uint stride = gl_NumWorkGroups.x * gl_WorkGroupSize.x;
    for (uint i = gl_GlobalInvocationID.x; i < n; i += stride) splat(i, particles[i]);
}
