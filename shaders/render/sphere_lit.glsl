// The sphere modes' lit sphere, shared by particles.frag (the raster impostors) and
// spheres.frag (the compute splats' pixels). Included after frame.glsl.

// The eye ray `dir` (unit, view space, from the eye at the origin) against the sphere at
// `center` (view space) of radius `radius` (m): false where it misses; else the window
// depth of the nearest hit and the colour there, `base` lit by the scene's light (its
// shadows, the water's) and fogged.
bool lit_sphere(vec3 dir, vec3 center, float radius, vec3 base, float specular, float shininess, out float depth,
                out vec4 colour)
{
    depth = 1.0;
    colour = vec4(0.0);
    float b = dot(dir, center);
    float h = b * b - (dot(center, center) - radius * radius);
    if (h < 0.0) return false;
    vec3 hit = dir * (b - sqrt(h));
    vec3 n_view = (hit - center) / radius;
    vec4 clip = u_proj * vec4(hit, 1.0);
    float ndc_z = clip.z / clip.w;
    depth = ((gl_DepthRange.far - gl_DepthRange.near) * ndc_z + gl_DepthRange.near + gl_DepthRange.far) * 0.5;
    vec3 n = normalize(mat3(u_inv_view) * n_view);
    vec3 p = (u_inv_view * vec4(hit, 1.0)).xyz;
    colour = vec4(fog(shade(base, n, p, specular, shininess), p), 1.0);
    return true;
}
