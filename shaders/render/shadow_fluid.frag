#version 430 core
// The shadow map's water: each particle seen from the light (orthographic, looking down
// -z of the light's view). Target 0 keeps the nearest water's distance from the light
// (MIN blending), target 1 adds up the water crossed along the light ray (the chord
// through each sphere times `u_fill`, as fluid_thickness.frag). Tested against the opaque
// casters' depth (at the quad's depth, so that early tests stay on), not written.
in vec3 v_view_pos;
flat in vec3 v_center;

uniform float u_radius;
uniform float u_fill;
uniform float u_light_near; // m: the light's near plane, from its eye

layout(location = 0) out float o_front;
layout(location = 1) out float o_thickness;

void main()
{
    vec2 d = v_view_pos.xy - v_center.xy;
    float h = u_radius * u_radius - dot(d, d);
    if (h <= 0.0) discard;
    float half_chord = sqrt(h);
    float z = v_center.z + half_chord; // the side facing the light
    o_front = -z - u_light_near;
    o_thickness = 2.0 * half_chord * u_fill;
}
