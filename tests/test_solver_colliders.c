// The solver around colliders, GPU against the CPU reference (fluid/pbf_cpu): analytic
// shapes, convex hulls, distance grids and planes, and moving bodies, compared step by step
// (positions, forces and torques, contacts and push-outs, densities); and collider
// definitions checked alike on both sides, naming the field.
#include "tests/support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fluid/pbf.h"
#include "fluid/pbf_cpu.h"

typedef support_gpu fixture;

// Densities: the dam break's bound (test_solver.c: float noise 4e-7 relative, epsilon
// doubled 1.2e-3), which the colliders' density noise (4.9e-6, below) meets as well.
#define DENSITY_REL 1e-4
// Densities after a push-out switched (check_collider_result): positions may then differ
// by up to COLLIDER_SWITCHED, and a density by about 0.04 of the position's deviation in
// spacings (an NVIDIA H200, 2026-11-27: the hull scene switched 3 push-outs at step 1 and 6
// at step 3; at step 6 positions 3.2e-3 spacing apart, densities 1.3e-4). 5e-4 is 3.8 times
// that and 3.2 times below the smallest density slip (the metrics without colliders, 1.6e-3).
#define DENSITY_SWITCHED 5e-4

// ---- GPU against the CPU reference around colliders --------------------------------------

// Three scenes, 12 steps each: the analytic shapes under a falling slab; a convex hull, a
// distance grid and a plane collider with particles starting inside (the push-out), over
// relaxed; a thin paddle and a hull moving through a pool (poses interpolated per substep,
// the hull's quaternion flipping sign). Between them every path of colliders.glsl runs
// (counted once in the CPU reference: thousands of boundary shares and swept hits per
// shape type, hundreds of push-outs and corner fix-ups, sphere traces of 1 to 24 steps).
// Compared every step: positions, the force and torque on every body (the fixed-point
// accumulators), contact and push-out counts, and the metrics' densities.
//
// Tolerances, from measurement (llvmpipe) and from breaking the CPU reference on purpose.
// Noise over steps 1-6 in the three scenes: positions 5.6e-6 to 7.2e-6 spacing after step 1
// and at most 2.3e-4 spacing; forces at most 2.1e-3 N (2.8e-5 of the scene's largest |F|,
// 75 to 190 N at the impacts); torques 2.6e-4 of the largest |T|; densities 4.9e-6;
// contacts equal step by step, push-outs within 3 of about 40 a step. Deliberate slips,
// worst over the scenes by step 6, in spacings: boxes as one half-space instead of slabs
// 7.3, boundary share inside bodies 10, push-out at once 18, push-out from within r instead
// of r/2 4.8, no sweep (discrete collision) 1.6, sweep from the iteration's start instead
// of the substep's 8.9, colliders' correction at delta's output instead of the iteration's
// start 2.8, that correction without omega 6.0e-2, no container planes after the bodies
// 5.3, no pose interpolation 11, slab gradient sign flipped 11, reach h replaced by r 4.3,
// sphere tracing by d instead of d - r 7.3, stopping at the hit point 8.7, grid normal not
// normalised 3.7, quaternions interpolated the long way 31, slab share without the lattice
// factor 2.5. Slips only forces see: the reaction without omega 2.6e-2 of the largest |F|,
// collision pushes left out of the force 110 N (the largest |F| is 130 N); torques only:
// the contact point at the particle instead of the surface 1.3e-2 of the largest |T|;
// densities only: the metrics without colliders 1.6e-3 at step 1, at the first substep's
// pose instead of the last 0.11. So over steps 1-6 the bounds are 2e-3 spacing (8.7 times
// the noise, 30 times below the smallest slip), 2e-4 of the largest |F| (7 times the noise,
// 130 times below), 2e-3 of the largest |T| (7.7 times, 6.5 times below) and DENSITY_REL;
// 5e-5 spacing after step 1 (7 times the noise; the omega slip gives 4.1e-4 there). From
// step 7 on, as in the dam break, the switches (a swept hit or none, a push-out or none, d
// < h or not) turn rounding noise into differences that grow two- to fourfold per step
// (measured at step 12: 2.1e-2 spacing, 1.4e-1 N, 1.9e-2 N m, densities 1.4e-4); the sides
// must then agree as physics: a quarter spacing (one switch moves a particle by at most a
// radius, half a spacing), 5 % of the largest force, 15 % of the largest torque, densities
// within 1 %. (With the hashed grid's neighbour order, one swept hit that switches at step
// 12 of the hull scene makes 2.4 % of the largest force, 1.85 N of 76 N, and 10.4 % of the
// largest torque, 0.16 of 1.56 N m; the bounds were 2 % and 5 %. With the even counts' pair
// of relaxation factors (2026-11-26) two push-outs switch at step 5 of the hull scene and
// step 12 differs by 2.54 N of 83.7 N, 3.03 %: the force bound went from 3 to 5 %, still
// 40 times below the slip that leaves collision pushes out of the force. Steps 1-6 and the
// stage-by-stage comparison of tests/test_mirror.c are where the two must agree closely.)
#define COLLIDER_STEP1 5e-5  // spacings, after the first step
#define COLLIDER_TIGHT 2e-3  // spacings, steps 1-6
#define COLLIDER_SWITCHED 1e-2 // spacings, steps 1-6 after a push-out switched (below)
#define COLLIDER_LOOSE 0.25  // spacings, steps 7-12
#define FORCE_TIGHT 2e-4     // of the largest |F| of the run, steps 1-6
#define FORCE_SWITCHED 1e-3 // of the largest |F|, steps 1-6 after a push-out switched
#define FORCE_LOOSE 5e-2
#define TORQUE_TIGHT 2e-3    // of the largest |T| of the run, steps 1-6
#define TORQUE_LOOSE 0.15
#define TIGHT_STEPS 6

