// The per-frame uniform block and the lighting model shared by every render pass:
// Phong with one directional light, ambient and a specular highlight, the light's shadow
// map (opaque casters, and the water's thickness along the light ray), distance fog
// towards the sky colour, and the sky and floor as reflections see them. The C mirror is
// eng_frame_block in engine/render/render_internal.h (std140).
#include "render_shared.glsl"

layout(std140, binding = ENG_RENDER_FRAME_UBO_BINDING) uniform Frame {
    mat4 u_view;            // world -> view
    mat4 u_proj;            // view -> clip
    mat4 u_inv_view;        // view -> world
    mat4 u_light_viewproj;  // world -> the light's clip space (orthographic)
    vec4 u_camera_pos;      // xyz: eye in world space, m
    vec4 u_light_dir;       // xyz: unit vector from the scene towards the light (world)
    vec4 u_light_color;     // rgb: light colour times intensity
    vec4 u_ambient;         // rgb: ambient light
    vec4 u_sky_color;       // rgb: background and fog colour
    vec4 u_fog;             // x: fog start m, y: fog end m (from the eye)
    vec4 u_ground_color;    // rgb: ground albedo (the floor in reflections)
    vec4 u_shadow;          // x: 1 = shadows on, y: shadow map texel (1 / size), z: the light's
                            // depth range m (far - near), w: normal offset of receivers, m
    vec4 u_water_light;     // rgb: water's absorption of light, 1/m; w: depth under the water's
                            // front (from the light) before the water darkens a receiver, m
    vec4 u_viewport;        // xy: target size in pixels, zw: 1 / size
};

layout(binding = ENG_RENDER_TEX_SHADOW) uniform sampler2DShadow u_shadow_map;
layout(binding = ENG_RENDER_TEX_SHADOW_FRONT) uniform sampler2D u_shadow_front;
layout(binding = ENG_RENDER_TEX_SHADOW_THICK) uniform sampler2D u_shadow_thick;

// Light reaching world point `p` (unit normal `n`), per channel 0..1: the opaque casters'
// shadow (3x3 PCF, each tap a 2x2 hardware comparison) times the Beer-Lambert transmittance
// of the water between the light and `p`: the water met along the light ray before `p`,
// at most the whole thickness of water on that ray.
vec3 light_visibility(vec3 p, vec3 n)
{
    if (u_shadow.x < 0.5) return vec3(1.0);
    vec3 q = p + n * u_shadow.w;
    vec4 c = u_light_viewproj * vec4(q, 1.0);
    vec3 s = c.xyz / c.w * 0.5 + 0.5;
    if (any(lessThan(s, vec3(0.0))) || any(greaterThan(s, vec3(1.0)))) return vec3(1.0);
    float vis = 0.0;
    for (int y = -1; y <= 1; y++)
        for (int x = -1; x <= 1; x++) vis += texture(u_shadow_map, vec3(s.xy + vec2(x, y) * u_shadow.y, s.z));
    vis *= 1.0 / 9.0;
    float front = texture(u_shadow_front, s.xy).r;
    float thick = texture(u_shadow_thick, s.xy).r;
    float inside = clamp(s.z * u_shadow.z - front - u_water_light.w, 0.0, thick);
    return vis * exp(-u_water_light.rgb * inside);
}

// Lit colour of a surface with albedo `base` at world position `p`, unit normal `n`.
vec3 shade(vec3 base, vec3 n, vec3 p, float specular, float shininess)
{
    vec3 l = normalize(u_light_dir.xyz);
    vec3 v = normalize(u_camera_pos.xyz - p);
    float diff = max(dot(n, l), 0.0);
    vec3 vis = diff > 0.0 ? light_visibility(p, n) : vec3(1.0);
    vec3 r = reflect(-l, n);
    float spec = diff > 0.0 ? pow(max(dot(r, v), 0.0), shininess) : 0.0;
    return base * (u_ambient.rgb + diff * vis * u_light_color.rgb) + specular * spec * vis * u_light_color.rgb;
}

// Blends towards the sky with distance, so the ground plane's edge melts into the horizon.
vec3 fog(vec3 c, vec3 p)
{
    float d = length(p - u_camera_pos.xyz);
    float f = clamp((d - u_fog.x) / max(u_fog.y - u_fog.x, 1e-3), 0.0, 1.0);
    return mix(c, u_sky_color.rgb, f * f);
}

// What a mirror sees in world direction `d` (unit): the sky, paler at the horizon and
// deeper overhead, with a glow around the sun; below the horizon the lit floor fading
// into the horizon with distance.
vec3 environment(vec3 d)
{
    vec3 l = normalize(u_light_dir.xyz);
    vec3 horizon = mix(u_sky_color.rgb, vec3(1.0), 0.2);
    vec3 zenith = u_sky_color.rgb * vec3(0.55, 0.72, 0.95);
    if (d.y >= 0.0) {
        vec3 sky = mix(horizon, zenith, pow(d.y, 0.5));
        return sky + u_light_color.rgb * 0.25 * pow(max(dot(d, l), 0.0), 64.0);
    }
    vec3 floor_lit = u_ground_color.rgb * (u_ambient.rgb + max(l.y, 0.0) * u_light_color.rgb);
    return mix(horizon, floor_lit, clamp(-d.y * 6.0, 0.0, 1.0));
}
