#version 430 core
// Surface pass 3, smoothing (separable: run along y, then along x).
// The depth: the narrow-range filter (Truong & Yuksel, "A Narrow-Range Filter for
// Screen-Space Fluid Rendering", I3D 2018). Around each pixel's depth z0, neighbours
// farther than z0 + range are another layer (water behind) and ignored, nearer than
// z0 - range are clamped to it, the rest averaged with Gaussian weights; pixels without
// water stay without. The thickness: a plain Gaussian over the water in the same footprint
// (the sum of the spheres' chords is speckled at the particles' scale; pixels without
// water do not thin the edges). The radius is a world length projected at z0, capped in
// pixels. Run along y first: what the second pass leaves is streaks along its direction,
// and along x they lie with the water line instead of across it.
#include "render_shared.glsl"

layout(binding = ENG_RENDER_TEX_FLUID_DEPTH) uniform sampler2D u_depth; // eye depth m, 0 = none
layout(binding = ENG_RENDER_TEX_FLUID_THICK) uniform sampler2D u_thick; // m

uniform ivec2 u_step;         // (0, 1), then (1, 0)
uniform float u_world_radius; // m
uniform float u_px_per_m;     // pixels one metre covers 1 m from the eye
uniform int u_max_px;         // the radius in pixels at most
uniform float u_range;        // m

layout(location = 0) out float o_depth;
layout(location = 1) out float o_thick;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    float z0 = texelFetch(u_depth, p, 0).r;
    float t0 = texelFetch(u_thick, p, 0).r;
    if (z0 <= 0.0) {
        o_depth = 0.0;
        o_thick = t0;
        return;
    }
    int k = clamp(int(u_world_radius * u_px_per_m / z0 + 0.5), 0, u_max_px);
    float sigma = max(0.5 * float(k), 0.5);
    float inv_2s2 = 0.5 / (sigma * sigma);
    ivec2 top = textureSize(u_depth, 0) - 1;
    float lo = z0 - u_range, hi = z0 + u_range;
    float sum = z0, wsum = 1.0, tsum = t0, twsum = 1.0;
    for (int i = 1; i <= k; i++) {
        float w = exp(-float(i * i) * inv_2s2);
        ivec2 a = clamp(p - i * u_step, ivec2(0), top), b = clamp(p + i * u_step, ivec2(0), top);
        float za = texelFetch(u_depth, a, 0).r;
        float zb = texelFetch(u_depth, b, 0).r;
        if (za > 0.0 && za <= hi) {
            sum += w * max(za, lo);
            wsum += w;
        }
        if (zb > 0.0 && zb <= hi) {
            sum += w * max(zb, lo);
            wsum += w;
        }
        if (za > 0.0) {
            tsum += w * texelFetch(u_thick, a, 0).r;
            twsum += w;
        }
        if (zb > 0.0) {
            tsum += w * texelFetch(u_thick, b, 0).r;
            twsum += w;
        }
    }
    o_depth = sum / wsum;
    o_thick = tsum / twsum;
}