enum { MAX_BODIES = 6, MAX_COLLIDER_STEPS = 24, GRID_N = 24 };

/// Where a moving collider is at time t (s); NULL for static scenes.
typedef void pose_fn(int body, double t, float position[3], float rotation[4]);

typedef struct collider_scene {
    support_scene s;
    int bodies;
    pbf_collider_def def[MAX_BODIES];
    pose_fn *pose;
    int steps;
} collider_scene;

/// What a run of a collider scene measured, GPU against CPU, per step.
typedef struct collider_result {
    double dev[MAX_COLLIDER_STEPS];   ///< m, max |x_gpu - x_cpu| over particles
    double fdev[MAX_COLLIDER_STEPS];  ///< N, max over bodies |F_gpu - F_cpu|
    double tdev[MAX_COLLIDER_STEPS];  ///< N m, max over bodies |T_gpu - T_cpu|
    double rho[MAX_COLLIDER_STEPS];   ///< relative, max of |avg_gpu / avg_cpu - 1|, |max_gpu / max_cpu - 1|
    double fmax;                      ///< N, largest |F_cpu| of any body in any step
    double tmax;                      ///< N m, largest |T_cpu|
    uint32_t contacts[2], pushed[2];  ///< summed over bodies and steps: GPU, CPU
    int32_t contact_diff[MAX_COLLIDER_STEPS]; ///< contacts_gpu - contacts_cpu over the bodies, per step
    int32_t pushed_diff[MAX_COLLIDER_STEPS];
    double effect;                    ///< m, max |x_cpu - x_cpu without the bodies| at the end
    double density[2][2];             ///< avg, max after the last step: GPU, CPU
    uint32_t n;
} collider_result;

static double norm3(const float *a, const float *b)
{
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) d2 += ((double)a[k] - b[k]) * ((double)a[k] - b[k]);
    return sqrt(d2);
}

