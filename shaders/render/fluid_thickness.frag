#version 430 core
// Surface pass 1, the water's thickness along each view ray: every particle adds the
// length of the ray inside its sphere (additive blending, tested against the opaque
// scene's depth, not written), times `u_fill`: the lattice's volume over the spheres'
// (spacing^3 / (4/3 pi r^3)), so that a filled block reads its thickness in metres.
// A second target gathers the tinted particles' share: colour times chord (rgb), chord (a).
in vec3 v_view_pos;
flat in vec3 v_center;
flat in vec4 v_tint;

uniform float u_radius;
uniform float u_fill;

layout(location = 0) out float o_thickness;
layout(location = 1) out vec4 o_tint;

void main()
{
    vec3 dir = normalize(v_view_pos);
    float b = dot(dir, v_center);
    float h = b * b - (dot(v_center, v_center) - u_radius * u_radius);
    if (h <= 0.0) discard;
    o_thickness = 2.0 * sqrt(h) * u_fill;
    o_tint = v_tint * o_thickness;
}
