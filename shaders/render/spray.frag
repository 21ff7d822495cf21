#version 430 core
// Surface pass 5, spray: drops flying on their own (particles.vert, SPRAY) drawn over the
// composite as soft white discs, lit by the scene's light and its shadow map, blended
// over what is there, depth-tested against the composite's depth (the water included),
// not written.
#include "frame.glsl"

in vec3 v_view_pos;
flat in vec3 v_center;
flat in float v_alpha;

uniform float u_radius;
uniform float u_spray; // opacity of the fastest drops, 0..1

out vec4 o_color;

void main()
{
    vec3 dir = normalize(v_view_pos);
    float b = dot(dir, v_center);
    float h = b * b - (dot(v_center, v_center) - u_radius * u_radius);
    if (h <= 0.0) discard;
    float edge = sqrt(h) / u_radius; // 1 at the middle, 0 at the rim
    vec3 pw = (u_inv_view * vec4(v_center, 1.0)).xyz;
    vec3 lit = u_ambient.rgb + u_light_color.rgb * light_visibility(pw, normalize(u_light_dir.xyz));
    vec3 c = vec3(0.92, 0.96, 1.0) * lit;
    o_color = vec4(fog(c, pw), u_spray * v_alpha * edge * edge);
}
