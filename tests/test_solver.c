// The solver against its specification: kernel and boundary integrals, the GPU step
// against the CPU reference (fluid/pbf_cpu), the sign of the curl and of vorticity
// confinement, determinism, and parameter checks that name the field.
//
// Scenes are small (about 1000 particles) so the whole program stays well under a minute
// on llvmpipe with two cores.
#include "tests/support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fluid/pbf.h"
#include "fluid/pbf_cpu.h"

#define PI 3.14159265358979323846

// ---- fixture: one headless context for the GPU tests -----------------------------------

typedef support_gpu fixture;

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

// ---- scenes built identically on both sides ------------------------------------------------

typedef struct scene {
    pbf_params params;
    uint32_t capacity;
    float domain_min[3], domain_max[3];
    bool container;
    float box_min[3], box_max[3];
    bool closed_top;
    pbf_block_def block;
    const float *positions; ///< extra particles (xyz triples) after the block, or NULL
    const float *velocities;
    uint32_t extra;
} scene;

/// A dam break: a 0.25 m cube of water (10^3 particles at the default 2.5 cm spacing) in
/// the corner of an open 0.5 x 0.5 x 0.25 m tank, default parameters.
static scene dam_break(void)
{
    scene s;
    memset(&s, 0, sizeof s);
    s.params = pbf_default_params();
    s.capacity = 2048;
    const float dmin[3] = { -0.05f, -0.05f, -0.05f }, dmax[3] = { 0.55f, 0.6f, 0.3f };
    const float bmin[3] = { 0.0f, 0.0f, 0.0f }, bmax[3] = { 0.5f, 0.5f, 0.26f };
    memcpy(s.domain_min, dmin, sizeof dmin);
    memcpy(s.domain_max, dmax, sizeof dmax);
    s.container = true;
    memcpy(s.box_min, bmin, sizeof bmin);
    memcpy(s.box_max, bmax, sizeof bmax);
    s.closed_top = false;
    s.block = pbf_default_block_def();
    // The block stands 3 mm (0.12 spacing) off the walls. Placed right against them its
    // wall layer starts exactly in balance (the wall model is calibrated to the lattice),
    // C = max(rho / rho0 - 1, 0) then flips on rounding noise, and the two sides part ways
    // for reasons that say nothing about the implementation.
    const float lo[3] = { 0.003f, 0.003f, 0.003f }, hi[3] = { 0.253f, 0.253f, 0.253f };
    memcpy(s.block.min, lo, sizeof lo);
    memcpy(s.block.max, hi, sizeof hi);
    return s;
}

static pbf_world *gpu_world(const fixture *f, const scene *s)
{
    pbf_world_def def = pbf_default_world_def();
    def.params = s->params;
    def.capacity = s->capacity;
    def.max_neighbours = pbf_suggest_max_neighbours(&s->params);
    memcpy(def.domain_min, s->domain_min, sizeof def.domain_min);
    memcpy(def.domain_max, s->domain_max, sizeof def.domain_max);
    def.shader_dir = f->shader_dir;
    char err[1024];
    pbf_world *w = pbf_world_create(&def, err, sizeof err);
    if (!w) fail_msg("pbf_world_create: %s", err);
    if (s->container) assert_int_equal(pbf_world_set_container(w, s->box_min, s->box_max, s->closed_top), PBF_OK);
    if (s->block.max[0] > s->block.min[0]) assert_int_equal(pbf_world_add_block(w, &s->block, NULL), PBF_OK);
    if (s->extra) assert_int_equal(pbf_world_add_particles(w, s->positions, s->velocities, s->extra), PBF_OK);
    return w;
}

static pbf_cpu_world *cpu_world(const scene *s)
{
    char err[1024];
    pbf_cpu_world *w = pbf_cpu_world_create(&s->params, s->capacity, s->domain_min, s->domain_max, err, sizeof err);
    if (!w) fail_msg("pbf_cpu_world_create: %s", err);
    if (s->container)
        assert_int_equal(pbf_cpu_world_set_container(w, s->box_min, s->box_max, s->closed_top), PBF_OK);
    if (s->block.max[0] > s->block.min[0]) assert_int_equal(pbf_cpu_world_add_block(w, &s->block, NULL), PBF_OK);
    if (s->extra)
        assert_int_equal(pbf_cpu_world_add_particles(w, s->positions, s->velocities, s->extra), PBF_OK);
    return w;
}

/// Largest distance between corresponding particles of two xyzw arrays (m or m/s).
static double max_deviation(const float *a, const float *b, uint32_t n)
{
    double worst = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        double d2 = 0.0;
        for (int k = 0; k < 3; k++) {
            double d = (double)a[4 * i + k] - (double)b[4 * i + k];
            d2 += d * d;
        }
        if (!(d2 <= worst * worst)) worst = sqrt(d2); // NaN counts as the worst
    }
    return worst;
}

static double kinetic_energy(const float *vel, uint32_t n, float mass)
{
    double e = 0.0;
    for (uint32_t i = 0; i < n; i++) {
        const float *v = vel + 4 * i;
        e += 0.5 * mass * ((double)v[0] * v[0] + (double)v[1] * v[1] + (double)v[2] * v[2]);
    }
    return e;
}

