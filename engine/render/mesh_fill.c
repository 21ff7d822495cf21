// Filling a closed mesh with lattice sites (mesh_file.h, eng_mesh_fill_points).
//
// Ray parity, a row at a time. The lattice's longest axis is the ray axis `a`; the other two
// (u, v) index the rows. Each triangle is projected onto the (u, v) plane and tested against
// the rows inside its projected bounds; where a row's line passes through it, the crossing's
// coordinate along `a` is kept for that row. A row's crossings, sorted, pair up into the
// intervals that are inside.
//
// A line through an edge or a corner shared by several triangles must count one crossing
// where the surface is crossed and none (or two) where it only touches. The point-in-triangle
// test gets that from two rules:
//   - every edge is evaluated once, in one direction (from its lower vertex index to its
//     higher), so the two triangles of an edge see the same number for it, rounding and all;
//   - a line exactly on an edge is treated as moved by (eps, eps^2) in (u, v), eps
//     infinitesimal (the rasterisers' tie rule), which puts it strictly on one side.
// A triangle holds the line when it lies on the same side of all three of its edges taken
// in order (either side: front and back faces both cross). Edge-on triangles hold nothing.
#include "engine/render/mesh_file.h"
#include "engine/core/log.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

eng_mesh_fill_options eng_default_mesh_fill_options(void)
{
    eng_mesh_fill_options o;
    memset(&o, 0, sizeof o);
    o.clearance = 0.0f;
    o.max_points = ENG_MESH_FILL_MAX_SITES;
    o.rotation[3] = 1.0f;
    return o;
}

// The lattice: n sites per axis at lo + spacing (i + 1/2), as pbf_block_point places them.
typedef struct lattice {
    float lo[3];
    float spacing;
    uint32_t n[3];
    int a, u, v; // ray axis and row axes
} lattice;

static double site(const lattice *l, int axis, uint32_t i)
{
    return (double)(l->lo[axis] + l->spacing * (0.5f + (float)i));
}

// Sites of `axis` whose coordinate lies in [lo, hi]: [*i0, *i1]; false when none.
static bool site_range(const lattice *l, int axis, double lo, double hi, uint32_t *i0, uint32_t *i1)
{
    double s = l->spacing, first = (lo - l->lo[axis]) / s - 0.5, last = (hi - l->lo[axis]) / s - 0.5;
    if (last < 0.0 || first > (double)l->n[axis] - 1.0) return false;
    long a = (long)ceil(first) - 1, b = (long)floor(last) + 1; // one more each side: rounding
    if (a < 0) a = 0;
    if (b > (long)l->n[axis] - 1) b = (long)l->n[axis] - 1;
    if (a > b) return false;
    *i0 = (uint32_t)a;
    *i1 = (uint32_t)b;
    return true;
}

// Side of the point (qu, qv) from the edge p -> q (vertex indices ip, iq), with the tie rule
// above: +1 left, -1 right, 0 when the edge projects to a point.
static int edge_side(const float *pos, uint32_t ip, uint32_t iq, int u, int v, double qu, double qv, double *value)
{
    int s = 1;
    if (ip > iq) {
        uint32_t t = ip;
        ip = iq;
        iq = t;
        s = -1;
    }
    const float *a = pos + 3 * (size_t)ip, *b = pos + 3 * (size_t)iq;
    double du = (double)b[u] - (double)a[u], dv = (double)b[v] - (double)a[v];
    double e = du * (qv - (double)a[v]) - dv * (qu - (double)a[u]);
    *value = s * e;
    if (e > 0.0) return s;
    if (e < 0.0) return -s;
    if (dv != 0.0) return dv < 0.0 ? s : -s; // moved by eps along u: -dv eps
    if (du != 0.0) return du > 0.0 ? s : -s; // moved by eps^2 along v: du eps^2
    return 0;
}

typedef struct crossing {
    uint32_t row;
    double at; // m, along the ray axis
} crossing;

typedef struct crossings {
    crossing *c;
    size_t n, cap;
} crossings;

static bool push(crossings *cs, uint32_t row, double at)
{
    if (cs->n == cs->cap) {
        size_t cap = cs->cap ? 2 * cs->cap : 1024;
        crossing *c = realloc(cs->c, cap * sizeof *c);
        if (!c) return false;
        cs->c = c;
        cs->cap = cap;
    }
    cs->c[cs->n++] = (crossing){ row, at };
    return true;
}

