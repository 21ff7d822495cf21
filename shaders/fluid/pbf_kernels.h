// The formulas the shaders and the CPU reference share: SPH kernels, the density
// constraint, the boundary model's closed forms, container planes and rigid frames (the
// colliders' geometry, in the same vocabulary: pbf_shapes.h).
//
// One definition, compiled as GLSL (included by common.glsl after the parameter block P is
// declared) and as C (by the CPU reference, fluid/pbf_cpu_*.c). GL_core_profile tells
// which, as in pbf_shared.h. To read and write the same text in both, the bodies use:
// - `pbf_vec3` and function-style vector operations (pbf_add, pbf_sub, pbf_scale (scalar
//   times vector), pbf_div, pbf_dot, pbf_length, pbf_cross, pbf_xyz of a vec4, ...): GLSL
//   macros that expand to the operators and built-ins, small C functions in C;
// - the parameter block as `P.field`: the GLSL uniform block; in C, a first parameter
//   `const pbf_gpu_params *pbf_p` that P stands for (declared by PBF_P_ARG, or PBF_P_ONLY
//   when it is the only one, and passed on by PBF_P_ or PBF_P; C callers pass their own
//   pointer first);
// - collider data (hull planes, distance grids) as `collider_data[i]`: the GLSL storage
//   block; in C, a parameter (PBF_DATA_ARG, PBF_DATA_);
// - `out` and `inout` parameters as PBF_OUT(type) name and PBF_INOUT(type) name, written and
//   read as PBF_REF(name), passed on as PBF_ADDR(name): `out type` / name / name in GLSL, a
//   pointer in C;
// - float literals with an f suffix (GLSL 4.30 takes it), so C computes in float too.
// What stays on each side is the plumbing: buffers and thread indices, the loops over
// neighbours and colliders, atomics (see docs/solver.md, "One source of truth").
#ifndef PBF_KERNELS_H
#define PBF_KERNELS_H

#include "pbf_shared.h"

#ifdef GL_core_profile
#define PBF_FN
#define PBF_P_ONLY void
#define PBF_P_ARG
#define PBF_P
#define PBF_P_
#define PBF_DATA_ARG
#define PBF_DATA_
#define PBF_OUT(type) out type
#define PBF_INOUT(type) inout type
#define PBF_REF(name) name
#define PBF_ADDR(name) name
#define pbf_vec3 vec3
#define pbf_v3(x, y, z) vec3(x, y, z)
#define pbf_xyz(a) ((a).xyz)
#define pbf_add(a, b) ((a) + (b))
#define pbf_sub(a, b) ((a) - (b))
#define pbf_neg(a) (-(a))
#define pbf_scale(s, a) ((s) * (a))
#define pbf_div(a, s) ((a) / (s))
#define pbf_dot dot
#define pbf_length length
#define pbf_cross cross
#define pbf_normalize normalize
#define pbf_clamp clamp
#define pbf_min min
#define pbf_max max
#define pbf_abs abs
#define pbf_sign sign
#define pbf_sqrt sqrt
#define pbf_pow pow
#define pbf_length2(x, y) length(vec2(x, y))
#define pbf_distance distance
#define pbf_mixf mix
#define pbf_mix3 mix
#define pbf_clampi clamp
#define PBF_FLOAT_OF(x) float(x)
#define PBF_INT_OF(x) int(x)
#define PBF_UINT_OF(x) uint(x)
#define PBF_FLOOR_INT(x) int(floor(x))
#define pbf_dot4 dot
#define pbf_neg4(a) (-(a))
#define pbf_mix4 mix
#define pbf_normalize4 normalize
#define pbf_quat_conj(q) vec4(-(q).xyz, (q).w)
#define pbf_comp(v, k) ((v)[k])
#define PBF_LEVEL_ARG
#define PBF_LEVEL_
#else
#include <math.h>
#include <stdbool.h>
#include <stdint.h>

#define PBF_FN static inline
#define PBF_P_ONLY const pbf_gpu_params *pbf_p
#define PBF_P_ARG const pbf_gpu_params *pbf_p,
#define PBF_P pbf_p
#define PBF_P_ pbf_p,
#define PBF_DATA_ARG const float *collider_data,
#define PBF_DATA_ collider_data,
#define PBF_LEVEL_ARG const pbf_gpu_level_cell *level,
#define PBF_LEVEL_ level,
#define PBF_OUT(type) type *
#define PBF_INOUT(type) type *
#define PBF_REF(name) (*(name))
#define PBF_ADDR(name) (&(name))
#define P (*pbf_p)

typedef struct pbf_vec3 {
    float x, y, z;
} pbf_vec3;

