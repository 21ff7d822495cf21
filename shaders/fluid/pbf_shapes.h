// The colliders' geometry, shared by colliders.glsl and the CPU reference: signed distances
// to each shape, poses through a substep, the boundary share a body takes, the swept hit.
//
// Compiled as GLSL (colliders.glsl includes it after the collider buffers) and as C
// (fluid/pbf_cpu_colliders.c), in the vocabulary of pbf_kernels.h. A collider comes in by
// value (`pbf_gpu_collider c`: colliders[b] in GLSL); its hull planes and distance grid in
// collider_data (PBF_DATA_ARG). What each side keeps is the passes' plumbing around these:
// the loops over colliders, the force accumulators (atomics on the GPU) and the collide
// pass's choice between push-out and sweep (colliders.glsl, pbf_cpu_colliders.c), which
// tests/test_mirror.c compares.
#ifndef PBF_SHAPES_H
#define PBF_SHAPES_H

#include "pbf_kernels.h"

#ifndef GL_core_profile
#define P (*pbf_p)
#endif

// ---- shapes in the collider frame -------------------------------------------------------

/// Sample (x, y, z) of a distance grid at `base` in collider_data, dx by dy by any, x fastest.
PBF_FN float grid_sample(PBF_DATA_ARG PBF_UINT base, PBF_UINT dx, PBF_UINT dy, int x, int y, int z)
{
    return collider_data[base + PBF_UINT_OF(x) + dx * (PBF_UINT_OF(y) + dy * PBF_UINT_OF(z))];
}

/// Trilinear distance and its gradient; outside the grid's box the distance to the box is
/// added (the grid carries a margin, so this only matters far from the surface). Dims
/// packed 10 bits each (x lowest); frame: first sample xyz, spacing w (m).
PBF_FN float grid_distance(PBF_DATA_ARG PBF_UINT base, PBF_UINT packed_dims, PBF_VEC4 frame, pbf_vec3 l,
                           PBF_OUT(pbf_vec3) ln)
{
    PBF_UINT dx = packed_dims & 1023u, dy = (packed_dims >> 10) & 1023u, dz = (packed_dims >> 20) & 1023u;
    pbf_vec3 lo = pbf_xyz(frame);
    pbf_vec3 hi = pbf_add(lo, pbf_scale(frame.w, pbf_v3(PBF_FLOAT_OF(dx - 1u), PBF_FLOAT_OF(dy - 1u), PBF_FLOAT_OF(dz - 1u))));
    pbf_vec3 lc = pbf_v3(pbf_clamp(l.x, lo.x, hi.x), pbf_clamp(l.y, lo.y, hi.y), pbf_clamp(l.z, lo.z, hi.z));
    pbf_vec3 g = pbf_div(pbf_sub(lc, lo), frame.w);
    int ix = pbf_clampi(PBF_FLOOR_INT(g.x), 0, PBF_INT_OF(dx) - 2);
    int iy = pbf_clampi(PBF_FLOOR_INT(g.y), 0, PBF_INT_OF(dy) - 2);
    int iz = pbf_clampi(PBF_FLOOR_INT(g.z), 0, PBF_INT_OF(dz) - 2);
    pbf_vec3 f = pbf_v3(g.x - PBF_FLOAT_OF(ix), g.y - PBF_FLOAT_OF(iy), g.z - PBF_FLOAT_OF(iz));
    float c000 = grid_sample(PBF_DATA_ base, dx, dy, ix, iy, iz);
    float c100 = grid_sample(PBF_DATA_ base, dx, dy, ix + 1, iy, iz);
    float c010 = grid_sample(PBF_DATA_ base, dx, dy, ix, iy + 1, iz);
    float c110 = grid_sample(PBF_DATA_ base, dx, dy, ix + 1, iy + 1, iz);
    float c001 = grid_sample(PBF_DATA_ base, dx, dy, ix, iy, iz + 1);
    float c101 = grid_sample(PBF_DATA_ base, dx, dy, ix + 1, iy, iz + 1);
    float c011 = grid_sample(PBF_DATA_ base, dx, dy, ix, iy + 1, iz + 1);
    float c111 = grid_sample(PBF_DATA_ base, dx, dy, ix + 1, iy + 1, iz + 1);
    float x00 = pbf_mixf(c000, c100, f.x), x10 = pbf_mixf(c010, c110, f.x);
    float x01 = pbf_mixf(c001, c101, f.x), x11 = pbf_mixf(c011, c111, f.x);
    float y0 = pbf_mixf(x00, x10, f.y), y1 = pbf_mixf(x01, x11, f.y);
    float d = pbf_mixf(y0, y1, f.z);
    pbf_vec3 grad = pbf_v3(pbf_mixf(pbf_mixf(c100 - c000, c110 - c010, f.y), pbf_mixf(c101 - c001, c111 - c011, f.y), f.z),
                           pbf_mixf(x10 - x00, x11 - x01, f.z), y1 - y0);
    float gl = pbf_length(grad);
    PBF_REF(ln) = gl > 1e-12f ? pbf_div(grad, gl) : pbf_v3(0.0f, 1.0f, 0.0f);
    pbf_vec3 out_of_box = pbf_sub(l, lc);
    float ob = pbf_length(out_of_box);
    if (ob > 0.0f) {
        d += ob;
        PBF_REF(ln) = pbf_normalize(pbf_add(out_of_box, pbf_scale(pbf_max(d - ob, 0.0f), PBF_REF(ln))));
    }
    return d;
}

