// Solver parameters: defaults, the seed preset, validation. See pbf.h for units/ranges.
#include "fluid/pbf.h"
#include "fluid/pbf_uniforms.h"

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

pbf_params pbf_default_params(void)
{
    pbf_params p;
    p.particle_radius = 0.0125f; // 2.5 cm spacing
    p.kernel_radius = 0.05f;     // h = 2 spacings: about 30 neighbours
    p.rest_density = 1000.0f;
    p.iterations = 2; // "small steps": more substeps beat more iterations (docs/solver.md)
    p.substeps = 4;
    p.relaxation = 0.01f;
    p.sor = 0.0f; // a factor per iteration (pbf_relaxation): at a constant 1 a tank at rest never settles
    p.scorr_k = 0.0f; // the unilateral constraint already prevents clustering
    p.scorr_n = 4.0f;
    p.scorr_dq = 0.2f;
    p.vorticity = 0.01f;
    p.viscosity = 0.01f;
    p.gravity[0] = 0.0f;
    p.gravity[1] = -9.81f;
    p.gravity[2] = 0.0f;
    p.damping = 0.0f;
    p.max_speed = 20.0f;
    p.surface_tension = 0.0f;
    p.cfl = 0.5f;
    p.max_substeps = 32;
    p.guard_compression = 0.0f; // off: a change of substeps moves the water (docs/solver.md)
    p.surface_fill = 0.0f;  // off: measured, not yet the default (docs/solver.md)
    p.level_sweeps = 0;     // off: measured, not yet the default (docs/solver.md)
    p.level_cell = 1.0f;
    p.level_tolerance = 0.005f;
    p.wall_friction = 0.02f; // a rough wall: the dam-break front on Martin & Moyce's (docs/solver.md)
    return p;
}

pbf_params pbf_seed_params(void)
{
    pbf_params p = pbf_default_params();
    p.kernel_radius = 2.5f * 2.0f * p.particle_radius; // 2.5 spacings (see pbf.h)
    p.rest_density = 125.0f;
    p.iterations = 3;
    p.substeps = 1;
    p.vorticity = 0.008f;
    p.viscosity = 0.01f;
    // The seed had no relaxation factor (1); with the density and its gradient from one
    // kernel 1 overshoots (docs/solver.md, "Departures"), so the preset keeps the default.
    p.scorr_k = 0.1f;
    p.scorr_n = 4.0f;
    p.scorr_dq = 0.2f;
    p.cfl = 0.0f; // the seed had no guard; with more substeps its s_corr adds energy faster
    return p;
}

#define PBF_PI 3.14159265358979323846

static double spiky(double r, double h)
{
    return r < h ? 15.0 / (PBF_PI * pow(h, 6)) * (h - r) * (h - r) * (h - r) : 0.0;
}

static double spiky_grad_mag(double r, double h)
{
    if (r <= 0.0 || r >= h) return 0.0;
    return 45.0 / (PBF_PI * pow(h, 6)) * (h - r) * (h - r);
}

pbf_constants pbf_derive_constants(const pbf_params *p)
{
    pbf_constants c;
    memset(&c, 0, sizeof c);
    // Only a valid set has constants: the lattice sums below run over (h / 2r)^3 sites.
    if (pbf_params_validate(p, NULL, 0) != PBF_OK) return c;
    double h = p->kernel_radius;
    double s = 2.0 * p->particle_radius;
    // Sums over a cubic lattice of spacing s around a particle on a site (self included).
    int n = (int)ceil(h / s) + 1;
    double sw = 0.0, sg2 = 0.0, missing = 0.0;
    for (int z = -n; z <= n; z++)
        for (int y = -n; y <= n; y++)
            for (int x = -n; x <= n; x++) {
                double r = s * sqrt((double)(x * x + y * y + z * z));
                sw += spiky(r, h);
                if (z < 0) missing += spiky(r, h); // rows beyond a wall half a spacing below
                double g = spiky_grad_mag(r, h);
                sg2 += g * g;
            }
    c.spacing = (float)s;
    c.mass = (float)(p->rest_density * s * s * s);
    c.mass_density = (float)(p->rest_density / sw);
    double k = c.mass_density / p->rest_density;
    c.lattice_grad2 = (float)(k * k * sg2);
    c.epsilon = p->relaxation * c.lattice_grad2;
    c.poly6 = (float)(315.0 / (64.0 * PBF_PI * pow(h, 9)));
    c.spiky_grad = (float)(-45.0 / (PBF_PI * pow(h, 6)));
    double dq = p->scorr_dq * h;
    c.scorr_inv_wdq = (float)(1.0 / spiky(dq, h));
    c.scorr_scale = (float)(1.0 / c.lattice_grad2);
    // The continuous share of a half-space at d = s/2 (pbf_boundary_volume's closed form).
    double u = 0.5 * s / h;
    double v_half = 0.5 * pow(1.0 - u, 5) * (1.0 + 2.0 * u);
    c.boundary_scale = (float)((missing / sw) / v_half);
    c.jacobi_mu_max = (float)pbf_jacobi_mu_max(h / s);
    return c;
}

// mu(q) of a lattice neighbourhood: sites (spacing units) and their spiky gradients' shape
// (kappa - r)^2 / r times the site (the constant factors cancel in the ratio).
#define JACOBI_SITES 260 // half of r < 5 spacings (kernel_radius at most 10 particle radii): 257
typedef struct jacobi_sites {
    int count;
    double norm; // sum_j |grad W(r_j)|^2 over the half kept
    float site[JACOBI_SITES][3];
    float grad[JACOBI_SITES][3];
} jacobi_sites;

static double jacobi_mu(const jacobi_sites *js, const double q[3])
{
    double g[3] = { 0.0, 0.0, 0.0 };
    for (int j = 0; j < js->count; j++) {
        double sn = sin(q[0] * js->site[j][0] + q[1] * js->site[j][1] + q[2] * js->site[j][2]);
        g[0] += js->grad[j][0] * sn;
        g[1] += js->grad[j][1] * sn;
        g[2] += js->grad[j][2] * sn;
    }
    return 2.0 * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]) / js->norm; // (2g)^2 / (2 norm) over the half
}