static void run_collider_scene(const fixture *f, const collider_scene *cs, collider_result *out)
{
    const float dt = 1.0f / 120.0f;
    memset(out, 0, sizeof *out);
    assert_true(cs->steps <= MAX_COLLIDER_STEPS);
    pbf_world *g = support_gpu_world(f, &cs->s);
    pbf_cpu_world *c = support_cpu_world(&cs->s);
    pbf_collider_id ids[MAX_BODIES];
    for (int b = 0; b < cs->bodies; b++) {
        uint32_t index = 99;
        assert_int_equal(pbf_world_add_collider(g, &cs->def[b], &ids[b]), PBF_OK);
        assert_int_equal(pbf_cpu_world_add_collider(c, &cs->def[b], &index), PBF_OK);
        assert_int_equal(index, (uint32_t)b);
    }
    uint32_t n = pbf_world_particle_count(g);
    assert_int_equal(pbf_cpu_world_particle_count(c), n);
    out->n = n;
    float *gp = malloc((size_t)n * 16), *cp = malloc((size_t)n * 16);
    assert_non_null(gp);
    assert_non_null(cp);
    for (int k = 0; k < cs->steps; k++) {
        if (cs->pose) {
            // The pose at the end of this step, set between steps: both sides interpolate
            // it substep by substep.
            for (int b = 0; b < cs->bodies; b++) {
                float p[3], q[4];
                cs->pose(b, (double)(k + 1) * dt, p, q);
                assert_int_equal(pbf_world_set_collider_pose(g, ids[b], p, q, NULL, NULL, NULL), PBF_OK);
                assert_int_equal(pbf_cpu_world_set_collider_pose(c, (uint32_t)b, p, q, NULL), PBF_OK);
            }
        }
        assert_int_equal(pbf_world_step(g, dt), PBF_OK);
        assert_int_equal(pbf_cpu_world_step(c, dt), PBF_OK);
        assert_int_equal(pbf_world_read_particles(g, gp, NULL, NULL, n), n);
        assert_int_equal(pbf_cpu_world_read_particles(c, cp, NULL, NULL, n), n);
        out->dev[k] = support_max_deviation(gp, cp, n);
        for (int b = 0; b < cs->bodies; b++) {
            pbf_collider_report rg, rc;
            assert_int_equal(pbf_world_collider_report(g, ids[b], 1, true, &rg), PBF_OK);
            assert_int_equal(pbf_cpu_world_collider_report(c, (uint32_t)b, &rc), PBF_OK);
            assert_true(rg.ready && rc.ready);
            assert_int_equal(rg.step, (uint64_t)k);
            assert_int_equal(rc.step, (uint64_t)k);
            out->fdev[k] = fmax(out->fdev[k], norm3(rg.force, rc.force));
            out->tdev[k] = fmax(out->tdev[k], norm3(rg.torque, rc.torque));
            const float zero[3] = { 0.0f, 0.0f, 0.0f };
            out->fmax = fmax(out->fmax, norm3(rc.force, zero));
            out->tmax = fmax(out->tmax, norm3(rc.torque, zero));
            out->contacts[0] += rg.contacts;
            out->contacts[1] += rc.contacts;
            out->pushed[0] += rg.pushed_out;
            out->pushed[1] += rc.pushed_out;
            out->contact_diff[k] += (int32_t)rg.contacts - (int32_t)rc.contacts;
            out->pushed_diff[k] += (int32_t)rg.pushed_out - (int32_t)rc.pushed_out;
        }
        // Densities as the metrics pass computes them, colliders' share included.
        pbf_step_stats gs;
        assert_int_equal(pbf_world_poll_stats(g, &gs, 1, true), 1);
        assert_int_equal(gs.step, (uint64_t)k);
        pbf_cpu_stats st = pbf_cpu_world_density_stats(c);
        assert_int_equal(gs.nan_count, 0);
        assert_int_equal(st.nan_count, 0);
        assert_int_equal(gs.particles, st.particles);
        out->rho[k] = fmax(fabs(gs.density_avg / st.density_avg - 1.0), fabs(gs.density_max / st.density_max - 1.0));
        out->density[0][0] = gs.density_avg;
        out->density[0][1] = gs.density_max;
        out->density[1][0] = st.density_avg;
        out->density[1][1] = st.density_max;
    }
    // The bodies took part: the same scene without them ends up elsewhere.
    pbf_cpu_world *bare = support_cpu_world(&cs->s);
    for (int k = 0; k < cs->steps; k++) assert_int_equal(pbf_cpu_world_step(bare, dt), PBF_OK);
    float *bp = malloc((size_t)n * 16);
    assert_non_null(bp);
    assert_int_equal(pbf_cpu_world_read_particles(bare, bp, NULL, NULL, n), n);
    out->effect = support_max_deviation(bp, cp, n);
    free(bp);
    pbf_cpu_world_destroy(bare);
    float spacing = pbf_derive_constants(&cs->s.params).spacing;
    for (int k = 0; k < cs->steps; k++)
        print_message("step %2d: max |x_gpu - x_cpu| = %.2e spacing, max |F_gpu - F_cpu| = %.2e N, |T_gpu - T_cpu| = "
                      "%.2e N m, density %.1e, contacts %+d, pushed out %+d\n", k + 1, out->dev[k] / spacing,
                      out->fdev[k], out->tdev[k], out->rho[k], out->contact_diff[k], out->pushed_diff[k]);
    print_message("largest |F| %.3e N, |T| %.3e N m; contacts GPU %u CPU %u, pushed out GPU %u CPU %u; bodies move "
                  "particles by %.3e m = %.2f spacing; density GPU avg %.3f max %.3f, CPU avg %.3f max %.3f\n",
                  out->fmax, out->tmax, out->contacts[0], out->contacts[1], out->pushed[0], out->pushed[1],
                  out->effect, out->effect / spacing, out->density[0][0], out->density[0][1], out->density[1][0],
                  out->density[1][1]);
    free(gp);
    free(cp);
    pbf_cpu_world_destroy(c);
    pbf_world_destroy(g);
}

/// The bounds above (see there for the numbers behind them).
static void check_collider_result(const collider_scene *cs, const collider_result *r)
{
    double spacing = pbf_derive_constants(&cs->s.params).spacing;
    assert_true(r->dev[0] < COLLIDER_STEP1 * spacing);
    // A push-out that happens on one side only (counts 3 or more apart, or a contact) moves
    // a particle by up to half a spacing and the difference grows from there: since the walls
    // are mirrors (2026-11-26) the hull scene switches 3 push-outs at step 4 and reaches
    // 2.3e-3 spacing at step 6, the moving scene at step 3 (4.9e-4 at step 4). Positions
    // after such a step take COLLIDER_SWITCHED, 4.4 times that and 6 times below the
    // smallest slip (omega left out, 6.0e-2 by step 6). Forces after such a step take
    // FORCE_SWITCHED: on an NVIDIA H100 (2026-11-26) the hull scene switched 3 push-outs at
    // step 1 and 6 at step 3, and step 6's forces differed by 1.81e-2 N, 2.2e-4 of the
    // largest 83.7 N (the tight bound is 2e-4); 1e-3 is still 26 times below the smallest
    // force slip (the reaction without omega). Torques stay tight.
    bool switched = false;
    for (int k = 0; k < cs->steps; k++) {
        bool tight = k < TIGHT_STEPS;
        double near = switched ? COLLIDER_SWITCHED : COLLIDER_TIGHT;
        assert_true(r->dev[k] < (tight ? near : COLLIDER_LOOSE) * spacing);
        if (abs(r->pushed_diff[k]) >= 3 || r->contact_diff[k] != 0) switched = true;
        double force_near = switched ? FORCE_SWITCHED : FORCE_TIGHT;
        assert_true(r->fdev[k] <= (tight ? force_near : FORCE_LOOSE) * r->fmax);
        assert_true(r->tdev[k] <= (tight ? TORQUE_TIGHT : TORQUE_LOOSE) * r->tmax);
        assert_true(r->rho[k] < (tight ? (switched ? DENSITY_SWITCHED : DENSITY_REL) : 1e-2));
    }
    // Counts over the run. Noise: contacts within 7 of 24000 to 40000 (2.9e-4), push-outs
    // within 2 of 266 and 1 of 364 on llvmpipe (7.5e-3; 3 of 460 before the contact margin).
    // Slips: reach r instead of h -29 to -61 % contacts, boxes as half-spaces -1.1 %, omega
    // left out +0.12 %; push-out at once -72 to -88 % push-outs,
    // from within r +44 % or more, grid normal not normalised +276 %. Bounds 1e-3 and 6e-2:
    // on an NVIDIA H200 (2026-11-27) the hull scene, whose push-outs switched from step 1,
    // counted 276 push-outs against the CPU's 266 (3.8 %; since the contact margin of 0.13.0
    // the scenes push out fewer particles), 7 times below the smallest slip.
    assert_true(fabs((double)r->contacts[0] - r->contacts[1]) <= 1e-3 * r->contacts[1]);
    assert_true(fabs((double)r->pushed[0] - r->pushed[1]) <= 6e-2 * r->pushed[1]);
    // The bodies took part (measured: 4.8, 8.0 and 22 spacings) and pushed back.
    assert_true(r->effect > spacing);
    assert_true(r->fmax > 1.0);
    assert_true(r->contacts[1] > 1000);
}

