#version 430
// Tint (between steps, not a stage of the step): every live particle inside the box
// [u_box_min, u_box_max] gets the w `u_tint` (a tint code, pbf_tint_encode), or, with
// u_untint, its colour parameter back: its height in the domain, [0, 1] (pbf_colour_of).
#define USE_POS
#define WRITE_POS
#include "common.glsl"
layout(local_size_x = PBF_WG) in;

uniform vec3 u_box_min; // m
uniform vec3 u_box_max; // m
uniform float u_tint;   // w of the tint
uniform int u_untint;   // 1: the height parameter instead

void main()
{
    uint i = gl_GlobalInvocationID.x;
    if (i >= particle_count()) return;
    vec3 x = pos[i].xyz;
    if (any(lessThan(x, u_box_min)) || any(greaterThan(x, u_box_max))) return;
    float w = u_tint;
    if (u_untint != 0)
        w = clamp((x.y - P.domain_min.y) / (P.domain_max.y - P.domain_min.y), 0.0, 1.0);
    pos[i].w = w;
}