double pbf_jacobi_mu_max(double spacings)
{
    if (!(spacings > 0.0) || spacings > 5.0 + 1e-4) return 0.0; // 10 r, with the floats' rounding
    // Every parameter change derives the constants again (18 ms at 5 spacings): remember the
    // last kernel asked on this thread.
    static _Thread_local double last_spacings = 0.0, last_mu = 0.0;
    if (spacings == last_spacings) return last_mu;
    jacobi_sites js; // 6 KiB
    js.count = 0;
    js.norm = 0.0;
    int n = (int)ceil(spacings);
    for (int z = -n; z <= n; z++)
        for (int y = -n; y <= n; y++)
            for (int x = -n; x <= n; x++) {
                double r = sqrt((double)(x * x + y * y + z * z));
                // Half the sites: -r gives the same term as r (sin and the gradient both flip).
                bool half = z > 0 || (z == 0 && (y > 0 || (y == 0 && x > 0)));
                if (!half || r >= spacings || js.count >= JACOBI_SITES) continue;
                double m = (spacings - r) * (spacings - r) / r;
                js.site[js.count][0] = (float)x, js.site[js.count][1] = (float)y, js.site[js.count][2] = (float)z;
                js.grad[js.count][0] = (float)(x * m), js.grad[js.count][1] = (float)(y * m);
                js.grad[js.count][2] = (float)(z * m);
                js.norm += (double)js.grad[js.count][0] * js.grad[js.count][0] +
                           (double)js.grad[js.count][1] * js.grad[js.count][1] +
                           (double)js.grad[js.count][2] * js.grad[js.count][2];
                js.count++;
            }
    if (js.count == 0) return 0.0;
    // The lattice is symmetric under the axes' permutations and signs: q in pi >= q0 >= q1
    // >= q2 >= 0 covers the zone. A grid of pi/12, then a pattern search from its best.
    const int steps = 12;
    double best = -1.0, at[3] = { 0.0, 0.0, 0.0 };
    for (int a = 0; a <= steps; a++)
        for (int b = 0; b <= a; b++)
            for (int c = 0; c <= b; c++) {
                double q[3] = { PBF_PI * a / steps, PBF_PI * b / steps, PBF_PI * c / steps };
                double mu = jacobi_mu(&js, q);
                if (mu > best) best = mu, at[0] = q[0], at[1] = q[1], at[2] = q[2];
            }
    for (double step = PBF_PI / steps; step > 1e-4;) {
        bool moved = false;
        for (int axis = 0; axis < 3; axis++)
            for (int sign = -1; sign <= 1; sign += 2) {
                double q[3] = { at[0], at[1], at[2] };
                q[axis] = fmin(PBF_PI, fmax(0.0, q[axis] + sign * step));
                double mu = jacobi_mu(&js, q);
                if (mu > best) best = mu, at[0] = q[0], at[1] = q[1], at[2] = q[2], moved = true;
            }
        if (!moved) step *= 0.5;
    }
    last_spacings = spacings, last_mu = best;
    return best;
}

// ---- the cohesion's tension on the rest lattice ---------------------------------------------
// Akinci's spline in units of the spacing (H the kernel in spacings): pulls beyond H/2.
static double akinci_spline(double r, double H)
{
    if (r <= 0.0 || r >= H) return 0.0;
    double a = (H - r) * (H - r) * (H - r) * r * r * r;
    return 2.0 * r > H ? a : 2.0 * a - pow(H, 6) / 64.0;
}

// The deepest layer below a face whose density the sums read: 3 depth + 2, 80 for the faces
// averaged below (indices up to 3) at 5 spacings.
#define COHESION_LAYERS 96
#define COHESION_SITES 528 // r < 5 spacings, the centre included: 515

double pbf_cohesion_face_stress(double spacings, const int face[3])
{
    double H = spacings;
    int n2 = face[0] * face[0] + face[1] * face[1] + face[2] * face[2];
    if (!(H > 0.0) || H > 5.0 + 1e-4 || n2 == 0) return 0.0;
    double len = sqrt((double)n2);
    int depth = (int)ceil(H * len); // |face . g| < depth for every site g of the neighbourhood
    if (3 * depth + 2 > COHESION_LAYERS) return 0.0;
    // The neighbourhood's sites g once: their height face . g over the face's layers, their
    // distance and Akinci's pull at it. rho[m]: the spiky sum of a particle m layers deep in
    // the half-space face . x <= 0 (its sites face . g <= m) over the bulk's.
    struct { int proj; double r, spline; } site[COHESION_SITES];
    int count = 0, n = (int)ceil(H);
    double rho[COHESION_LAYERS] = { 0.0 }, bulk = 0.0;
    for (int z = -n; z <= n; z++)
        for (int y = -n; y <= n; y++)
            for (int x = -n; x <= n; x++) {
                double r = sqrt((double)(x * x + y * y + z * z));
                if (r >= H || count >= COHESION_SITES) continue;
                int proj = face[0] * x + face[1] * y + face[2] * z;
                double w = (H - r) * (H - r) * (H - r);
                bulk += w;
                for (int m = proj < 0 ? 0 : proj; m < COHESION_LAYERS; m++) rho[m] += w;
                site[count].proj = proj, site[count].r = r, site[count].spline = akinci_spline(r, H);
                count++;
            }
    for (int m = 0; m < COHESION_LAYERS; m++) rho[m] /= bulk;
    // Kirkwood-Buff: sigma A = the sum over the surface's pairs of f(r) (r^2 - 3 z^2) / (2r),
    // z along the normal, f the pull K_ij S(r). A face's cell (area len) holds one particle
    // of each layer, which takes half of each of its pairs.
    // Deeper than 2 depth a particle and its neighbours have the bulk's density and its sum
    // vanishes by the lattice's symmetry.
    double sum = 0.0;
    for (int m = 0; m <= 2 * depth + 1; m++)
        for (int q = 0; q < count; q++) {
            int mj = m - site[q].proj; // the neighbour's depth
            double r = site[q].r, z = site[q].proj / len;
            if (r <= 0.0 || mj < 0) continue;
            sum += 0.5 * 2.0 / (rho[m] + rho[mj]) * site[q].spline * (r * r - 3.0 * z * z) / (2.0 * r);
        }
    return sum / len;
}

// (pi/8) int_0^H r^4 S(r) dr: the tension of a flat cut through a uniform continuum of
// particles one per cubic spacing, per unit k (pbf_cohesion_factor's closed form).
static double cohesion_continuum(double H)
{
    const double half = 0.5;
    double inner = pow(half, 8) / 8.0 - 3.0 * pow(half, 9) / 9.0 + 3.0 * pow(half, 10) / 10.0 - pow(half, 11) / 11.0 -
                   pow(half, 5) / (5.0 * 64.0);
    return PBF_PI / 8.0 * (1.0 / 1320.0 + inner) * pow(H, 11);
}

static int gcd(int a, int b)
{
    while (b) {
        int t = a % b;
        a = b;
        b = t;
    }
    return a;
}

