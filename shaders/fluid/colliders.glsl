// Rigid colliders (bodies) as fluid boundaries: signed distances, their share of the
// density, the position correction they cause, collisions, and the reaction forces.
// Included by the passes that touch colliders (after common.glsl, with USE_COLLIDERS and,
// for the delta pass, USE_FORCES). The C side is fluid/pbf_colliders.c.

// Signed distance from x to a collider's surface (positive outside the solid, where the
// fluid is) and the outward unit normal, for the collider at pose (p, q).
float collider_sdf(pbf_gpu_collider c, vec3 p, vec4 q, vec3 x, out vec3 n)
{
    uint type = c.info.x;
    if (type == PBF_COLLIDER_PLANE) {
        n = c.params.xyz;
        return dot(x, n) - c.params.w;
    }
    vec3 l = quat_rotate_inv(q, x - p);
    vec3 ln;
    float d;
    if (type == PBF_COLLIDER_SPHERE) {
        float len = length(l);
        ln = len > 1e-9 ? l / len : vec3(0.0, 1.0, 0.0);
        d = len - c.params.x;
    } else if (type == PBF_COLLIDER_BOX) {
        vec3 b = c.params.xyz;
        vec3 q3 = abs(l) - b;
        if (max(q3.x, max(q3.y, q3.z)) > 0.0) {
            vec3 o = max(q3, vec3(0.0));
            d = length(o);
            ln = sign(l) * o / max(d, 1e-12);
        } else {
            // inside: nearest face
            if (q3.x > q3.y && q3.x > q3.z) ln = vec3(sign(l.x), 0.0, 0.0);
            else if (q3.y > q3.z) ln = vec3(0.0, sign(l.y), 0.0);
            else ln = vec3(0.0, 0.0, sign(l.z));
            d = max(q3.x, max(q3.y, q3.z));
        }
    } else if (type == PBF_COLLIDER_CAPSULE) {
        vec3 a = vec3(0.0, clamp(l.y, -c.params.y, c.params.y), 0.0);
        vec3 r = l - a;
        float len = length(r);
        ln = len > 1e-9 ? r / len : vec3(1.0, 0.0, 0.0);
        d = len - c.params.x;
    } else { // cylinder
        vec2 q2 = vec2(length(l.xz) - c.params.x, abs(l.y) - c.params.y);
        vec3 radial = length(l.xz) > 1e-9 ? vec3(l.x, 0.0, l.z) / length(l.xz) : vec3(1.0, 0.0, 0.0);
        vec3 axial = vec3(0.0, sign(l.y), 0.0);
        if (q2.x > 0.0 && q2.y > 0.0) {
            d = length(q2);
            ln = normalize(radial * q2.x + axial * q2.y);
        } else if (q2.x > q2.y) {
            d = q2.x;
            ln = radial;
        } else {
            d = q2.y;
            ln = axial;
        }
    }
    n = quat_rotate(q, ln);
    return d;
}

#ifdef USE_COLLIDERS
bool collider_near(uint b, vec3 x, float reach)
{
    return distance(x, colliders[b].position.xyz) <= colliders[b].position.w + reach;
}

float collider_distance(uint b, vec3 x, out vec3 n)
{
    return collider_sdf(colliders[b], colliders[b].position.xyz, colliders[b].rotation, x, n);
}

// Adds the colliders' share of the density at x (kg/m^3) and of grad_i C_i (1/m).
void colliders_density(vec3 x, inout float rho, inout vec3 grad_i)
{
    for (uint b = 0u; b < P.collider_count; b++) {
        if (!collider_near(b, x, P.h)) continue;
        vec3 n;
        float d = collider_distance(b, x, n);
        if (d < P.h) {
            rho += P.rest_density * boundary_volume(d);
            grad_i -= boundary_gradient(d) * n;
        }
    }
}

#ifdef USE_FORCES
void add_force(uint b, vec3 f, vec3 at)
{
    if ((colliders[b].info.y & 1u) == 0u) return;
    vec3 t = cross(at - colliders[b].center_of_mass.xyz, f);
    int base = int(b) * 8;
    atomicAdd(forces[base + 0], int(round(f.x * PBF_FORCE_SCALE)));
    atomicAdd(forces[base + 1], int(round(f.y * PBF_FORCE_SCALE)));
    atomicAdd(forces[base + 2], int(round(f.z * PBF_FORCE_SCALE)));
    atomicAdd(forces[base + 4], int(round(t.x * PBF_FORCE_SCALE)));
    atomicAdd(forces[base + 5], int(round(t.y * PBF_FORCE_SCALE)));
    atomicAdd(forces[base + 6], int(round(t.z * PBF_FORCE_SCALE)));
}

// The colliders' part of the position correction of particle x with multiplier lambda;
// the particle's reaction pushes two-way colliders (f = -m dx / dt^2).
void colliders_delta(vec3 x, float lambda, inout vec3 dp)
{
    float to_force = -P.mass * P.inv_dt * P.inv_dt;
    for (uint b = 0u; b < P.collider_count; b++) {
        if (!collider_near(b, x, P.h)) continue;
        vec3 n;
        float d = collider_distance(b, x, n);
        if (d < P.h) {
            vec3 bdp = -lambda * boundary_gradient(d) * n;
            dp += bdp;
            add_force(b, to_force * P.omega * bdp, x - d * n);
        }
    }
}

// Moves x out of every collider to a particle radius from its surface.
vec3 colliders_collide(vec3 x)
{
    float to_force = -P.mass * P.inv_dt * P.inv_dt;
    for (uint b = 0u; b < P.collider_count; b++) {
        if (!collider_near(b, x, P.radius)) continue;
        vec3 n;
        float d = collider_distance(b, x, n);
        if (d < P.radius) {
            vec3 push = (P.radius - d) * n;
            x += push;
            add_force(b, to_force * push, x - P.radius * n);
        }
    }
    return x;
}
#endif
#endif