/// The dam-break tank with a slab of water above the bodies, falling onto them at `v0` m/s.
static support_scene slab_over_bodies(float v0)
{
    support_scene s = support_dam_break();
    s.block.min[0] = 0.0f, s.block.min[1] = 0.17f, s.block.min[2] = 0.0f;
    s.block.max[0] = 0.5f, s.block.max[1] = 0.27f, s.block.max[2] = 0.25f;
    s.block.velocity[1] = v0;
    return s;
}

/// The four analytic shapes but planes, posed off-axis.
static collider_scene analytic_shapes(void)
{
    collider_scene cs;
    memset(&cs, 0, sizeof cs);
    cs.s = slab_over_bodies(-1.0f);
    cs.steps = 12;
    const float h30 = 0.258819045f, c30 = 0.965925826f; // sin, cos of 15 degrees: a 30 degree turn
    const float s45 = 0.707106781f;                      // 90 degrees
    pbf_collider_def *d = cs.def;
    cs.bodies = 4;
    for (int k = 0; k < cs.bodies; k++) d[k] = pbf_default_collider_def();
    d[0].type = PBF_SHAPE_SPHERE;
    d[0].size[0] = 0.06f;
    d[0].position[0] = 0.12f, d[0].position[1] = 0.10f, d[0].position[2] = 0.12f;
    d[1].type = PBF_SHAPE_BOX;
    d[1].size[0] = 0.06f, d[1].size[1] = 0.03f, d[1].size[2] = 0.06f;
    d[1].position[0] = 0.36f, d[1].position[1] = 0.09f, d[1].position[2] = 0.12f;
    d[1].rotation[1] = h30, d[1].rotation[3] = c30; // about y
    d[2].type = PBF_SHAPE_CAPSULE;
    d[2].size[0] = 0.03f, d[2].size[1] = 0.05f;
    d[2].position[0] = 0.25f, d[2].position[1] = 0.08f, d[2].position[2] = 0.06f;
    d[2].rotation[2] = s45, d[2].rotation[3] = s45; // about z: axis along x
    d[3].type = PBF_SHAPE_CYLINDER;
    d[3].size[0] = 0.04f, d[3].size[1] = 0.07f;
    d[3].position[0] = 0.25f, d[3].position[1] = 0.07f, d[3].position[2] = 0.19f;
    d[3].rotation[0] = h30, d[3].rotation[3] = c30; // tilted about x
    return cs;
}

static const float roof_planes[5 * 4];

