// The solver against its specification: kernel and boundary integrals, the dam break on
// the GPU against the CPU reference (fluid/pbf_cpu) step by step, the sign of the curl and
// of vorticity confinement, determinism, and parameter checks that name the field. The
// same around colliders: test_solver_colliders.c; stage by stage: test_mirror.c.
//
// Scenes are small (about 1000 particles, tests/support.c) so the whole program stays well
// under a minute on llvmpipe with two cores.
#include "tests/support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fluid/pbf.h"
#include "fluid/pbf_cpu.h"
#include "fluid/pbf_uniforms.h"

#define PI 3.14159265358979323846

// ---- fixture: one headless context for the GPU tests, the scenes of tests/support.h ------

typedef support_gpu fixture;

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

/// Integral of f(r, z) over a ball of radius R whose surface is at distance d along z
/// (centre at z = R + d), by the midpoint rule on a (z, rho) grid of n x n cells inside the
/// kernel's reach: independent of the cap-area derivation pbf_curved_boundary uses.
static double ball_integral(double (*f)(double r, double z, double h, double c), double d, double R, double h,
                            double c, int n)
{
    double dz = (h - d) / n, drho = h / n, sum = 0.0, D = R + d;
    for (int a = 0; a < n; a++) {
        double z = d + (a + 0.5) * dz;
        for (int b = 0; b < n; b++) {
            double rho = (b + 0.5) * drho;
            double r = sqrt(z * z + rho * rho);
            if (r < h && (z - D) * (z - D) + rho * rho < R * R) sum += f(r, z, h, c) * 2.0 * PI * rho;
        }
    }
    return sum * dz * drho;
}