// The faces whose stresses are averaged: 0 <= a <= b <= c <= 3, coprime (the lattice's
// symmetric wedge covers every orientation).
static int cohesion_faces(int faces[][3], int most)
{
    int count = 0;
    for (int c = 1; c <= 3; c++)
        for (int b = 0; b <= c; b++)
            for (int a = 0; a <= b; a++) {
                if (gcd(gcd(c, b), a) != 1 || count >= most) continue;
                faces[count][0] = a, faces[count][1] = b, faces[count][2] = c;
                count++;
            }
    return count;
}

double pbf_cohesion_lattice_ratio(double spacings)
{
    if (!(spacings > 0.0) || spacings > 5.0 + 1e-4) return 0.0;
    static _Thread_local double last_spacings = 0.0, last_ratio = 0.0;
    if (spacings == last_spacings) return last_ratio;
    double H = spacings < 2.0 ? 2.0 : spacings; // narrower: too few neighbours for a surface
    int faces[32][3];
    int count = cohesion_faces(faces, 32);
    double unit[32][3];
    for (int f = 0; f < count; f++) {
        double l = sqrt((double)(faces[f][0] * faces[f][0] + faces[f][1] * faces[f][1] + faces[f][2] * faces[f][2]));
        for (int a = 0; a < 3; a++) unit[f][a] = faces[f][a] / l;
    }
    // Each face's share of the sphere: the directions (uniform in cos theta and phi over an
    // octant, sorted into the wedge) nearest to it.
    double weight[32] = { 0.0 };
    const int grid = 48;
    for (int i = 0; i < grid; i++)
        for (int j = 0; j < grid; j++) {
            double u = (i + 0.5) / grid, phi = 0.5 * PBF_PI * (j + 0.5) / grid, w = sqrt(1.0 - u * u);
            double v[3] = { w * cos(phi), w * sin(phi), u };
            for (int a = 0; a < 2; a++) // sort ascending
                for (int b = 0; b < 2 - a; b++)
                    if (v[b] > v[b + 1]) { double t = v[b]; v[b] = v[b + 1]; v[b + 1] = t; }
            int best = 0;
            double near = -1.0;
            for (int f = 0; f < count; f++) {
                double d = v[0] * unit[f][0] + v[1] * unit[f][1] + v[2] * unit[f][2];
                if (d > near) near = d, best = f;
            }
            weight[best] += 1.0;
        }
    double sum = 0.0, total = 0.0;
    for (int f = 0; f < count; f++) {
        if (weight[f] <= 0.0) continue;
        sum += weight[f] * pbf_cohesion_face_stress(H, faces[f]);
        total += weight[f];
    }
    double ratio = sum / total / cohesion_continuum(H);
    last_spacings = spacings, last_ratio = ratio;
    return ratio;
}

#define CHECK(cond, field, fmt, value, rule)                                                  \
    do {                                                                                      \
        if (!(cond)) {                                                                        \
            if (err && err_size) snprintf(err, err_size, "pbf_params.%s must be %s (got " fmt ")", \
                                          field, rule, value);                                \
            return PBF_ERR_INVALID_ARG;                                                       \
        }                                                                                     \
    } while (0)

pbf_result pbf_params_validate(const pbf_params *p, char *err, size_t err_size)
{
    if (!p) {
        if (err && err_size) snprintf(err, err_size, "pbf_params_validate: params must not be NULL");
        return PBF_ERR_INVALID_ARG;
    }
    float r = p->particle_radius;
    CHECK(isfinite(r) && r > 0.0005f && r <= 1.0f, "particle_radius", "%g", (double)r,
          "in (0.0005, 1] m");
    char rule[96];
    snprintf(rule, sizeof rule, "in (%g, %g] m (more than one spacing 2r, at most 10 r)",
             (double)(2.0f * r), (double)(10.0f * r));
    CHECK(isfinite(p->kernel_radius) && p->kernel_radius > 2.0f * r && p->kernel_radius <= 10.0f * r,
          "kernel_radius", "%g", (double)p->kernel_radius, rule);
    CHECK(isfinite(p->rest_density) && p->rest_density >= 1.0f && p->rest_density <= 100000.0f,
          "rest_density", "%g", (double)p->rest_density, "in [1, 100000] kg/m^3");
    CHECK(p->iterations >= 1 && p->iterations <= 100, "iterations", "%d", p->iterations, "in [1, 100]");
    CHECK(p->substeps >= 1 && p->substeps <= 64, "substeps", "%d", p->substeps, "in [1, 64]");
    CHECK(isfinite(p->relaxation) && p->relaxation >= 0.0f && p->relaxation <= 100.0f, "relaxation",
          "%g", (double)p->relaxation, "in [0, 100]");
    CHECK(isfinite(p->sor) && p->sor >= 0.0f && p->sor < 2.0f, "sor", "%g", (double)p->sor,
          "0 (the relaxation schedule) or a constant factor in (0, 2)");
    CHECK(isfinite(p->scorr_k) && p->scorr_k >= 0.0f && p->scorr_k <= 1.0f, "scorr_k", "%g",
          (double)p->scorr_k, "in [0, 1]");
    CHECK(isfinite(p->scorr_n) && p->scorr_n >= 1.0f && p->scorr_n <= 8.0f, "scorr_n", "%g",
          (double)p->scorr_n, "in [1, 8]");
    CHECK(isfinite(p->scorr_dq) && p->scorr_dq > 0.0f && p->scorr_dq < 1.0f, "scorr_dq", "%g",
          (double)p->scorr_dq, "in (0, 1) (a fraction of kernel_radius)");
    CHECK(isfinite(p->vorticity) && p->vorticity >= 0.0f && p->vorticity <= 10.0f, "vorticity", "%g",
          (double)p->vorticity, "in [0, 10] m/s");
    CHECK(isfinite(p->viscosity) && p->viscosity >= 0.0f && p->viscosity <= 1.0f, "viscosity", "%g",
          (double)p->viscosity, "in [0, 1]");
    static const char *const gname[3] = { "gravity[0]", "gravity[1]", "gravity[2]" };
    for (int k = 0; k < 3; k++)
        CHECK(isfinite(p->gravity[k]) && fabsf(p->gravity[k]) <= 1000.0f, gname[k], "%g",
              (double)p->gravity[k], "finite and in [-1000, 1000] m/s^2");
    CHECK(isfinite(p->damping) && p->damping >= 0.0f && p->damping <= 100.0f, "damping", "%g",
          (double)p->damping, "in [0, 100] 1/s");
    CHECK(isfinite(p->max_speed) && p->max_speed > 0.0f && p->max_speed <= 1000.0f, "max_speed", "%g",
          (double)p->max_speed, "in (0, 1000] m/s");
    CHECK(isfinite(p->surface_tension) && p->surface_tension >= 0.0f && p->surface_tension <= 1000.0f,
          "surface_tension", "%g", (double)p->surface_tension, "in [0, 1000] N/m (0: off)");
    CHECK(isfinite(p->cfl) && p->cfl >= 0.0f && p->cfl <= 10.0f, "cfl", "%g", (double)p->cfl,
          "in [0, 10] particle spacings per substep (0: off)");
    CHECK(p->max_substeps >= 1 && p->max_substeps <= 64, "max_substeps", "%d", p->max_substeps, "in [1, 64]");
    CHECK(isfinite(p->guard_compression) && p->guard_compression >= 0.0f && p->guard_compression <= 1.0f,
          "guard_compression", "%g", (double)p->guard_compression, "in [0, 1] (a fraction of rho0; 0: off)");
    CHECK(isfinite(p->wall_friction) && p->wall_friction >= 0.0f && p->wall_friction <= 1.0f, "wall_friction", "%g",
          (double)p->wall_friction, "in [0, 1] (0: frictionless walls)");
    CHECK(isfinite(p->surface_fill) && p->surface_fill >= 0.0f && p->surface_fill <= 1.0f, "surface_fill", "%g",
          (double)p->surface_fill, "in [0, 1] (0: off)");
    CHECK(p->level_sweeps >= 0 && p->level_sweeps <= 200, "level_sweeps", "%d", p->level_sweeps, "in [0, 200] (0: off)");
    CHECK(isfinite(p->level_cell) && p->level_cell >= 1.0f && p->level_cell <= 16.0f, "level_cell", "%g",
          (double)p->level_cell, "in [1, 16] kernel radii");
    CHECK(isfinite(p->level_tolerance) && p->level_tolerance >= 0.0f && p->level_tolerance <= 0.1f, "level_tolerance",
          "%g", (double)p->level_tolerance, "in [0, 0.1] (a share of rest_density)");
    if (err && err_size) err[0] = 0;
    return PBF_OK;
}

