// The signed distance grids baked for static and kinematic triangle meshes
// (fluid/bullet/coupling_mesh.h): exact distances with the sign of the side the nearest
// triangle faces, for closed and open meshes, and a cost that grows with the samples, not with
// samples times triangles (a mesh of many triangles must not stall a scene for hours).
#include "tests/support.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "fluid/bullet/coupling_mesh.h"

static const double PI = 3.14159265358979323846;

typedef struct mesh_arrays {
    phys_vec3 *v;
    uint32_t *idx;
    uint32_t nv, nt;
} mesh_arrays;

static float grid_at(const cpl_mesh_bake *b, uint32_t x, uint32_t y, uint32_t z, phys_vec3 *p)
{
    *p = (phys_vec3){ b->grid.origin[0] + b->grid.cell * (float)x, b->grid.origin[1] + b->grid.cell * (float)y,
                      b->grid.origin[2] + b->grid.cell * (float)z };
    return b->grid.values[x + b->grid.dims[0] * ((size_t)y + b->grid.dims[1] * (size_t)z)];
}

static size_t sample_count(const cpl_mesh_bake *b)
{
    return (size_t)b->grid.dims[0] * b->grid.dims[1] * b->grid.dims[2];
}

// The grid's promise (coupling_mesh.h): the exact signed distance within `band` of the mesh,
// beyond it the same side and a distance at most 13 % long (the chamfer's worst direction),
// never short. The error against `want`: beyond the band, how far |v| lies outside
// [|want|, 1.13 |want|].
static double distance_error(double v, double want, double band)
{
    if (fabs(want) <= band) return fabs(v - want);
    if ((v < 0.0) != (want < 0.0)) return INFINITY;
    return fmax(fmax(fabs(want) - fabs(v), fabs(v) / 1.13 - fabs(want)), 0.0);
}

// A closed box, half sizes e, its faces divided into n x n squares of two triangles each,
// counter-clockwise seen from outside.
static mesh_arrays divided_box(const double e[3], int n)
{
    mesh_arrays m = { malloc(6 * (size_t)(n + 1) * (n + 1) * sizeof(phys_vec3)),
                      malloc(6 * 6 * (size_t)n * n * sizeof(uint32_t)), 0, 0 };
    assert_non_null(m.v);
    assert_non_null(m.idx);
    for (int axis = 0; axis < 3; axis++)
        for (int side = -1; side <= 1; side += 2) {
            int u = (axis + 1) % 3, w = (axis + 2) % 3;
            uint32_t base = m.nv;
            for (int j = 0; j <= n; j++)
                for (int i = 0; i <= n; i++) {
                    double c[3];
                    c[axis] = side * e[axis];
                    c[u] = e[u] * (2.0 * i / n - 1.0);
                    c[w] = e[w] * (2.0 * j / n - 1.0);
                    m.v[m.nv++] = (phys_vec3){ (float)c[0], (float)c[1], (float)c[2] };
                }
            for (int j = 0; j < n; j++)
                for (int i = 0; i < n; i++) {
                    uint32_t a = base + (uint32_t)(j * (n + 1) + i), b = a + 1, c = a + (uint32_t)(n + 1), d = c + 1;
                    // u x w is +axis: (a, b, d) turns counter-clockwise seen from +axis.
                    uint32_t q[6] = { a, b, d, a, d, c };
                    if (side < 0) q[1] = d, q[2] = b, q[4] = c, q[5] = d;
                    for (int k = 0; k < 6; k++) m.idx[3 * m.nt + (uint32_t)k] = q[k];
                    m.nt += 2;
                }
        }
    return m;
}

static double box_distance(const double e[3], phys_vec3 p)
{
    double q[3] = { fabs(p.x) - e[0], fabs(p.y) - e[1], fabs(p.z) - e[2] };
    double out = 0.0, in = fmax(q[0], fmax(q[1], q[2]));
    for (int k = 0; k < 3; k++) out += fmax(q[k], 0.0) * fmax(q[k], 0.0);
    return in > 0.0 ? sqrt(out) : in;
}