/// W_spiky = c (h - r)^3 (c = -spiky_grad / 3), the density kernel.
static double spiky_at(double r, double z, double h, double c)
{
    (void)z;
    return r < h ? c * (h - r) * (h - r) * (h - r) : 0.0;
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
        double v_num = half_space_integral(spiky_at, d, h, -k.spiky_grad / 3.0, 400);
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

    // A ball's share (spheres, capsules) against the integral over the ball; a large ball
    // is the plane's. At R = h a half-space overstates the share by half at d = h/4.
    const double radii[] = { 0.4, 1.0, 3.0 };
    for (size_t a = 0; a < sizeof radii / sizeof radii[0]; a++) {
        for (size_t i = 0; i < 4; i++) {
            double d = fractions[i] * h, R = radii[a] * h;
            float G;
            double v = pbf_cpu_curved_boundary((float)d, (float)h, (float)R, &G);
            double v_num = ball_integral(spiky_at, d, R, h, -k.spiky_grad / 3.0, 800);
            double g_num = ball_integral(spiky_grad_z, d, R, h, -k.spiky_grad, 800);
            print_message("ball R = %.1f h, d = %.2f h: V %.5f (integral %.5f), G h %.5f (integral %.5f)\n", radii[a],
                          fractions[i], v, v_num, G * h, g_num * h);
            assert_true(fabs(v - v_num) < 2e-3);
            assert_true(fabs(G - g_num) * h < 4e-3);
        }
    }
    float G_far, G_plane = pbf_cpu_boundary_gradient(0.25f * (float)h, (float)h);
    double v_far = pbf_cpu_curved_boundary(0.25f * (float)h, (float)h, 1e5f * (float)h, &G_far);
    assert_true(fabs(v_far - pbf_cpu_boundary_volume(0.25f * (float)h, (float)h)) < 1e-6);
    assert_true(fabsf(G_far - G_plane) * (float)h < 1e-5f);
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
    support_scene s = support_dam_break();
    s.params = *params;
    pbf_world *g = support_gpu_world(f, &s);
    pbf_cpu_world *c = support_cpu_world(&s);
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
        double t0 = support_seconds();
        assert_int_equal(pbf_world_step(g, dt), PBF_OK);
        assert_int_equal(pbf_world_read_particles(g, gp, gv, NULL, n), n);
        // Poll every step: the world keeps only its last 8 records.
        assert_int_equal(pbf_world_poll_stats(g, &gs[k], 1, true), 1);
        assert_int_equal(gs[k].step, (uint64_t)k);
        double t1 = support_seconds();
        assert_int_equal(pbf_cpu_world_step(c, dt), PBF_OK);
        cs[k] = pbf_cpu_world_density_stats(c);
        assert_int_equal(pbf_cpu_world_read_particles(c, cp, cv, NULL, n), n);
        double t2 = support_seconds();
        t_gpu += t1 - t0;
        t_cpu += t2 - t1;
        dev[k] = support_max_deviation(gp, cp, n);
        vdev[k] = support_max_deviation(gv, cv, n);
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
static void gpu_dam_break_matches_cpu_reference_with_scorr_damping_sor_and_friction(void **state)
{
    pbf_params p = pbf_default_params();
    p.scorr_k = 0.1f; // the paper's k (s_corr is scaled to a constraint violation of k)
    p.damping = 0.5f;
    p.sor = 1.2f;
    p.iterations = 4;
    p.substeps = 1;
    p.kernel_radius = 0.06f;
    p.wall_friction = 0.05f; // the container's friction in the velocity pass, on both sides
    // GLSL pow (exp2 of log2 on llvmpipe) and powf differ by ulps, and a real s_corr
    // (k = 0.1) feeds them back: measured 1.3e-3 spacing after 10 steps, so this case gets
    // 5e-3 over the ten steps (still far below the slips listed above, e.g. 4e-2).
    compare_dam_break(*state, &p, DEV_STEP1, 5e-3);
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
/// volume V = m / rho = spacing^3 (the velocity pass stores the physical volume, and the
/// lattice is at rest density). The continuous integrals make it 1; on the lattice at
/// h = 2 spacings it is 0.956.
static double lattice_curl_factor(double spacing, double h)
{
    int n = (int)ceil(h / spacing);
    double sum_g = 0.0;
    for (int z = -n; z <= n; z++)
        for (int y = -n; y <= n; y++)
            for (int x = -n; x <= n; x++) {
                double r = spacing * sqrt((double)(x * x + y * y + z * z));
                if (r > 0.0 && r < h) sum_g += 45.0 / (PI * pow(h, 6)) * (h - r) * (h - r) * r;
            }
    return sum_g * spacing * spacing * spacing / 3.0;
}

static void rigid_rotation_has_vorticity_twice_the_angular_velocity(void **state)
{
    (void)state;
    // v = Omega x (x - c) on a 12^3 lattice; curl v = 2 Omega. The corrected gradient
    // (corrected_curl, pbf_kernels.h) is exact for a linear field in any neighbourhood its
    // regularisation d leaves alone: in a full one the plain sum's lattice factor kappa becomes
    // (1 + d) kappa / (kappa + d); at the block's faces, edges and corners, where the plain sum
    // reads a half to a sixth of the interior's, within a few per cent (the corners' least).
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
    const double d = PBF_CURL_REGULARISATION;
    double full = (1.0 + d) * kappa / (kappa + d);
    double worst = 0.0, along = 0.0, cosine = 1.0, skin_worst = 0.0, face_worst = 0.0;
    int counted = 0;
    const double two = 2.0 * sqrt(omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]);
    for (int z = 0; z < N; z++)
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                const float *o = curl + 4 * (x + N * (y + N * z));
                bool inside = x >= EDGE && y >= EDGE && z >= EDGE && x < N - EDGE && y < N - EDGE && z < N - EDGE;
                int outer = (x == 0 || x == N - 1) + (y == 0 || y == N - 1) + (z == 0 || z == N - 1);
                double e2 = 0.0, f2 = 0.0, dotp = 0.0, o2 = 0.0;
                for (int k = 0; k < 3; k++) {
                    double expect = full * 2.0 * omega[k];
                    e2 += (o[k] - expect) * (o[k] - expect);
                    f2 += (o[k] - 2.0 * omega[k]) * (o[k] - 2.0 * omega[k]);
                    dotp += o[k] * 2.0 * omega[k];
                    o2 += (double)o[k] * o[k];
                }
                skin_worst = fmax(skin_worst, sqrt(f2) / two);
                if (outer <= 1) face_worst = fmax(face_worst, sqrt(f2) / two);
                if (!inside) continue;
                worst = fmax(worst, sqrt(e2) / (full * two));
                cosine = fmin(cosine, dotp / (two * sqrt(o2)));
                along += dotp / (two * two);
                counted++;
            }
    along /= counted;
    print_message("interior curl over %d particles: omega . 2 Omega / |2 Omega|^2 = %.5f on average (plain sum's "
                  "lattice factor kappa %.5f, corrected %.5f), worst |omega - 2 full Omega| / |2 full Omega| = %.2e, "
                  "least cosine to Omega %.6f; everywhere |omega - 2 Omega| / |2 Omega| at most %.4f (on the faces "
                  "%.4f)\n", counted, along, kappa, full, worst, cosine, skin_worst, face_worst);
    // The sign and direction: omega is along +Omega (a flipped curl gives -1).
    assert_true(cosine > 0.9999);
    // The size: 2 Omega up to the regularisation's factor, to float precision.
    assert_true(fabs(kappa - 1.0) < 0.06);
    assert_true(fabs(full - 1.0) < 0.003);
    assert_true(worst < 1e-4);
    assert_true(fabs(along - full) < 1e-4);
    // The skin: the plain sum reads 0.5 kappa on a face; the corrected one within 3 %, and
    // within 15 % at the cube's edges and corners.
    assert_true(face_worst < 0.03);
    assert_true(skin_worst < 0.15);
    pbf_cpu_world_destroy(w);
}