// Every crossing of every row with the mesh's triangles.
static bool cross_rows(const eng_mesh_data *m, const lattice *l, crossings *cs)
{
    int a = l->a, u = l->u, v = l->v;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->indices + 3 * (size_t)t;
        const float *p[3] = { m->positions + 3 * (size_t)tri[0], m->positions + 3 * (size_t)tri[1],
                              m->positions + 3 * (size_t)tri[2] };
        double lo_u = fmin(p[0][u], fmin(p[1][u], p[2][u])), hi_u = fmax(p[0][u], fmax(p[1][u], p[2][u]));
        double lo_v = fmin(p[0][v], fmin(p[1][v], p[2][v])), hi_v = fmax(p[0][v], fmax(p[1][v], p[2][v]));
        uint32_t j0, j1, k0, k1;
        if (!site_range(l, u, lo_u, hi_u, &j0, &j1) || !site_range(l, v, lo_v, hi_v, &k0, &k1)) continue;
        for (uint32_t k = k0; k <= k1; k++)
            for (uint32_t j = j0; j <= j1; j++) {
                double qu = site(l, u, j), qv = site(l, v, k), w[3];
                int s0 = edge_side(m->positions, tri[1], tri[2], u, v, qu, qv, &w[0]);
                int s1 = edge_side(m->positions, tri[2], tri[0], u, v, qu, qv, &w[1]);
                int s2 = edge_side(m->positions, tri[0], tri[1], u, v, qu, qv, &w[2]);
                if (s0 == 0 || s0 != s1 || s1 != s2) continue;
                // Where the row meets the triangle's plane: barycentric weights from the
                // edge values (each the doubled area opposite its corner).
                double sum = 0.0, at = 0.0;
                for (int c = 0; c < 3; c++) {
                    double wc = fmax(w[c] * s0, 0.0);
                    sum += wc;
                    at += wc * p[c][a];
                }
                at = sum > 0.0 ? at / sum : (p[0][a] + p[1][a] + p[2][a]) / 3.0;
                if (!push(cs, j + l->n[u] * k, at)) return false;
            }
    }
    return true;
}

static int compare_double(const void *x, const void *y)
{
    double a = *(const double *)x, b = *(const double *)y;
    return a < b ? -1 : a > b;
}

// Closest point on triangle abc to p, squared distance (Ericson, Real-Time Collision
// Detection, 5.1.5), in double.
static double distance2_to_triangle(const double p[3], const float *a, const float *b, const float *c)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3], q[3];
    for (int k = 0; k < 3; k++) {
        ab[k] = (double)b[k] - a[k];
        ac[k] = (double)c[k] - a[k];
        ap[k] = p[k] - a[k];
        bp[k] = p[k] - b[k];
        cp[k] = p[k] - c[k];
    }
#define DOT(x, y) ((x)[0] * (y)[0] + (x)[1] * (y)[1] + (x)[2] * (y)[2])
    double d1 = DOT(ab, ap), d2 = DOT(ac, ap), d3 = DOT(ab, bp), d4 = DOT(ac, bp), d5 = DOT(ab, cp), d6 = DOT(ac, cp);
#undef DOT
    double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
    double s = 0.0, t = 0.0; // q = a + s ab + t ac
    if (d1 <= 0 && d2 <= 0) s = 0, t = 0;
    else if (d3 >= 0 && d4 <= d3) s = 1, t = 0;
    else if (vc <= 0 && d1 >= 0 && d3 <= 0) s = d1 / (d1 - d3), t = 0;
    else if (d6 >= 0 && d5 <= d6) s = 0, t = 1;
    else if (vb <= 0 && d2 >= 0 && d6 <= 0) s = 0, t = d2 / (d2 - d6);
    else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        s = 1 - w, t = w;
    } else {
        double den = 1.0 / (va + vb + vc);
        s = vb * den, t = vc * den;
    }
    double d2sum = 0.0;
    for (int k = 0; k < 3; k++) {
        q[k] = a[k] + s * ab[k] + t * ac[k];
        d2sum += (p[k] - q[k]) * (p[k] - q[k]);
    }
    return d2sum;
}

// Marks (1) the sites nearer than `clearance` to some triangle.
static void mark_near(const eng_mesh_data *m, const lattice *l, float clearance, unsigned char *near)
{
    double c2 = (double)clearance * clearance;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->indices + 3 * (size_t)t;
        const float *p[3] = { m->positions + 3 * (size_t)tri[0], m->positions + 3 * (size_t)tri[1],
                              m->positions + 3 * (size_t)tri[2] };
        uint32_t i0[3], i1[3];
        bool any = true;
        for (int k = 0; k < 3 && any; k++) {
            double lo = fmin(p[0][k], fmin(p[1][k], p[2][k])) - clearance;
            double hi = fmax(p[0][k], fmax(p[1][k], p[2][k])) + clearance;
            any = site_range(l, k, lo, hi, &i0[k], &i1[k]);
        }
        if (!any) continue;
        for (uint32_t z = i0[2]; z <= i1[2]; z++)
            for (uint32_t y = i0[1]; y <= i1[1]; y++)
                for (uint32_t x = i0[0]; x <= i1[0]; x++) {
                    size_t s = x + (size_t)l->n[0] * (y + (size_t)l->n[1] * z);
                    if (near[s]) continue;
                    const double q[3] = { site(l, 0, x), site(l, 1, y), site(l, 2, z) };
                    if (distance2_to_triangle(q, p[0], p[1], p[2]) < c2) near[s] = 1;
                }
    }
}

