#version 430 core
// Surface pass 1, the water's thickness along each view ray: every particle adds the
// length of the ray inside its sphere (additive blending, tested against the opaque
// scene's depth, not written), times `u_fill`: the lattice's volume over the spheres'
// (spacing^3 / (4/3 pi r^3)), so that a filled block reads its thickness in metres.
in vec3 v_view_pos;
flat in vec3 v_center;

uniform float u_radius;
uniform float u_fill;

out float o_thickness;

void main()
{
    vec3 dir = normalize(v_view_pos);
    float b = dot(dir, v_center);
    float h = b * b - (dot(v_center, v_center) - u_radius * u_radius);
    if (h <= 0.0) discard;
    o_thickness = 2.0 * sqrt(h) * u_fill;
}
