#version 430 core
// Scene meshes: positions and normals to world space. With SHADOW_PASS defined: positions
// to the light's clip space, for the shadow map (depth only).
#include "frame.glsl"

layout(location = ENG_RENDER_ATTRIB_POSITION) in vec3 a_position;
layout(location = ENG_RENDER_ATTRIB_NORMAL) in vec3 a_normal;

uniform mat4 u_model;        // object -> world
uniform mat3 u_normal_model; // inverse transpose of u_model's 3x3

out vec3 v_world;
out vec3 v_normal;

void main()
{
    vec4 w = u_model * vec4(a_position, 1.0);
    v_world = w.xyz;
    v_normal = u_normal_model * a_normal;
#ifdef SHADOW_PASS
    gl_Position = u_light_viewproj * w;
#else
    gl_Position = u_proj * (u_view * w);
#endif
}