/// A Gaussian vortex along z in a 16 x 16 x 8 block, zero gravity, no walls:
/// v = a (-(y - cy), x - cx, 0) exp(-rho^2 / sigma^2), a = 5 1/s, sigma = 8 cm. Its
/// vorticity peaks on the axis, so N = grad|omega| / |grad|omega|| points inwards and
/// confinement eps N x omega points along the flow: it must add kinetic energy.
static support_scene swirl(float confinement, float *pos, float *vel)
{
    enum { NX = 16, NZ = 8 };
    support_scene s;
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
        support_scene s = swirl(with ? eps : 0.0f, pos, vel);
        mass = pbf_derive_constants(&s.params).mass;
        pbf_cpu_world *c = support_cpu_world(&s);
        pbf_world *g = support_gpu_world(f, &s);
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
    support_scene s = support_dam_break();
    uint64_t gpu_hash[2], cpu_hash[2];
    uint32_t n = 0;
    float *bytes[2] = { NULL, NULL };
    for (int run = 0; run < 2; run++) {
        pbf_world *g = support_gpu_world(f, &s);
        pbf_cpu_world *c = support_cpu_world(&s);
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

// ---- relaxation schedule: every lattice mode damped, the low modes stiffer ------------------

// The Jacobi sweep's iteration matrix A D^-1 on a filled cubic lattice, the kernel `h`
// spacings wide: mu(q) = |sum_j grad W(r_j) sin(q . r_j)|^2 / sum_j |grad W(r_j)|^2 (spiky
// gradient; the constant factors cancel), largest over a grid of the Brillouin zone.
static double lattice_mu_max(double h)
{
    double best = 0.0;
    const int steps = 24, n = (int)ceil(h);
    for (int a = 0; a <= steps; a++)
        for (int b = 0; b <= steps; b++)
            for (int c = 0; c <= steps; c++) {
                double q[3] = { PI * a / steps, PI * b / steps, PI * c / steps };
                double g[3] = { 0, 0, 0 }, norm = 0.0;
                for (int x = -n; x <= n; x++)
                    for (int y = -n; y <= n; y++)
                        for (int z = -n; z <= n; z++) {
                            double r = sqrt((double)(x * x + y * y + z * z));
                            if (r == 0.0 || r >= h) continue;
                            double mag = (h - r) * (h - r) / r; // |grad W| / r, spiky
                            double d[3] = { x * mag, y * mag, z * mag };
                            double sn = sin(q[0] * x + q[1] * y + q[2] * z);
                            for (int k = 0; k < 3; k++) g[k] += d[k] * sn;
                            norm += d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                        }
                double mu = (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) / norm;
                if (mu > best) best = mu;
            }
    return best;
}

// The schedule of p->iterations factors at the constants k, on a lattice whose largest
// eigenvalue is mu_max: every mode damped up to it, the even counts up to the deep water's
// PBF_JACOBI_MU_DEEP as far beyond it as the default kernel's.
static void check_schedule(const pbf_params *p, const pbf_constants *k, double mu_max, double scale, bool verbose)
{
    int n = p->iterations;
    double stretch = mu_max / PBF_JACOBI_MU_MAX; // this kernel's spectrum over the default's
    // A mode's error after the n iterations: prod (1 - w_i mu). A PBD step keeps it stable
    // only in (-1/3, 1): check it with a margin up to the lattice's largest mu, and inside
    // the bounds over 7 % more (disordered neighbourhoods).
    double lo = 1.0, hi = -1.0, edge = -1.0, sum = 0.0;
    for (int i = 0; i < n; i++) sum += pbf_relaxation(p, k, i);
    for (int m = 1; m <= 3210; m++) {
        double mu = mu_max * m / 3000.0, e = 1.0;
        for (int i = 0; i < n; i++) e *= 1.0 - pbf_relaxation(p, k, i) * mu;
        if (e < lo) lo = e;
        if (m <= 3000 && mu >= 0.5 * stretch && e > hi) hi = e;
        if (m > 3000 && e > edge) edge = e;
    }
    if (verbose)
        print_message("%3d iterations: sum of factors %.3f; error factor over mu in (0, 1.07 mu_max] >= %.3f, "
                      "at most %.3f over [0.5, 1] mu_max, %.3f beyond\n", n, sum, lo, hi, edge);
    assert_true(lo > -0.3 && hi < 0.9 && edge < 1.0);
    // An even count still damps up to PBF_JACOBI_MU_DEEP (compressed, disordered water
    // at depth; the constant 0.6 it replaced is undamped from 3.33), by the same sum.
    if (n % 2 == 0) {
        double deep = 0.0, top = 0.98 * PBF_JACOBI_MU_DEEP * stretch;
        for (int m = 1; m <= 100; m++) {
            double mu = mu_max + (top - mu_max) * m / 100.0, e = 1.0;
            for (int i = 0; i < n; i++) e *= 1.0 - pbf_relaxation(p, k, i) * mu;
            if (fabs(e) > deep) deep = fabs(e);
        }
        if (verbose) print_message("%3d iterations: error factor up to 0.98 mu_deep at most %.3f\n", n, deep);
        assert_true(deep < 0.95);
        assert_true(fabs(sum - 0.6 * n * scale) < 1e-5 * n);
    }
    // The low modes (mu -> 0) lose sum * mu per step: an odd count is stiffer than at a
    // constant 0.6 (which leaves three iterations at the edge and one unstable).
    if (n % 2 == 1 && n >= 3) assert_true(sum > (0.6 * n + 0.5) * scale);
}

static void relaxation_schedule_damps_every_lattice_mode_and_stiffens_the_low_ones(void **state)
{
    (void)state;
    double mu_max = lattice_mu_max(2.0);
    print_message("lattice: largest eigenvalue of A D^-1 %.3f (PBF_JACOBI_MU_MAX %.2f)\n", mu_max, PBF_JACOBI_MU_MAX);
    assert_true(mu_max > PBF_JACOBI_MU_MAX - 0.1 && mu_max <= PBF_JACOBI_MU_MAX + 0.02);
    pbf_params p = pbf_default_params();
    assert_true(p.sor == 0.0f); // the schedule is the default
    pbf_constants k = pbf_derive_constants(&p);
    for (int n = 1; n <= 100; n++) {
        p.iterations = n;
        // The default kernel's factors are not scaled.
        for (int i = 0; i < n; i++) assert_true(pbf_relaxation(&p, &k, i) == pbf_relaxation(&p, NULL, i));
        check_schedule(&p, &k, PBF_JACOBI_MU_MAX, 1.0, n <= 4 || n == 100);
    }
    // A positive sor is a constant factor on every iteration.
    p.sor = 1.2f;
    p.iterations = 3;
    for (int i = 0; i < 3; i++) assert_true(pbf_relaxation(&p, &k, i) == 1.2f);
}

// A wider kernel has more neighbours and larger eigenvalues (6.7 at 3 spacings): the default
// kernel's even pair (0.845, 0.355) multiplies such a mode by 6.5 a step, and a droplet under
// cohesion, whose constraint is loaded everywhere, boiled. The factors are scaled so each
// kernel's spectrum is damped as the default's is.
static void a_wide_kernel_scales_the_relaxation_to_its_spectrum(void **state)
{
    (void)state;
    const double widths[] = { 1.5, 2.05, 2.25, 2.5, 3.0, 4.0, 5.0 };
    for (size_t w = 0; w < sizeof widths / sizeof widths[0]; w++) {
        double grid = lattice_mu_max(widths[w]), found = pbf_jacobi_mu_max(widths[w]);
        // The library refines the grid's best: at least it, and not far above.
        print_message("kernel %.2f spacings: mu_max %.3f (grid %.3f)\n", widths[w], found, grid);
        assert_true(found >= grid - 1e-9 && found <= grid * 1.02);
        pbf_params p = pbf_default_params();
        p.kernel_radius = (float)(widths[w] * 2.0 * p.particle_radius);
        pbf_constants k = pbf_derive_constants(&p);
        assert_true(fabs(k.jacobi_mu_max - found) < 1e-3 * found);
        double scale = found > PBF_JACOBI_MU_LATTICE * 1.001 ? PBF_JACOBI_MU_LATTICE / found : 1.0;
        for (int n = 1; n <= 12; n++) {
            p.iterations = n;
            check_schedule(&p, &k, fmax(found, PBF_JACOBI_MU_MAX), scale, false);
        }
    }
    assert_true(fabs(pbf_jacobi_mu_max(2.0) - PBF_JACOBI_MU_LATTICE) < 1e-4);
    // The widest kernel allowed, at radii whose float ratio rounds either way.
    const float radii[] = { 0.0125f, 0.007f, 0.0333f, 0.1f };
    int widest = 0;
    for (size_t i = 0; i < sizeof radii / sizeof radii[0]; i++) {
        pbf_params p = pbf_default_params();
        p.particle_radius = radii[i];
        p.kernel_radius = 10.0f * radii[i];
        if (pbf_params_validate(&p, NULL, 0) != PBF_OK) continue;
        assert_true(pbf_derive_constants(&p).jacobi_mu_max > 27.0f);
        widest++;
    }
    assert_int_equal(widest, 4);
    assert_true(pbf_jacobi_mu_max(3.0) > 6.5); // why the scaling is there
}

// ---- 5. parameter checks name the field, the value and the range -------------------------

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
        support_assert_mentions(err, cases[i].needles);

        pbf_world_def def = pbf_default_world_def();
        def.params = cases[i].params;
        def.shader_dir = f->shader_dir;
        char gerr[512] = "untouched";
        assert_null(pbf_world_create(&def, gerr, sizeof gerr));
        support_assert_mentions(gerr, cases[i].needles);

        // A running world refuses them too, and keeps its parameters.
        pbf_params good = pbf_default_params();
        pbf_cpu_world *w = pbf_cpu_world_create(&good, 100, dmin, dmax, err, sizeof err);
        assert_non_null(w);
        assert_int_equal(pbf_cpu_world_set_params(w, &cases[i].params), PBF_ERR_INVALID_ARG);
        support_assert_mentions(pbf_cpu_world_last_error(w), cases[i].needles);
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
    support_assert_mentions(pbf_cpu_world_last_error(c), capacity_needles);
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
    support_assert_mentions(pbf_world_last_error(g), capacity_needles);
    pbf_world_destroy(g);
}

// ---- 5. the compression guard ----------------------------------------------------------

/// pbf_guard_compression, the rule both worlds share: over the target it asks at once for
/// the substeps that bring the measured step to half of it (compression ~ 1/substeps^2),
/// counted from what that step took, so a record that predates the raise asks for nothing
/// more; a worst that rose since the step before (at the same substeps) is carried on
/// at that pace over the two steps it sees late; under a quarter of the target for PBF_GUARD_QUIET_STEPS steps in a row
/// it takes one substep fewer, down to `substeps`, and anything else holds; past
/// max_substeps it stops there and says so; no record or a NaN leave no mark, and off
/// means `substeps`.
static void compression_guard_raises_at_once_and_eases_back_slowly(void **state)
{
    (void)state;
    pbf_params p = pbf_default_params(); // 4 substeps, at most 32
    p.guard_compression = 0.1f;          // worst +10 %, mean 1 %
    bool capped = false;
    pbf_guard_state g = { 0, 0 };
    const pbf_guard_seen worst4 = { 0.40f, 0.005f, 4 }, mean4 = { 0.02f, 0.04f, 4 };
    assert_int_equal(pbf_guard_compression(&p, &g, &worst4, NULL, &capped), 12); // ceil(4 sqrt(8)) = ceil(11.3)
    g = (pbf_guard_state){ 0, 0 };
    assert_int_equal(pbf_guard_compression(&p, &g, &mean4, NULL, &capped), 12); // the mean 4x its tenth
    assert_int_equal(pbf_guard_compression(&p, &g, &worst4, NULL, &capped), 12); // the step before the raise
    assert_false(capped);

    // A worst that rose 3 points a step, seen at 7 %: 13 % two steps on, ceil(4 sqrt(2.6)).
    const pbf_guard_seen rising = { 0.07f, 0.002f, 4 }, earlier = { 0.04f, 0.002f, 4 },
                         higher = { 0.09f, 0.002f, 4 }, other = { 0.04f, 0.002f, 8 };
    g = (pbf_guard_state){ 0, 0 };
    assert_int_equal(pbf_guard_compression(&p, &g, &rising, NULL, NULL), 4);      // alone: 0.7 of the target
    assert_int_equal(pbf_guard_compression(&p, &g, &rising, &earlier, NULL), 7);
    g = (pbf_guard_state){ 0, 0 };
    assert_int_equal(pbf_guard_compression(&p, &g, &rising, &higher, NULL), 4);   // falling: as measured
    assert_int_equal(pbf_guard_compression(&p, &g, &rising, &other, NULL), 4);    // other substeps: no pace

    const pbf_guard_seen held = { 0.05f, 0.003f, 12 }, quiet = { 0.01f, 0.001f, 12 };
    g = (pbf_guard_state){ 12, 0 };
    for (int k = 1; k < PBF_GUARD_QUIET_STEPS; k++) assert_int_equal(pbf_guard_compression(&p, &g, &quiet, NULL, NULL), 12);
    assert_int_equal(pbf_guard_compression(&p, &g, &held, NULL, NULL), 12); // half the target: the quiet starts over
    for (int k = 1; k < PBF_GUARD_QUIET_STEPS; k++) assert_int_equal(pbf_guard_compression(&p, &g, &quiet, NULL, NULL), 12);
    assert_int_equal(pbf_guard_compression(&p, &g, &quiet, NULL, NULL), 11); // a quiet second: one fewer
    g = (pbf_guard_state){ 4, PBF_GUARD_QUIET_STEPS };
    assert_int_equal(pbf_guard_compression(&p, &g, &quiet, NULL, NULL), 4);  // not under `substeps`

    const pbf_guard_seen crushed = { 10.0f, 0.5f, 4 };
    g = (pbf_guard_state){ 4, 0 };
    assert_int_equal(pbf_guard_compression(&p, &g, &crushed, NULL, &capped), 32);
    assert_true(capped);
    const pbf_guard_seen nan = { NAN, 0.5f, 4 };
    g = (pbf_guard_state){ 7, 0 };
    assert_int_equal(pbf_guard_compression(&p, &g, &nan, NULL, NULL), 7);
    assert_int_equal(pbf_guard_compression(&p, &g, NULL, NULL, NULL), 7);
    g = (pbf_guard_state){ 0, 0 };
    assert_int_equal(pbf_guard_compression(&p, &g, NULL, NULL, NULL), 4);
    p.guard_compression = 0.0f;
    g = (pbf_guard_state){ 12, 3 };
    assert_int_equal(pbf_guard_compression(&p, &g, &worst4, NULL, NULL), 4); // turned off: `substeps`
}

/// A column of water 0.4 m deep at 2 cm particles, one iteration and one substep of a
/// 1/60 s step: with the compression guard off the water sinks into itself (the mean
/// compression grows to several per cent, over and over as the column bounces); at
/// guard_compression 0.1 the steps take more substeps and it stays mostly under the 1 %
/// it aims at. Twice the same state (the
/// guard reads step n - 2 only), and the CPU reference takes the same substeps.
typedef struct column_run {
    double mean[40];
    int substeps[40];
    uint64_t hash;
} column_run;

static support_scene column_scene(float guard)
{
    support_scene s = support_dam_break(); // its container and block, resized below
    s.params.particle_radius = 0.01f;
    s.params.kernel_radius = 0.04f;
    s.params.iterations = 1;
    s.params.substeps = 1;
    s.params.guard_compression = guard;
    s.capacity = 1000;
    const float tank[3] = { 0.1f, 0.6f, 0.1f }, water[3] = { 0.1f, 0.4f, 0.1f };
    for (int k = 0; k < 3; k++) {
        s.domain_min[k] = -0.02f, s.domain_max[k] = tank[k] + 0.02f;
        s.box_min[k] = 0.0f, s.box_max[k] = tank[k];
        s.block.min[k] = 0.0f, s.block.max[k] = water[k];
    }
    return s;
}

static void run_column(const support_gpu *f, float guard, column_run *out)
{
    support_scene s = column_scene(guard);
    pbf_world *g = support_gpu_world(f, &s);
    assert_int_equal(pbf_world_particle_count(g), 500);
    for (int k = 0; k < 40; k++) {
        assert_int_equal(pbf_world_step(g, 1.0f / 60.0f), PBF_OK);
        pbf_step_stats st;
        assert_int_equal(pbf_world_poll_stats(g, &st, 1, true), 1);
        assert_int_equal(st.step, (uint64_t)k);
        out->mean[k] = st.density_error_avg;
        out->substeps[k] = st.substeps;
    }
    out->hash = pbf_world_state_hash(g);
    pbf_world_destroy(g);
}

static void compression_guard_keeps_a_column_from_sinking_into_itself(void **state)
{
    const support_gpu *f = *state;
    static column_run off, on, again;
    run_column(f, 0.0f, &off);
    run_column(f, 0.1f, &on);
    run_column(f, 0.1f, &again);
    assert_true(on.hash == again.hash);
    double off_avg = 0.0, on_avg = 0.0, off_max = 0.0, on_max = 0.0;
    int off_most = 0, on_most = 0;
    for (int k = 0; k < 40; k++) {
        off_most = off.substeps[k] > off_most ? off.substeps[k] : off_most;
        on_most = on.substeps[k] > on_most ? on.substeps[k] : on_most;
        assert_int_equal(on.substeps[k], again.substeps[k]);
        if (k < 15) continue; // after the first collapse, which the guard sees two steps late
        off_avg += off.mean[k] / 25.0;
        on_avg += on.mean[k] / 25.0;
        off_max = fmax(off_max, off.mean[k]);
        on_max = fmax(on_max, on.mean[k]);
    }
    print_message("mean compression over steps 15-39: guard off %.2f %% (at worst %.2f %%, most substeps %d), "
                  "guard 0.1 %.2f %% (at worst %.2f %%, most substeps %d)\n", 100 * off_avg, 100 * off_max, off_most,
                  100 * on_avg, 100 * on_max, on_most);
    // Measured: off 5.3 % (19 % at worst), on 0.7 % (7 % at worst: the column bounces back
    // and squeezes itself fourfold per step, which a guard that sees step n - 2 lets through
    // once before it answers).
    assert_true(on_most > off_most);
    assert_true(on_avg < 0.25 * off_avg);
    assert_true(on_max < 0.5 * off_max);

    // The CPU reference applies the same rule to its own measurements: the same substeps
    // through the collapse and the guard's first raise.
    support_scene s = column_scene(0.1f);
    pbf_cpu_world *c = support_cpu_world(&s);
    for (int k = 0; k < 10; k++) {
        assert_int_equal(pbf_cpu_world_step(c, 1.0f / 60.0f), PBF_OK);
        assert_int_equal(pbf_cpu_world_last_substeps(c), on.substeps[k]);
    }
    pbf_cpu_world_destroy(c);
}

static const struct CMUnitTest tests[] = {
    cmocka_unit_test(kernels_are_normalised_and_boundary_closed_forms_match_integrals),
    cmocka_unit_test(gpu_dam_break_matches_cpu_reference),
    cmocka_unit_test(gpu_dam_break_matches_cpu_reference_with_scorr_damping_sor_and_friction),
    cmocka_unit_test(rigid_rotation_has_vorticity_twice_the_angular_velocity),
    cmocka_unit_test(vorticity_confinement_adds_energy_to_a_swirl_on_cpu_and_gpu),
    cmocka_unit_test(same_scene_gives_identical_state_twice_on_gpu_and_on_cpu),
    cmocka_unit_test(relaxation_schedule_damps_every_lattice_mode_and_stiffens_the_low_ones),
    cmocka_unit_test(a_wide_kernel_scales_the_relaxation_to_its_spectrum),
    cmocka_unit_test(bad_parameters_are_rejected_naming_field_value_and_range),
    cmocka_unit_test(compression_guard_raises_at_once_and_eases_back_slowly),
    cmocka_unit_test(compression_guard_keeps_a_column_from_sinking_into_itself),
};

int main(void) { return cmocka_run_group_tests(tests, support_gpu_setup, support_gpu_teardown); }
