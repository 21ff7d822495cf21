#version 430 core
// Scene meshes: Phong-lit flat colour; the ground adds a subtle checker (u_checker_cell > 0)
// so that scale reads, filtered to grey with distance so it does not shimmer.
#include "frame.glsl"

in vec3 v_world;
in vec3 v_normal;

uniform vec3 u_color;         // albedo, rgb 0..1
uniform float u_specular;     // highlight strength 0..1
uniform float u_shininess;    // Phong exponent
uniform float u_checker_cell; // m; 0 = no checker

out vec4 o_color;

// 1 on "white" cells, 0 on "black" ones, box-filtered over the pixel footprint.
float checker(vec2 p)
{
    vec2 w = max(fwidth(p), vec2(1e-4));
    // Integral of a square wave, differenced over the footprint (filtered checker).
    vec2 i = 2.0 * (abs(fract((p - 0.5 * w) * 0.5) - 0.5) - abs(fract((p + 0.5 * w) * 0.5) - 0.5)) / w;
    return 0.5 - 0.5 * i.x * i.y;
}

void main()
{
    vec3 n = normalize(v_normal);
    if (!gl_FrontFacing) n = -n; // triangles from physics may face either way
    vec3 base = u_color;
    if (u_checker_cell > 0.0) base *= mix(0.88, 1.0, checker(v_world.xz / u_checker_cell));
    vec3 c = shade(base, n, v_world, u_specular, u_shininess);
    o_color = vec4(fog(c, v_world), 1.0);
}