// ---- 1. kernels and boundary integrals -------------------------------------------------

static double poly6(double r, double h, double c)
{
    double d = h * h - r * r;
    return d > 0.0 ? c * d * d * d : 0.0;
}

/// Integral over the half-space z > d of f(r, z), f radially symmetric in the xy plane,
/// by the midpoint rule on a (z, rho) grid of n x n cells (cylindrical shells).
static double half_space_integral(double (*f)(double r, double z, double h, double c), double d, double h,
                                  double c, int n)
{
    if (d >= h) return 0.0;
    double dz = (h - d) / n, drho = h / n, sum = 0.0;
    for (int a = 0; a < n; a++) {
        double z = d + (a + 0.5) * dz;
        for (int b = 0; b < n; b++) {
            double rho = (b + 0.5) * drho;
            double r = sqrt(z * z + rho * rho);
            if (r < h) sum += f(r, z, h, c) * 2.0 * PI * rho;
        }
    }
    return sum * dz * drho;
}

static double poly6_at(double r, double z, double h, double c)
{
    (void)z;
    return poly6(r, h, c);
}

/// |grad W_spiky| z / r with |grad W| = -spiky_grad (h - r)^2 (c = -spiky_grad).
static double spiky_grad_z(double r, double z, double h, double c)
{
    return r > 0.0 ? c * (h - r) * (h - r) * z / r : 0.0;
}

static void kernels_are_normalised_and_boundary_closed_forms_match_integrals(void **state)
{
    (void)state;
    pbf_params p = pbf_default_params();
    pbf_constants k = pbf_derive_constants(&p);
    double h = p.kernel_radius;
    // Radial integrals 4 pi int_0^h r^2 W(r) dr by Simpson's rule.
    const int n = 2000;
    double s6 = 0.0, sspiky = 0.0;
    for (int i = 0; i <= n; i++) {
        double r = h * i / n, wgt = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        s6 += wgt * 4.0 * PI * r * r * poly6(r, h, k.poly6);
        // spiky W = 15 / (pi h^6) (h - r)^3; its derivative is spiky_grad (h - r)^2, so
        // the constant the solver uses, -spiky_grad / 3, must be that normalisation.
        sspiky += wgt * 4.0 * PI * r * r * (-k.spiky_grad / 3.0) * pow(h - r, 3);
    }
    s6 *= h / n / 3.0;
    sspiky *= h / n / 3.0;
    print_message("int W_poly6 = %.7f, int W_spiky = %.7f\n", s6, sspiky);
    assert_true(fabs(s6 - 1.0) < 1e-3);
    assert_true(fabs(sspiky - 1.0) < 1e-3);
    assert_true(fabs(-k.spiky_grad / 3.0 - 15.0 / (PI * pow(h, 6))) < 1e-6 * 15.0 / (PI * pow(h, 6)));

    // Boundary volume: the closed form against the numerical half-space integral.
    assert_true(fabsf(pbf_cpu_boundary_volume(0.0f, (float)h) - 0.5f) < 1e-6f);
    assert_true(fabsf(pbf_cpu_boundary_volume((float)h, (float)h)) < 1e-6f);
    assert_true(fabsf(pbf_cpu_boundary_gradient((float)h, (float)h)) < 1e-6f / (float)h);
    const double fractions[] = { 0.0, 0.1, 0.25, 0.5, 0.75, 0.9 };
    double worst_v = 0.0, worst_g = 0.0;
    for (size_t i = 0; i < sizeof fractions / sizeof fractions[0]; i++) {
        double d = fractions[i] * h;
        double v_num = half_space_integral(poly6_at, d, h, k.poly6, 400);
        double v = pbf_cpu_boundary_volume((float)d, (float)h);
        double g_num = half_space_integral(spiky_grad_z, d, h, -k.spiky_grad, 400);
        double g = pbf_cpu_boundary_gradient((float)d, (float)h);
        print_message("d = %.2f h: V %.6f (integral %.6f), G h %.6f (integral %.6f)\n", fractions[i], v, v_num,
                      g * h, g_num * h);
        // Absolute tolerances on the dimensionless V and G h (both at most 1/2 and 3/2).
        assert_true(fabs(v - v_num) < 1e-3);
        assert_true(fabs(g - g_num) * h < 1e-3);
        if (fabs(v - v_num) > worst_v) worst_v = fabs(v - v_num);
        if (fabs(g - g_num) * h > worst_g) worst_g = fabs(g - g_num) * h;
    }
    print_message("worst |V - integral| = %.2e, |G - integral| h = %.2e\n", worst_v, worst_g);
    assert_true(fabs(pbf_cpu_boundary_gradient(0.0f, (float)h) * h - 1.5) < 1e-5);
}

// ---- 2. GPU against the CPU reference ----------------------------------------------------