static bool check_fill_options(const eng_mesh_data *m, float spacing, const eng_mesh_fill_options *o, char *err,
                               size_t err_size)
{
    if (!isfinite(spacing) || !(spacing > 0.0f))
        return eng_fail(err, err_size, "mesh '%s': eng_mesh_fill_points: spacing must be finite and > 0 m (got %g)", m->name,
                    (double)spacing);
    if (!isfinite(o->clearance) || o->clearance < 0.0f)
        return eng_fail(err, err_size, "mesh '%s': eng_mesh_fill_options.clearance must be finite and >= 0 m (got %g)",
                    m->name, (double)o->clearance);
    if (o->max_points < 1)
        return eng_fail(err, err_size, "mesh '%s': eng_mesh_fill_options.max_points must be >= 1 (got 0)", m->name);
    static const char *const xyz = "xyzw";
    for (int k = 0; k < 3; k++)
        if (!isfinite(o->position[k]))
            return eng_fail(err, err_size, "mesh '%s': eng_mesh_fill_options.position.%c must be finite (got %g)", m->name,
                        xyz[k], (double)o->position[k]);
    double len2 = 0.0;
    for (int k = 0; k < 4; k++) {
        if (!isfinite(o->rotation[k]))
            return eng_fail(err, err_size, "mesh '%s': eng_mesh_fill_options.rotation.%c must be finite (got %g)", m->name,
                        xyz[k], (double)o->rotation[k]);
        len2 += (double)o->rotation[k] * o->rotation[k];
    }
    if (fabs(sqrt(len2) - 1.0) > 1e-3)
        return eng_fail(err, err_size, "mesh '%s': eng_mesh_fill_options.rotation must be a unit quaternion (x, y, z, w) "
                    "within 1e-3 (got length %g)", m->name, sqrt(len2));
    return true;
}

// position + rotation * p, rotation a unit quaternion (x, y, z, w).
static void place(const eng_mesh_fill_options *o, const double p[3], float out[3])
{
    double q[4], n = 0.0;
    for (int k = 0; k < 4; k++) n += (double)o->rotation[k] * o->rotation[k];
    n = 1.0 / sqrt(n);
    for (int k = 0; k < 4; k++) q[k] = o->rotation[k] * n;
    double t[3] = { 2.0 * (q[1] * p[2] - q[2] * p[1]), 2.0 * (q[2] * p[0] - q[0] * p[2]), 2.0 * (q[0] * p[1] - q[1] * p[0]) };
    double r[3] = { p[0] + q[3] * t[0] + (q[1] * t[2] - q[2] * t[1]), p[1] + q[3] * t[1] + (q[2] * t[0] - q[0] * t[2]),
                    p[2] + q[3] * t[2] + (q[0] * t[1] - q[1] * t[0]) };
    for (int k = 0; k < 3; k++) out[k] = (float)(o->position[k] + r[k]);
}