#define F(field, unit, lo, hi, text) { #field, unit, text, false, lo, hi, offsetof(pbf_params, field) }
#define I(field, unit, lo, hi, text) { #field, unit, text, true, lo, hi, offsetof(pbf_params, field) }
static const pbf_param_info param_table[] = {
    F(particle_radius, "m", 0.0005, 1.0, "particle radius; particles sit 2 radii apart at rest"),
    F(kernel_radius, "m", 0.001, 10.0, "smoothing kernel radius h, more than 2 and at most 10 particle radii"),
    F(rest_density, "kg/m^3", 1.0, 100000.0, "rest density rho0"),
    I(iterations, "", 1, 100, "density solver iterations per substep"),
    I(substeps, "", 1, 64, "substeps per step"),
    F(relaxation, "", 0.0, 100.0, "constraint relaxation epsilon, relative to a filled neighbourhood's sum |grad C|^2"),
    F(sor, "", 0.0, 2.0, "0 (default): the relaxation schedule of docs/solver.md; in (0, 2): that factor on every correction"),
    F(scorr_k, "", 0.0, 1.0, "artificial pressure strength k"),
    F(scorr_n, "", 1.0, 8.0, "artificial pressure exponent n"),
    F(scorr_dq, "", 0.0, 1.0, "artificial pressure reference distance, fraction of kernel_radius, (0, 1)"),
    F(vorticity, "m/s", 0.0, 10.0, "vorticity confinement epsilon"),
    F(viscosity, "", 0.0, 1.0, "XSPH viscosity c"),
    F(damping, "1/s", 0.0, 100.0, "linear velocity damping"),
    F(max_speed, "m/s", 0.0, 1000.0, "particle speed clamp, (0, 1000]"),
    F(surface_tension, "N/m", 0.0, 1000.0, "surface tension sigma of the cohesion force (Akinci 2013); 0 off"),
    F(cfl, "", 0.0, 10.0, "time-step guard: most particle spacings the fastest particle moves per substep (0 off)"),
    I(max_substeps, "", 1, 64, "most substeps the time-step guard may take"),
    F(guard_compression, "", 0.0, 1.0, "time-step guard: worst compression (mean: a tenth) a step aims under (0 off)"),
    F(wall_friction, "", 0.0, 1.0, "skin-friction coefficient of the container's walls and floor; 0 frictionless"),
    F(surface_fill, "", 0.0, 1.0, "share of a free-surface particle's missing neighbourhood its constraint counts (0 off)"),
    I(level_sweeps, "", 0, 200, "sweeps per substep of the coarse level's pressure solve (deep water's compression; 0 off)"),
    F(level_cell, "", 1.0, 16.0, "the coarse level's cell, in kernel radii"),
    F(level_tolerance, "", 0.0, 0.1, "compression the coarse level leaves to the particle iterations (share of rho0)"),
};
#undef F
#undef I

const pbf_param_info *pbf_param_table(int *count)
{
    if (count) *count = (int)(sizeof param_table / sizeof param_table[0]);
    return param_table;
}

const pbf_param_info *pbf_param_find(const char *name)
{
    if (!name) return NULL;
    for (size_t i = 0; i < sizeof param_table / sizeof param_table[0]; i++)
        if (strcmp(param_table[i].name, name) == 0) return &param_table[i];
    return NULL;
}

double pbf_params_get(const pbf_params *p, const pbf_param_info *info)
{
    if (!p || !info) return NAN;
    const char *base = (const char *)p + info->offset;
    if (info->is_int) {
        int v;
        memcpy(&v, base, sizeof v);
        return v;
    }
    float v;
    memcpy(&v, base, sizeof v);
    return v;
}

// Writes one field by name, checking only that the name exists and that an integer field
// gets a whole number; the set is checked by the caller.
static pbf_result set_field(pbf_params *p, const char *name, double value, char *err, size_t err_size)
{
    const pbf_param_info *info = pbf_param_find(name);
    if (!info) {
        if (err && err_size) {
            int n = snprintf(err, err_size, "unknown fluid parameter '%s' (known:", name);
            for (size_t i = 0; i < sizeof param_table / sizeof param_table[0] && n > 0 && (size_t)n < err_size; i++)
                n += snprintf(err + n, err_size - (size_t)n, " %s", param_table[i].name);
            if (n > 0 && (size_t)n < err_size) snprintf(err + n, err_size - (size_t)n, ")");
        }
        return PBF_ERR_INVALID_ARG;
    }
    char *base = (char *)p + info->offset;
    if (info->is_int) {
        if (!(value == floor(value)) || value < -2e9 || value > 2e9) {
            if (err && err_size)
                snprintf(err, err_size, "pbf_params.%s must be a whole number in [%g, %g] (got %g)", name,
                         info->min, info->max, value);
            return PBF_ERR_INVALID_ARG;
        }
        int v = (int)value;
        memcpy(base, &v, sizeof v);
    } else {
        float v = (float)value;
        memcpy(base, &v, sizeof v);
    }
    return PBF_OK;
}