/// The colliders' share is what the constraint's gradient says it is: at points within a
/// kernel radius of each analytic shape and of a hull (posed off-axis), the returned
/// gradient against central differences of the share. A slip in one of the product rules
/// (cylinders, hulls) or the curvature (spheres, capsules) shows here before it shows as
/// water that will not rest. And a hull of a box's six faces takes the box's share.
static void collider_share_gradient_matches_its_differences(void **state)
{
    (void)state;
    collider_scene cs = analytic_shapes();
    pbf_params p = pbf_default_params();
    const float lo[3] = { 0.0f, 0.0f, 0.0f }, hi[3] = { 0.5f, 0.4f, 0.3f };
    char err[256];
    pbf_cpu_world *w = pbf_cpu_world_create(&p, 16, lo, hi, err, sizeof err);
    assert_non_null(w);
    pbf_collider_def roof = pbf_default_collider_def();
    roof.type = PBF_SHAPE_CONVEX_HULL;
    roof.planes = roof_planes;
    roof.plane_count = 5;
    roof.size[0] = 0.085f;
    roof.position[0] = 0.40f, roof.position[1] = 0.30f, roof.position[2] = 0.15f;
    roof.rotation[1] = 0.258819045f, roof.rotation[3] = 0.965925826f;
    cs.def[cs.bodies++] = roof;
    for (int b = 0; b < cs.bodies; b++) {
        uint32_t index;
        assert_int_equal(pbf_cpu_world_add_collider(w, &cs.def[b], &index), PBF_OK);
    }
    const float h = p.kernel_radius, e = 1e-4f * h;
    uint32_t seed = 12345u, checked = 0;
    double worst = 0.0;
    for (int trial = 0; trial < 20000 && checked < 400; trial++) {
        float x[3];
        for (int k = 0; k < 3; k++) {
            seed = seed * 1664525u + 1013904223u;
            x[k] = lo[k] + (hi[k] - lo[k]) * (float)(seed >> 8) / 16777216.0f;
        }
        float g[3];
        float v = pbf_cpu_world_collider_share(w, x, g);
        if (v < 0.01f || v > 0.45f) continue; // near a surface, not at a share's kink
        double worst_here = 0.0, scale = 0.0;
        for (int k = 0; k < 3; k++) {
            float xp[3] = { x[0], x[1], x[2] }, xm[3] = { x[0], x[1], x[2] }, unused[3];
            xp[k] += e, xm[k] -= e;
            double fd = ((double)pbf_cpu_world_collider_share(w, xp, unused) -
                         (double)pbf_cpu_world_collider_share(w, xm, unused)) / (2.0 * (double)e);
            worst_here = fmax(worst_here, fabs(fd - (double)g[k]));
            scale = fmax(scale, fabs((double)g[k]));
        }
        if (!(worst_here * h < 0.02 + 0.01 * scale * h))
            print_message("at (%.4f, %.4f, %.4f): V %.4f, grad h (%.4f %.4f %.4f), off by %.4f\n", x[0], x[1], x[2], v,
                          g[0] * h, g[1] * h, g[2] * h, worst_here * h);
        // float32 differences over 1e-4 h: about 1e-3 of G(0) = 1.5 / h of noise
        assert_true(worst_here * h < 0.02 + 0.01 * scale * h);
        worst = fmax(worst, worst_here * h);
        checked++;
    }
    print_message("%u points near the shapes: worst |grad V - differences| h = %.2e\n", checked, worst);
    assert_true(checked >= 200);
    pbf_cpu_world_destroy(w);

    // A box (half extents 6 x 6 x 7 cm, thicker than 2h) and a hull of its six faces, each
    // alone in a world, at the same pose: the same share and gradient next to faces, edges
    // and corners.
    const float half[3] = { 0.06f, 0.06f, 0.07f };
    const float cube[6 * 4] = { 1, 0, 0, half[0], -1, 0, 0, half[0], 0, 1, 0, half[1],
                                0, -1, 0, half[1], 0, 0, 1, half[2], 0, 0, -1, half[2] };
    pbf_collider_def box = pbf_default_collider_def(), hull = pbf_default_collider_def();
    box.type = PBF_SHAPE_BOX;
    memcpy(box.size, half, sizeof half);
    hull.type = PBF_SHAPE_CONVEX_HULL;
    hull.planes = cube;
    hull.plane_count = 6;
    hull.size[0] = 0.11f;
    for (int k = 0; k < 3; k++) box.position[k] = hull.position[k] = 0.5f * (lo[k] + hi[k]);
    box.rotation[0] = hull.rotation[0] = 0.173648178f, box.rotation[3] = hull.rotation[3] = 0.984807753f;
    pbf_cpu_world *wb = pbf_cpu_world_create(&p, 16, lo, hi, err, sizeof err);
    pbf_cpu_world *wh = pbf_cpu_world_create(&p, 16, lo, hi, err, sizeof err);
    uint32_t index;
    assert_int_equal(pbf_cpu_world_add_collider(wb, &box, &index), PBF_OK);
    assert_int_equal(pbf_cpu_world_add_collider(wh, &hull, &index), PBF_OK);
    uint32_t compared = 0;
    for (int trial = 0; trial < 4000; trial++) {
        float x[3];
        for (int k = 0; k < 3; k++) {
            seed = seed * 1664525u + 1013904223u;
            x[k] = box.position[k] + 0.14f * ((float)(seed >> 8) / 16777216.0f - 0.5f) * 2.0f;
        }
        float gb[3], gh[3];
        float vb = pbf_cpu_world_collider_share(wb, x, gb), vh = pbf_cpu_world_collider_share(wh, x, gh);
        if (vb <= 0.0f && vh <= 0.0f) continue;
        assert_true(fabsf(vb - vh) < 1e-5f);
        for (int k = 0; k < 3; k++) assert_true(fabsf(gb[k] - gh[k]) * h < 1e-4f);
        compared++;
    }
    print_message("box and box-shaped hull: %u points compared\n", compared);
    assert_true(compared >= 100);
    pbf_cpu_world_destroy(wb);
    pbf_cpu_world_destroy(wh);
}

static void gpu_matches_cpu_reference_around_colliders(void **state)
{
    collider_scene cs = analytic_shapes();
    collider_result r;
    run_collider_scene(*state, &cs, &r);
    check_collider_result(&cs, &r);
    assert_int_equal(r.pushed[1], 0); // nothing starts inside here
}

/// A triangular prism (a roof, ridge along local z), as hull face planes: outward unit
/// normal xyz, offset w (inside: dot(n, x) <= w), m.
static const float roof_planes[5 * 4] = {
    0.0f, -1.0f, 0.0f, 0.02f, 0.8f, 0.6f, 0.0f, 0.03f, -0.8f, 0.6f, 0.0f, 0.03f,
    0.0f, 0.0f, 1.0f, 0.06f,  0.0f, 0.0f, -1.0f, 0.06f,
};