bool eng_mesh_fill_points(const eng_mesh_data *m, float spacing, const eng_mesh_fill_options *options,
                          float **out_points, uint32_t *out_count, char *err, size_t err_size)
{
    if (!out_points || !out_count)
        return eng_fail(err, err_size, "eng_mesh_fill_points: %s must not be NULL", !out_points ? "out_points" : "out_count");
    *out_points = NULL;
    *out_count = 0;
    if (!m || !m->positions || !m->indices || !m->triangle_count)
        return eng_fail(err, err_size, "eng_mesh_fill_points: mesh must be a loaded mesh (got %s)",
                    !m ? "NULL" : "an empty one");
    eng_mesh_fill_options o = options ? *options : eng_default_mesh_fill_options();
    if (!check_fill_options(m, spacing, &o, err, err_size)) return false;
    uint32_t open = eng_mesh_open_edges(m);
    if (open == UINT32_MAX) return eng_fail(err, err_size, "mesh '%s': out of memory checking its edges", m->name);
    if (open > 0)
        return eng_fail(err, err_size, "mesh '%s' has %u open edge%s (edges of one triangle only: holes): it has no inside "
                    "to fill (close it, e.g. cap its holes)", m->name, open, open == 1 ? "" : "s");
    lattice l;
    l.spacing = spacing;
    double sites = 1.0;
    for (int k = 0; k < 3; k++) {
        l.lo[k] = m->bounds_min[k];
        double c = floor((double)(m->bounds_max[k] - m->bounds_min[k]) / spacing + 1e-4);
        if (c > (double)ENG_MESH_FILL_MAX_SITES) c = (double)ENG_MESH_FILL_MAX_SITES + 1.0;
        l.n[k] = c < 1.0 ? 1u : (uint32_t)c;
        sites *= l.n[k];
    }
    if (sites > (double)ENG_MESH_FILL_MAX_SITES)
        return eng_fail(err, err_size, "mesh '%s': a lattice of %g m over its %g x %g x %g m bounds has %.0f sites, more than "
                    "%u (use a larger spacing)", m->name, (double)spacing,
                    (double)(m->bounds_max[0] - m->bounds_min[0]), (double)(m->bounds_max[1] - m->bounds_min[1]),
                    (double)(m->bounds_max[2] - m->bounds_min[2]), sites, ENG_MESH_FILL_MAX_SITES);
    l.a = l.n[0] >= l.n[1] && l.n[0] >= l.n[2] ? 0 : l.n[1] >= l.n[2] ? 1 : 2;
    l.u = (l.a + 1) % 3;
    l.v = (l.a + 2) % 3;
    uint32_t rows = l.n[l.u] * l.n[l.v];

    crossings cs = { NULL, 0, 0 };
    uint32_t *first = calloc((size_t)rows + 1, sizeof *first);
    double *at = NULL;
    unsigned char *near = NULL;
    bool ok = false;
    if (!first || !cross_rows(m, &l, &cs)) goto oom;
    // Counting sort of the crossings by row; each row's sorted along the ray.
    for (size_t i = 0; i < cs.n; i++) first[cs.c[i].row + 1]++;
    for (uint32_t r = 0; r < rows; r++) first[r + 1] += first[r];
    at = malloc((cs.n + 1) * sizeof *at);
    if (!at) goto oom;
    {
        uint32_t *fill = malloc((size_t)rows * sizeof *fill + 4);
        if (!fill) goto oom;
        memcpy(fill, first, (size_t)rows * sizeof *fill);
        for (size_t i = 0; i < cs.n; i++) at[fill[cs.c[i].row]++] = cs.c[i].at;
        free(fill);
    }
    free(cs.c);
    cs.c = NULL;
    for (uint32_t r = 0; r < rows; r++) {
        uint32_t n = first[r + 1] - first[r];
        if (n & 1u) {
            eng_fail(err, err_size, "mesh '%s': a row of sites at %c = %g, %c = %g crosses its surface %u times, an odd number, "
                 "though every edge is shared: the mesh is degenerate there (overlapping or tiny triangles)", m->name,
                 "xyz"[l.u], site(&l, l.u, r % l.n[l.u]), "xyz"[l.v], site(&l, l.v, r / l.n[l.u]), n);
            goto done;
        }
        if (n > 1) qsort(at + first[r], n, sizeof *at, compare_double);
    }
    if (o.clearance > 0.0f) {
        near = calloc((size_t)sites, 1);
        if (!near) goto oom;
        mark_near(m, &l, o.clearance, near);
    }
    // Two passes over the rows: count, then write.
    uint32_t count = 0;
    float *points = NULL;
    for (int pass = 0; pass < 2; pass++) {
        uint32_t written = 0;
        for (uint32_t r = 0; r < rows; r++) {
            const double *c = at + first[r];
            uint32_t n = first[r + 1] - first[r], p = 0;
            if (n == 0) continue;
            uint32_t idx[3];
            idx[l.u] = r % l.n[l.u];
            idx[l.v] = r / l.n[l.u];
            for (uint32_t i = 0; i < l.n[l.a]; i++) {
                double x = site(&l, l.a, i);
                while (p < n && c[p] < x) p++;
                if (!(p & 1u) || (p < n && c[p] == x)) continue; // outside, or on the surface
                idx[l.a] = i;
                if (near && near[idx[0] + (size_t)l.n[0] * (idx[1] + (size_t)l.n[1] * idx[2])]) continue;
                if (pass == 1) {
                    const double q[3] = { site(&l, 0, idx[0]), site(&l, 1, idx[1]), site(&l, 2, idx[2]) };
                    place(&o, q, points + 3 * (size_t)written);
                }
                written++;
            }
        }
        if (pass == 0) {
            count = written;
            if (count > o.max_points) {
                eng_fail(err, err_size, "mesh '%s' holds %u lattice sites of %g m, more than max_points %u", m->name, count,
                     (double)spacing, o.max_points);
                goto done;
            }
            if (count == 0) break;
            points = malloc(3 * (size_t)count * sizeof *points);
            if (!points) goto oom;
        }
    }
    *out_points = points;
    *out_count = count;
    ok = true;
    goto done;
oom:
    eng_fail(err, err_size, "mesh '%s': out of memory filling it", m->name);
done:
    free(cs.c);
    free(first);
    free(at);
    free(near);
    return ok;
}