pbf_result pbf_params_set(pbf_params *p, const char *name, double value, char *err, size_t err_size)
{
    if (!p || !name) {
        if (err && err_size) snprintf(err, err_size, "pbf_params_set: %s must not be NULL", !p ? "params" : "name");
        return PBF_ERR_INVALID_ARG;
    }
    pbf_params tmp = *p;
    pbf_result r = set_field(&tmp, name, value, err, err_size);
    if (r == PBF_OK) r = pbf_params_validate(&tmp, err, err_size);
    if (r == PBF_OK) *p = tmp;
    return r;
}

pbf_result pbf_params_apply(pbf_params *p, const char *const *names, const double *values, int count, char *err,
                            size_t err_size)
{
    if (count < 0) {
        if (err && err_size) snprintf(err, err_size, "pbf_params_apply: count must be >= 0 (got %d)", count);
        return PBF_ERR_INVALID_ARG;
    }
    if (!p || (count > 0 && (!names || !values))) {
        if (err && err_size) snprintf(err, err_size, "pbf_params_apply: params, names and values must not be NULL");
        return PBF_ERR_INVALID_ARG;
    }
    pbf_params tmp = *p;
    bool radius = false, kernel = false;
    for (int i = 0; i < count; i++) {
        if (!names[i]) {
            if (err && err_size) snprintf(err, err_size, "pbf_params_apply: names[%d] is NULL", i);
            return PBF_ERR_INVALID_ARG;
        }
        pbf_result r = set_field(&tmp, names[i], values[i], err, err_size);
        if (r != PBF_OK) return r;
        radius |= strcmp(names[i], "particle_radius") == 0;
        kernel |= strcmp(names[i], "kernel_radius") == 0;
    }
    // A new particle size alone keeps the kernel's size in particle radii.
    if (radius && !kernel && p->particle_radius > 0.0f)
        tmp.kernel_radius = tmp.particle_radius * (p->kernel_radius / p->particle_radius);
    pbf_result r = pbf_params_validate(&tmp, err, err_size);
    if (r == PBF_OK) *p = tmp;
    return r;
}

double pbf_cohesion_factor(const pbf_params *p)
{
    // sigma = k rho0 s^8 T: T the tension per unit k of a flat cut through the rest lattice
    // (spacing units), by Kirkwood and Buff with Akinci's K_ij at the lattice's densities,
    // averaged over the cut's orientations (pbf_cohesion_lattice_ratio times the continuum's
    // (pi/8) int_0^H u^4 S(u) du; docs/solver.md, "Surface tension").
    if (!(p->surface_tension > 0.0f)) return 0.0; // off: no lattice sums to do
    double h = p->kernel_radius, s = 2.0 * p->particle_radius, H = h / s;
    double ratio = pbf_cohesion_lattice_ratio(H);
    if (!(ratio > 0.0)) return 0.0; // a kernel that validation refuses
    return (double)p->surface_tension / (p->rest_density * pow(s, 8) * ratio * cohesion_continuum(H));
}

void pbf_uniforms_solver(pbf_gpu_params *g, const pbf_params *p, const pbf_constants *k, float dt)
{
    double h = p->kernel_radius;
    g->gravity = (pbf_float4){ p->gravity[0], p->gravity[1], p->gravity[2], 0.0f };
    g->dt = dt;
    g->inv_dt = 1.0f / dt;
    g->h = (float)h;
    g->poly6 = k->poly6;
    g->spiky_grad = k->spiky_grad;
    g->rest_density = p->rest_density;
    g->inv_rest_density = 1.0f / p->rest_density;
    g->mass_density = k->mass_density;
    g->mass = k->mass;
    g->epsilon = k->epsilon;
    g->scorr_k = p->scorr_k;
    g->scorr_n = p->scorr_n;
    g->scorr_inv_wdq = k->scorr_inv_wdq;
    g->scorr_scale = k->scorr_scale;
    g->boundary_scale = k->boundary_scale;
    g->vorticity = p->vorticity;
    g->viscosity = p->viscosity;
    g->damping = p->damping;
    g->max_speed = p->max_speed;
    g->radius = p->particle_radius;
    g->surface_tension = p->surface_tension;
    g->wall_friction = p->wall_friction;
    g->surface_fill = p->surface_fill;
    g->cohesion_norm = (float)pbf_cohesion_factor(p);
}

int pbf_tension_substeps(const pbf_params *p, float dt)
{
    if (!(p->surface_tension > 0.0f) || !(dt > 0.0f)) return 1;
    // A pair's strongest pull, k S(h/2) = k h^6 / 64 (m/s^2), times a substep squared stays
    // under PBF_TENSION_STIFFNESS of the kernel radius (docs/solver.md, "Surface tension").
    double h = p->kernel_radius;
    double pull = pbf_cohesion_factor(p) * pow(h, 6) / 64.0;
    double n = ceil((double)dt * sqrt(pull / (PBF_TENSION_STIFFNESS * h)) - 1e-9);
    return n < 1.0 ? 1 : n > 1e6 ? 1000000 : (int)n;
}

int pbf_most_substeps(const pbf_params *p)
{
    return p->max_substeps > p->substeps ? p->max_substeps : p->substeps;
}

int pbf_guard_substeps(const pbf_params *p, float spacing, float dt, uint64_t step, float seen,
                       const float added[PBF_GUARD_HISTORY], bool *capped)
{
    if (capped) *capped = false;
    int base = p->substeps;
    int most = pbf_most_substeps(p);
    // The cohesion force is explicit: it needs substeps short enough for its stiffness
    // whether or not the guard is on (pbf_tension_substeps).
    int tension = pbf_tension_substeps(p, dt);
    if (tension > base) base = tension < most ? tension : most; // beyond most: pbf_world warns
    if (!(p->cfl > 0.0f) || !(spacing > 0.0f)) return base;
    if (seen != seen || seen > 1e30f) return base; // diverged: the host's check reports it
    // Unknown (the first steps) counts as at rest: what gravity adds is still expected.
    float g = sqrtf(p->gravity[0] * p->gravity[0] + p->gravity[1] * p->gravity[1] + p->gravity[2] * p->gravity[2]);
    float v = (seen > 0.0f ? seen : 0.0f) + g * dt * (float)PBF_GUARD_LATENCY;
    for (uint64_t k = 0; k < PBF_GUARD_LATENCY && k <= step; k++)
        if (added[(step - k) % PBF_GUARD_HISTORY] > v) v = added[(step - k) % PBF_GUARD_HISTORY];
    if (v > p->max_speed) v = p->max_speed; // the solver clamps faster particles
    double needed = ceil((double)v * dt / ((double)p->cfl * spacing));
    if (needed > most) {
        if (capped) *capped = true;
        return most;
    }
    return needed > base ? (int)needed : base;
}

