// The per-frame uniform block and the lighting model shared by every render pass:
// Phong with one directional light, ambient and a specular highlight, plus distance fog
// towards the sky colour. The C mirror is eng_frame_block in engine/renderer.c (std140).
#include "render_shared.glsl"

layout(std140, binding = ENG_RENDER_FRAME_UBO_BINDING) uniform Frame {
    mat4 u_view;        // world -> view
    mat4 u_proj;        // view -> clip
    mat4 u_inv_view;    // view -> world
    vec4 u_camera_pos;  // xyz: eye in world space, m
    vec4 u_light_dir;   // xyz: unit vector from the scene towards the light (world)
    vec4 u_light_color; // rgb: light colour times intensity
    vec4 u_ambient;     // rgb: ambient light
    vec4 u_sky_color;   // rgb: background and fog colour
    vec4 u_fog;         // x: fog start m, y: fog end m (from the eye)
};

// Lit colour of a surface with albedo `base` at world position `p`, unit normal `n`.
vec3 shade(vec3 base, vec3 n, vec3 p, float specular, float shininess)
{
    vec3 l = normalize(u_light_dir.xyz);
    vec3 v = normalize(u_camera_pos.xyz - p);
    float diff = max(dot(n, l), 0.0);
    vec3 r = reflect(-l, n);
    float spec = diff > 0.0 ? pow(max(dot(r, v), 0.0), shininess) : 0.0;
    return base * (u_ambient.rgb + diff * u_light_color.rgb) + specular * spec * u_light_color.rgb;
}

// Blends towards the sky with distance, so the ground plane's edge melts into the horizon.
vec3 fog(vec3 c, vec3 p)
{
    float d = length(p - u_camera_pos.xyz);
    float f = clamp((d - u_fog.x) / max(u_fog.y - u_fog.x, 1e-3), 0.0, 1.0);
    return mix(c, u_sky_color.rgb, f * f);
}
