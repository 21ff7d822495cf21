#version 430 core
// Particles as sphere impostors, straight from the fluid's GPU buffers: one quad per
// instance (a 4-vertex triangle strip, no vertex attributes); the centre comes from the
// SSBO by gl_InstanceID. Every particle pass uses this shader:
//   (default)    the camera's view; the quad lies in the plane through the centre facing
//                the eye, grown to cover the sphere's whole perspective silhouette
//   NEAR_QUAD    the same quad moved along the eye rays to the sphere's nearest depth: the
//                ray-cast depth is then never nearer than the quad's, which the fragment
//                shader declares (depth_greater) so that early depth tests stay on
//   LIGHT_PASS   the light's orthographic view (the shadow map)
//   COLOR_MODES  also the colour of the sphere modes: initial height, density or speed
//   TINT         also each particle's tint (v_tint: rgb, 1; zero when untinted), for
//                the surface's thickness pass
//   SPRAY        only spray: particles faster than the look's spray_speed whose density
//                is below 0.7 rho0 (few neighbours: drops in the air), which
//                spray_cull.comp listed (instance k draws the k-th); v_alpha rises with
//                the speed.
// The fragment shader ray-casts the sphere inside the quad.
#include "frame.glsl"

layout(std430, binding = ENG_RENDER_PARTICLE_SSBO_BINDING) readonly buffer Particles {
    vec4 particles[]; // xyz: position m, w: colour parameter 0..1, or a tint (w <= -1)
};

#include "particle_colour.glsl"

uniform float u_radius; // m
uniform int u_count;    // particles the buffers hold; instances past it are dropped

#ifdef LIGHT_PASS
uniform mat4 u_light_view; // world -> the light's view (looking down -z)
uniform mat4 u_light_proj; // the light's view -> clip (orthographic)
#endif

// (One name per #ifdef: the strict GL mode reads which blocks are active from the source,
// and it follows `#ifdef NAME`, not `#if defined(A) || defined(B)`.)
#ifdef SPRAY
// The spray found by spray_cull.comp, drawn as instances: the particle's index and v_alpha.
layout(std430, binding = ENG_RENDER_SPRAY_LIST_BINDING) readonly buffer SprayList {
    uvec2 spray_list[];
};
flat out float v_alpha;
#endif
#ifdef COLOR_MODES
flat out vec3 v_color;
#endif

#ifdef TINT
flat out vec4 v_tint; // rgb: the particle's tint, a: 1 (all zero when untinted)
#endif

out vec3 v_view_pos;    // this corner on the quad, view space (the light's in LIGHT_PASS)
flat out vec3 v_center; // sphere centre, same space

void skip()
{
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0); // outside the clip volume: no fragments
    v_view_pos = vec3(0.0);
    v_center = vec3(0.0);
#ifdef COLOR_MODES
    v_color = vec3(0.0);
#endif
#ifdef SPRAY
    v_alpha = 0.0;
#endif
#ifdef TINT
    v_tint = vec4(0.0);
#endif
}

void main()
{
    if (gl_InstanceID >= u_count) {
        skip();
        return;
    }
#ifdef SPRAY
    uvec2 drop = spray_list[gl_InstanceID];
    vec4 p = particles[drop.x];
    v_alpha = uintBitsToFloat(drop.y);
#else
    vec4 p = particles[gl_InstanceID];
#endif
    vec2 corner = vec2((gl_VertexID & 1) != 0 ? 1.0 : -1.0, (gl_VertexID & 2) != 0 ? 1.0 : -1.0);
    float r2 = u_radius * u_radius;
#ifdef LIGHT_PASS
    vec3 c = (u_light_view * vec4(p.xyz, 1.0)).xyz;
    v_center = c;
    vec3 q = c + vec3(corner * u_radius * 1.02, 0.0);
    v_view_pos = q;
    gl_Position = u_light_proj * vec4(q, 1.0);
#else
    vec3 c = (u_view * vec4(p.xyz, 1.0)).xyz;
    float d2 = dot(c, c);
    if (d2 <= r2 * 1.0001 || c.z > -0.0) {
        skip(); // eye inside the sphere or behind it
        return;
    }
    v_center = c;
    // Silhouette cone of half-angle asin(r / d), cut by the plane through the centre
    // facing the eye: radius d r / sqrt(d^2 - r^2), stretched by 1/cos of the off-axis
    // angle (d / |z|). 2 % margin.
    float d = sqrt(d2);
    float grow = (d / sqrt(d2 - r2)) * (d / -c.z) * 1.02;
    vec3 q = c + vec3(corner * u_radius * grow, 0.0);
    v_view_pos = q;
#ifdef NEAR_QUAD
    // Along the eye ray through q, to the depth of the sphere's nearest point: the same
    // pixels, a nearer depth. (The eye is at the origin; q.z = c.z < 0.)
    q *= max(-c.z - u_radius, 1e-4) / -c.z;
#endif
#ifdef SPRAY
    // A radius in front of the drop's own water surface, which the composite wrote.
    q *= max(-c.z - 2.0 * u_radius, 1e-4) / -c.z;
#endif
    gl_Position = u_proj * vec4(q, 1.0);
#endif
#ifdef COLOR_MODES
    v_color = particle_color(uint(gl_InstanceID), p.w);
#endif
#ifdef TINT
    v_tint = is_tint(p.w) ? vec4(tint_colour(p.w), 1.0) : vec4(0.0);
#endif
}
