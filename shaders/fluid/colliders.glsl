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
// enters the collider inflated by the particle radius, the particle is put back on the
// side it came from (so a thin wall moving fast neither lets particles through nor
// tunnels). A particle that was already inside at the start of the substep (fluid that
// started overlapping a body, or was squeezed in) is moved out at PBF_PUSH_OUT_SPEED, with no reaction
// force and no boundary density (which would push it out at once): gentle, not explosive.

#ifdef USE_COLLIDERS
layout(std430, binding = PBF_B_COLLIDER_DATA) readonly buffer ColliderData { float collider_data[]; };

// ---- shapes in the collider frame -------------------------------------------------------

float grid_sample(uint base, uvec3 dims, ivec3 c)
{
    return collider_data[base + uint(c.x) + dims.x * (uint(c.y) + dims.y * uint(c.z))];
}

// Trilinear distance and its gradient; outside the grid's box the distance to the box is
// added (the grid carries a margin, so this only matters far from the surface).
float grid_distance(uint base, uint packed_dims, vec4 frame, vec3 l, out vec3 ln)
{
    uvec3 dims = uvec3(packed_dims & 1023u, (packed_dims >> 10) & 1023u, (packed_dims >> 20) & 1023u);
    vec3 lo = frame.xyz;
    vec3 hi = lo + vec3(dims - 1u) * frame.w;
    vec3 lc = clamp(l, lo, hi);
    vec3 g = (lc - lo) / frame.w;
    ivec3 i0 = clamp(ivec3(floor(g)), ivec3(0), ivec3(dims) - 2);
    vec3 f = g - vec3(i0);
    float c000 = grid_sample(base, dims, i0);
    float c100 = grid_sample(base, dims, i0 + ivec3(1, 0, 0));
    float c010 = grid_sample(base, dims, i0 + ivec3(0, 1, 0));
    float c110 = grid_sample(base, dims, i0 + ivec3(1, 1, 0));
    float c001 = grid_sample(base, dims, i0 + ivec3(0, 0, 1));
    float c101 = grid_sample(base, dims, i0 + ivec3(1, 0, 1));
    float c011 = grid_sample(base, dims, i0 + ivec3(0, 1, 1));
    float c111 = grid_sample(base, dims, i0 + ivec3(1, 1, 1));
    float x00 = mix(c000, c100, f.x), x10 = mix(c010, c110, f.x);
    float x01 = mix(c001, c101, f.x), x11 = mix(c011, c111, f.x);
    float y0 = mix(x00, x10, f.y), y1 = mix(x01, x11, f.y);
    float d = mix(y0, y1, f.z);
    vec3 grad;
    grad.x = mix(mix(c100 - c000, c110 - c010, f.y), mix(c101 - c001, c111 - c011, f.y), f.z);
    grad.y = mix(x10 - x00, x11 - x01, f.z);
    grad.z = y1 - y0;
    float gl = length(grad);
    ln = gl > 1e-12 ? grad / gl : vec3(0.0, 1.0, 0.0);
    vec3 out_of_box = l - lc;
    float ob = length(out_of_box);
    if (ob > 0.0) {
        d += ob;
        ln = normalize(out_of_box + max(d - ob, 0.0) * ln);
    }
    return d;
}

// Convex hull: the largest face-plane distance (exact inside and next to faces, a lower
// bound near edges and corners outside).
float hull_distance(uint base, uint count, vec3 l, out vec3 ln)
{
    float best = -1e30;
    ln = vec3(0.0, 1.0, 0.0);
    for (uint k = 0u; k < count; k++) {
        uint o = base + 4u * k;
        vec3 n = vec3(collider_data[o], collider_data[o + 1u], collider_data[o + 2u]);
        float d = dot(n, l) - collider_data[o + 3u];
        if (d > best) {
            best = d;
            ln = n;
        }
    }
    return best;
}