// Tolerances, from measurement (llvmpipe, this scene) and from breaking the CPU reference
// on purpose. Float32 noise alone (the shader compiler's contractions and rounding; the
// sums run in the same order on both sides) leaves 1.9e-6 spacing after 1 step and
// 5.5e-5 spacing after 10, about 2 ulps of a coordinate per step. Deliberate slips give,
// after 1 / 10 steps: confinement sign flipped 7.9e-5 / 1.1e-2 spacing, XSPH left out
// 2.8e-4 / 7.7e-2, epsilon doubled 3.1e-3 / 4.0e-2, one iteration fewer 6.0e-2 / 0.48,
// wall gradient sign flipped 0.19 / 0.6. So 2e-5 spacing after 1 step and 1e-3 spacing
// over 10 steps sit about ten times above the noise and at least four times below the
// smallest slip. A looser "1e-3 spacing after one step" would let the confinement sign
// and a missing XSPH through. Densities: noise 4e-7 relative, epsilon doubled 1.2e-3;
// the bound is 1e-4 (the 0.5% of a coarse check would miss that slip).
#define DEV_STEP1 2e-5      // spacings, after the first step
#define DEV_ALL 1e-3        // spacings, after every step up to 10
#define DENSITY_REL 1e-4    // relative, average and maximum density

/// Steps the dam break with `params` 10 times on both sides and compares every step;
/// step1_bound (spacings) bounds the first step, all_bound every step.
static void compare_dam_break(const fixture *f, const pbf_params *params, double step1_bound, double all_bound)
{
    const int steps = 10;
    const float dt = 1.0f / 120.0f;
    scene s = dam_break();
    s.params = *params;
    pbf_world *g = gpu_world(f, &s);
    pbf_cpu_world *c = cpu_world(&s);
    uint32_t n = pbf_world_particle_count(g);
    assert_int_equal(n, 1000);
    assert_int_equal(pbf_cpu_world_particle_count(c), n);
    float *gp = malloc((size_t)n * 16), *cp = malloc((size_t)n * 16);
    float *gv = malloc((size_t)n * 16), *cv = malloc((size_t)n * 16);
    assert_non_null(gp);
    assert_non_null(cp);
    assert_non_null(gv);
    assert_non_null(cv);
    // The initial lattice is the same, bit for bit (ids, positions, colour parameter).
    assert_int_equal(pbf_world_read_particles(g, gp, gv, NULL, n), n);
    assert_int_equal(pbf_cpu_world_read_particles(c, cp, cv, NULL, n), n);
    assert_memory_equal(gp, cp, (size_t)n * 16);
    assert_memory_equal(gv, cv, (size_t)n * 16);

    float spacing = pbf_derive_constants(&s.params).spacing;
    pbf_cpu_stats cs[16];
    pbf_step_stats gs[16];
    double dev[16], vdev[16], t_gpu = 0.0, t_cpu = 0.0;
    for (int k = 0; k < steps; k++) {
        double t0 = now_s();
        assert_int_equal(pbf_world_step(g, dt), PBF_OK);
        assert_int_equal(pbf_world_read_particles(g, gp, gv, NULL, n), n);
        // Poll every step: the world keeps only its last 8 records.
        assert_int_equal(pbf_world_poll_stats(g, &gs[k], 1, true), 1);
        assert_int_equal(gs[k].step, (uint64_t)k);
        double t1 = now_s();
        assert_int_equal(pbf_cpu_world_step(c, dt), PBF_OK);
        cs[k] = pbf_cpu_world_density_stats(c);
        assert_int_equal(pbf_cpu_world_read_particles(c, cp, cv, NULL, n), n);
        double t2 = now_s();
        t_gpu += t1 - t0;
        t_cpu += t2 - t1;
        dev[k] = max_deviation(gp, cp, n);
        vdev[k] = max_deviation(gv, cv, n);
        print_message("step %2d: max |x_gpu - x_cpu| = %.3e m = %.2e spacing, max |v_gpu - v_cpu| = %.3e m/s\n",
                      k + 1, dev[k], dev[k] / spacing, vdev[k]);
    }
    print_message("%d steps of %u particles: GPU (llvmpipe) %.3f s, CPU reference %.3f s\n", steps, n, t_gpu, t_cpu);
    double worst_avg = 0.0, worst_max = 0.0;
    for (int k = 0; k < steps; k++) {
        assert_int_equal(gs[k].particles, cs[k].particles);
        assert_int_equal(gs[k].nan_count, 0);
        assert_int_equal(cs[k].nan_count, 0);
        assert_int_equal(gs[k].overflow_count, cs[k].overflow_count);
        double ea = fabs(gs[k].density_avg - cs[k].density_avg) / cs[k].density_avg;
        double em = fabs(gs[k].density_max - cs[k].density_max) / cs[k].density_max;
        if (ea > worst_avg) worst_avg = ea;
        if (em > worst_max) worst_max = em;
        // From the floor impact on (about step 7 here), the two switches of the step, the
        // clamp C = max(rho / rho0 - 1, 0) and the collision projection, turn rounding
        // noise into real differences that grow about fivefold per step (measured: 2.8e-4
        // spacing at step 7, 4.3e-3 at step 10). The tight bounds hold to step 6; after
        // that the sides must still agree as physics: densities within 1 %, positions
        // within 5 % of a spacing. Every slip listed above fails the tight bounds first.
        bool tight = k < 6;
        // The compression error (a mean of max(rho / rho0 - 1, 0)) agrees in absolute terms.
        assert_true(fabs(gs[k].density_error_avg - cs[k].density_error_avg) < (tight ? 1e-5 : 1e-3));
        assert_true(ea < (tight ? DENSITY_REL : 1e-2));
        assert_true(em < (tight ? DENSITY_REL : 1e-2));
        assert_true(dev[k] < (tight ? all_bound : 5e-2) * spacing);
    }
    assert_true(dev[0] < step1_bound * spacing);
    // The dam really collapses (this is not a comparison of two resting lattices): after
    // 1/12 s the fastest particles move at a good part of g t = 0.82 m/s.
    double fastest = 0.0;
    for (uint32_t i = 0; i < n; i++)
        fastest = fmax(fastest, sqrt((double)cv[4 * i] * cv[4 * i] + (double)cv[4 * i + 1] * cv[4 * i + 1] +
                                     (double)cv[4 * i + 2] * cv[4 * i + 2]));
    print_message("fastest particle after %d steps: %.3f m/s\n", steps, fastest);
    assert_true(fastest > 0.3);
    print_message("density: GPU avg %.3f max %.3f, CPU avg %.3f max %.3f kg/m^3 after %d steps; "
                  "worst relative difference avg %.2e, max %.2e\n",
                  (double)gs[steps - 1].density_avg, (double)gs[steps - 1].density_max,
                  (double)cs[steps - 1].density_avg, (double)cs[steps - 1].density_max, steps, worst_avg, worst_max);
    free(gp);
    free(cp);
    free(gv);
    free(cv);
    pbf_cpu_world_destroy(c);
    pbf_world_destroy(g);
}

