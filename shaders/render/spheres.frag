#version 430 core
// The sphere modes drawn from compute splats (eng_fluid_look.splat = compute): a
// full-screen triangle (fullscreen.vert) over the scene; at each pixel the particle
// splat.comp found nearest (SPLAT_NEAREST, then SPLAT_ID) is ray-cast through the pixel's
// centre and lit as particles.frag lights the raster impostor, and the window depth of its
// hit meets the scene's depth test (nothing nearer than the nearest sphere can hide the
// others). COLOR_MODES.
#include "frame.glsl"
#include "sphere_lit.glsl"

layout(std430, binding = ENG_RENDER_PARTICLE_SSBO_BINDING) readonly buffer Particles {
    vec4 particles[]; // xyz: position m, w: colour parameter 0..1, or a tint (w <= -1)
};

#include "particle_colour.glsl"

// The nearest particle's index per pixel (all ones: none).
layout(r32ui, binding = ENG_RENDER_IMG_SPLAT) uniform readonly uimage2D u_ids;

uniform float u_radius;
uniform float u_specular;
uniform float u_shininess;

out vec4 o_color;

void main()
{
    uint id = imageLoad(u_ids, ivec2(gl_FragCoord.xy)).r;
    if (id == 0xffffffffu) discard;
    vec4 p = particles[id];
    vec3 c = (u_view * vec4(p.xyz, 1.0)).xyz;
    // The ray through this pixel's centre (as splat.comp walks it).
    vec2 ndc = gl_FragCoord.xy * u_viewport.zw * 2.0 - 1.0;
    vec3 dir = normalize(vec3((ndc.x + u_proj[2][0]) / u_proj[0][0], (ndc.y + u_proj[2][1]) / u_proj[1][1], -1.0));
    float depth;
    vec4 colour;
    if (!lit_sphere(dir, c, u_radius, particle_color(id, p.w), u_specular, u_shininess, depth, colour)) discard;
    gl_FragDepth = depth;
    o_color = colour;
}
