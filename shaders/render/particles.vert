#version 430 core
// Particles as sphere impostors, straight from the fluid's GPU buffer: one camera-facing
// quad per instance (a 4-vertex triangle strip, no vertex attributes); the centre comes
// from the SSBO by gl_InstanceID. The quad is grown so that it covers the sphere's whole
// perspective silhouette; the fragment shader ray-casts the sphere inside it.
#include "frame.glsl"

layout(std430, binding = ENG_RENDER_PARTICLE_SSBO_BINDING) readonly buffer Particles {
    vec4 particles[]; // xyz: position m, w: colour parameter 0..1
};

uniform float u_radius; // m
uniform int u_count;    // vec4s in the buffer; instances past it are dropped

out vec3 v_view_pos;    // this corner on the quad, view space
flat out vec3 v_center; // sphere centre, view space
flat out float v_param; // colour parameter

void main()
{
    if (gl_InstanceID >= u_count) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // outside the clip volume: no fragments
        return;
    }
    vec4 p = particles[gl_InstanceID];
    vec3 c = (u_view * vec4(p.xyz, 1.0)).xyz;
    v_center = c;
    v_param = p.w;
    vec2 corner = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
    float d2 = dot(c, c);
    float r2 = u_radius * u_radius;
    if (d2 <= r2 * 1.0001 || c.z > -0.0) {
        gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // eye inside the sphere or behind: skip
        v_view_pos = c;
        return;
    }
    // Silhouette cone of half-angle asin(r / d), cut by the plane through the centre
    // facing the eye: radius d r / sqrt(d^2 - r^2), stretched by 1/cos of the off-axis
    // angle (d / |z|). 2 % margin.
    float d = sqrt(d2);
    float grow = (d / sqrt(d2 - r2)) * (d / -c.z) * 1.02;
    vec3 q = c + vec3(corner * u_radius * grow, 0.0);
    v_view_pos = q;
    gl_Position = u_proj * vec4(q, 1.0);
}