/// Convex hull of `count` face planes at `base` (outward n xyz, offset w; inside: n.x <= w):
/// the largest face-plane distance (exact inside and next to faces, a lower bound near
/// edges and corners outside).
PBF_FN float hull_distance(PBF_DATA_ARG PBF_UINT base, PBF_UINT count, pbf_vec3 l, PBF_OUT(pbf_vec3) ln)
{
    float best = -1e30f;
    PBF_REF(ln) = pbf_v3(0.0f, 1.0f, 0.0f);
    for (PBF_UINT k = 0u; k < count; k++) {
        PBF_UINT o = base + 4u * k;
        pbf_vec3 n = pbf_v3(collider_data[o], collider_data[o + 1u], collider_data[o + 2u]);
        float d = pbf_dot(n, l) - collider_data[o + 3u];
        if (d > best) {
            best = d;
            PBF_REF(ln) = n;
        }
    }
    return best;
}

/// Signed distance from local point l to the surface of collider c's shape (m, positive
/// outside the solid, where the fluid is) and the outward unit normal, both local.
PBF_FN float shape_distance_of(PBF_DATA_ARG pbf_gpu_collider c, pbf_vec3 l, PBF_OUT(pbf_vec3) ln)
{
    PBF_UINT type = c.info.x;
    PBF_VEC4 s = c.params;
    float d;
    if (type == PBF_COLLIDER_PLANE) {
        PBF_REF(ln) = pbf_xyz(s);
        d = pbf_dot(l, PBF_REF(ln)) - s.w;
    } else if (type == PBF_COLLIDER_SPHERE) {
        float len = pbf_length(l);
        PBF_REF(ln) = len > 1e-9f ? pbf_div(l, len) : pbf_v3(0.0f, 1.0f, 0.0f);
        d = len - s.x;
    } else if (type == PBF_COLLIDER_BOX) {
        pbf_vec3 q3 = pbf_v3(pbf_abs(l.x) - s.x, pbf_abs(l.y) - s.y, pbf_abs(l.z) - s.z);
        if (pbf_max(q3.x, pbf_max(q3.y, q3.z)) > 0.0f) {
            pbf_vec3 o = pbf_v3(pbf_max(q3.x, 0.0f), pbf_max(q3.y, 0.0f), pbf_max(q3.z, 0.0f));
            d = pbf_length(o);
            PBF_REF(ln) = pbf_div(pbf_v3(pbf_sign(l.x) * o.x, pbf_sign(l.y) * o.y, pbf_sign(l.z) * o.z), pbf_max(d, 1e-12f));
        } else {
            // inside: nearest face
            if (q3.x > q3.y && q3.x > q3.z) PBF_REF(ln) = pbf_v3(l.x < 0.0f ? -1.0f : 1.0f, 0.0f, 0.0f);
            else if (q3.y > q3.z) PBF_REF(ln) = pbf_v3(0.0f, l.y < 0.0f ? -1.0f : 1.0f, 0.0f);
            else PBF_REF(ln) = pbf_v3(0.0f, 0.0f, l.z < 0.0f ? -1.0f : 1.0f);
            d = pbf_max(q3.x, pbf_max(q3.y, q3.z));
        }
    } else if (type == PBF_COLLIDER_CAPSULE) {
        pbf_vec3 r = pbf_sub(l, pbf_v3(0.0f, pbf_clamp(l.y, -s.y, s.y), 0.0f));
        float len = pbf_length(r);
        PBF_REF(ln) = len > 1e-9f ? pbf_div(r, len) : pbf_v3(1.0f, 0.0f, 0.0f);
        d = len - s.x;
    } else if (type == PBF_COLLIDER_CYLINDER) {
        float rl = pbf_length2(l.x, l.z);
        float qx = rl - s.x, qy = pbf_abs(l.y) - s.y;
        pbf_vec3 radial = rl > 1e-9f ? pbf_div(pbf_v3(l.x, 0.0f, l.z), rl) : pbf_v3(1.0f, 0.0f, 0.0f);
        pbf_vec3 axial = pbf_v3(0.0f, l.y < 0.0f ? -1.0f : 1.0f, 0.0f);
        if (qx > 0.0f && qy > 0.0f) {
            d = pbf_length2(qx, qy);
            PBF_REF(ln) = pbf_normalize(pbf_add(pbf_scale(qx, radial), pbf_scale(qy, axial)));
        } else if (qx > qy) {
            d = qx;
            PBF_REF(ln) = radial;
        } else {
            d = qy;
            PBF_REF(ln) = axial;
        }
    } else if (type == PBF_COLLIDER_HULL) {
        d = hull_distance(PBF_DATA_ c.info.z, c.info.w, l, ln);
    } else {
        d = grid_distance(PBF_DATA_ c.info.z, c.info.w, s, l, ln);
    }
    return d;
}

