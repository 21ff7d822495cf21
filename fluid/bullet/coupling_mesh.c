// Triangle meshes as signed distance grids for the fluid (coupling_mesh.h).
#include "fluid/bullet/coupling_mesh.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct v3 {
    double x, y, z;
} v3;

static v3 vsub(v3 a, v3 b) { return (v3){ a.x - b.x, a.y - b.y, a.z - b.z }; }
static v3 vadd(v3 a, v3 b) { return (v3){ a.x + b.x, a.y + b.y, a.z + b.z }; }
static v3 vmul(v3 a, double s) { return (v3){ a.x * s, a.y * s, a.z * s }; }
static double vdot(v3 a, v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static v3 vcross(v3 a, v3 b) { return (v3){ a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x }; }
static v3 from_phys(phys_vec3 p) { return (v3){ p.x, p.y, p.z }; }

// Closest point to p on triangle abc (Ericson, Real-Time Collision Detection 5.1.5).
static v3 closest_on_triangle(v3 p, v3 a, v3 b, v3 c)
{
    v3 ab = vsub(b, a), ac = vsub(c, a), ap = vsub(p, a);
    double d1 = vdot(ab, ap), d2 = vdot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    v3 bp = vsub(p, b);
    double d3 = vdot(ab, bp), d4 = vdot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return vadd(a, vmul(ab, d1 / (d1 - d3)));
    v3 cp = vsub(p, c);
    double d5 = vdot(ab, cp), d6 = vdot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return vadd(a, vmul(ac, d2 / (d2 - d6)));
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
        return vadd(b, vmul(vsub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
    double denom = 1.0 / (va + vb + vc);
    return vadd(a, vadd(vmul(ab, vb * denom), vmul(ac, vc * denom)));
}

// ---- open or closed ---------------------------------------------------------------------------

// Vertices are told apart by position, not index: a mesh from a file may repeat a corner once
// per face it belongs to.
typedef struct vkey {
    float p[3];
    uint32_t index;
} vkey;

static int cmp_vkey(const void *a, const void *b)
{
    const vkey *x = a, *y = b;
    for (int k = 0; k < 3; k++)
        if (x->p[k] != y->p[k]) return x->p[k] < y->p[k] ? -1 : 1;
    return 0;
}

static int cmp_edge(const void *a, const void *b)
{
    const uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

// Closed when every edge (between two distinct corners) belongs to exactly two triangles.
// -1 when out of memory.
static int mesh_is_closed(const phys_triangle_mesh *m)
{
    uint32_t nv = m->vertex_count;
    size_t ne = 3 * (size_t)m->triangle_count;
    vkey *keys = malloc((size_t)nv * sizeof *keys);
    uint32_t *canon = malloc((size_t)nv * sizeof *canon);
    uint64_t *edges = malloc(ne * sizeof *edges);
    if (!keys || !canon || !edges) {
        free(keys);
        free(canon);
        free(edges);
        return -1;
    }
    for (uint32_t i = 0; i < nv; i++) {
        keys[i] = (vkey){ { m->vertices[i].x, m->vertices[i].y, m->vertices[i].z }, i };
    }
    qsort(keys, nv, sizeof *keys, cmp_vkey);
    for (uint32_t i = 0, first = 0; i < nv; i++) {
        if (i > 0 && cmp_vkey(&keys[i], &keys[first]) != 0) first = i;
        canon[keys[i].index] = keys[first].index;
    }
    size_t n = 0;
    for (uint32_t t = 0; t < m->triangle_count; t++)
        for (int k = 0; k < 3; k++) {
            uint32_t a = canon[m->indices[3 * t + k]], b = canon[m->indices[3 * t + (k + 1) % 3]];
            if (a == b) continue; // a degenerate triangle's collapsed edge
            edges[n++] = a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
        }
    qsort(edges, n, sizeof *edges, cmp_edge);
    int closed = n > 0;
    for (size_t i = 0; i < n && closed;) {
        size_t j = i;
        while (j < n && edges[j] == edges[i]) j++;
        if (j - i != 2) closed = 0;
        i = j;
    }
    free(keys);
    free(canon);
    free(edges);
    return closed;
}

// ---- the grid --------------------------------------------------------------------------------

bool cpl_bake_mesh(const phys_triangle_mesh *m, float h, float *cell_io, cpl_mesh_bake *out)
{
    memset(out, 0, sizeof *out);
    int closed = mesh_is_closed(m);
    if (closed < 0) return false;
    // An open mesh's shell ends h behind it; the grid reaches a kernel past that too.
    double shell = h;
    double margin = (closed ? h : shell + h) + 2.0 * (double)*cell_io;
    v3 lo = { INFINITY, INFINITY, INFINITY }, hi = { -INFINITY, -INFINITY, -INFINITY };
    for (uint32_t t = 0; t < 3 * m->triangle_count; t++) {
        v3 p = from_phys(m->vertices[m->indices[t]]);
        lo = (v3){ fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z) };
        hi = (v3){ fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z) };
    }
    double cell = *cell_io;
    double ext[3] = { hi.x - lo.x + 2 * margin, hi.y - lo.y + 2 * margin, hi.z - lo.z + 2 * margin };
    double biggest = fmax(ext[0], fmax(ext[1], ext[2]));
    if (biggest / cell > 127.0) cell = biggest / 127.0;
    uint32_t dims[3];
    for (int k = 0; k < 3; k++) dims[k] = (uint32_t)ceil(ext[k] / cell) + 1;
    size_t n = (size_t)dims[0] * dims[1] * dims[2];
    float *values = malloc(n * sizeof *values);
    size_t tc = m->triangle_count;
    v3 *tri = malloc(tc * 4 * sizeof *tri); // corners and unit normal, gathered once
    if (!values || !tri) {
        free(values);
        free(tri);
        return false;
    }
    v3 origin = { lo.x - margin, lo.y - margin, lo.z - margin };
    for (size_t t = 0; t < tc; t++) {
        v3 a = from_phys(m->vertices[m->indices[3 * t]]);
        v3 b = from_phys(m->vertices[m->indices[3 * t + 1]]);
        v3 cc = from_phys(m->vertices[m->indices[3 * t + 2]]);
        v3 nrm = vcross(vsub(b, a), vsub(cc, a));
        double l = sqrt(vdot(nrm, nrm));
        tri[4 * t] = a;
        tri[4 * t + 1] = b;
        tri[4 * t + 2] = cc;
        tri[4 * t + 3] = l > 0 ? vmul(nrm, 1.0 / l) : (v3){ 0, 0, 0 };
    }
    for (uint32_t z = 0; z < dims[2]; z++)
        for (uint32_t y = 0; y < dims[1]; y++)
            for (uint32_t x = 0; x < dims[0]; x++) {
                v3 p = { origin.x + x * cell, origin.y + y * cell, origin.z + z * cell };
                double best = INFINITY, best_align = 0.0, sign = 1.0;
                for (size_t t = 0; t < tc; t++) {
                    v3 q = closest_on_triangle(p, tri[4 * t], tri[4 * t + 1], tri[4 * t + 2]);
                    v3 dv = vsub(p, q);
                    double d2 = vdot(dv, dv);
                    if (d2 > best * (1.0 + 1e-9) + 1e-18) continue;
                    double d = sqrt(d2);
                    // Among (nearly) equally near triangles, the one whose normal is most
                    // aligned with the direction to p decides the side (edges, corners).
                    double along = d > 0 ? vdot(dv, tri[4 * t + 3]) / d : 0.0;
                    if (d2 < best * (1.0 - 1e-9) - 1e-18 || fabs(along) > best_align) {
                        best = d2;
                        best_align = fabs(along);
                        sign = along >= 0 ? 1.0 : -1.0;
                    }
                }
                double sd = sign * sqrt(best);
                // Behind an open mesh: inside its shell, then outside again past its back.
                if (!closed && sd < 0.0) sd = fmax(sd, -shell - sd);
                values[x + dims[0] * ((size_t)y + dims[1] * (size_t)z)] = (float)sd;
            }
    free(tri);
    out->values = values;
    out->grid.values = values;
    for (int k = 0; k < 3; k++) out->grid.dims[k] = dims[k];
    out->grid.origin[0] = (float)origin.x;
    out->grid.origin[1] = (float)origin.y;
    out->grid.origin[2] = (float)origin.z;
    out->grid.cell = (float)cell;
    out->extent = (float)biggest;
    out->closed = closed == 1;
    *cell_io = (float)cell;
    return true;
}