int pbf_guard_compression(const pbf_params *p, pbf_guard_state *state, const pbf_guard_seen *seen,
                          const pbf_guard_seen *before, bool *capped)
{
    int base = p->substeps;
    int most = pbf_most_substeps(p);
    float target = p->guard_compression;
    if (!(target > 0.0f)) { // off (or turned off since): no say
        state->level = base;
        state->quiet = 0;
        return base;
    }
    if (state->level < base) state->level = base;
    if (state->level > most) state->level = most;
    if (!seen || seen->substeps <= 0) return state->level;
    float worst = seen->density_error_max, mean = seen->density_error_avg;
    if (!isfinite(worst) || !isfinite(mean)) return state->level; // diverged: the host's check reports it
    // The worst two steps on, at the pace it rose from `before` (same substeps: one regime):
    // water that settles slows down, a column the substeps cannot hold speeds up.
    if (before && before->substeps == seen->substeps && isfinite(before->density_error_max) &&
        worst > before->density_error_max)
        worst += (float)PBF_GUARD_LATENCY * (worst - before->density_error_max);
    float ratio = fmaxf(worst / target, mean / (0.1f * target));
    if (ratio > 1.0f) { // over: at once, the substeps that bring it to half the target
        state->quiet = 0;
        double want = ceil((double)seen->substeps * sqrt(2.0 * (double)ratio) - 1e-9);
        if (want > most) {
            if (capped) *capped = true;
            want = most;
        }
        if (want > state->level) state->level = (int)want;
    } else if (ratio < 0.25f && state->level > base) { // well under: one fewer after a quiet while
        if (++state->quiet >= PBF_GUARD_QUIET_STEPS) {
            state->level--;
            state->quiet = 0;
        }
    } else {
        state->quiet = 0;
    }
    return state->level;
}

uint64_t pbf_grid_geometry(const float domain_min[3], const float domain_max[3], float h,
                           uint32_t cells_per_kernel, float origin[3], uint32_t dims[3])
{
    double cs = (double)h / (double)cells_per_kernel;
    double total = 1.0; // in double: three 32-bit dimensions overflow 64 bits
    for (int k = 0; k < 3; k++) {
        origin[k] = domain_min[k] - h;
        double n = ceil(((double)domain_max[k] - (double)domain_min[k] + 2.0 * h) / cs - 1e-9);
        if (!(n >= 1.0)) n = 1.0; // NaN too
        dims[k] = n > 4e9 ? 4000000000u : (uint32_t)n;
        total *= n;
    }
    return total >= 1.8e19 ? UINT64_MAX : (uint64_t)total;
}

uint32_t pbf_hash_buckets(uint32_t capacity)
{
    uint64_t want = 4ull * capacity, t = 4096;
    while (t < want && t < (1ull << 28)) t <<= 1;
    return (uint32_t)t;
}

// Consecutive rows on the curve are `stride` buckets apart, at least a row's length so that
// rows do not overlap before the curve wraps around the buckets. Each time it wraps, the rows
// land shifted by (-buckets) mod stride; a shift near a golden fraction of the stride puts the
// rows of every wrap between those of the earlier ones (a Weyl sequence), so rows share
// buckets only when the buckets are nearly full. An odd stride alone (dims_x | 1) left 42 %
// of a 262k block's cells sharing buckets with other rows in a tank 80 m wide; the hash of the
// row before it 60 % for 1M particles spread 3 m over the floor (docs/solver.md).
uint32_t pbf_row_stride(uint32_t dims_x, uint32_t buckets)
{
    const double golden = 0.6180339887498949;
    uint32_t first = (dims_x < 1u ? 1u : dims_x) | 1u, best = first;
    double best_off = 1.0;
    for (uint32_t k = 0; k < 1024u && first + 2u * k >= first; k++) {
        uint32_t s = first + 2u * k;
        double f = (double)(buckets % s) / (double)s;
        double off = fmin(fabs(f - golden), fabs(f - (1.0 - golden)));
        if (off < best_off) {
            best_off = off;
            best = s;
        }
        if (off < 0.01) break;
    }
    return best;
}

// The relaxation factors (sor 0; docs/solver.md, "Under-relaxed Jacobi"). On a filled
// lattice the Jacobi iteration matrix has eigenvalues mu in (0, PBF_JACOBI_MU_MAX]; K
// iterations with factors w_k multiply a mode's error by p(mu) = prod (1 - w_k mu), and a
// PBD step is stable only while p stays in (-1/3, 1). An even count takes pairs (w_a, w_b)
// with the sum 1.2 of the constant 0.6 they replace (the low modes, which carry the
// hydrostatic pressure, lose the same 1.2 mu a pair) and p(PBF_JACOBI_MU_DEEP) = 1: the
// roots of w^2 - 1.2 w + 1.2 / mu_deep, 0.845 and 0.355, whose p >= -0.2 everywhere and
// stays below 1 up to mu_deep (0.6's up to 3.33 only: compressed water at depth boiled).
// An odd count starts with the triple (1, 1, w3) whose p(mu_max) = 0.25 and p >= 0
// elsewhere (at 0.6 three iterations give p(mu_max) = -0.31, one -0.68: a tank boils), then
// pairs; one iteration alone takes 0.35 (0.43, p(mu_max) = -0.2, still left a tank at
// 42 mm/s).
//
// The eigenvalues grow with the kernel (pbf_jacobi_mu_max: 6.7 at 3 spacings), and at 3
// spacings the even pair's p(mu_max) is 6.5 a step: the water boils wherever the constraint
// is loaded (under a droplet's cohesion, at depth). A wider kernel scales every factor by
// mu_max(2) / mu_max(its own), which maps its spectrum onto the default kernel's; a narrower
// one keeps them (its modes are damped already).
static double relaxation_scale(const pbf_constants *k)
{
    if (!k || !(k->jacobi_mu_max > PBF_JACOBI_MU_LATTICE * (1.0 + 1e-3))) return 1.0;
    return PBF_JACOBI_MU_LATTICE / (double)k->jacobi_mu_max;
}