/// Samples of a box with rounded edges (half extents 4 x 2.5 x 5 cm, edge radius 1 cm) on a
/// GRID_N^3 grid of 1 cm cells centred on it, margin 7 cm (more than h + 2 cells).
static pbf_sdf_grid rounded_box_grid(float *values)
{
    const double b[3] = { 0.04, 0.025, 0.05 }, round = 0.01, cell = 0.01;
    const double o = -0.5 * cell * (GRID_N - 1);
    for (int z = 0; z < GRID_N; z++)
        for (int y = 0; y < GRID_N; y++)
            for (int x = 0; x < GRID_N; x++) {
                const double p[3] = { o + cell * x, o + cell * y, o + cell * z };
                double q[3], out2 = 0.0, in = -1e9;
                for (int k = 0; k < 3; k++) {
                    q[k] = fabs(p[k]) - (b[k] - round);
                    out2 += q[k] > 0.0 ? q[k] * q[k] : 0.0;
                    in = fmax(in, q[k]);
                }
                values[x + GRID_N * (y + GRID_N * z)] = (float)(sqrt(out2) + fmin(in, 0.0) - round);
            }
    pbf_sdf_grid g;
    memset(&g, 0, sizeof g);
    g.values = values;
    g.dims[0] = g.dims[1] = g.dims[2] = GRID_N;
    g.origin[0] = g.origin[1] = g.origin[2] = (float)o;
    g.cell = (float)cell;
    return g;
}

static float grid_values[GRID_N * GRID_N * GRID_N];

/// A convex hull (the roof, turned 30 degrees about y) and a distance grid (the rounded box,
/// tilted 20 degrees about x) over a sloping floor that is a plane collider (one-way,
/// turned 8 degrees about z), under the falling slab; a few particles start inside the hull
/// and the grid body (the push-out). Over-relaxed (sor 1.2), which scales the colliders'
/// correction and its reaction.
static collider_scene hull_grid_and_plane(float *extra)
{
    collider_scene cs;
    memset(&cs, 0, sizeof cs);
    cs.s = slab_over_bodies(-1.0f);
    cs.s.params.sor = 1.2f;
    cs.steps = 12;
    cs.bodies = 3;
    pbf_collider_def *d = cs.def;
    for (int k = 0; k < cs.bodies; k++) d[k] = pbf_default_collider_def();
    d[0].type = PBF_SHAPE_CONVEX_HULL;
    d[0].planes = roof_planes;
    d[0].plane_count = 5;
    d[0].size[0] = 0.085f; // bounding radius: the farthest corner is 8.2 cm out
    d[0].position[0] = 0.13f, d[0].position[1] = 0.10f, d[0].position[2] = 0.13f;
    d[0].rotation[1] = 0.258819045f, d[0].rotation[3] = 0.965925826f;
    d[1].type = PBF_SHAPE_SDF;
    d[1].grid = rounded_box_grid(grid_values);
    d[1].position[0] = 0.37f, d[1].position[1] = 0.10f, d[1].position[2] = 0.13f;
    d[1].rotation[0] = 0.173648178f, d[1].rotation[3] = 0.984807753f;
    d[2].type = PBF_SHAPE_PLANE;
    d[2].size[0] = 0.0f, d[2].size[1] = 1.0f, d[2].size[2] = 0.0f, d[2].size[3] = 0.0f;
    d[2].position[0] = 0.25f, d[2].position[1] = 0.04f, d[2].position[2] = 0.13f;
    d[2].rotation[2] = 0.069756474f, d[2].rotation[3] = 0.997564050f;
    d[2].two_way = false;
    // Particles starting inside: 2 x 2 x 3 in the hull's core, 3 x 2 x 3 in the grid body.
    int n = 0;
    for (int z = 0; z < 3; z++)
        for (int y = 0; y < 2; y++) {
            for (int x = 0; x < 2; x++, n++) {
                extra[3 * n + 0] = 0.12f + 0.02f * (float)x;
                extra[3 * n + 1] = 0.095f + 0.015f * (float)y;
                extra[3 * n + 2] = 0.10f + 0.03f * (float)z;
            }
            for (int x = 0; x < 3; x++, n++) {
                extra[3 * n + 0] = 0.35f + 0.02f * (float)x;
                extra[3 * n + 1] = 0.09f + 0.02f * (float)y;
                extra[3 * n + 2] = 0.10f + 0.03f * (float)z;
            }
        }
    cs.s.positions = extra;
    cs.s.extra = (uint32_t)n;
    cs.s.capacity = 2048;
    return cs;
}

static void gpu_matches_cpu_reference_around_hulls_grids_and_planes(void **state)
{
    static float extra[3 * 30];
    collider_scene cs = hull_grid_and_plane(extra);
    collider_result r;
    run_collider_scene(*state, &cs, &r);
    check_collider_result(&cs, &r);
    assert_true(r.pushed[1] > 100); // the particles placed inside were moved out (measured 453)
}