static void gpu_dam_break_matches_cpu_reference(void **state)
{
    pbf_params p = pbf_default_params();
    compare_dam_break(*state, &p, DEV_STEP1, DEV_ALL);
}

/// The paths the defaults leave out: artificial pressure (s_corr, through pow), damping,
/// over-relaxation, one substep, four iterations, h = 2.4 spacings. s_corr is kept at
/// k = 0.1 as in the paper: s_corr is scaled by 1 / (sum |grad C|^2 of a filled
/// neighbourhood), so it acts like a constraint violated by k (before that scale, k = 1e-3
/// already exploded this dam break, on both sides alike).
static void gpu_dam_break_matches_cpu_reference_with_scorr_damping_and_sor(void **state)
{
    pbf_params p = pbf_default_params();
    p.scorr_k = 0.1f; // the paper's k (s_corr is scaled to a constraint violation of k)
    p.damping = 0.5f;
    p.sor = 1.2f;
    p.iterations = 4;
    p.substeps = 1;
    p.kernel_radius = 0.06f;
    // GLSL pow (exp2 of log2 on llvmpipe) and powf differ by ulps, and a real s_corr
    // (k = 0.1) feeds them back: measured 1.3e-3 spacing after 10 steps, so this case gets
    // 5e-3 over the ten steps (still far below the slips listed above, e.g. 4e-2).
    compare_dam_break(*state, &p, DEV_STEP1, 5e-3);
}

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
// radius, half a spacing), 2 % of the largest force, 5 % of the largest torque, densities
// within 1 %.
#define COLLIDER_STEP1 5e-5  // spacings, after the first step
#define COLLIDER_TIGHT 2e-3  // spacings, steps 1-6
#define COLLIDER_LOOSE 0.25  // spacings, steps 7-12
#define FORCE_TIGHT 2e-4     // of the largest |F| of the run, steps 1-6
#define FORCE_LOOSE 2e-2
#define TORQUE_TIGHT 2e-3    // of the largest |T| of the run, steps 1-6
#define TORQUE_LOOSE 5e-2
#define TIGHT_STEPS 6

enum { MAX_BODIES = 6, MAX_COLLIDER_STEPS = 24, GRID_N = 24 };

/// Where a moving collider is at time t (s); NULL for static scenes.
typedef void pose_fn(int body, double t, float position[3], float rotation[4]);

typedef struct collider_scene {
    scene s;
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
    pbf_world *g = gpu_world(f, &cs->s);
    pbf_cpu_world *c = cpu_world(&cs->s);
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
        out->dev[k] = max_deviation(gp, cp, n);
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
    pbf_cpu_world *bare = cpu_world(&cs->s);
    for (int k = 0; k < cs->steps; k++) assert_int_equal(pbf_cpu_world_step(bare, dt), PBF_OK);
    float *bp = malloc((size_t)n * 16);
    assert_non_null(bp);
    assert_int_equal(pbf_cpu_world_read_particles(bare, bp, NULL, NULL, n), n);
    out->effect = max_deviation(bp, cp, n);
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
    for (int k = 0; k < cs->steps; k++) {
        bool tight = k < TIGHT_STEPS;
        assert_true(r->dev[k] < (tight ? COLLIDER_TIGHT : COLLIDER_LOOSE) * spacing);
        assert_true(r->fdev[k] <= (tight ? FORCE_TIGHT : FORCE_LOOSE) * r->fmax);
        assert_true(r->tdev[k] <= (tight ? TORQUE_TIGHT : TORQUE_LOOSE) * r->tmax);
        assert_true(r->rho[k] < (tight ? DENSITY_REL : 1e-2));
    }
    // Counts over the run. Noise: contacts within 3 of 25000 to 40000 (1.2e-4), push-outs
    // within 3 of 460 (6.5e-3). Slips: reach r instead of h -29 to -61 % contacts, boxes as
    // half-spaces -1.1 %, omega left out +0.12 %; push-out at once -72 to -88 % push-outs,
    // from within r +44 % or more, grid normal not normalised +276 %. Bounds 1e-3 and 2e-2.
    assert_true(fabs((double)r->contacts[0] - r->contacts[1]) <= 1e-3 * r->contacts[1]);
    assert_true(fabs((double)r->pushed[0] - r->pushed[1]) <= 2e-2 * r->pushed[1]);
    // The bodies took part (measured: 4.8, 8.0 and 22 spacings) and pushed back.
    assert_true(r->effect > spacing);
    assert_true(r->fmax > 1.0);
    assert_true(r->contacts[1] > 1000);
}