/// A closed box of many triangles (each face cut into squares, so that corners and edges are
/// shared by several triangles): every sample within the band (a kernel and two cells) is the
/// box's exact signed distance, inside negative, those beyond it on the right side within 13 %;
/// and the bake tests a small number of triangles per sample, not all 4800.
static void closed_box_bakes_its_exact_distance_cheaply(void **state)
{
    (void)state;
    const double e[3] = { 0.2, 0.1, 0.15 };
    mesh_arrays a = divided_box(e, 20);
    phys_triangle_mesh m = { a.v, a.nv, a.idx, a.nt };
    float cell = 0.02f;
    cpl_mesh_bake b;
    assert_true(cpl_bake_mesh(&m, 0.05f, &cell, &b));
    assert_true(b.closed);
    assert_float_equal(cell, 0.02f, 1e-7f);
    double worst = 0.0;
    size_t inside = 0;
    for (uint32_t z = 0; z < b.grid.dims[2]; z++)
        for (uint32_t y = 0; y < b.grid.dims[1]; y++)
            for (uint32_t x = 0; x < b.grid.dims[0]; x++) {
                phys_vec3 p;
                double v = grid_at(&b, x, y, z, &p), want = box_distance(e, p);
                worst = fmax(worst, distance_error(v, want, 0.05 + 2 * 0.02));
                inside += v < 0.0;
            }
    size_t samples = sample_count(&b);
    printf("box of %u triangles: %zu samples (%zu inside), worst error %.2g m, %.1f triangle tests per sample\n",
           a.nt, samples, inside, worst, (double)b.triangle_tests / (double)samples);
    assert_true(worst < 1e-5);
    assert_true(inside > 0);
    // Testing every triangle at every sample would be 4800 per sample.
    assert_true(b.triangle_tests < 100 * samples);
    free(b.values);
    free(a.v);
    free(a.idx);
}

/// An open mesh (the box's top face alone, facing up) is a shell h thick behind its triangles:
/// positive above it, negative just under it, positive again past the shell.
static void open_sheet_is_a_shell_behind_its_face(void **state)
{
    (void)state;
    const double e[3] = { 0.2, 0.1, 0.15 };
    mesh_arrays a = divided_box(e, 8);
    // Keep the +y face's triangles only (the second face built: axis 1, side +1).
    uint32_t per_face = 2 * 8 * 8, keep = 3 * per_face;
    phys_vec3 *v = a.v;
    uint32_t *idx = malloc(keep * sizeof *idx);
    assert_non_null(idx);
    for (uint32_t i = 0; i < keep; i++) idx[i] = a.idx[3 * 3 * per_face + i];
    phys_triangle_mesh m = { v, a.nv, idx, per_face };
    const float h = 0.05f;
    float cell = 0.01f;
    cpl_mesh_bake b;
    assert_true(cpl_bake_mesh(&m, h, &cell, &b));
    assert_false(b.closed);
    // Samples straight above and below the face's middle (x, z near 0).
    int checked = 0;
    for (uint32_t z = 0; z < b.grid.dims[2]; z++)
        for (uint32_t y = 0; y < b.grid.dims[1]; y++)
            for (uint32_t x = 0; x < b.grid.dims[0]; x++) {
                phys_vec3 p;
                double v2 = grid_at(&b, x, y, z, &p);
                if (fabs(p.x) > 0.1 || fabs(p.z) > 0.07) continue;
                double dy = p.y - e[1];
                double want = dy >= 0.0 ? dy : fmax(dy, -h - dy);
                if (fabs(dy) <= 2 * h + 2 * 0.01)
                    assert_float_equal(v2, want, 1e-5);
                else
                    assert_true(v2 >= want - 1e-6 && v2 <= want * 1.13 + 1e-6);
                checked++;
            }
    assert_true(checked > 100);
    free(b.values);
    free(v);
    free(idx);
    free(a.idx);
}