float pbf_relaxation(const pbf_params *p, const pbf_constants *k, int it)
{
    if (p->sor > 0.0f) return p->sor;
    const double m = PBF_JACOBI_MU_MAX, scale = relaxation_scale(k);
    if (p->iterations == 1) return (float)(0.35 * scale);
    if (p->iterations % 2 == 1 && it < 3)
        return (float)(scale * (it < 2 ? 1.0 : (1.0 - 0.25 / ((1.0 - m) * (1.0 - m))) / m));
    const double sum = 1.2, d = sqrt(sum * sum - 4.0 * sum / PBF_JACOBI_MU_DEEP);
    int i = p->iterations % 2 == 1 ? it - 3 : it; // the pairs' own index
    return (float)(scale * (i % 2 == 0 ? 0.5 * (sum + d) : 0.5 * (sum - d)));
}

void pbf_uniforms_space(pbf_gpu_params *g, const float grid_origin[3], const uint32_t grid_dims[3],
                        uint32_t cells, float cell_size, const float domain_min[3], const float domain_max[3],
                        const float (*planes)[4], uint32_t plane_count, uint32_t max_neighbours)
{
    g->inv_cell = 1.0f / cell_size;
    g->grid_origin = (pbf_float4){ grid_origin[0], grid_origin[1], grid_origin[2], 0.0f };
    g->grid_dims = (pbf_uint4){ grid_dims[0], grid_dims[1], grid_dims[2], cells };
    g->row_stride = pbf_row_stride(grid_dims[0], cells);
    g->domain_min = (pbf_float4){ domain_min[0], domain_min[1], domain_min[2], 0.0f };
    g->domain_max = (pbf_float4){ domain_max[0], domain_max[1], domain_max[2], 0.0f };
    for (uint32_t i = 0; i < plane_count && i < PBF_MAX_PLANES; i++)
        g->planes[i] = (pbf_float4){ planes[i][0], planes[i][1], planes[i][2], planes[i][3] };
    g->plane_count = plane_count;
    g->max_neighbours = max_neighbours;
}

int pbf_container_planes(const float min[3], const float max[3], bool closed_top, const float domain_min[3],
                         const float domain_max[3], float planes[PBF_MAX_PLANES][4], char *err, size_t err_size)
{
    static const char *const axis = "xyz";
    for (int k = 0; k < 3; k++) {
        if (!isfinite(min[k]) || !isfinite(max[k]) || !(max[k] > min[k])) {
            snprintf(err, err_size, "container.max.%c must be finite and greater than min.%c (got min %g, max %g)",
                     axis[k], axis[k], (double)min[k], (double)max[k]);
            return 0;
        }
        if (min[k] < domain_min[k] || max[k] > domain_max[k]) {
            snprintf(err, err_size, "container.%c range [%g, %g] must lie inside the domain [%g, %g]", axis[k],
                     (double)min[k], (double)max[k], (double)domain_min[k], (double)domain_max[k]);
            return 0;
        }
    }
    // This order (floor, x min, x max, z min, z max, lid) is what pbf_kernels.h's
    // opposite_plane pairs facing planes by.
    const float p[PBF_MAX_PLANES][4] = {
        { 0, 1, 0, min[1] },  { 1, 0, 0, min[0] },   { -1, 0, 0, -max[0] },
        { 0, 0, 1, min[2] },  { 0, 0, -1, -max[2] }, { 0, -1, 0, -max[1] },
    };
    memcpy(planes, p, sizeof p);
    return closed_top ? 6 : 5;
}

uint32_t pbf_collider_data_count(const pbf_collider_def *d)
{
    if (d->type == PBF_SHAPE_CONVEX_HULL) return 5 * d->plane_count;
    if (d->type == PBF_SHAPE_SDF) return d->grid.dims[0] * d->grid.dims[1] * d->grid.dims[2];
    return 0;
}

void pbf_collider_data_fill(const pbf_collider_def *d, float *out)
{
    if (d->type == PBF_SHAPE_SDF) {
        memcpy(out, d->grid.values, (size_t)pbf_collider_data_count(d) * sizeof *out);
        return;
    }
    if (d->type != PBF_SHAPE_CONVEX_HULL) return;
    uint32_t n = d->plane_count;
    memcpy(out, d->planes, (size_t)n * 4 * sizeof *out);
    for (uint32_t f = 0; f < n; f++) {
        const float *a = d->planes + 4 * f;
        double sum = 0.0;
        for (uint32_t g = 0; g < n; g++) {
            const float *b = d->planes + 4 * g;
            double c = (double)a[0] * b[0] + (double)a[1] * b[1] + (double)a[2] * b[2];
            if (c > 0.0) sum += pow(c, 8.0);
        }
        out[4 * n + f] = (float)(1.0 / sum); // sum >= 1: the face itself
    }
}

float pbf_collider_bounding_radius(const pbf_collider_def *d)
{
    const float *z = d->size;
    switch (d->type) {
    case PBF_SHAPE_PLANE: return 1e30f;
    case PBF_SHAPE_BOX: return sqrtf(z[0] * z[0] + z[1] * z[1] + z[2] * z[2]);
    case PBF_SHAPE_SPHERE: return z[0];
    case PBF_SHAPE_CAPSULE: return z[0] + z[1];
    case PBF_SHAPE_CYLINDER: return sqrtf(z[0] * z[0] + z[1] * z[1]);
    case PBF_SHAPE_CONVEX_HULL: return z[0];
    case PBF_SHAPE_SDF: {
        // The surface lies inside the grid's box: its farthest corner bounds it.
        float r2 = 0.0f;
        for (int k = 0; k < 3; k++) {
            float lo = fabsf(d->grid.origin[k]);
            float hi = fabsf(d->grid.origin[k] + (float)(d->grid.dims[k] - 1) * d->grid.cell);
            float m = lo > hi ? lo : hi;
            r2 += m * m;
        }
        return sqrtf(r2);
    }
    }
    return 1e30f;
}

double pbf_wide_sum(const int32_t *words)
{
    uint64_t u = (uint64_t)(uint32_t)words[1] << 32 | (uint32_t)words[0];
    return (double)(int64_t)u;
}

void pbf_water_of_sums(const int32_t *words, float force_scale, int substeps, pbf_collider_report *rep)
{
    double push = pbf_wide_sum(words + 14);
    rep->fluid_push = (float)(push / (double)force_scale / (double)(substeps > 0 ? substeps : 1));
    for (int k = 0; k < 3; k++) rep->fluid_velocity[k] = push > 0.0 ? (float)(pbf_wide_sum(words + 8 + 2 * k) / push) : 0.0f;
}

