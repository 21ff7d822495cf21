#version 430 core
// Sphere impostor of the sphere modes: the eye ray through this fragment meets the sphere
// or the fragment is discarded; the hit point gives the normal (the scene's light, its
// shadows) and the true depth. The colour comes from the vertex shader (COLOR_MODES).
// Drawn with NEAR_QUAD: the quad lies at the sphere's nearest depth and the hit is never
// nearer, which depth_greater declares, so a GPU keeps its early depth test and does not
// shade the spheres hidden behind nearer ones.
#include "frame.glsl"
#include "sphere_lit.glsl"

layout(depth_greater) out float gl_FragDepth;

in vec3 v_view_pos;
flat in vec3 v_center;
flat in vec3 v_color;

uniform float u_radius;
uniform float u_specular;
uniform float u_shininess;

out vec4 o_color;

void main()
{
    float depth;
    vec4 colour;
    if (!lit_sphere(normalize(v_view_pos), v_center, u_radius, v_color, u_specular, u_shininess, depth, colour)) discard;
    gl_FragDepth = depth;
    o_color = colour;
}