PBF_FN pbf_vec3 pbf_v3(float x, float y, float z) { return (pbf_vec3){ x, y, z }; }
PBF_FN pbf_vec3 pbf_xyz(pbf_float4 a) { return (pbf_vec3){ a.x, a.y, a.z }; }
PBF_FN pbf_vec3 pbf_add(pbf_vec3 a, pbf_vec3 b) { return (pbf_vec3){ a.x + b.x, a.y + b.y, a.z + b.z }; }
PBF_FN pbf_vec3 pbf_sub(pbf_vec3 a, pbf_vec3 b) { return (pbf_vec3){ a.x - b.x, a.y - b.y, a.z - b.z }; }
PBF_FN pbf_vec3 pbf_neg(pbf_vec3 a) { return (pbf_vec3){ -a.x, -a.y, -a.z }; }
PBF_FN pbf_vec3 pbf_scale(float s, pbf_vec3 a) { return (pbf_vec3){ s * a.x, s * a.y, s * a.z }; }
PBF_FN pbf_vec3 pbf_div(pbf_vec3 a, float s) { return (pbf_vec3){ a.x / s, a.y / s, a.z / s }; }
PBF_FN float pbf_dot(pbf_vec3 a, pbf_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
PBF_FN float pbf_length(pbf_vec3 a) { return sqrtf(pbf_dot(a, a)); }
PBF_FN pbf_vec3 pbf_cross(pbf_vec3 a, pbf_vec3 b)
{
    return (pbf_vec3){ a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y };
}
PBF_FN pbf_vec3 pbf_normalize(pbf_vec3 a) { return pbf_div(a, pbf_length(a)); }
PBF_FN float pbf_clamp(float x, float lo, float hi) { return fminf(fmaxf(x, lo), hi); }
PBF_FN float pbf_min(float a, float b) { return fminf(a, b); }
PBF_FN float pbf_max(float a, float b) { return fmaxf(a, b); }
PBF_FN float pbf_abs(float a) { return fabsf(a); }
PBF_FN float pbf_sign(float a) { return a > 0.0f ? 1.0f : a < 0.0f ? -1.0f : 0.0f; }
PBF_FN float pbf_sqrt(float a) { return sqrtf(a); }
PBF_FN float pbf_pow(float a, float b) { return powf(a, b); }
PBF_FN float pbf_length2(float x, float y) { return sqrtf(x * x + y * y); }
PBF_FN float pbf_distance(pbf_vec3 a, pbf_vec3 b) { return pbf_length(pbf_sub(a, b)); }
PBF_FN int pbf_clampi(int x, int lo, int hi) { return x < lo ? lo : x > hi ? hi : x; }
#define PBF_FLOAT_OF(x) ((float)(x))
#define PBF_INT_OF(x) ((int)(x))
#define PBF_UINT_OF(x) ((uint32_t)(x))
#define PBF_FLOOR_INT(x) ((int)floorf(x))
PBF_FN float pbf_dot4(pbf_float4 a, pbf_float4 b) { return a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w; }
PBF_FN pbf_float4 pbf_neg4(pbf_float4 a) { return (pbf_float4){ -a.x, -a.y, -a.z, -a.w }; }
/// GLSL mix as its specification writes it: x (1 - a) + y a.
PBF_FN float pbf_mixf(float x, float y, float a) { return x * (1.0f - a) + y * a; }
PBF_FN pbf_vec3 pbf_mix3(pbf_vec3 x, pbf_vec3 y, float a)
{
    return (pbf_vec3){ pbf_mixf(x.x, y.x, a), pbf_mixf(x.y, y.y, a), pbf_mixf(x.z, y.z, a) };
}
PBF_FN pbf_float4 pbf_mix4(pbf_float4 x, pbf_float4 y, float a)
{
    return (pbf_float4){ pbf_mixf(x.x, y.x, a), pbf_mixf(x.y, y.y, a), pbf_mixf(x.z, y.z, a), pbf_mixf(x.w, y.w, a) };
}
PBF_FN pbf_float4 pbf_normalize4(pbf_float4 a)
{
    float len = sqrtf(pbf_dot4(a, a));
    return (pbf_float4){ a.x / len, a.y / len, a.z / len, a.w / len };
}
PBF_FN pbf_float4 pbf_quat_conj(pbf_float4 q) { return (pbf_float4){ -q.x, -q.y, -q.z, q.w }; }
PBF_FN float pbf_comp3(pbf_vec3 v, int k) { return k == 0 ? v.x : k == 1 ? v.y : v.z; }
PBF_FN float pbf_comp4(pbf_float4 v, int k) { return k == 0 ? v.x : k == 1 ? v.y : k == 2 ? v.z : v.w; }
PBF_FN uint32_t pbf_comp4u(pbf_uint4 v, int k) { return k == 0 ? v.x : k == 1 ? v.y : k == 2 ? v.z : v.w; }
/// Component k of a vector, as GLSL's v[k].
#define pbf_comp(v, k) _Generic((v), pbf_vec3: pbf_comp3, pbf_float4: pbf_comp4, pbf_uint4: pbf_comp4u)(v, k)
#endif

// ---- kernels (h = P.h) -----------------------------------------------------------------

/// The poly6 kernel W(r) for r^2 = r2 (1/m^3): the XSPH viscosity's weight.
PBF_FN float w_poly6(PBF_P_ARG float r2)
{
    float d = P.h * P.h - r2;
    return d > 0.0f ? P.poly6 * d * d * d : 0.0f;
}

/// The spiky kernel W(r) = 15 / (pi h^6) (h - r)^3 for r = |x_i - x_j| (1/m^3): the density
/// kernel. The constraint's gradient is grad_spiky, the gradient of this same kernel, so a
/// position correction is the true gradient of the density it corrects. (The paper sums
/// the density with poly6 and corrects along spiky's gradient; that mismatch makes the
/// correction a non-conservative force, and a tank left alone kept an rms speed of
/// 85 mm/s instead of coming to rest: docs/validation.md, "Rest".)
PBF_FN float w_spiky(PBF_P_ARG float r)
{
    float d = P.h - r;
    return d > 0.0f ? (-1.0f / 3.0f) * P.spiky_grad * d * d * d : 0.0f;
}

/// Gradient of the spiky kernel with respect to x_i for r = x_i - x_j (1/m^4).
PBF_FN pbf_vec3 grad_spiky(PBF_P_ARG pbf_vec3 r)
{
    float len = pbf_length(r);
    if (len <= 1e-9f * P.h || len >= P.h) return pbf_v3(0.0f, 0.0f, 0.0f);
    float d = P.h - len;
    return pbf_scale(P.spiky_grad * d * d / len, r);
}

// ---- vorticity (vorticity.comp, viscosity.comp) ----------------------------
// The plain estimate omega_i = sum_j V_j grad W_ij x (v_j - v_i) is exact for a linear
// velocity field only where the neighbourhood is full, where A = sum_j V_j (x_j - x_i) (x)
// grad W_ij is the identity. At a free surface A falls to about half along the normal, so a
// droplet turning as a rigid body reads less vorticity in its skin than inside, and the
// confinement, pushing along grad|omega| x omega, spun it up (13 % more angular momentum
// after 2 s at the default epsilon than without it; docs/solver.md, "Departures from the
// paper"). The corrected gradient G = B A^-1, B = sum_j V_j (v_j - v_i) (x) grad W_ij, is
// exact for any linear field whatever the neighbourhood (Bonet and Lok 1999); its curl is the
// vorticity. A is symmetric (grad W_ij lies along x_i - x_j) and positive semi-definite; it
// is inverted as (A + d I) / (1 + d), d = PBF_CURL_REGULARISATION (pbf_shared.h), so a
// particle with one or two neighbours (A singular) is amplified at most (1 + d) / d times,
// and a full neighbourhood reads 0.998 of the curl.

/// The curl of G = B (A + d I)^-1 (1 + d): B by its rows bx, by, bz (row a: sum_j V_j
/// (v_j - v_i)_a grad W_ij), A by its diagonal ad and its off-diagonal ao = (A_xy, A_xz, A_yz).
PBF_FN pbf_vec3 corrected_curl(pbf_vec3 bx, pbf_vec3 by, pbf_vec3 bz, pbf_vec3 ad, pbf_vec3 ao)
{
    float d = PBF_CURL_REGULARISATION;
    float a = ad.x + d, b = ao.x, c = ao.y, e = ad.y + d, f = ao.z, k = ad.z + d;
    // Cofactors of the symmetric [[a b c] [b e f] [c f k]]: its inverse times the determinant.
    float c00 = e * k - f * f, c01 = c * f - b * k, c02 = b * f - c * e;
    float c11 = a * k - c * c, c12 = b * c - a * f, c22 = a * e - b * b;
    float det = a * c00 + b * c01 + c * c02; // at least d^3 for a semi-definite A
    float s = (1.0f + d) / pbf_max(det, d * d * d);
    pbf_vec3 mx = pbf_scale(s, pbf_v3(c00, c01, c02));
    pbf_vec3 my = pbf_scale(s, pbf_v3(c01, c11, c12));
    pbf_vec3 mz = pbf_scale(s, pbf_v3(c02, c12, c22));
    // G_ab = B_a . M_b (M symmetric); the curl (G_zy - G_yz, G_xz - G_zx, G_yx - G_xy).
    return pbf_v3(pbf_dot(bz, my) - pbf_dot(by, mz), pbf_dot(bx, mz) - pbf_dot(bz, mx),
                  pbf_dot(by, mx) - pbf_dot(bx, my));
}

/// The confinement's velocity change over dt: eps (N x omega_i) with N = eta / |eta|, eta =
/// sum_j V_j (|omega_j| - |omega_i|) grad W_ij, as in the paper where |omega| changes by
/// |omega_i| or more over a kernel radius (a vortex the kernel resolves), and scaled down by
/// |eta| h / |omega_i| where it changes less: the paper's unit N turns the rounding of a uniform
/// |omega| (a body of water turning rigidly) into a push of full strength in any direction.
/// `omega_len` is |omega_i|, which the vorticity pass stores beside it.
PBF_FN pbf_vec3 confinement_dv(PBF_P_ARG pbf_vec3 eta, pbf_vec3 omega_i, float omega_len)
{
    float scale = pbf_max(pbf_length(eta), omega_len / P.h);
    if (scale <= 0.0f) return pbf_v3(0.0f, 0.0f, 0.0f);
    return pbf_scale(P.dt * P.vorticity / scale, pbf_cross(eta, omega_i));
}

// ---- surface tension (tension.comp) ----------------------------------------
// The cohesion force of Akinci, Akinci & Teschner 2013 ("Versatile surface tension and
// adhesion for SPH fluids"): along each pair, k S(r) with S their spline, which pulls beyond
// h/2 and pushes closer, times K_ij = 2 rho0 / (rho_i + rho_j) (evens out the particle
// deficiency at the surface). k comes from the surface tension sigma (N/m) the pair force
// gives the rest lattice's flat surfaces, K_ij included, averaged over their orientations
// (pbf_cohesion_factor). Their curvature term is
// left out: its push on the particles under the surface scattered droplets under the
// unilateral density constraint (docs/solver.md, "Surface tension").

/// S(r) of Akinci's spline, m^6: (h - r)^3 r^3 for h/2 < r <= h, 2 (h - r)^3 r^3 - h^6 / 64
/// for 0 < r <= h/2, 0 elsewhere; times P.cohesion_norm (k) it is a pair's pull, m/s^2.
PBF_FN float cohesion_of(PBF_P_ARG float r)
{
    if (r <= 0.0f || r > P.h) return 0.0f;
    float a = (P.h - r) * (P.h - r) * (P.h - r) * r * r * r;
    if (2.0f * r > P.h) return P.cohesion_norm * a;
    float h3 = P.h * P.h * P.h;
    return P.cohesion_norm * (2.0f * a - h3 * h3 / 64.0f);
}

/// Neighbour j's share of i's surface tension acceleration (m/s^2), r = x_i - x_j:
/// -K_ij k S(|r|) r / |r| (towards j where S > 0).
PBF_FN pbf_vec3 tension_pair(PBF_P_ARG pbf_vec3 r, float rho_i, float rho_j)
{
    float len = pbf_length(r);
    if (len <= 1e-9f * P.h || len >= P.h) return pbf_v3(0.0f, 0.0f, 0.0f);
    float k = 2.0f * P.rest_density / pbf_max(rho_i + rho_j, 1e-6f * P.rest_density);
    return pbf_scale(-k * cohesion_of(PBF_P_ len) / len, r);
}

// ---- the density constraint (density.glsl) ----------------------------------------------

/// Adds neighbour j at r = x_i - x_j to the sums: sum W (spiky), grad_i C_i (fluid part,
/// 1/m) and sum_j |grad_j C_i|^2 (1/m^2).
PBF_FN void density_add(PBF_P_ARG pbf_vec3 r, PBF_INOUT(float) sum_w, PBF_INOUT(pbf_vec3) grad_i,
                        PBF_INOUT(float) sum_grad2)
{
    // w_spiky and grad_spiky from one length (the two share it: one square root, not two)
    float len = pbf_length(r);
    if (len >= P.h) return;
    PBF_REF(sum_w) += w_spiky(PBF_P_ len);
    if (len <= 1e-9f * P.h) return;
    float d = P.h - len;
    float k = P.mass_density * P.inv_rest_density;
    pbf_vec3 g = pbf_scale(k * P.spiky_grad * d * d / len, r);
    PBF_REF(grad_i) = pbf_add(PBF_REF(grad_i), g);
    PBF_REF(sum_grad2) += pbf_dot(g, g);
}

/// The share of particle i's neighbourhood that is missing at a free surface (air), from
/// g = |grad_i C_i| (1/m, boundaries included, so it is about 0 in the bulk and next to a
/// wall, and about G(d) at distance d below a free surface). A plane of air at distance d
/// takes k V(d) and gives k G(d) (the wall model of the boundaries below, with its lattice
/// calibration k = P.boundary_scale): with c = 1 - d/h, G h / (1.5 k) = c^4 (5 - 4c) is
/// solved for c (bisection, then linear interpolation in the last bracket) and
/// V = k c^5 (3 - 2c) / 2 returned, times P.surface_fill.
/// It depends on the neighbours' balance, not their number, so a surface layer that crowds
/// within itself cannot fill its missing half that way.
PBF_FN float free_surface_share(PBF_P_ARG float g)
{
    float k = P.boundary_scale;
    float y = g * P.h / (1.5f * k);
    if (y >= 1.0f) return P.surface_fill * 0.5f * k;
    // Bisection to a bracket of 2^-10, then one step of linear interpolation in it: the
    // result is continuous in y to rounding (the bracket's midpoint was not: a comparison
    // that fell the other way in the GPU's or the CPU's rounding moved c by the bracket).
    float lo = 0.0f, hi = 1.0f, flo = 0.0f, fhi = 1.0f;
    for (int it = 0; it < 10; it++) {
        float c = 0.5f * (lo + hi), f = c * c * c * c * (5.0f - 4.0f * c);
        if (f < y) { lo = c; flo = f; }
        else { hi = c; fhi = f; }
    }
    float c = lo + (hi - lo) * pbf_clamp((y - flo) / pbf_max(fhi - flo, 1e-20f), 0.0f, 1.0f), c2 = c * c;
    return P.surface_fill * 0.5f * k * c2 * c2 * c * (3.0f - 2.0f * c);
}

/// The most the free surface's missing share may add to a constraint: with x = rho/rho0 - 1,
/// C = max(x, min(x + A, cap)), so the share lifts C to at most `cap` and a particle
/// compressed beyond it takes none. The share is estimated from the gradient, which in
/// deep, compressed and disordered water is noise: uncapped, that noise pushed the water
/// apart at fine spacing (a column 32 layers deep blew up within a second;
/// docs/solver.md, "The free surface's missing share").
#define PBF_SURFACE_FILL_CAP 0.05f

/// The multiplier of a particle with density rho (kg/m^3) and the sums above (boundaries
/// included): C_i = max(rho_i / rho0 - 1, min(rho_i / rho0 - 1 + A_i, PBF_SURFACE_FILL_CAP), 0)
/// with A_i the free surface's missing share (0 unless surface_fill > 0),
/// lambda_i = -C_i / (|grad_i C_i|^2 + sum_j |grad_j C_i|^2 + epsilon), m^2. C_i never
/// falls as rho_i rises.
PBF_FN float density_lambda(PBF_P_ARG float rho, pbf_vec3 grad_i, float sum_grad2)
{
    float x = rho * P.inv_rest_density - 1.0f;
    if (P.surface_fill > 0.0f) {
        float air = free_surface_share(PBF_P_ pbf_length(grad_i));
        x = pbf_max(x, pbf_min(x + air, PBF_SURFACE_FILL_CAP));
    }
    float C = pbf_max(x, 0.0f);
    return -C / (pbf_dot(grad_i, grad_i) + sum_grad2 + P.epsilon);
}

// ---- boundaries -------------------------------------------------------------------------
// A boundary is seen by a particle as a half-space at distance d along the inward normal
// n (the semi-analytic model of docs/solver.md). The share of a filled neighbourhood
// that the wall takes is V(d) = int_{z>d} W_spiky, and the gradient of that share with
// respect to the particle is -G(d) n with G(d) = -dV/dd = int_{z>d} |grad W_spiky| (z/r).
// Both are closed-form polynomials in u = d/h, V(0) = 1/2 and G(0) = 1.5/h, times
// `scale`: P.boundary_scale in the solver, which calibrates the continuous model to the
// particle lattice (a rest block against a wall starts in balance; see
// pbf_constants.boundary_scale), 1 for the continuous V and G themselves.

/// V(d) for kernel radius h (m), times scale (dimensionless).
PBF_FN float pbf_boundary_volume(float d, float h, float scale)
{
    // 30 int_u^1 (1-t)^3 t (t-u) dt, the kernel's mass beyond the plane
    float u = pbf_clamp(d / h, 0.0f, 1.0f);
    float c = 1.0f - u, c2 = c * c;
    return scale * 0.5f * c2 * c2 * c * (1.0f + 2.0f * u);
}

/// G(d) for kernel radius h (m), times scale (1/m).
PBF_FN float pbf_boundary_gradient(float d, float h, float scale)
{
    // (30 / h) int_u^1 t (1-t)^3 dt = -dV/dd
    float u = pbf_clamp(d / h, 0.0f, 1.0f);
    float c = 1.0f - u, c2 = c * c;
    return scale * (1.5f / h) * c2 * c2 * (1.0f + 4.0f * u);
}

/// V(d) and G(d) (the return value, 1/m, into PBF_REF(G)) of a convex solid whose surface
/// is curved with radius R (m) at the particle's nearest point, times scale. Exact for a
/// ball of radius R: the kernel's sphere of radius r about the particle cuts the ball in a
/// cap of area pi r (r - d)(2R - (r - d)) / (R + d) (2 pi r (r - d) for a plane), so with
/// t = r/h, u = d/h, q = R/h and the moments M_k = int_u^T (1-t)^3 t (t-u)^k dt,
/// T = min(1, u + 2q):
///   V = 15 (2q M1 - M2) / (q + u),   G h = (V + 30 q M0 - 30 M1) / (q + u)
/// (no boundary terms: the cap's area vanishes at both ends). As R grows they become the
/// plane's V and G above. A solid curved in one direction only (a cylinder's side) is
/// passed the radius of the ball with its mean curvature, 2R: right to first order in h/R.
PBF_FN float pbf_curved_boundary(float d, float h, float R, float scale, PBF_OUT(float) G)
{
    float u = pbf_clamp(d / h, 0.0f, 1.0f), q = R / h;
    if (q > 1.0e4f) {
        PBF_REF(G) = pbf_boundary_gradient(d, h, scale);
        return pbf_boundary_volume(d, h, scale);
    }
    float c = 1.0f - u, c2 = c * c;
    // (1-t)^3 t = a0 + a1 s + a2 s^2 + a3 s^3 - s^4 in s = t - u, integrated to S = T - u
    float a0 = u * c2 * c, a1 = c2 * c - 3.0f * u * c2, a2 = 3.0f * u * c - 3.0f * c2, a3 = 3.0f * c - u;
    float S = pbf_min(c, 2.0f * q);
    float S2 = S * S, S3 = S2 * S;
    float M0 = S * (a0 + S * (a1 / 2.0f + S * (a2 / 3.0f + S * (a3 / 4.0f - S / 5.0f))));
    float M1 = S2 * (a0 / 2.0f + S * (a1 / 3.0f + S * (a2 / 4.0f + S * (a3 / 5.0f - S / 6.0f))));
    float M2 = S3 * (a0 / 3.0f + S * (a1 / 4.0f + S * (a2 / 5.0f + S * (a3 / 6.0f - S / 7.0f))));
    float V = 15.0f * (2.0f * q * M1 - M2) / (q + u);
    PBF_REF(G) = scale * (V + 30.0f * q * M0 - 30.0f * M1) / ((q + u) * h);
    return scale * V;
}

/// The solver's V(d) and G(d): calibrated to the lattice.
PBF_FN float boundary_volume(PBF_P_ARG float d) { return pbf_boundary_volume(d, P.h, P.boundary_scale); }
PBF_FN float boundary_gradient(PBF_P_ARG float d) { return pbf_boundary_gradient(d, P.h, P.boundary_scale); }

/// Container plane p: distance of x on the inside (positive) and the inward normal.
PBF_FN float plane_distance(PBF_P_ARG PBF_UINT p, pbf_vec3 x, PBF_OUT(pbf_vec3) n)
{
    PBF_REF(n) = pbf_xyz(P.planes[p]);
    return pbf_dot(x, PBF_REF(n)) - P.planes[p].w;
}

// ---- the container as mirrors ------------------------------------------------------------
// The container's walls act on the fluid's density as mirrors (the ghost-particle image
// method): a particle near a wall counts, besides its neighbours, their images and its own
// in that wall, each image moving with its particle. Whatever order the liquid has, its
// mirror image has the same, so a particle next to a wall sees the neighbourhood it would
// see in the bulk: no calibration, and no layer packed tighter or looser than the bulk
// (docs/solver.md, "Walls as mirrors"). The container is a box, so the mirrors of one
// particle are at most one plane per axis (the nearest closer than h); a particle near an
// edge or a corner also counts the images in two and three of them, which are exact for
// perpendicular planes. Bodies keep the half-space share (boundary_volume and
// boundary_gradient below).

/// The plane facing container plane p (pbf_container_planes' order: floor, x min, x max,
/// z min, z max, lid).
PBF_FN PBF_UINT opposite_plane(PBF_UINT p) { return p == 0u ? 5u : p == 5u ? 0u : (p & 1u) == 1u ? p + 1u : p - 1u; }

/// The mirrors of a particle at x: per axis the nearest container plane closer than h (of
/// two equally near, the first). Returns a mask, bit k for a mirror across axis k and bit
/// 3 + k when that plane's inward normal points down axis k; `twice` gets 2 c_k, c_k the
/// plane's coordinate, so the image of a point is 2 c_k - x_k on the mirrored axes.
PBF_FN PBF_UINT mirror_mask(PBF_P_ARG pbf_vec3 x, PBF_OUT(pbf_vec3) twice)
{
    PBF_UINT mask = 0u;
    PBF_REF(twice) = pbf_v3(0.0f, 0.0f, 0.0f);
    for (PBF_UINT p = 0u; p < P.plane_count; p++) {
        pbf_vec3 n;
        float d = plane_distance(PBF_P_ p, x, PBF_ADDR(n));
        if (d >= P.h) continue;
        PBF_UINT o = opposite_plane(p);
        if (o < P.plane_count) {
            pbf_vec3 m;
            float e = plane_distance(PBF_P_ o, x, PBF_ADDR(m));
            if (e < d || (e == d && o < p)) continue;
        }
        // n is +-e_k, the plane n.x = w: c_k = w n_k
        float w = P.planes[p].w;
        if (pbf_abs(n.x) > 0.5f) {
            mask |= n.x > 0.0f ? 1u : 9u;
            PBF_REF(twice).x = 2.0f * w * n.x;
        } else if (pbf_abs(n.y) > 0.5f) {
            mask |= n.y > 0.0f ? 2u : 18u;
            PBF_REF(twice).y = 2.0f * w * n.y;
        } else {
            mask |= n.z > 0.0f ? 4u : 36u;
            PBF_REF(twice).z = 2.0f * w * n.z;
        }
    }
    return mask;
}

/// x reflected across the mirrored axes in `axes` (bits 0-2, a subset of a mirror mask's).
PBF_FN pbf_vec3 mirror_point(pbf_vec3 x, PBF_UINT axes, pbf_vec3 twice)
{
    return pbf_v3((axes & 1u) != 0u ? twice.x - x.x : x.x, (axes & 2u) != 0u ? twice.y - x.y : x.y,
                  (axes & 4u) != 0u ? twice.z - x.z : x.z);
}

/// A direction reflected across the axes in `axes`.
PBF_FN pbf_vec3 mirror_direction(pbf_vec3 v, PBF_UINT axes)
{
    return pbf_v3((axes & 1u) != 0u ? -v.x : v.x, (axes & 2u) != 0u ? -v.y : v.y, (axes & 4u) != 0u ? -v.z : v.z);
}

/// From particle i at xi to its own image across the axes in `axes`: 2 |x_k - c_k| along
/// each plane's inward normal, so a particle that the prediction carried past a wall is
/// pushed back in, not out.
PBF_FN pbf_vec3 self_image_offset(pbf_vec3 xi, PBF_UINT mask, PBF_UINT axes, pbf_vec3 twice)
{
    pbf_vec3 r = pbf_v3(0.0f, 0.0f, 0.0f);
    if ((axes & 1u) != 0u) r.x = ((mask & 8u) != 0u ? -1.0f : 1.0f) * pbf_abs(2.0f * xi.x - twice.x);
    if ((axes & 2u) != 0u) r.y = ((mask & 16u) != 0u ? -1.0f : 1.0f) * pbf_abs(2.0f * xi.y - twice.y);
    if ((axes & 4u) != 0u) r.z = ((mask & 32u) != 0u ? -1.0f : 1.0f) * pbf_abs(2.0f * xi.z - twice.z);
    return r;
}

/// density_add for the images of neighbour j (at xj) in particle i's mirrors (`mask`,
/// `twice`: mirror_mask), not j itself, each image counted as a particle of its own, as it
/// is in the container mirrored about the wall (so a particle next to a wall solves exactly
/// what a particle in the middle of that doubled container would). The passes add j itself
/// while they walk the neighbours and the images after, over the list, so only particles
/// next to a wall take the second loop.
PBF_FN void density_add_images(PBF_P_ARG pbf_vec3 xi, pbf_vec3 xj, PBF_UINT mask, pbf_vec3 twice, PBF_INOUT(float) sum_w,
                               PBF_INOUT(pbf_vec3) grad_i, PBF_INOUT(float) sum_grad2)
{
    PBF_UINT axes = mask & 7u;
    for (PBF_UINT sub = axes; sub != 0u; sub = (sub - 1u) & axes)
        density_add(PBF_P_ pbf_sub(xi, mirror_point(xj, sub, twice)), sum_w, grad_i, sum_grad2);
}

/// density_add for particle i's own images in its mirrors. In the doubled container an
/// image is a particle of its own whose multiplier equals i's, so the delta pass moves i by
/// twice lambda_i times the image's gradient (self_image_correction).
PBF_FN void density_add_self_images(PBF_P_ARG pbf_vec3 xi, PBF_UINT mask, pbf_vec3 twice, PBF_INOUT(float) sum_w,
                                    PBF_INOUT(pbf_vec3) grad_i, PBF_INOUT(float) sum_grad2)
{
    PBF_UINT axes = mask & 7u;
    for (PBF_UINT sub = axes; sub != 0u; sub = (sub - 1u) & axes)
        density_add(PBF_P_ self_image_offset(xi, mask, sub, twice), sum_w, grad_i, sum_grad2);
}

/// The artificial pressure s_corr of a pair at r (0 when P.scorr_k is 0): the delta pass's
/// -k (W(r) / W(dq))^n, times the scale that makes k read as a constraint violation.
PBF_FN float scorr_of(PBF_P_ARG pbf_vec3 r)
{
    if (P.scorr_k <= 0.0f) return 0.0f;
    return -P.scorr_k * pbf_pow(w_spiky(PBF_P_ pbf_length(r)) * P.scorr_inv_wdq, P.scorr_n) * P.scorr_scale;
}

/// The delta pass's sum for neighbour j's images in particle i's mirrors (not j itself):
/// (lambda_i + lambda_j + s_corr) grad W towards each image, lambda_sum = lambda_i + lambda_j.
PBF_FN pbf_vec3 mirrored_correction(PBF_P_ARG pbf_vec3 xi, pbf_vec3 xj, float lambda_sum, PBF_UINT mask, pbf_vec3 twice)
{
    pbf_vec3 g = pbf_v3(0.0f, 0.0f, 0.0f);
    PBF_UINT axes = mask & 7u;
    for (PBF_UINT sub = axes; sub != 0u; sub = (sub - 1u) & axes) {
        pbf_vec3 r = pbf_sub(xi, mirror_point(xj, sub, twice));
        g = pbf_add(g, pbf_scale(lambda_sum + scorr_of(PBF_P_ r), grad_spiky(PBF_P_ r)));
    }
    return g;
}

/// The same for particle i's own images, whose multiplier is lambda_i's
/// (density_add_self_images): (2 lambda_i + s_corr) grad W towards each.
PBF_FN pbf_vec3 self_image_correction(PBF_P_ARG pbf_vec3 xi, float lambda_i, PBF_UINT mask, pbf_vec3 twice)
{
    pbf_vec3 g = pbf_v3(0.0f, 0.0f, 0.0f);
    PBF_UINT axes = mask & 7u;
    for (PBF_UINT sub = axes; sub != 0u; sub = (sub - 1u) & axes) {
        pbf_vec3 r = self_image_offset(xi, mask, sub, twice);
        g = pbf_add(g, pbf_scale(2.0f * lambda_i + scorr_of(PBF_P_ r), grad_spiky(PBF_P_ r)));
    }
    return g;
}

// ---- wall friction (velocity.comp) -------------------------------------------------------
// Water sliding along a wall at speed u feels the shear stress rho C_f u^2 of a rough
// turbulent boundary (a skin-friction law, as shallow-water models take for a bed), so the
// force per area, not per particle, is fixed and the effect does not fade as the particles
// shrink. The stress is carried by the particles within about a spacing of the wall:
// weight w(d) = 1 for d <= s/2 falling linearly to 0 at d = 3s/2 (a band that holds half a
// layer's worth of particles, n s/2 per area), so each takes the acceleration
// 2 C_f w u^2 / s. It is applied implicitly, u' = u / (1 + dt 2 C_f w u / s), which cannot
// reverse the motion however large dt is.

/// v after the container's friction for a particle at x (m) moving at v (m/s).
PBF_FN pbf_vec3 wall_friction_of(PBF_P_ARG pbf_vec3 x, pbf_vec3 v)
{
    float s = 2.0f * P.radius;
    for (PBF_UINT p = 0u; p < P.plane_count; p++) {
        pbf_vec3 n;
        float d = plane_distance(PBF_P_ p, x, PBF_ADDR(n));
        float w = pbf_clamp((1.5f * s - d) / s, 0.0f, 1.0f);
        if (w <= 0.0f) continue;
        pbf_vec3 vn = pbf_scale(pbf_dot(v, n), n);
        pbf_vec3 vt = pbf_sub(v, vn);
        float u = pbf_length(vt);
        vt = pbf_scale(1.0f / (1.0f + P.dt * 2.0f * P.wall_friction * w * u / s), vt);
        v = pbf_add(vn, vt);
    }
    return v;
}

/// Share of the kernel beyond a plane at signed distance d (negative: the particle is past
/// it), and its derivative with respect to d, for the continuous kernel (beyond(0) = 1/2):
/// V and G above carry the lattice calibration (V(0) = factor / 2), divided out here and
/// applied once to the combined share (colliders.glsl's boxes).
PBF_FN float boundary_factor(PBF_P_ONLY) { return 2.0f * boundary_volume(PBF_P_ 0.0f); }
PBF_FN float beyond(PBF_P_ARG float d, float inv_factor)
{
    return d >= 0.0f ? boundary_volume(PBF_P_ d) * inv_factor : 1.0f - boundary_volume(PBF_P_ - d) * inv_factor;
}
PBF_FN float beyond_slope(PBF_P_ARG float d, float inv_factor)
{
    return -boundary_gradient(PBF_P_ pbf_abs(d)) * inv_factor;
}

// ---- rigid frames -----------------------------------------------------------------------

/// v rotated by the unit quaternion q (xyzw).
PBF_FN pbf_vec3 quat_rotate(PBF_VEC4 q, pbf_vec3 v)
{
    pbf_vec3 u = pbf_xyz(q);
    pbf_vec3 t = pbf_scale(2.0f, pbf_cross(u, v));
    return pbf_add(pbf_add(v, pbf_scale(q.w, t)), pbf_cross(u, t));
}

PBF_FN pbf_vec3 quat_rotate_inv(PBF_VEC4 q, pbf_vec3 v) { return quat_rotate(pbf_quat_conj(q), v); }

/// Normalised linear interpolation from a to b (the short way round).
PBF_FN PBF_VEC4 quat_nlerp(PBF_VEC4 a, PBF_VEC4 b, float t)
{
    if (pbf_dot4(a, b) < 0.0f) b = pbf_neg4(b);
    return pbf_normalize4(pbf_mix4(a, b, t));
}

// ---- the neighbour grid (docs/solver.md, "The hashed grid") --------------------------------

/// The row of cell (x, y, z): y + dims_y z, told apart from other rows in the same buckets.
PBF_FN PBF_UINT grid_row(PBF_P_ARG PBF_UINT y, PBF_UINT z) { return y + P.grid_dims.y * z; }

/// The 16 bits of v spread to the even bits of the result.
PBF_FN PBF_UINT spread_bits(PBF_UINT v)
{
    v &= 0xffffu;
    v = (v | (v << 8)) & 0x00ff00ffu;
    v = (v | (v << 4)) & 0x0f0f0f0fu;
    v = (v | (v << 2)) & 0x33333333u;
    return (v | (v << 1)) & 0x55555555u;
}

/// The bucket of cell (x, y, z): a row's cells take consecutive buckets, the rows follow a
/// Morton curve of (y, z), P.row_stride buckets apart (pbf_row_stride), wrapping at the
/// bucket count (32-bit arithmetic wraps alike in GLSL and C).
PBF_FN PBF_UINT grid_bucket(PBF_P_ARG PBF_UINT x, PBF_UINT y, PBF_UINT z)
{
    PBF_UINT curve = spread_bits(y) | (spread_bits(z) << 1);
    return (curve * P.row_stride + x) & (P.grid_dims.w - 1u);
}

// ---- the coarse level (docs/solver.md, "The coarse level") ---------------------------------
// A grid of P.level_dims.xyz cells of P.level_cell.xyz metres over the domain (its walls are
// cell faces). The particles' compression is gathered onto it (level_corner), each cell's
// share of excess volume E is taken (level_compression), and -lap p = E with p >= 0 is
// relaxed in red-black sweeps (level_relaxed): p is a pressure-like potential (m^2), zero in
// air, with no flow through the walls. Its gradient on the cells' faces, interpolated to a
// particle (level_correction), moves the water out of the compressed cells. `level[i]` is the
// storage block in GLSL (passes with USE_LEVEL) and a parameter in C (PBF_LEVEL_ARG).

/// Index of cell (x, y, z), each within the grid.
PBF_FN PBF_UINT level_index(PBF_P_ARG int x, int y, int z)
{
    return PBF_UINT_OF(x) + P.level_dims.x * (PBF_UINT_OF(y) + P.level_dims.y * PBF_UINT_OF(z));
}

/// x's coordinate along axis a in cells, cell centres at integers.
PBF_FN float level_coord(PBF_P_ARG pbf_vec3 x, int a)
{
    return (pbf_comp(x, a) - pbf_comp(P.domain_min, a)) / pbf_comp(P.level_cell, a) - 0.5f;
}

/// Cell `id`'s coordinates.
PBF_FN void level_cell_of(PBF_P_ARG PBF_UINT id, PBF_OUT(int) x, PBF_OUT(int) y, PBF_OUT(int) z)
{
    PBF_REF(x) = PBF_INT_OF(id % P.level_dims.x);
    PBF_REF(y) = PBF_INT_OF((id / P.level_dims.x) % P.level_dims.y);
    PBF_REF(z) = PBF_INT_OF(id / (P.level_dims.x * P.level_dims.y));
}

/// Cell `id`'s colour in the sweeps' red-black order: the parity of x + y + z.
PBF_FN PBF_UINT level_parity(PBF_P_ARG PBF_UINT id)
{
    int x, y, z;
    level_cell_of(PBF_P_ id, PBF_ADDR(x), PBF_ADDR(y), PBF_ADDR(z));
    return PBF_UINT_OF(x + y + z) % 2u;
}

/// A particle's compression rho / rho0 - 1 for the deposit, clamped to [-1, 1]; false when
/// its density is not finite (it then adds nothing; the metrics report it).
PBF_FN bool level_excess(PBF_P_ARG float rho, PBF_OUT(float) e)
{
    float c = rho * P.inv_rest_density - 1.0f;
    if (!(pbf_abs(c) < 1e30f)) return false;
    PBF_REF(e) = pbf_clamp(c, -1.0f, 1.0f);
    return true;
}

/// A weight in the deposit's fixed point (rounded half up on both sides: GLSL's round may
/// go either way at a half).
PBF_FN int level_fixed(float v) { return PBF_FLOOR_INT(v * PBF_LEVEL_FIXED + 0.5f); }

/// Corner k (0-7, a bit per axis) of the trilinear deposit of a particle at x: its cell and
/// weight. A corner beyond a wall is the cell inside it (the wall's mirror image of it).
PBF_FN float level_corner(PBF_P_ARG pbf_vec3 x, int k, PBF_OUT(PBF_UINT) cell)
{
    float wgt = 1.0f;
    int c[3];
    for (int a = 0; a < 3; a++) {
        int n = PBF_INT_OF(pbf_comp(P.level_dims, a));
        float g = pbf_clamp(level_coord(PBF_P_ x, a), -0.5f, PBF_FLOAT_OF(n) - 0.5f);
        int c0 = PBF_FLOOR_INT(g);
        float t = g - PBF_FLOAT_OF(c0);
        int o = (k >> a) & 1;
        wgt *= o != 0 ? t : 1.0f - t;
        c[a] = pbf_clampi(c0 + o, 0, n - 1);
    }
    PBF_REF(cell) = level_index(PBF_P_ c[0], c[1], c[2]);
    return wgt;
}

/// A cell's E from its deposit sums: the excess volume of its water (sum w (rho / rho0 - 1)
/// s^3) over the cell's volume, less the tolerance the particle iterations are left
/// (P.level_solve.x, either sign); PBF_LEVEL_AIR where the weights fill less than half the
/// cell (a full cell's weights sum to V / s^3 = 1 / P.level_cell.w).
PBF_FN float level_compression(PBF_P_ARG int weight, int excess)
{
    if (PBF_FLOAT_OF(weight) / PBF_LEVEL_FIXED * P.level_cell.w < 0.5f) return PBF_LEVEL_AIR;
    float e = PBF_FLOAT_OF(excess) / PBF_LEVEL_FIXED * P.level_cell.w;
    return pbf_sign(e) * pbf_max(pbf_abs(e) - P.level_solve.x, 0.0f);
}

#if !defined(GL_core_profile) || defined(USE_LEVEL)
/// p of cell `id` after one projected over-relaxation step of -lap p = E, p >= 0, from its
/// neighbours' p (a wall's side drops out of the stencil: no flow through it; air reads
/// p = 0). Air stays at 0.
PBF_FN float level_relaxed(PBF_P_ARG PBF_LEVEL_ARG PBF_UINT id)
{
    float e = level[id].e;
    float p = level[id].p;
    if (e <= PBF_LEVEL_AIR) return p;
    int c[3];
    level_cell_of(PBF_P_ id, PBF_ADDR(c[0]), PBF_ADDR(c[1]), PBF_ADDR(c[2]));
    float sum = e, diag = 0.0f;
    for (int a = 0; a < 3; a++) {
        float inv_c2 = 1.0f / (pbf_comp(P.level_cell, a) * pbf_comp(P.level_cell, a));
        for (int d = -1; d <= 1; d += 2) {
            int nb[3];
            nb[0] = c[0];
            nb[1] = c[1];
            nb[2] = c[2];
            nb[a] += d;
            if (nb[a] < 0 || nb[a] >= PBF_INT_OF(pbf_comp(P.level_dims, a))) continue;
            sum += inv_c2 * level[level_index(PBF_P_ nb[0], nb[1], nb[2])].p;
            diag += inv_c2;
        }
    }
    if (diag <= 0.0f) return p;
    return pbf_max(0.0f, p + P.level_solve.y * (sum / diag - p));
}

/// p of cell (x, y, z) clamped into the grid.
PBF_FN float level_p(PBF_P_ARG PBF_LEVEL_ARG int x, int y, int z)
{
    x = pbf_clampi(x, 0, PBF_INT_OF(P.level_dims.x) - 1);
    y = pbf_clampi(y, 0, PBF_INT_OF(P.level_dims.y) - 1);
    z = pbf_clampi(z, 0, PBF_INT_OF(P.level_dims.z) - 1);
    return level[level_index(PBF_P_ x, y, z)].p;
}

/// p at x (m^2), trilinear between the centres of the water cells around it (the deposit's
/// weights, level_corner; air cells left out and the weights renormalised; 0 among air only):
/// the coarse level's p beside a body, whose inside the level counts as air.
PBF_FN float level_pressure(PBF_P_ARG PBF_LEVEL_ARG pbf_vec3 x)
{
    float sum = 0.0f, wsum = 0.0f;
    for (int k = 0; k < 8; k++) {
        PBF_UINT id;
        float wgt = level_corner(PBF_P_ x, k, PBF_ADDR(id));
        if (level[id].e <= PBF_LEVEL_AIR) continue;
        sum += wgt * level[id].p;
        wsum += wgt;
    }
    return wsum > 0.0f ? sum / wsum : 0.0f;
}

/// The correction at x (m): -grad p on the cells' faces (the Laplacian's own gradient, zero
/// on the walls), interpolated along each axis a from the faces of a (at half-integer
/// coordinates along a, the cell centres along the other two).
PBF_FN pbf_vec3 level_correction(PBF_P_ARG PBF_LEVEL_ARG pbf_vec3 x)
{
    float g[3], u[3];
    int n[3];
    for (int a = 0; a < 3; a++) {
        g[a] = level_coord(PBF_P_ x, a);
        n[a] = PBF_INT_OF(pbf_comp(P.level_dims, a));
    }
    for (int a = 0; a < 3; a++) {
        int b = (a + 1) % 3, c = (a + 2) % 3;
        float fa = pbf_clamp(g[a] + 0.5f, 0.0f, PBF_FLOAT_OF(n[a]));
        int ia = pbf_clampi(PBF_FLOOR_INT(fa), 0, n[a] - 1);
        float ta = fa - PBF_FLOAT_OF(ia);
        float gb = pbf_clamp(g[b], 0.0f, PBF_FLOAT_OF(n[b] - 1));
        float gc = pbf_clamp(g[c], 0.0f, PBF_FLOAT_OF(n[c] - 1));
        int ib = pbf_clampi(PBF_FLOOR_INT(gb), 0, n[b] - 1 > 0 ? n[b] - 2 : 0);
        int ic = pbf_clampi(PBF_FLOOR_INT(gc), 0, n[c] - 1 > 0 ? n[c] - 2 : 0);
        float tb = gb - PBF_FLOAT_OF(ib), tc = gc - PBF_FLOAT_OF(ic);
        float sum = 0.0f;
        for (int k = 0; k < 8; k++) {
            int f[3];
            f[a] = ia + (k & 1);
            f[b] = ib + ((k >> 1) & 1);
            f[c] = ic + ((k >> 2) & 1);
            if (f[a] == 0 || f[a] == n[a] || f[b] >= n[b] || f[c] >= n[c]) continue; // a wall, or a one-cell axis
            float wgt = ((k & 1) != 0 ? ta : 1.0f - ta) * (((k >> 1) & 1) != 0 ? tb : 1.0f - tb) *
                        (((k >> 2) & 1) != 0 ? tc : 1.0f - tc);
            int lo[3];
            lo[0] = f[0];
            lo[1] = f[1];
            lo[2] = f[2];
            lo[a] -= 1;
            sum += wgt * (level_p(PBF_P_ PBF_LEVEL_ lo[0], lo[1], lo[2]) - level_p(PBF_P_ PBF_LEVEL_ f[0], f[1], f[2]));
        }
        u[a] = sum / pbf_comp(P.level_cell, a);
    }
    return pbf_v3(u[0], u[1], u[2]);
}
#endif

#ifndef GL_core_profile
#undef P
#endif
#endif