pbf_result pbf_block_lattice(const pbf_block_def *b, float spacing, const float domain_min[3],
                             const float domain_max[3], uint32_t in_use, uint32_t capacity, uint32_t n[3],
                             uint64_t *total, char *err, size_t err_size)
{
    static const char *const axis = "xyz";
    for (int k = 0; k < 3; k++) {
        if (!isfinite(b->min[k]) || !isfinite(b->max[k]) || !(b->max[k] > b->min[k])) {
            snprintf(err, err_size, "pbf_block_def.max.%c must be finite and greater than min.%c (got min %g, max %g)",
                     axis[k], axis[k], (double)b->min[k], (double)b->max[k]);
            return PBF_ERR_INVALID_ARG;
        }
        if (b->min[k] < domain_min[k] || b->max[k] > domain_max[k]) {
            snprintf(err, err_size, "pbf_block_def.%c range [%g, %g] must lie inside the domain [%g, %g]", axis[k],
                     (double)b->min[k], (double)b->max[k], (double)domain_min[k], (double)domain_max[k]);
            return PBF_ERR_INVALID_ARG;
        }
        if (!isfinite(b->velocity[k])) {
            snprintf(err, err_size, "pbf_block_def.velocity.%c must be finite (got %g)", axis[k], (double)b->velocity[k]);
            return PBF_ERR_INVALID_ARG;
        }
    }
    *total = 1;
    for (int k = 0; k < 3; k++) {
        double c = floor((double)(b->max[k] - b->min[k]) / spacing + 1e-4);
        n[k] = c < 1.0 ? 1u : (uint32_t)c;
        *total *= n[k];
    }
    if (*total > capacity - in_use) {
        snprintf(err, err_size, "pbf_block_def: the block holds %llu particles but only %u of capacity %u are free",
                 (unsigned long long)*total, capacity - in_use, capacity);
        return PBF_ERR_CAPACITY;
    }
    return PBF_OK;
}

void pbf_block_point(const pbf_block_def *b, float spacing, uint32_t x, uint32_t y, uint32_t z, float out[3])
{
    out[0] = b->min[0] + spacing * (0.5f + (float)x);
    out[1] = b->min[1] + spacing * (0.5f + (float)y);
    out[2] = b->min[2] + spacing * (0.5f + (float)z);
}

bool pbf_points_check(const char *fn, const float *positions, const float *velocities, uint32_t n,
                      const float domain_min[3], const float domain_max[3], char *err, size_t err_size)
{
    for (uint32_t i = 0; i < n; i++) {
        const float *x = positions + 3 * i;
        for (int k = 0; k < 3; k++)
            if (!(x[k] >= domain_min[k] && x[k] <= domain_max[k])) {
                snprintf(err, err_size, "%s: positions[%u] = (%g, %g, %g) must be finite and inside the domain", fn, i,
                         (double)x[0], (double)x[1], (double)x[2]);
                return false;
            }
        if (velocities)
            for (int k = 0; k < 3; k++)
                if (!isfinite(velocities[3 * i + k])) {
                    snprintf(err, err_size, "%s: velocities[%u] must be finite (got %g)", fn, i,
                             (double)velocities[3 * i + k]);
                    return false;
                }
    }
    return true;
}

const char *pbf_version(void) { return PBF_VERSION_STRING; }

pbf_result pbf_level_layout(const pbf_params *p, const float domain_min[3], const float domain_max[3], uint32_t dims[4],
                            float cell[3], char *err, size_t err_size)
{
    dims[0] = dims[1] = dims[2] = dims[3] = 0;
    cell[0] = cell[1] = cell[2] = 0.0f;
    if (p->level_sweeps == 0) return PBF_OK;
    double want = (double)p->level_cell * p->kernel_radius, total = 1.0;
    // The world validates its def first; pbf_world_def_memory may be asked about any def,
    // so nothing below may meet a NaN (its conversion to an integer is undefined).
    if (!isfinite(want) || !(want > 0.0)) {
        snprintf(err, err_size, "pbf_params.level_cell x kernel_radius must be a positive size (got %g x %g)",
                 (double)p->level_cell, (double)p->kernel_radius);
        return PBF_ERR_INVALID_ARG;
    }
    uint32_t n[3];
    for (int k = 0; k < 3; k++) {
        double len = (double)domain_max[k] - domain_min[k];
        if (!isfinite(len) || !(len > 0.0)) {
            snprintf(err, err_size, "the coarse level needs a finite domain with domain_max[%d] > domain_min[%d] (got min %g, max %g)",
                     k, k, (double)domain_min[k], (double)domain_max[k]);
            return PBF_ERR_INVALID_ARG;
        }
        double m = floor(len / want + 0.5);
        if (m < 1.0) m = 1.0;
        total *= m;
        n[k] = m > PBF_LEVEL_MAX_CELLS ? PBF_LEVEL_MAX_CELLS : (uint32_t)m;
    }
    if (total > PBF_LEVEL_MAX_CELLS) {
        snprintf(err, err_size,
                 "pbf_params.level_sweeps %d needs a coarse grid over the domain (%g x %g x %g m) in cells of level_cell x "
                 "kernel_radius = %g m: %.0f cells, at most %u (raise level_cell, shrink the domain, or set level_sweeps 0)",
                 p->level_sweeps, (double)(domain_max[0] - domain_min[0]), (double)(domain_max[1] - domain_min[1]),
                 (double)(domain_max[2] - domain_min[2]), want, total, PBF_LEVEL_MAX_CELLS);
        return PBF_ERR_INVALID_ARG;
    }
    for (int k = 0; k < 3; k++) {
        dims[k] = n[k];
        cell[k] = (float)(((double)domain_max[k] - domain_min[k]) / n[k]);
    }
    dims[3] = n[0] * n[1] * n[2];
    return PBF_OK;
}

int pbf_level_iteration(const pbf_params *p) { return p->level_sweeps > 0 ? p->iterations - 1 : -1; }

void pbf_uniforms_level(pbf_gpu_params *g, const pbf_params *p, const uint32_t dims[4], const float cell[3])
{
    g->level_dims = (pbf_uint4){ dims[0], dims[1], dims[2], dims[3] };
    float s = 2.0f * p->particle_radius;
    g->level_cell = (pbf_float4){ cell[0], cell[1], cell[2], dims[3] ? s * s * s / (cell[0] * cell[1] * cell[2]) : 0.0f };
    g->level_solve = (pbf_float4){ p->level_tolerance, PBF_LEVEL_OMEGA, 0.0f, 0.0f };
}