/// Many triangles in few cells: a sphere of 38 920 triangles bakes with a few hundred tests
/// per sample at most (brute force: 38 920; a sample near the centre of a round solid is about
/// as near every facet, which the chamfered far field spares), its values within the facets'
/// chord error of |p| - R near it, and the triangles' order does not matter (the same grid
/// from a shuffled list).
static void fine_sphere_bakes_in_time_that_grows_with_the_samples(void **state)
{
    (void)state;
    const int nu = 140, nvv = 140;
    const double R = 0.1;
    uint32_t nv = (uint32_t)(nu * (nvv - 1) + 2), nt = (uint32_t)(2 * nu * (nvv - 1));
    phys_vec3 *v = malloc(nv * sizeof *v);
    uint32_t *idx = malloc(3 * (size_t)nt * sizeof *idx), *shuffled = malloc(3 * (size_t)nt * sizeof *idx);
    assert_non_null(v);
    assert_non_null(idx);
    assert_non_null(shuffled);
    uint32_t k = 0, t = 0;
    v[k++] = (phys_vec3){ 0, (float)R, 0 };
    for (int j = 1; j < nvv; j++)
        for (int i = 0; i < nu; i++) {
            double th = PI * j / nvv, ph = 2 * PI * i / nu;
            v[k++] = (phys_vec3){ (float)(R * sin(th) * cos(ph)), (float)(R * cos(th)), (float)(R * sin(th) * sin(ph)) };
        }
    v[k++] = (phys_vec3){ 0, (float)-R, 0 };
    assert_int_equal(k, nv);
    // Rings j = 1 .. nvv - 1 start at 1 + (j - 1) nu. Outward (counter-clockwise from outside).
    for (int i = 0; i < nu; i++) {
        uint32_t a = 1 + (uint32_t)i, b2 = 1 + (uint32_t)((i + 1) % nu);
        uint32_t tri1[3] = { 0, b2, a };
        uint32_t last = 1 + (uint32_t)((nvv - 2) * nu);
        uint32_t tri2[3] = { nv - 1, last + (uint32_t)i, last + (uint32_t)((i + 1) % nu) };
        for (int c = 0; c < 3; c++) idx[3 * t + (uint32_t)c] = tri1[c], idx[3 * (t + 1) + (uint32_t)c] = tri2[c];
        t += 2;
    }
    for (int j = 1; j < nvv - 1; j++)
        for (int i = 0; i < nu; i++) {
            uint32_t a = 1 + (uint32_t)((j - 1) * nu + i), b2 = 1 + (uint32_t)((j - 1) * nu + (i + 1) % nu);
            uint32_t c = a + (uint32_t)nu, d = b2 + (uint32_t)nu;
            uint32_t q[6] = { a, b2, d, a, d, c };
            for (int m2 = 0; m2 < 6; m2++) idx[3 * t + (uint32_t)m2] = q[m2];
            t += 2;
        }
    assert_int_equal(t, nt);
    phys_triangle_mesh m = { v, nv, idx, nt };
    float cell = 0.01f;
    cpl_mesh_bake b;
    assert_true(cpl_bake_mesh(&m, 0.05f, &cell, &b));
    assert_true(b.closed);
    size_t samples = sample_count(&b);
    double worst = 0.0, chord = R * (1.0 - cos(PI / nvv)); // the facets lie up to this far inside
    for (uint32_t z = 0; z < b.grid.dims[2]; z++)
        for (uint32_t y = 0; y < b.grid.dims[1]; y++)
            for (uint32_t x = 0; x < b.grid.dims[0]; x++) {
                phys_vec3 p;
                double val = grid_at(&b, x, y, z, &p);
                double r = sqrt((double)p.x * p.x + (double)p.y * p.y + (double)p.z * p.z);
                // Within the band the facets' distance, beyond it that within 13 %.
                worst = fmax(worst, distance_error(val, r - R, 0.05 + 2 * 0.01 - chord));
            }
    printf("sphere of %u triangles: %zu samples, worst error %.2g m (chord %.2g), %.1f triangle tests per sample\n",
           nt, samples, worst, chord, (double)b.triangle_tests / (double)samples);
    assert_true(worst < chord + 1e-5);
    assert_true(b.triangle_tests < 500 * samples);

    // The same triangles in another order (a fixed shuffle) bake the same grid.
    uint32_t *perm = malloc(nt * sizeof *perm);
    assert_non_null(perm);
    for (uint32_t i = 0; i < nt; i++) perm[i] = i;
    uint64_t rng = 12345;
    for (uint32_t i = nt - 1; i > 0; i--) {
        rng = rng * 6364136223846793005ull + 1442695040888963407ull;
        uint32_t j = (uint32_t)((rng >> 33) % (i + 1)), tmp = perm[i];
        perm[i] = perm[j];
        perm[j] = tmp;
    }
    for (uint32_t i = 0; i < nt; i++)
        for (int c = 0; c < 3; c++) shuffled[3 * i + (uint32_t)c] = idx[3 * perm[i] + (uint32_t)c];
    phys_triangle_mesh ms = { v, nv, shuffled, nt };
    float cell2 = 0.01f;
    cpl_mesh_bake b2;
    assert_true(cpl_bake_mesh(&ms, 0.05f, &cell2, &b2));
    assert_int_equal(sample_count(&b2), samples);
    for (size_t i = 0; i < samples; i++) assert_float_equal(b2.values[i], b.values[i], 0.0f);
    free(b.values);
    free(b2.values);
    free(perm);
    free(v);
    free(idx);
    free(shuffled);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(closed_box_bakes_its_exact_distance_cheaply),
        cmocka_unit_test(open_sheet_is_a_shell_behind_its_face),
        cmocka_unit_test(fine_sphere_bakes_in_time_that_grows_with_the_samples),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