/// A thin paddle (a box 2 x 12 x 10 cm) pushed through a pool at 3 m/s while it yaws, and the
/// roof hull spinning about y at 8 rad/s: poses set between steps, interpolated substep by
/// substep (linear and normalised-linear) on both sides.
static void moving_pose(int body, double t, float position[3], float rotation[4])
{
    double angle;
    if (body == 0) {
        position[0] = (float)(0.08 + 3.0 * t), position[1] = 0.07f, position[2] = 0.07f;
        angle = 2.0 * t; // rad
    } else {
        position[0] = 0.38f, position[1] = 0.07f, position[2] = 0.19f;
        angle = 8.0 * t;
    }
    // The hull's quaternion changes sign every other step (q and -q are the same turn, as
    // a physics engine may hand them out): the interpolation must take the short way.
    double sign = body == 1 && lround(t * 120.0) % 2 == 1 ? -1.0 : 1.0;
    rotation[0] = 0.0f, rotation[2] = 0.0f;
    rotation[1] = (float)(sign * sin(0.5 * angle));
    rotation[3] = (float)(sign * cos(0.5 * angle));
}

static collider_scene moving_bodies(void)
{
    collider_scene cs;
    memset(&cs, 0, sizeof cs);
    cs.s = support_dam_break();
    const float lo[3] = { 0.0f, 0.0f, 0.0f }, hi[3] = { 0.5f, 0.1f, 0.25f };
    memcpy(cs.s.block.min, lo, sizeof lo);
    memcpy(cs.s.block.max, hi, sizeof hi);
    cs.steps = 12;
    cs.bodies = 2;
    cs.pose = moving_pose;
    pbf_collider_def *d = cs.def;
    for (int k = 0; k < cs.bodies; k++) {
        d[k] = pbf_default_collider_def();
        moving_pose(k, 0.0, d[k].position, d[k].rotation);
    }
    d[0].type = PBF_SHAPE_BOX;
    d[0].size[0] = 0.01f, d[0].size[1] = 0.06f, d[0].size[2] = 0.05f;
    d[1].type = PBF_SHAPE_CONVEX_HULL;
    d[1].planes = roof_planes;
    d[1].plane_count = 5;
    d[1].size[0] = 0.085f;
    return cs;
}

static void gpu_matches_cpu_reference_around_moving_colliders(void **state)
{
    collider_scene cs = moving_bodies();
    collider_result r;
    run_collider_scene(*state, &cs, &r);
    check_collider_result(&cs, &r);
}

/// Collider definitions are checked alike on both sides, naming the field, the rule and
/// the value; the CPU's pose and report calls check the index.
static void bad_colliders_are_rejected_naming_the_field_on_cpu_and_gpu(void **state)
{
    fixture *f = *state;
    support_scene s = support_dam_break();
    pbf_world *g = support_gpu_world(f, &s);
    pbf_cpu_world *c = support_cpu_world(&s);
    static float values[8];
    pbf_collider_def d[4];
    for (int k = 0; k < 4; k++) d[k] = pbf_default_collider_def();
    d[0].type = PBF_SHAPE_CONVEX_HULL;
    d[0].planes = roof_planes;
    d[0].plane_count = 3;
    d[0].size[0] = 0.1f;
    d[1].type = PBF_SHAPE_SDF;
    d[1].grid.values = values;
    d[1].grid.dims[0] = 2, d[1].grid.dims[1] = 1, d[1].grid.dims[2] = 2;
    d[1].grid.cell = 0.01f;
    d[2].size[2] = 0.0f;
    d[3].rotation[3] = 2.0f;
    const char *const needles[4][4] = {
        { "pbf_collider_def.plane_count", "[4, 256]", "got 3", NULL },
        { "pbf_collider_def.grid.dims[1]", "[2, 1023]", "got 1", NULL },
        { "pbf_collider_def.size[2]", "> 0 m", "got 0", NULL },
        { "pbf_collider_def.rotation", "unit quaternion", "got length 2", NULL },
    };
    for (int k = 0; k < 4; k++) {
        pbf_collider_id id;
        uint32_t index = 0;
        assert_int_equal(pbf_world_add_collider(g, &d[k], &id), PBF_ERR_INVALID_ARG);
        assert_int_equal(pbf_cpu_world_add_collider(c, &d[k], &index), PBF_ERR_INVALID_ARG);
        assert_int_equal(index, UINT32_MAX);
        print_message("%s\n", pbf_cpu_world_last_error(c));
        support_assert_mentions(pbf_world_last_error(g), needles[k]);
        support_assert_mentions(pbf_cpu_world_last_error(c), needles[k]);
    }
    const float p[3] = { 0.1f, 0.1f, 0.1f }, q[4] = { 0.0f, 0.0f, 0.0f, 1.0f };
    assert_int_equal(pbf_cpu_world_set_collider_pose(c, 0, p, q, NULL), PBF_ERR_STALE_ID);
    static const char *const index_needles[] = { "index", "got 0", NULL };
    support_assert_mentions(pbf_cpu_world_last_error(c), index_needles);
    pbf_collider_report rep;
    assert_int_equal(pbf_cpu_world_collider_report(c, 0, &rep), PBF_ERR_STALE_ID);
    pbf_cpu_world_destroy(c);
    pbf_world_destroy(g);
}