// Signed distance from local point l to the surface of collider b's shape (positive
// outside the solid, where the fluid is) and the outward unit normal, both local.
float shape_distance(uint b, vec3 l, out vec3 ln)
{
    uint type = colliders[b].info.x;
    vec4 s = colliders[b].params;
    float d;
    if (type == PBF_COLLIDER_PLANE) {
        ln = s.xyz;
        d = dot(l, ln) - s.w;
    } else if (type == PBF_COLLIDER_SPHERE) {
        float len = length(l);
        ln = len > 1e-9 ? l / len : vec3(0.0, 1.0, 0.0);
        d = len - s.x;
    } else if (type == PBF_COLLIDER_BOX) {
        vec3 q3 = abs(l) - s.xyz;
        if (max(q3.x, max(q3.y, q3.z)) > 0.0) {
            vec3 o = max(q3, vec3(0.0));
            d = length(o);
            ln = sign(l) * o / max(d, 1e-12);
        } else {
            // inside: nearest face
            if (q3.x > q3.y && q3.x > q3.z) ln = vec3(l.x < 0.0 ? -1.0 : 1.0, 0.0, 0.0);
            else if (q3.y > q3.z) ln = vec3(0.0, l.y < 0.0 ? -1.0 : 1.0, 0.0);
            else ln = vec3(0.0, 0.0, l.z < 0.0 ? -1.0 : 1.0);
            d = max(q3.x, max(q3.y, q3.z));
        }
    } else if (type == PBF_COLLIDER_CAPSULE) {
        vec3 a = vec3(0.0, clamp(l.y, -s.y, s.y), 0.0);
        vec3 r = l - a;
        float len = length(r);
        ln = len > 1e-9 ? r / len : vec3(1.0, 0.0, 0.0);
        d = len - s.x;
    } else if (type == PBF_COLLIDER_CYLINDER) {
        float rl = length(l.xz);
        vec2 q2 = vec2(rl - s.x, abs(l.y) - s.y);
        vec3 radial = rl > 1e-9 ? vec3(l.x, 0.0, l.z) / rl : vec3(1.0, 0.0, 0.0);
        vec3 axial = vec3(0.0, l.y < 0.0 ? -1.0 : 1.0, 0.0);
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
    } else if (type == PBF_COLLIDER_HULL) {
        d = hull_distance(colliders[b].info.z, colliders[b].info.w, l, ln);
    } else {
        d = grid_distance(colliders[b].info.z, colliders[b].info.w, s, l, ln);
    }
    return d;
}

// ---- poses ------------------------------------------------------------------------------

// The collider's pose at the start (p0, q0) and at the end (p1, q1) of this substep.
void collider_poses(uint b, out vec3 p0, out vec4 q0, out vec3 p1, out vec4 q1)
{
    vec3 pa = colliders[b].prev_position.xyz, pb = colliders[b].position.xyz;
    vec4 qa = colliders[b].prev_rotation, qb = colliders[b].rotation;
    float span = colliders[b].linear_velocity.w;
    if (span > 1.5) {
        float t0 = float(P.substep) / span, t1 = min(float(P.substep + 1u) / span, 1.0);
        p0 = mix(pa, pb, t0);
        q0 = quat_nlerp(qa, qb, t0);
        p1 = mix(pa, pb, t1);
        q1 = quat_nlerp(qa, qb, t1);
    } else {
        p0 = pa;
        q0 = qa;
        p1 = pb;
        q1 = qb;
    }
}

void collider_end_pose(uint b, out vec3 p1, out vec4 q1)
{
    vec3 p0;
    vec4 q0;
    collider_poses(b, p0, q0, p1, q1);
}

bool collider_near(vec3 p1, uint b, vec3 x, float reach)
{
    if (colliders[b].info.x == PBF_COLLIDER_PLANE) return true;
    return distance(x, p1) <= colliders[b].position.w + reach;
}

// Signed distance (world units) and outward world normal of collider b at pose (p, q).
float collider_distance_at(uint b, vec3 p, vec4 q, vec3 x, out vec3 n)
{
    vec3 ln;
    float d = shape_distance(b, quat_rotate_inv(q, x - p), ln);
    n = quat_rotate(q, ln);
    return d;
}