/// The dam-break tank with a slab of water above the bodies, falling onto them at `v0` m/s.
static scene slab_over_bodies(float v0)
{
    scene s = dam_break();
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
    cs.s = dam_break();
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

// ---- 3. the sign of the curl and of vorticity confinement ------------------------------

/// Places particles on a cubic lattice of n^3 sites at spacing `spacing` from `lo` (cell
/// centres, like pbf_world_add_block), xyz triples into `pos`.
static void lattice(float *pos, int n, float spacing, const float lo[3])
{
    int i = 0;
    for (int z = 0; z < n; z++)
        for (int y = 0; y < n; y++)
            for (int x = 0; x < n; x++, i++) {
                pos[3 * i + 0] = lo[0] + spacing * (0.5f + (float)x);
                pos[3 * i + 1] = lo[1] + spacing * (0.5f + (float)y);
                pos[3 * i + 2] = lo[2] + spacing * (0.5f + (float)z);
            }
}

/// The factor by which the SPH curl of a linear field on a filled cubic lattice differs
/// from the exact curl: kappa = (V / 3) sum_j |grad W_spiky(r_j)| |r_j| with the particle
/// volume V = 1 / sum_j W_poly6(r_j) that the calibrated mass gives. The continuous
/// integrals make it 1; on the lattice at h = 2 spacings it is 0.947.
static double lattice_curl_factor(double spacing, double h)
{
    int n = (int)ceil(h / spacing);
    double sum_w = 0.0, sum_g = 0.0;
    for (int z = -n; z <= n; z++)
        for (int y = -n; y <= n; y++)
            for (int x = -n; x <= n; x++) {
                double r = spacing * sqrt((double)(x * x + y * y + z * z));
                sum_w += poly6(r, h, 315.0 / (64.0 * PI * pow(h, 9)));
                if (r > 0.0 && r < h) sum_g += 45.0 / (PI * pow(h, 6)) * (h - r) * (h - r) * r;
            }
    return sum_g / (3.0 * sum_w);
}

static void rigid_rotation_has_vorticity_twice_the_angular_velocity(void **state)
{
    (void)state;
    // v = Omega x (x - c) on a 12^3 lattice; curl v = 2 Omega. Only particles whose whole
    // neighbourhood has a full neighbourhood (two kernel radii = 4 spacings inside) see
    // the interior value: 4^3 of them.
    enum { N = 12, EDGE = 4 };
    pbf_params p = pbf_default_params();
    float s = 2.0f * p.particle_radius;
    const float dmin[3] = { 0, 0, 0 }, dmax[3] = { 1, 1, 1 }, lo[3] = { 0.3f, 0.3f, 0.3f };
    const double omega[3] = { 0.3, -0.5, 1.0 };
    const double c = lo[0] + 0.5 * N * s;
    float pos[3 * N * N * N], vel[3 * N * N * N], curl[4 * N * N * N];
    lattice(pos, N, s, lo);
    for (int i = 0; i < N * N * N; i++) {
        double r[3] = { pos[3 * i] - c, pos[3 * i + 1] - c, pos[3 * i + 2] - c };
        vel[3 * i + 0] = (float)(omega[1] * r[2] - omega[2] * r[1]);
        vel[3 * i + 1] = (float)(omega[2] * r[0] - omega[0] * r[2]);
        vel[3 * i + 2] = (float)(omega[0] * r[1] - omega[1] * r[0]);
    }
    char err[512];
    pbf_cpu_world *w = pbf_cpu_world_create(&p, N * N * N, dmin, dmax, err, sizeof err);
    assert_non_null(w);
    assert_int_equal(pbf_cpu_world_add_particles(w, pos, vel, N * N * N), PBF_OK);
    assert_int_equal(pbf_cpu_world_vorticity(w, curl, N * N * N), N * N * N);
    double kappa = lattice_curl_factor(s, p.kernel_radius);
    double worst = 0.0, along = 0.0, cosine = 1.0;
    int counted = 0;
    const double two = 2.0 * sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
    for (int z = EDGE; z < N - EDGE; z++)
        for (int y = EDGE; y < N - EDGE; y++)
            for (int x = EDGE; x < N - EDGE; x++) {
                const float *o = curl + 4 * (x + N * (y + N * z));
                double e2 = 0.0, dotp = 0.0, o2 = 0.0;
                for (int k = 0; k < 3; k++) {
                    double expect = kappa * 2.0 * omega[k];
                    e2 += (o[k] - expect) * (o[k] - expect);
                    dotp += o[k] * 2.0 * omega[k];
                    o2 += (double)o[k] * o[k];
                }
                worst = fmax(worst, sqrt(e2) / (kappa * two));
                cosine = fmin(cosine, dotp / (two * sqrt(o2)));
                along += dotp / (two * two);
                counted++;
            }
    along /= counted;
    print_message("interior curl over %d particles: omega . 2 Omega / |2 Omega|^2 = %.5f on average (lattice "
                  "factor kappa %.5f), worst |omega - 2 kappa Omega| / |2 kappa Omega| = %.2e, least cosine "
                  "to Omega %.6f\n", counted, along, kappa, worst, cosine);
    // The sign and direction: omega is along +Omega (a flipped curl gives -1).
    assert_true(cosine > 0.9999);
    // The size: 2 Omega up to the lattice factor of the spiky gradient at h = 2 spacings,
    // which the curl reproduces to float precision; kappa itself is within 6% of 1.
    assert_true(fabs(kappa - 1.0) < 0.06);
    assert_true(worst < 1e-4);
    assert_true(fabs(along - kappa) < 1e-4);
    pbf_cpu_world_destroy(w);
}

/// A Gaussian vortex along z in a 16 x 16 x 8 block, zero gravity, no walls:
/// v = a (-(y - cy), x - cx, 0) exp(-rho^2 / sigma^2), a = 5 1/s, sigma = 8 cm. Its
/// vorticity peaks on the axis, so N = grad|omega| / |grad|omega|| points inwards and
/// confinement eps N x omega points along the flow: it must add kinetic energy.
static scene swirl(float confinement, float *pos, float *vel)
{
    enum { NX = 16, NZ = 8 };
    scene s;
    memset(&s, 0, sizeof s);
    s.params = pbf_default_params();
    s.params.gravity[1] = 0.0f;
    s.params.viscosity = 0.0f;
    s.params.vorticity = confinement;
    s.params.substeps = 1;
    s.capacity = NX * NX * NZ;
    const float dmin[3] = { 0, 0, 0 }, dmax[3] = { 1, 1, 1 };
    memcpy(s.domain_min, dmin, sizeof dmin);
    memcpy(s.domain_max, dmax, sizeof dmax);
    float sp = 2.0f * s.params.particle_radius;
    const double a = 5.0, sigma = 0.08, cx = 0.5, cy = 0.5;
    int i = 0;
    for (int z = 0; z < NZ; z++)
        for (int y = 0; y < NX; y++)
            for (int x = 0; x < NX; x++, i++) {
                pos[3 * i + 0] = 0.3f + sp * (0.5f + (float)x);
                pos[3 * i + 1] = 0.3f + sp * (0.5f + (float)y);
                pos[3 * i + 2] = 0.4f + sp * (0.5f + (float)z);
                double rx = pos[3 * i] - cx, ry = pos[3 * i + 1] - cy;
                double g = a * exp(-(rx * rx + ry * ry) / (sigma * sigma));
                vel[3 * i + 0] = (float)(-ry * g);
                vel[3 * i + 1] = (float)(rx * g);
                vel[3 * i + 2] = 0.0f;
            }
    s.positions = pos;
    s.velocities = vel;
    s.extra = (uint32_t)i;
    return s;
}

static void vorticity_confinement_adds_energy_to_a_swirl_on_cpu_and_gpu(void **state)
{
    fixture *f = *state;
    enum { COUNT = 16 * 16 * 8 };
    static float pos[3 * COUNT], vel[3 * COUNT];
    static float v_cpu[2][4 * COUNT], v_gpu[2][4 * COUNT];
    const float eps = 0.1f, dt = 1.0f / 120.0f;
    double e0 = 0.0, e_cpu[2], e_gpu[2];
    float mass = 0.0f;
    for (int with = 0; with < 2; with++) {
        scene s = swirl(with ? eps : 0.0f, pos, vel);
        mass = pbf_derive_constants(&s.params).mass;
        pbf_cpu_world *c = cpu_world(&s);
        pbf_world *g = gpu_world(f, &s);
        if (with == 0) {
            float v0[4 * COUNT];
            pbf_cpu_world_read_particles(c, NULL, v0, NULL, COUNT);
            e0 = kinetic_energy(v0, COUNT, mass);
        }
        assert_int_equal(pbf_cpu_world_step(c, dt), PBF_OK);
        assert_int_equal(pbf_world_step(g, dt), PBF_OK);
        assert_int_equal(pbf_cpu_world_read_particles(c, NULL, v_cpu[with], NULL, COUNT), COUNT);
        assert_int_equal(pbf_world_read_particles(g, NULL, v_gpu[with], NULL, COUNT), COUNT);
        e_cpu[with] = kinetic_energy(v_cpu[with], COUNT, mass);
        e_gpu[with] = kinetic_energy(v_gpu[with], COUNT, mass);
        pbf_world_destroy(g);
        pbf_cpu_world_destroy(c);
    }
    print_message("swirl kinetic energy %.6e J; after one step without confinement: CPU %.6e, GPU %.6e; "
                  "with eps = %g: CPU %.6e (%+.3f%%), GPU %.6e (%+.3f%%)\n", e0, e_cpu[0], e_gpu[0], (double)eps,
                  e_cpu[1], 100.0 * (e_cpu[1] / e_cpu[0] - 1.0), e_gpu[1], 100.0 * (e_gpu[1] / e_gpu[0] - 1.0));
    // Expected gain: about dt eps |omega| / |v| ~ 1/120 * 0.1 * 10 / 0.2, a few percent.
    assert_true(e_cpu[1] > e_cpu[0] * 1.005);
    assert_true(e_gpu[1] > e_gpu[0] * 1.005);
    // The GPU's confinement increment is the CPU's: same direction and size per particle.
    double worst = 0.0, largest = 0.0;
    for (int i = 0; i < COUNT; i++) {
        double d2 = 0.0, c2 = 0.0;
        for (int k = 0; k < 3; k++) {
            double dc = (double)v_cpu[1][4 * i + k] - v_cpu[0][4 * i + k];
            double dg = (double)v_gpu[1][4 * i + k] - v_gpu[0][4 * i + k];
            d2 += (dg - dc) * (dg - dc);
            c2 += dc * dc;
        }
        if (sqrt(d2) > worst) worst = sqrt(d2);
        if (sqrt(c2) > largest) largest = sqrt(c2);
    }
    print_message("confinement dv: largest %.3e m/s, worst |dv_gpu - dv_cpu| = %.3e m/s\n", largest, worst);
    assert_true(largest > 1e-3);
    assert_true(worst < 1e-3 * largest);
}

// ---- 4. determinism ---------------------------------------------------------------------

static void same_scene_gives_identical_state_twice_on_gpu_and_on_cpu(void **state)
{
    fixture *f = *state;
    const int steps = 10;
    scene s = dam_break();
    uint64_t gpu_hash[2], cpu_hash[2];
    uint32_t n = 0;
    float *bytes[2] = { NULL, NULL };
    for (int run = 0; run < 2; run++) {
        pbf_world *g = gpu_world(f, &s);
        pbf_cpu_world *c = cpu_world(&s);
        for (int k = 0; k < steps; k++) {
            assert_int_equal(pbf_world_step(g, 1.0f / 120.0f), PBF_OK);
            assert_int_equal(pbf_cpu_world_step(c, 1.0f / 120.0f), PBF_OK);
        }
        gpu_hash[run] = pbf_world_state_hash(g);
        cpu_hash[run] = pbf_cpu_world_state_hash(c);
        n = pbf_cpu_world_particle_count(c);
        bytes[run] = malloc((size_t)n * 32);
        assert_non_null(bytes[run]);
        assert_int_equal(pbf_cpu_world_read_particles(c, bytes[run], bytes[run] + 4 * (size_t)n, NULL, n), n);
        pbf_cpu_world_destroy(c);
        pbf_world_destroy(g);
    }
    print_message("after %d steps: GPU hash %016llx / %016llx, CPU hash %016llx / %016llx\n", steps,
                  (unsigned long long)gpu_hash[0], (unsigned long long)gpu_hash[1], (unsigned long long)cpu_hash[0],
                  (unsigned long long)cpu_hash[1]);
    assert_true(gpu_hash[0] == gpu_hash[1]);
    assert_true(cpu_hash[0] == cpu_hash[1]);
    assert_memory_equal(bytes[0], bytes[1], (size_t)n * 32);
    free(bytes[0]);
    free(bytes[1]);
}

// ---- 5. parameter checks name the field, the value and the range -------------------------

static void assert_mentions(const char *message, const char *const *needles)
{
    for (; *needles; needles++)
        if (!strstr(message, *needles)) fail_msg("message \"%s\" does not mention \"%s\"", message, *needles);
}

static void bad_parameters_are_rejected_naming_field_value_and_range(void **state)
{
    fixture *f = *state;
    typedef struct bad_case {
        const char *what;
        pbf_params params;
        const char *needles[5];
    } bad_case;
    bad_case cases[4];
    for (int i = 0; i < 4; i++) cases[i].params = pbf_default_params();
    cases[0] = (bad_case){ "negative particle_radius", cases[0].params,
                           { "pbf_params.particle_radius", "(0.0005, 1] m", "got -0.01", NULL } };
    cases[0].params.particle_radius = -0.01f;
    cases[1] = (bad_case){ "kernel_radius equal to the spacing", cases[1].params,
                           { "pbf_params.kernel_radius", "(0.025, 0.125] m", "got 0.025", NULL } };
    cases[1].params.kernel_radius = 2.0f * cases[1].params.particle_radius;
    cases[2] = (bad_case){ "0 iterations", cases[2].params,
                           { "pbf_params.iterations", "[1, 100]", "got 0", NULL } };
    cases[2].params.iterations = 0;
    cases[3] = (bad_case){ "NaN gravity", cases[3].params,
                           { "pbf_params.gravity[1]", "finite", "[-1000, 1000] m/s^2", "got nan", NULL } };
    cases[3].params.gravity[1] = NAN;
    const float dmin[3] = { 0, 0, 0 }, dmax[3] = { 1, 1, 1 };
    for (int i = 0; i < 4; i++) {
        char err[512] = "untouched";
        assert_null(pbf_cpu_world_create(&cases[i].params, 100, dmin, dmax, err, sizeof err));
        print_message("%s: %s\n", cases[i].what, err);
        assert_mentions(err, cases[i].needles);

        pbf_world_def def = pbf_default_world_def();
        def.params = cases[i].params;
        def.shader_dir = f->shader_dir;
        char gerr[512] = "untouched";
        assert_null(pbf_world_create(&def, gerr, sizeof gerr));
        assert_mentions(gerr, cases[i].needles);

        // A running world refuses them too, and keeps its parameters.
        pbf_params good = pbf_default_params();
        pbf_cpu_world *w = pbf_cpu_world_create(&good, 100, dmin, dmax, err, sizeof err);
        assert_non_null(w);
        assert_int_equal(pbf_cpu_world_set_params(w, &cases[i].params), PBF_ERR_INVALID_ARG);
        assert_mentions(pbf_cpu_world_last_error(w), cases[i].needles);
        assert_memory_equal(pbf_cpu_world_params(w), &good, sizeof good);
        pbf_cpu_world_destroy(w);
    }

    // A block of 10^3 particles into a world of capacity 100: PBF_ERR_CAPACITY, nothing added.
    pbf_block_def block = pbf_default_block_def();
    block.max[0] = block.max[1] = block.max[2] = 0.25f;
    static const char *const capacity_needles[] = { "1000 particles", "capacity 100", NULL };
    pbf_params good = pbf_default_params();
    char err[512];
    pbf_cpu_world *c = pbf_cpu_world_create(&good, 100, dmin, dmax, err, sizeof err);
    assert_non_null(c);
    uint32_t added = 7;
    assert_int_equal(pbf_cpu_world_add_block(c, &block, &added), PBF_ERR_CAPACITY);
    assert_int_equal(added, 0);
    assert_int_equal(pbf_cpu_world_particle_count(c), 0);
    print_message("block over capacity: %s\n", pbf_cpu_world_last_error(c));
    assert_mentions(pbf_cpu_world_last_error(c), capacity_needles);
    pbf_cpu_world_destroy(c);

    pbf_world_def def = pbf_default_world_def();
    def.capacity = 100;
    def.shader_dir = f->shader_dir;
    pbf_world *g = pbf_world_create(&def, err, sizeof err);
    if (!g) fail_msg("pbf_world_create: %s", err);
    added = 7;
    assert_int_equal(pbf_world_add_block(g, &block, &added), PBF_ERR_CAPACITY);
    assert_int_equal(added, 0);
    assert_int_equal(pbf_world_particle_count(g), 0);
    assert_mentions(pbf_world_last_error(g), capacity_needles);
    pbf_world_destroy(g);
}

/// Collider definitions are checked alike on both sides, naming the field, the rule and
/// the value; the CPU's pose and report calls check the index.
static void bad_colliders_are_rejected_naming_the_field_on_cpu_and_gpu(void **state)
{
    fixture *f = *state;
    scene s = dam_break();
    pbf_world *g = gpu_world(f, &s);
    pbf_cpu_world *c = cpu_world(&s);
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
        assert_mentions(pbf_world_last_error(g), needles[k]);
        assert_mentions(pbf_cpu_world_last_error(c), needles[k]);
    }
    const float p[3] = { 0.1f, 0.1f, 0.1f }, q[4] = { 0.0f, 0.0f, 0.0f, 1.0f };
    assert_int_equal(pbf_cpu_world_set_collider_pose(c, 0, p, q, NULL), PBF_ERR_STALE_ID);
    static const char *const index_needles[] = { "index", "got 0", NULL };
    assert_mentions(pbf_cpu_world_last_error(c), index_needles);
    pbf_collider_report rep;
    assert_int_equal(pbf_cpu_world_collider_report(c, 0, &rep), PBF_ERR_STALE_ID);
    pbf_cpu_world_destroy(c);
    pbf_world_destroy(g);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(kernels_are_normalised_and_boundary_closed_forms_match_integrals),
    cmocka_unit_test(gpu_dam_break_matches_cpu_reference),
    cmocka_unit_test(gpu_dam_break_matches_cpu_reference_with_scorr_damping_and_sor),
    cmocka_unit_test(gpu_matches_cpu_reference_around_colliders),
    cmocka_unit_test(gpu_matches_cpu_reference_around_hulls_grids_and_planes),
    cmocka_unit_test(gpu_matches_cpu_reference_around_moving_colliders),
    cmocka_unit_test(bad_colliders_are_rejected_naming_the_field_on_cpu_and_gpu),
    cmocka_unit_test(rigid_rotation_has_vorticity_twice_the_angular_velocity),
    cmocka_unit_test(vorticity_confinement_adds_energy_to_a_swirl_on_cpu_and_gpu),
    cmocka_unit_test(same_scene_gives_identical_state_twice_on_gpu_and_on_cpu),
    cmocka_unit_test(bad_parameters_are_rejected_naming_field_value_and_range),
};

int main(void) { return cmocka_run_group_tests(tests, support_gpu_setup, support_gpu_teardown); }
