// The particles' colours, shared by the passes that colour them: particles.vert (the
// sphere modes' raster impostors, the surface's tinted thickness), spheres.frag (the
// sphere modes drawn from compute splats) and splat.comp (the tinted thickness). Included
// after render_shared.glsl; with COLOR_MODES also the sphere modes' colour maps, which read
// the velocities' storage block and the uniforms below.

// A tint's colour from a position's w (fluid/pbf.h, pbf_tint_decode: w = -(1 + R 65536 +
// G 256 + B), R, G, B in 0..255); tests/test_tint.c checks that both read the same colour.
bool is_tint(float w) { return w <= -1.0 && w >= -16777216.0; }
vec3 tint_colour(float w)
{
    uint code = uint(round(-w - 1.0)); // exact: an integer below 2^24
    return vec3(float((code >> 16) & 255u), float((code >> 8) & 255u), float(code & 255u)) / 255.0;
}

#ifdef COLOR_MODES
layout(std430, binding = ENG_RENDER_VELOCITY_SSBO_BINDING) readonly buffer Velocities {
    vec4 velocities[]; // xyz: m/s, w: the particle's volume m^3 (mass / density)
};
uniform float u_particle_mass;    // kg: density = mass / volume
uniform float u_inv_rest_density; // 1 / rho0, m^3/kg
uniform int u_color_mode;         // ENG_RENDER_COLOR_*
uniform vec2 u_color_range;       // the values at the map's ends: rho / rho0, or m/s
uniform vec3 u_color_low;         // height map: colour at parameter 0
uniform vec3 u_color_mid;         // at 0.5
uniform vec3 u_color_high;        // at 1

vec3 gradient3(vec3 a, vec3 b, vec3 c, float t)
{
    t = clamp(t, 0.0, 1.0);
    return t < 0.5 ? mix(a, b, t * 2.0) : mix(b, c, t * 2.0 - 1.0);
}

// Dark blue, blue, cyan, yellow, red (a perceptually ordered "speed" map).
vec3 speed_map(float t)
{
    const vec3 k[5] = vec3[5](vec3(0.05, 0.08, 0.35), vec3(0.10, 0.35, 0.90), vec3(0.15, 0.85, 0.90),
                              vec3(0.98, 0.90, 0.20), vec3(0.90, 0.15, 0.08));
    float x = clamp(t, 0.0, 1.0) * 4.0;
    int i = min(int(x), 3);
    return mix(k[i], k[i + 1], x - float(i));
}

vec3 particle_color(uint i, float param)
{
    if (u_color_mode == ENG_RENDER_COLOR_DENSITY) {
        float vol = velocities[i].w;
        float ratio = vol > 0.0 ? u_particle_mass / vol * u_inv_rest_density : 1.0;
        float t = (ratio - u_color_range.x) / max(u_color_range.y - u_color_range.x, 1e-6);
        // Under-dense blue, rest density white, compressed red.
        return gradient3(vec3(0.10, 0.30, 0.95), vec3(0.95, 0.95, 0.95), vec3(0.95, 0.15, 0.10), t);
    }
    if (u_color_mode == ENG_RENDER_COLOR_SPEED) {
        float s = length(velocities[i].xyz);
        return speed_map((s - u_color_range.x) / max(u_color_range.y - u_color_range.x, 1e-6));
    }
    if (is_tint(param)) return tint_colour(param);
    return gradient3(u_color_low, u_color_mid, u_color_high, param);
}
#endif
