#version 430 core
// Surface pass 2, the water's depth: each particle a sphere, ray-cast; the nearest one
// wins the depth test. Writes the eye depth of the hit (m, positive; 0 is cleared "no
// water") for the smoothing pass, and the window depth of the hit for the test. Drawn
// with NEAR_QUAD: the hit is never nearer than the quad, so early depth tests hold.
#include "frame.glsl"

layout(depth_greater) out float gl_FragDepth;

in vec3 v_view_pos;
flat in vec3 v_center;

uniform float u_radius;

out float o_depth;

void main()
{
    vec3 dir = normalize(v_view_pos);
    float b = dot(dir, v_center);
    float h = b * b - (dot(v_center, v_center) - u_radius * u_radius);
    if (h < 0.0) discard;
    vec3 hit = dir * (b - sqrt(h));
    vec4 clip = u_proj * vec4(hit, 1.0);
    gl_FragDepth = ((gl_DepthRange.far - gl_DepthRange.near) * (clip.z / clip.w) + gl_DepthRange.near +
                    gl_DepthRange.far) * 0.5;
    o_depth = -hit.z;
}
