#version 430 core
// Surface pass 4, the composite, at the target's full size: where the smoothed water is in
// front of the opaque scene, shade it and write its depth; elsewhere copy the scene's
// colour and depth. The water: normals from the smoothed depth (the smaller of the two
// one-sided differences, so that silhouettes do not bend them), the scene behind refracted
// (offset by the normal and the thickness; not where that would fetch something in front
// of the water), Beer-Lambert absorption by the thickness with light scattered back by the
// bulk (clear in thin sheets, deep blue in bulk), Fresnel (Schlick) reflection of the sky
// and the floor, the sun's highlight, the shadow map on both.
#include "frame.glsl"

layout(binding = ENG_RENDER_TEX_SCENE_COLOR) uniform sampler2D u_scene_color;
layout(binding = ENG_RENDER_TEX_SCENE_DEPTH) uniform sampler2D u_scene_depth;
layout(binding = ENG_RENDER_TEX_FLUID_DEPTH) uniform sampler2D u_fluid_depth; // smoothed, m
layout(binding = ENG_RENDER_TEX_FLUID_THICK) uniform sampler2D u_fluid_thick; // m
layout(binding = ENG_RENDER_TEX_FLUID_TINT) uniform sampler2D u_fluid_tint;   // rgb colour x m, a m

uniform vec2 u_fluid_size;   // pixels of the water's textures
uniform float u_layer;       // m: depths further apart than this are different layers
uniform vec3 u_absorption;   // 1/m per channel
uniform vec3 u_scatter;      // colour the bulk sends back (albedo of the water's body)
uniform float u_refraction;  // 0..: strength of the refraction offset (1: about water's)
uniform float u_reflection;  // F0 of Schlick's Fresnel (0.02 for water)
uniform float u_specular;    // strength of the sun's highlight
uniform float u_shininess;   // its Blinn-Phong exponent
uniform int u_view_mode;     // ENG_RENDER_VIEW_*

out vec4 o_color;

// Smoothed eye depth at uv (0: no water): bilinear over the texels that hold water in the
// nearest layer; no water where less than half the weight has water.
float water_depth(vec2 uv)
{
    vec2 t = uv * u_fluid_size - 0.5;
    vec2 f = fract(t);
    ivec2 i = ivec2(floor(t));
    ivec2 top = ivec2(u_fluid_size) - 1;
    float z[4], w[4];
    z[0] = texelFetch(u_fluid_depth, clamp(i, ivec2(0), top), 0).r;
    z[1] = texelFetch(u_fluid_depth, clamp(i + ivec2(1, 0), ivec2(0), top), 0).r;
    z[2] = texelFetch(u_fluid_depth, clamp(i + ivec2(0, 1), ivec2(0), top), 0).r;
    z[3] = texelFetch(u_fluid_depth, clamp(i + ivec2(1, 1), ivec2(0), top), 0).r;
    w[0] = (1.0 - f.x) * (1.0 - f.y);
    w[1] = f.x * (1.0 - f.y);
    w[2] = (1.0 - f.x) * f.y;
    w[3] = f.x * f.y;
    float near = 1e30, cover = 0.0;
    for (int k = 0; k < 4; k++)
        if (z[k] > 0.0) {
            near = min(near, z[k]);
            cover += w[k];
        }
    if (cover < 0.5) return 0.0;
    float sum = 0.0, wsum = 0.0;
    for (int k = 0; k < 4; k++)
        if (z[k] > 0.0 && z[k] <= near + u_layer) {
            sum += w[k] * z[k];
            wsum += w[k];
        }
    return sum / wsum;
}

// View-space point seen at uv at eye depth z (m).
vec3 view_point(vec2 uv, float z)
{
    vec2 ndc = uv * 2.0 - 1.0;
    return vec3((ndc.x + u_proj[2][0]) * z / u_proj[0][0], (ndc.y + u_proj[2][1]) * z / u_proj[1][1], -z);
}

float window_depth(vec3 p_view)
{
    vec4 c = u_proj * vec4(p_view, 1.0);
    return ((gl_DepthRange.far - gl_DepthRange.near) * (c.z / c.w) + gl_DepthRange.near + gl_DepthRange.far) * 0.5;
}

