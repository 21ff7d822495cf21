// Rigid colliders (bodies) as fluid boundaries: signed distances, their share of the
// density, the position correction they cause, swept collisions, and the reaction forces.
// Included by the passes that touch colliders (after common.glsl, with USE_COLLIDERS and,
// for the collide pass, USE_FORCES). The C side is fluid/pbf_colliders.c; the design is in
// docs/coupling.md.
//
// Poses. Each collider carries the pose it had at the start of the substep (prev_*) and
// the one it reaches at its end. A pose set once per step (linear_velocity.w = number of
// substeps it spans > 1) is interpolated here, substep by substep.
//
// Boundary model. A particle at signed distance d from a collider's surface (normal n)
// sees a half-space: density rho0 V(d), constraint gradient -G(d) n (common.glsl), exactly
// like a container wall. The correction -lambda G(d) n that this adds to a particle is
// the boundary's push; its reaction, -m dx / dt^2, is the force on the collider.
//
// Collisions are swept: in the collider's frame a particle moves from where it started the
// substep (start position, previous pose) to where it is now (current pose). If that path
// comes within PBF_CONTACT_MARGIN of a particle radius of the surface, the particle is put
// back on the side it came from (so a thin wall moving fast neither lets particles through
// nor tunnels). The boundary share, not this backstop, keeps the water at its rest
// distance from a body. A particle that was already inside at the start of the substep (fluid that
// started overlapping a body, or was squeezed in) is moved out at PBF_PUSH_OUT_SPEED, with no reaction
// force and no boundary density (which would push it out at once): gentle, not explosive.

#ifdef USE_COLLIDERS
layout(std430, binding = PBF_B_COLLIDER_DATA) readonly buffer ColliderData { float collider_data[]; };

// ---- shapes, poses, the boundary share: pbf_shapes.h (shared with the CPU reference) ---------
#include "pbf_shapes.h"

// The shared functions take the collider by value; the passes name it by index.
float shape_distance(uint b, vec3 l, out vec3 ln) { return shape_distance_of(colliders[b], l, ln); }

void collider_poses(uint b, out vec3 p0, out vec4 q0, out vec3 p1, out vec4 q1)
{
    collider_poses_of(colliders[b], p0, q0, p1, q1);
}

void collider_end_pose(uint b, out vec3 p1, out vec4 q1)
{
    vec3 p0;
    vec4 q0;
    collider_poses(b, p0, q0, p1, q1);
}

bool collider_near(vec3 p1, uint b, vec3 x, float reach) { return collider_near_of(colliders[b], p1, x, reach); }

bool collider_boundary(uint b, vec3 x, out float V, out vec3 gradV)
{
    return collider_boundary_of(colliders[b], x, V, gradV);
}

bool sweep_hit(uint b, vec3 a, vec3 e, float da, float r, out vec3 hit)
{
    return sweep_hit_of(colliders[b], a, e, da, r, hit);
}

// Signed distance (world units) and outward world normal of collider b at pose (p, q).
float collider_distance_at(uint b, vec3 p, vec4 q, vec3 x, out vec3 n)
{
    vec3 ln;
    float d = shape_distance(b, quat_rotate_inv(q, x - p), ln);
    n = quat_rotate(q, ln);
    return d;
}

// Adds the colliders' share of the density at x (kg/m^3) and of grad_i C_i (1/m).
void colliders_density(vec3 x, inout float rho, inout vec3 grad_i)
{
    for (uint b = 0u; b < P.collider_count; b++) {
        float V;
        vec3 gradV;
        if (!collider_boundary(b, x, V, gradV)) continue;
        rho += P.rest_density * V;
        grad_i += gradV;
    }
}

#ifdef USE_FORCES
#ifdef USE_POS
vec3 collider_start(uint i) { return pos[i].xyz; }
#else
layout(std430, binding = PBF_B_POS) readonly buffer ColliderStart { vec4 collider_start_pos[]; };
vec3 collider_start(uint i) { return collider_start_pos[i].xyz; }
#endif

// Adds force f (N) acting at point `at` to two-way collider b, in its fixed-point scale.
void add_force(uint b, vec3 f, vec3 at)
{
    if ((colliders[b].info.y & PBF_COLLIDER_TWO_WAY) == 0u) return;
    float scale = colliders[b].center_of_mass.w;
    vec3 t = cross(at - colliders[b].center_of_mass.xyz, f);
    ivec3 fi = ivec3(round(f * scale)), ti = ivec3(round(t * scale));
    int base = int(b) * PBF_FORCE_WORDS;
    if (fi.x != 0) atomicAdd(forces[base + 0], fi.x);
    if (fi.y != 0) atomicAdd(forces[base + 1], fi.y);
    if (fi.z != 0) atomicAdd(forces[base + 2], fi.z);
    if (ti.x != 0) atomicAdd(forces[base + 4], ti.x);
    if (ti.y != 0) atomicAdd(forces[base + 5], ti.y);
    if (ti.z != 0) atomicAdd(forces[base + 6], ti.z);
}

// A particle's velocity so far in the substep, from where it started (xs) to x, at most
// max_speed (the solver's clamp).
vec3 particle_velocity(vec3 xs, vec3 x)
{
    vec3 v = (x - xs) * P.inv_dt;
    float speed = length(v);
    return speed > P.max_speed ? v * (P.max_speed / speed) : v;
}

// Adds v (units) to the 64-bit sum at forces[at] (low word, taken as unsigned) and
// forces[at + 1] (high): the low word's carry and v's sign go to the high word.
void add_wide(int at, int v)
{
    if (v == 0) return;
    uint old = uint(atomicAdd(forces[at], v));
    int high = (old + uint(v) < old ? 1 : 0) + (v < 0 ? -1 : 0);
    if (high != 0) atomicAdd(forces[at + 1], high);
}