// ---- poses ------------------------------------------------------------------------------

/// Collider c's pose at the start (p0, q0) and at the end (p1, q1) of substep P.substep. A
/// pose set once per step (linear_velocity.w = the substeps it spans > 1) is interpolated,
/// linearly in position and normalised-linearly in rotation.
PBF_FN void collider_poses_of(PBF_P_ARG pbf_gpu_collider c, PBF_OUT(pbf_vec3) p0, PBF_OUT(PBF_VEC4) q0,
                              PBF_OUT(pbf_vec3) p1, PBF_OUT(PBF_VEC4) q1)
{
    pbf_vec3 pa = pbf_xyz(c.prev_position), pb = pbf_xyz(c.position);
    PBF_VEC4 qa = c.prev_rotation, qb = c.rotation;
    float span = c.linear_velocity.w;
    if (span > 1.5f) {
        float t0 = PBF_FLOAT_OF(P.substep) / span, t1 = pbf_min(PBF_FLOAT_OF(P.substep + 1u) / span, 1.0f);
        PBF_REF(p0) = pbf_mix3(pa, pb, t0);
        PBF_REF(q0) = quat_nlerp(qa, qb, t0);
        PBF_REF(p1) = pbf_mix3(pa, pb, t1);
        PBF_REF(q1) = quat_nlerp(qa, qb, t1);
    } else {
        PBF_REF(p0) = pa;
        PBF_REF(q0) = qa;
        PBF_REF(p1) = pb;
        PBF_REF(q1) = qb;
    }
}

/// Whether x may be within `reach` of collider c standing at p1 (planes always are).
PBF_FN bool collider_near_of(pbf_gpu_collider c, pbf_vec3 p1, pbf_vec3 x, float reach)
{
    if (c.info.x == PBF_COLLIDER_PLANE) return true;
    return pbf_distance(x, p1) <= c.position.w + reach;
}

// ---- the boundary share and the swept hit -------------------------------------------------