// The boundary share V (the fraction of a filled neighbourhood that collider b takes) at x,
// and its gradient with respect to x (1/m), at the collider's end pose. Boxes: the product
// over the three axes of the share of the kernel inside each slab |l_k| <= e_k, which is
// exact for separable kernels and, unlike one half-space, right at edges, corners and for
// boxes thinner than the kernel. Other shapes: the half-space at the signed distance.
// Returns false when x is out of reach.
bool collider_boundary(uint b, vec3 x, out float V, out vec3 gradV)
{
    V = 0.0;
    gradV = vec3(0.0);
    vec3 p1;
    vec4 q1;
    collider_end_pose(b, p1, q1);
    if (!collider_near(p1, b, x, P.h)) return false;
    vec3 l = quat_rotate_inv(q1, x - p1);
    vec3 ln;
    float d = shape_distance(b, l, ln);
    if (d >= P.h || d < 0.0) return false; // inside: only the gentle push-out moves it
    if (colliders[b].info.x == PBF_COLLIDER_BOX) {
        vec3 e = colliders[b].params.xyz;
        vec3 a = e - l, c = e + l; // distances to the + and - faces of each slab
        float k = boundary_factor(), ik = 1.0 / k;
        vec3 F = vec3(1.0) - vec3(beyond(a.x, ik), beyond(a.y, ik), beyond(a.z, ik)) -
                 vec3(beyond(c.x, ik), beyond(c.y, ik), beyond(c.z, ik));
        F = max(F, vec3(0.0));
        // dF/dl = d/dl [1 - beyond(e - l) - beyond(e + l)] = beyond'(e - l) - beyond'(e + l)
        vec3 dF = vec3(beyond_slope(a.x, ik) - beyond_slope(c.x, ik), beyond_slope(a.y, ik) - beyond_slope(c.y, ik),
                       beyond_slope(a.z, ik) - beyond_slope(c.z, ik));
        V = k * F.x * F.y * F.z;
        gradV = k * quat_rotate(q1, vec3(dF.x * F.y * F.z, F.x * dF.y * F.z, F.x * F.y * dF.z));
    } else {
        V = boundary_volume(d);
        gradV = -boundary_gradient(d) * quat_rotate(q1, ln);
    }
    return true;
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
    int base = int(b) * 8;
    if (fi.x != 0) atomicAdd(forces[base + 0], fi.x);
    if (fi.y != 0) atomicAdd(forces[base + 1], fi.y);
    if (fi.z != 0) atomicAdd(forces[base + 2], fi.z);
    if (ti.x != 0) atomicAdd(forces[base + 4], ti.x);
    if (ti.y != 0) atomicAdd(forces[base + 5], ti.y);
    if (ti.z != 0) atomicAdd(forces[base + 6], ti.z);
}

// The colliders' part of the position correction of particle x with multiplier lambda;
// the particle's reaction pushes two-way colliders (f = -m dx / dt^2, dx = omega * bdp).
void colliders_delta(vec3 x, float lambda, inout vec3 dp)
{
    float to_force = -P.mass * P.inv_dt * P.inv_dt * P.omega;
    for (uint b = 0u; b < P.collider_count; b++) {
        float V;
        vec3 gradV;
        if (!collider_boundary(b, x, V, gradV)) continue;
        vec3 bdp = lambda * gradV;
        dp += bdp;
        if ((colliders[b].info.y & PBF_COLLIDER_TWO_WAY) == 0u) continue;
        atomicAdd(forces[int(b) * 8 + 3], 1);
        if (lambda != 0.0) {
            // Acting at the particle's nearest surface point.
            vec3 p1, n;
            vec4 q1;
            collider_end_pose(b, p1, q1);
            float d = collider_distance_at(b, p1, q1, x, n);
            add_force(b, to_force * bdp, x - d * n);
        }
    }
}

// First point of the local path a -> e (within [0, 1]) that comes within r of the surface,
// by sphere tracing on the distance (which never overestimates); false when none.
bool sweep_hit(uint b, vec3 a, vec3 e, float da, float r, out vec3 hit)
{
    vec3 seg = e - a;
    float len = length(seg);
    hit = e;
    if (len < 1e-9) return false;
    float t = 0.0, d = da;
    for (int k = 0; k < 24; k++) {
        if (d <= r * 1.001) {
            hit = a + t * seg;
            return true;
        }
        t += (d - r) / len;
        if (t >= 1.0) return false;
        vec3 unused;
        d = shape_distance(b, a + t * seg, unused);
    }
    hit = a + t * seg;
    return true;
}

// Moves particle i at x out of every collider to a particle radius from its surface,
// sweeping its path through the substep in each collider's frame.
vec3 colliders_collide(uint i, vec3 x)
{
    float to_force = -P.mass * P.inv_dt * P.inv_dt;
    float r = P.radius;
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
                if ((colliders[b].info.y & PBF_COLLIDER_TWO_WAY) != 0u) atomicAdd(forces[int(b) * 8 + 7], 1);
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
        add_force(b, to_force * (xn - x), xn - r * quat_rotate(q1, nh));
        x = xn;
    }
    return x;
}
#endif
#endif