// Adds the velocity of a particle that started the substep at xs and is now at x (m/s, at
// most max_speed) weighted by the magnitude of its push f (N) on two-way collider b to b's
// sums of the water that pushes it (PBF_FORCE_WORDS), in its force scale.
void add_water(uint b, vec3 f, vec3 xs, vec3 x)
{
    vec3 v = particle_velocity(xs, x);
    // One particle's share fits an int by far (the clamp only keeps a conversion defined).
    float m = min(length(f) * colliders[b].center_of_mass.w, PBF_WIDE_MAX);
    ivec3 vi = ivec3(round(clamp(m * v, -PBF_WIDE_MAX, PBF_WIDE_MAX)));
    int base = int(b) * PBF_FORCE_WORDS;
    add_wide(base + 8, vi.x);
    add_wide(base + 10, vi.y);
    add_wide(base + 12, vi.z);
    add_wide(base + 14, int(round(m)));
}

// The colliders' part of the position correction of particle x with multiplier lambda;
// the particle's reaction pushes two-way colliders (f = -m dx / dt^2, dx = relax * bdp).
// level_lambda (0 but in the coarse level's iteration): -p(x), the level's push, which has
// no reaction of its own (it moves the water by -grad p); the colliders take it as the
// reaction to that multiplier, once per substep, and the particle does not move for it.
// xs: where the particle started the substep; its velocity so far joins the sums of the water
// that pushes each two-way collider, weighted by its push.
void colliders_delta(vec3 x, float lambda, float relax, float level_lambda, vec3 xs, inout vec3 dp)
{
    float to_force = -P.mass * P.inv_dt * P.inv_dt * relax;
    float to_level = -P.mass * P.inv_dt * P.inv_dt;
    for (uint b = 0u; b < P.collider_count; b++) {
        float V;
        vec3 gradV;
        if (!collider_boundary(b, x, V, gradV)) continue;
        vec3 bdp = lambda * gradV;
        dp += bdp;
        if ((colliders[b].info.y & PBF_COLLIDER_TWO_WAY) == 0u) continue;
        atomicAdd(forces[int(b) * PBF_FORCE_WORDS + 3], 1);
        if (lambda != 0.0 || level_lambda != 0.0) {
            // Acting at the particle's nearest surface point.
            vec3 p1, n;
            vec4 q1;
            collider_end_pose(b, p1, q1);
            float d = collider_distance_at(b, p1, q1, x, n);
            vec3 f = to_force * bdp;
            if (level_lambda != 0.0) f += to_level * level_lambda * gradV;
            add_force(b, f, x - d * n);
            add_water(b, f, xs, x);
        }
    }
}

// Moves particle i at x out of every collider to PBF_CONTACT_MARGIN of a particle radius
// from its surface, sweeping its path through the substep in each collider's frame.
vec3 colliders_collide(uint i, vec3 x)
{
    float to_force = -P.mass * P.inv_dt * P.inv_dt;
    float r = PBF_CONTACT_MARGIN * P.radius;
    vec3 xs = collider_start(i);
    for (uint b = 0u; b < P.collider_count; b++) {
        vec3 p0, p1;
        vec4 q0, q1;
        collider_poses(b, p0, q0, p1, q1);
        float turn = 2.0 * acos(min(abs(dot(q0, q1)), 1.0)); // rad turned in this substep
        float reach = r + distance(p0, p1) + distance(xs, x) + colliders[b].position.w * turn;
        if (!collider_near(p1, b, x, reach)) continue;
        vec3 l0 = quat_rotate_inv(q0, xs - p0); // where it started, in the collider's frame
        vec3 l1 = quat_rotate_inv(q1, x - p1);  // where it is now
        vec3 n0, n1;
        float d0 = shape_distance(b, l0, n0);
        float d1 = shape_distance(b, l1, n1);
        vec3 lnew = l1;
        if (d0 < 0.5 * r) {
            // Started inside (or deep in the radius shell): out along the normal, at most
            // PBF_PUSH_OUT_SPEED * dt farther out than it started this substep.
            float target = min(r, d0 + PBF_PUSH_OUT_SPEED * P.dt);
            if (d1 < target) {
                lnew = l1 + (target - d1) * n1;
                if ((colliders[b].info.y & PBF_COLLIDER_TWO_WAY) != 0u) atomicAdd(forces[int(b) * PBF_FORCE_WORDS + 7], 1);
            }
            x = p1 + quat_rotate(q1, lnew);
            continue;
        }
        // The path can only come within r of the surface if this bound allows it.
        float len = distance(l0, l1);
        if (d1 >= r && 0.5 * (d0 + d1 - len) > r) continue;
        vec3 hit;
        if (!sweep_hit(b, l0, l1, d0, r, hit)) continue;
        vec3 nh;
        shape_distance(b, hit, nh);
        // Keep the motion along the surface, remove the part into it.
        float into = dot(l1 - hit, nh);
        lnew = into < 0.0 ? l1 - into * nh : l1;
        // Still too close (a corner, or the path grazed it)? Out along the local normal.
        float dn = shape_distance(b, lnew, n1);
        if (dn < r) lnew += (r - dn) * n1;
        vec3 xn = p1 + quat_rotate(q1, lnew);
        vec3 f = to_force * (xn - x);
        add_force(b, f, xn - r * quat_rotate(q1, nh));
        if ((colliders[b].info.y & PBF_COLLIDER_TWO_WAY) != 0u) add_water(b, f, xs, x);
        x = xn;
    }
    return x;
}
#endif
#endif