/// The boundary share V (the fraction of a filled neighbourhood that collider c takes) at x,
/// and its gradient with respect to x (1/m), at the collider's end pose. Boxes: the product
/// over the three axes of the share of the kernel inside each slab |l_k| <= e_k, which is
/// exact for separable kernels and, unlike one half-space, right at edges, corners and for
/// boxes thinner than the kernel. Spheres and capsules: the share of a ball with the
/// surface's curvature (a half-space overstates a convex body's share, by half at a ball of
/// radius h, and kept the water off curved bodies: docs/coupling.md). Cylinders: curved
/// side times slab, as boxes. Hulls: the product of their faces' shares, each to an
/// exponent that keeps clusters of nearly parallel faces from counting many times (below).
/// Distance grids: the half-space at the signed distance.
/// Returns false when x is out of reach or inside (only the gentle push-out moves it).
PBF_FN bool collider_boundary_of(PBF_P_ARG PBF_DATA_ARG pbf_gpu_collider c, pbf_vec3 x, PBF_OUT(float) V,
                                 PBF_OUT(pbf_vec3) gradV)
{
    PBF_REF(V) = 0.0f;
    PBF_REF(gradV) = pbf_v3(0.0f, 0.0f, 0.0f);
    pbf_vec3 p0, p1;
    PBF_VEC4 q0, q1;
    collider_poses_of(PBF_P_ c, PBF_ADDR(p0), PBF_ADDR(q0), PBF_ADDR(p1), PBF_ADDR(q1));
    if (!collider_near_of(c, p1, x, P.h)) return false;
    pbf_vec3 l = quat_rotate_inv(q1, pbf_sub(x, p1));
    pbf_vec3 ln;
    float d = shape_distance_of(PBF_DATA_ c, l, PBF_ADDR(ln));
    if (d >= P.h || d < 0.0f) return false;
    if (c.info.x == PBF_COLLIDER_BOX) {
        pbf_vec3 e = pbf_xyz(c.params);
        pbf_vec3 a = pbf_sub(e, l), m = pbf_add(e, l); // distances to the + and - faces of each slab
        float k = boundary_factor(PBF_P), ik = 1.0f / k;
        pbf_vec3 F = pbf_v3(1.0f - beyond(PBF_P_ a.x, ik) - beyond(PBF_P_ m.x, ik),
                            1.0f - beyond(PBF_P_ a.y, ik) - beyond(PBF_P_ m.y, ik),
                            1.0f - beyond(PBF_P_ a.z, ik) - beyond(PBF_P_ m.z, ik));
        F = pbf_v3(pbf_max(F.x, 0.0f), pbf_max(F.y, 0.0f), pbf_max(F.z, 0.0f));
        // dF/dl = d/dl [1 - beyond(e - l) - beyond(e + l)] = beyond'(e - l) - beyond'(e + l)
        pbf_vec3 dF = pbf_v3(beyond_slope(PBF_P_ a.x, ik) - beyond_slope(PBF_P_ m.x, ik),
                             beyond_slope(PBF_P_ a.y, ik) - beyond_slope(PBF_P_ m.y, ik),
                             beyond_slope(PBF_P_ a.z, ik) - beyond_slope(PBF_P_ m.z, ik));
        PBF_REF(V) = k * F.x * F.y * F.z;
        PBF_REF(gradV) = pbf_scale(k, quat_rotate(q1, pbf_v3(dF.x * F.y * F.z, F.x * dF.y * F.z, F.x * F.y * dF.z)));
    } else if (c.info.x == PBF_COLLIDER_SPHERE || c.info.x == PBF_COLLIDER_CAPSULE) {
        // Curved: the ball's share (pbf_curved_boundary). A capsule's side is curved one
        // way only (a ball of twice its radius has its mean curvature), its ends both ways;
        // the radius of curvature goes from one to the other over a kernel radius.
        float R = c.params.x, G, unused, dVdy = 0.0f;
        if (c.info.x == PBF_COLLIDER_CAPSULE) {
            float b = (pbf_abs(l.y) - c.params.y) / P.h + 0.5f;
            R = 2.0f * R / (1.0f + pbf_clamp(b, 0.0f, 1.0f));
            if (b > 0.0f && b < 1.0f) {
                // V also changes along the axis through R: dV/dy = dV/dR dR/db db/dy
                float dVdR = (pbf_curved_boundary(d, P.h, 1.001f * R, P.boundary_scale, PBF_ADDR(unused)) -
                              pbf_curved_boundary(d, P.h, 0.999f * R, P.boundary_scale, PBF_ADDR(unused))) /
                             (0.002f * R);
                dVdy = dVdR * (-R / (1.0f + b)) * pbf_sign(l.y) / P.h;
            }
        }
        PBF_REF(V) = pbf_curved_boundary(d, P.h, R, P.boundary_scale, PBF_ADDR(G));
        PBF_REF(gradV) = quat_rotate(q1, pbf_add(pbf_scale(-G, ln), pbf_v3(0.0f, dVdy, 0.0f)));
    } else if (c.info.x == PBF_COLLIDER_CYLINDER) {
        // The product of the share inside the infinite round cylinder (curved outside it, a
        // plane from within) and the share inside the slab |y| <= e, as for boxes.
        float k = boundary_factor(PBF_P), ik = 1.0f / k;
        float rl = pbf_length2(l.x, l.z), dr = rl - c.params.x, Fr, Gr;
        pbf_vec3 radial = rl > 1e-9f ? pbf_div(pbf_v3(l.x, 0.0f, l.z), rl) : pbf_v3(1.0f, 0.0f, 0.0f);
        if (dr >= 0.0f) {
            Fr = pbf_curved_boundary(dr, P.h, 2.0f * c.params.x, 1.0f, PBF_ADDR(Gr));
        } else {
            Fr = 1.0f - pbf_boundary_volume(-dr, P.h, 1.0f);
            Gr = pbf_boundary_gradient(-dr, P.h, 1.0f);
        }
        float a = c.params.y - l.y, m = c.params.y + l.y;
        float Fy = pbf_max(1.0f - beyond(PBF_P_ a, ik) - beyond(PBF_P_ m, ik), 0.0f);
        float dFy = beyond_slope(PBF_P_ a, ik) - beyond_slope(PBF_P_ m, ik);
        PBF_REF(V) = k * Fr * Fy;
        pbf_vec3 g = pbf_add(pbf_scale(-Gr * Fy, radial), pbf_v3(0.0f, Fr * dFy, 0.0f));
        PBF_REF(gradV) = pbf_scale(k, quat_rotate(q1, g));
    } else if (c.info.x == PBF_COLLIDER_HULL) {
        // The product over the faces of the share inside each face's half-space, S_f, each
        // to its exponent a_f (pbf_collider_data_fill: 1 for a face with no neighbour near
        // its direction, about 1/m in a cluster of m nearly parallel faces). A box-like hull
        // gets the product, exact where faces meet square; a finely faceted one counts each
        // cluster about once (a plain product counts the same solid many times and lets the
        // water in; the largest face distance's half-space keeps it off every edge). One
        // smooth function of x, so grad V = V sum_f a_f grad S_f / S_f is its true gradient.
        float k = boundary_factor(PBF_P), ik = 1.0f / k, F = 1.0f;
        pbf_vec3 dlog = pbf_v3(0.0f, 0.0f, 0.0f);
        PBF_UINT exponents = c.info.z + 4u * c.info.w;
        for (PBF_UINT f = 0u; f < c.info.w; f++) {
            PBF_UINT o = c.info.z + 4u * f;
            pbf_vec3 n = pbf_v3(collider_data[o], collider_data[o + 1u], collider_data[o + 2u]);
            float inside = collider_data[o + 3u] - pbf_dot(n, l); // distance to the face from within
            if (inside >= P.h) continue;
            float S = 1.0f - beyond(PBF_P_ inside, ik);
            if (S <= 0.0f) {
                F = 0.0f;
                break;
            }
            float a = collider_data[exponents + f];
            F *= pbf_pow(S, a);
            dlog = pbf_add(dlog, pbf_scale(a * beyond_slope(PBF_P_ inside, ik) / S, n)); // dS/dl = beyond' n
        }
        if (F <= 1e-12f) return false;
        PBF_REF(V) = k * F;
        PBF_REF(gradV) = pbf_scale(k * F, quat_rotate(q1, dlog));
    } else {
        PBF_REF(V) = boundary_volume(PBF_P_ d);
        PBF_REF(gradV) = pbf_scale(-boundary_gradient(PBF_P_ d), quat_rotate(q1, ln));
    }
    // A body being placed in water grows its boundary in (pbf_world_set_collider_strength).
    // PBF_BODY_SHARE: the liquid's calibration over the lattice's (pbf_shared.h).
    float strength = PBF_BODY_SHARE * c.angular_velocity.w;
    PBF_REF(V) = strength * PBF_REF(V);
    PBF_REF(gradV) = pbf_scale(strength, PBF_REF(gradV));
    return true;
}

/// First point of the local path a -> e (within [0, 1]) that comes within r of collider c's
/// surface, by sphere tracing on the distance (which never overestimates; da = the
/// distance at a); false when none.
PBF_FN bool sweep_hit_of(PBF_DATA_ARG pbf_gpu_collider c, pbf_vec3 a, pbf_vec3 e, float da, float r,
                         PBF_OUT(pbf_vec3) hit)
{
    pbf_vec3 seg = pbf_sub(e, a);
    float len = pbf_length(seg);
    PBF_REF(hit) = e;
    if (len < 1e-9f) return false;
    float t = 0.0f, d = da;
    for (int k = 0; k < 24; k++) {
        if (d <= r * 1.001f) {
            PBF_REF(hit) = pbf_add(a, pbf_scale(t, seg));
            return true;
        }
        t += (d - r) / len;
        if (t >= 1.0f) return false;
        pbf_vec3 unused;
        d = shape_distance_of(PBF_DATA_ c, pbf_add(a, pbf_scale(t, seg)), PBF_ADDR(unused));
    }
    PBF_REF(hit) = pbf_add(a, pbf_scale(t, seg));
    return true;
}

#ifndef GL_core_profile
#undef P
#endif
#endif