// The surface's change from uv to uv + e (screen units): towards the side whose depth
// differs less from z, and flat (facing the eye) when neither side has water.
vec3 tangent(vec2 uv, vec3 p, float z, vec2 e)
{
    float za = water_depth(uv + e), zb = water_depth(uv - e);
    bool a = za > 0.0 && (zb <= 0.0 || abs(za - z) <= abs(z - zb));
    if (a) return view_point(uv + e, za) - p;
    if (zb > 0.0) return p - view_point(uv - e, zb);
    return view_point(uv + e, z) - p;
}

void main()
{
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec2 uv = gl_FragCoord.xy * u_viewport.zw;
    float scene_z = texelFetch(u_scene_depth, px, 0).r;
    float z = water_depth(uv);
    vec3 p = view_point(uv, z);
    float depth = z > 0.0 ? window_depth(p) : 1.0;
    if (z <= 0.0 || depth >= scene_z) {
        o_color = vec4(texelFetch(u_scene_color, px, 0).rgb, 1.0);
        gl_FragDepth = scene_z;
        return;
    }
    gl_FragDepth = depth;

    // The normal: one texel of the water's textures to each side, the smaller difference
    // (a side without water does not count; with neither, the surface faces the eye).
    vec2 d = 1.0 / u_fluid_size;
    vec3 ddx = tangent(uv, p, z, vec2(d.x, 0.0));
    vec3 ddy = tangent(uv, p, z, vec2(0.0, d.y));
    vec3 n_view = normalize(cross(ddx, ddy));
    vec3 v_view = normalize(-p);
    vec3 n = normalize(mat3(u_inv_view) * n_view);
    vec3 v = normalize(mat3(u_inv_view) * v_view);
    vec3 pw = (u_inv_view * vec4(p, 1.0)).xyz;
    float thick = textureLod(u_fluid_thick, uv, 0.0).r;

    if (u_view_mode == ENG_RENDER_VIEW_DEPTH) {
        o_color = vec4(vec3(fract(z)), 1.0);
        return;
    }
    if (u_view_mode == ENG_RENDER_VIEW_NORMALS) {
        o_color = vec4(n * 0.5 + 0.5, 1.0);
        return;
    }
    if (u_view_mode == ENG_RENDER_VIEW_THICKNESS) {
        o_color = vec4(vec3(1.0 - exp(-2.0 * thick)), 1.0);
        return;
    }

    // Refraction: the scene behind, displaced as a slab of water of this thickness would
    // (1 - 1/1.33 of the normal's tilt), in screen units at this depth.
    vec2 shift = n_view.xy * (0.25 * u_refraction * min(thick, 0.5)) * vec2(u_proj[0][0], u_proj[1][1]) * 0.5 / z;
    vec2 uv_r = clamp(uv - shift, vec2(0.0), vec2(1.0));
    if (texture(u_scene_depth, uv_r).r <= depth) uv_r = uv; // that would be in front of the water
    vec3 behind = textureLod(u_scene_color, uv_r, 0.0).rgb;

    vec3 l = normalize(u_light_dir.xyz);
    vec3 vis = light_visibility(pw, n);
    vec3 absorption = u_absorption;
    vec3 scatter = u_scatter;
    // Tinted water (seiche.colour): its share f of the thickness, of mean colour `dye`,
    // scatters that colour and absorbs the others (a dye: 6 / m at colour 1/e).
    vec4 tint = textureLod(u_fluid_tint, uv, 0.0);
    if (tint.a > 0.0) {
        vec3 dye = tint.rgb / tint.a;
        float f = clamp(tint.a / max(thick, 1e-4), 0.0, 1.0);
        absorption = mix(absorption, -6.0 * log(clamp(dye, vec3(0.02), vec3(1.0))), f);
        scatter = mix(scatter, dye, f);
    }
    vec3 transmit = exp(-absorption * thick);
    vec3 lit = u_ambient.rgb + u_light_color.rgb * vis * (0.35 + 0.65 * max(dot(n, l), 0.0));
    vec3 inside = behind * transmit + scatter * lit * (1.0 - transmit);

    float cos_v = clamp(dot(n, v), 0.0, 1.0);
    float fresnel = u_reflection + (1.0 - u_reflection) * pow(1.0 - cos_v, 5.0);
    vec3 env = environment(reflect(-v, n));
    vec3 h = normalize(l + v);
    vec3 spec = u_specular * pow(max(dot(n, h), 0.0), u_shininess) * vis * u_light_color.rgb;
    vec3 c = mix(inside, env, fresnel) + spec;
    o_color = vec4(fog(c, pw), 1.0);
}
