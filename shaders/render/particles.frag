#version 430 core
// Sphere impostor of the sphere modes: the eye ray through this fragment meets the sphere
// or the fragment is discarded; the hit point gives the normal (the scene's light, its
// shadows) and the true depth. The colour comes from the vertex shader (COLOR_MODES).
// Drawn with NEAR_QUAD: the quad lies at the sphere's nearest depth and the hit is never
// nearer, which depth_greater declares, so a GPU keeps its early depth test and does not
// shade the spheres hidden behind nearer ones.
#include "frame.glsl"

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
    vec3 dir = normalize(v_view_pos); // eye at the view-space origin
    float b = dot(dir, v_center);
    float h = b * b - (dot(v_center, v_center) - u_radius * u_radius);
    if (h < 0.0) discard;
    float t = b - sqrt(h);
    vec3 hit = dir * t;
    vec3 n_view = (hit - v_center) / u_radius;
    vec4 clip = u_proj * vec4(hit, 1.0);
    float ndc_z = clip.z / clip.w;
    gl_FragDepth = ((gl_DepthRange.far - gl_DepthRange.near) * ndc_z + gl_DepthRange.near + gl_DepthRange.far) * 0.5;
    vec3 n = normalize(mat3(u_inv_view) * n_view);
    vec3 p = (u_inv_view * vec4(hit, 1.0)).xyz;
    vec3 c = shade(v_color, n, p, u_specular, u_shininess);
    o_color = vec4(fog(c, p), 1.0);
}