// A report carries the water that pushes a two-way body (pbf_collider_report.fluid_velocity
// and fluid_push; the coupling lets the water bring a body up to that speed): a block of
// water moving at u in zero gravity hits a ball at rest; the water pressing on it moves
// along u, between 0.3 |u| (slowed on its front) and 1.5 |u| (potential flow's speed at its
// equator), the magnitudes of the pushes add up to at least the net force, and a ball away
// from the water reports none; the CPU reference the same.
static void a_report_carries_the_water_that_pushes_the_body(void **state)
{
    fixture *f = *state;
    support_scene s = support_dam_break();
    s.params.gravity[1] = 0.0f;
    s.container = false;
    for (int k = 0; k < 3; k++) s.domain_min[k] = 0.0f, s.domain_max[k] = 1.2f;
    s.block.max[0] = s.block.min[0]; // no block: the particles below
    const float u[3] = { 0.4f, 0.0f, -0.2f }, centre[3] = { 0.4f, 0.4f, 0.6f }, ball = 0.06f;
    float spacing = pbf_derive_constants(&s.params).spacing;
    enum { SIDE = 16 };
    static float pos[SIDE * SIDE * SIDE * 3], vel[SIDE * SIDE * SIDE * 3];
    uint32_t n = 0;
    for (int i = 0; i < SIDE; i++)
        for (int j = 0; j < SIDE; j++)
            for (int k = 0; k < SIDE; k++) {
                float p[3] = { 0.2f + (i + 0.5f) * spacing, 0.2f + (j + 0.5f) * spacing, 0.4f + (k + 0.5f) * spacing };
                float d2 = 0.0f;
                for (int a = 0; a < 3; a++) d2 += (p[a] - centre[a]) * (p[a] - centre[a]);
                if (d2 < (ball + 0.5f * spacing) * (ball + 0.5f * spacing)) continue; // the ball's room
                for (int a = 0; a < 3; a++) pos[3 * n + a] = p[a], vel[3 * n + a] = u[a];
                n++;
            }
    s.positions = pos;
    s.velocities = vel;
    s.extra = n;
    s.capacity = n;
    pbf_world *g = support_gpu_world(f, &s);
    pbf_cpu_world *c = support_cpu_world(&s);
    pbf_collider_def d[2] = { pbf_default_collider_def(), pbf_default_collider_def() };
    pbf_collider_id ids[2];
    for (int b = 0; b < 2; b++) {
        d[b].type = PBF_SHAPE_SPHERE;
        d[b].size[0] = ball;
        d[b].two_way = true;
        for (int a = 0; a < 3; a++) d[b].position[a] = b == 0 ? centre[a] : 1.0f;
        assert_int_equal(pbf_world_add_collider(g, &d[b], &ids[b]), PBF_OK);
        uint32_t index;
        assert_int_equal(pbf_cpu_world_add_collider(c, &d[b], &index), PBF_OK);
    }
    const float zero[3] = { 0.0f, 0.0f, 0.0f };
    double speed = norm3(u, zero);
    for (int step = 1; step <= 3; step++) {
        assert_int_equal(pbf_world_step(g, 1.0f / 60.0f), PBF_OK);
        assert_int_equal(pbf_cpu_world_step(c, 1.0f / 60.0f), PBF_OK);
        pbf_collider_report rg[2], rc[2];
        for (int b = 0; b < 2; b++) {
            assert_int_equal(pbf_world_collider_report(g, ids[b], 1, true, &rg[b]), PBF_OK);
            assert_int_equal(pbf_cpu_world_collider_report(c, (uint32_t)b, &rc[b]), PBF_OK);
        }
        const float *w = rg[0].fluid_velocity;
        double along = ((double)w[0] * u[0] + (double)w[1] * u[1] + (double)w[2] * u[2]) / speed;
        double across = sqrt(fmax(norm3(w, zero) * norm3(w, zero) - along * along, 0.0));
        print_message("step %d: the water pushing the ball moves at (%.4f, %.4f, %.4f) m/s: %.3f of |u| along u, %.3f "
                      "across (CPU reference %.1e m/s apart); pushes %.4f N for a net force of %.4f N; the dry ball "
                      "%.3g m/s, %.3g N\n", step, (double)w[0], (double)w[1], (double)w[2], along / speed,
                      across / speed, norm3(w, rc[0].fluid_velocity), (double)rg[0].fluid_push,
                      norm3(rg[0].force, zero), norm3(rg[1].fluid_velocity, zero), (double)rg[1].fluid_push);
        assert_true(along > 0.3 * speed && along < 1.5 * speed && across < 0.2 * speed);
        assert_true(norm3(w, rc[0].fluid_velocity) < 1e-3 * speed);
        assert_true(fabs((double)rg[0].fluid_push / rc[0].fluid_push - 1.0) < 1e-3);
        assert_true(rg[0].fluid_push >= 0.999f * (float)norm3(rg[0].force, zero) && rg[0].fluid_push > 0.0f);
        assert_true(rg[1].fluid_push == 0.0f && norm3(rg[1].fluid_velocity, zero) == 0.0);
    }
    pbf_cpu_world_destroy(c);
    pbf_world_destroy(g);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(collider_share_gradient_matches_its_differences),
    cmocka_unit_test(gpu_matches_cpu_reference_around_colliders),
    cmocka_unit_test(gpu_matches_cpu_reference_around_hulls_grids_and_planes),
    cmocka_unit_test(gpu_matches_cpu_reference_around_moving_colliders),
    cmocka_unit_test(bad_colliders_are_rejected_naming_the_field_on_cpu_and_gpu),
    cmocka_unit_test(a_report_carries_the_water_that_pushes_the_body),
};

int main(void) { return cmocka_run_group_tests(tests, support_gpu_setup, support_gpu_teardown); }
