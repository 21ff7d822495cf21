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

// ---- the nearest triangle ---------------------------------------------------------------------

// A bounding volume hierarchy over the triangles, so that a sample's nearest triangle costs a
// few dozen tests instead of one per triangle: split at the median of the centroids along
// their widest axis (depth at most log2 of the count, whatever the mesh), leaves of at most
// BVH_LEAF triangles, depth first (an inner node's first child is the next node).
#define BVH_LEAF 4
#define BVH_STACK 96

typedef struct bvh_node {
    double lo[3], hi[3];
    uint32_t first, count; // count > 0: a leaf of order[first, first + count)
    uint32_t right;        // an inner node's second child (its first is the next node)
} bvh_node;

typedef struct bake_tris {
    const v3 *tri; // four per triangle: corners a, b, c and the unit normal
    const bvh_node *nodes;
    const uint32_t *order;
    uint64_t tests;
} bake_tris;

static double axis_of(v3 p, int k) { return k == 0 ? p.x : k == 1 ? p.y : p.z; }

// Sorts ix[0, n) by key (heapsort: n log n whatever the order).
static void sift_down(uint32_t *ix, size_t root, size_t n, const double *key)
{
    for (;;) {
        size_t child = 2 * root + 1;
        if (child >= n) return;
        if (child + 1 < n && key[ix[child + 1]] > key[ix[child]]) child++;
        if (!(key[ix[child]] > key[ix[root]])) return;
        uint32_t t = ix[root];
        ix[root] = ix[child];
        ix[child] = t;
        root = child;
    }
}

static void sort_by_key(uint32_t *ix, size_t n, const double *key)
{
    for (size_t i = n / 2; i-- > 0;) sift_down(ix, i, n, key);
    for (size_t end = n; end-- > 1;) {
        uint32_t t = ix[0];
        ix[0] = ix[end];
        ix[end] = t;
        sift_down(ix, 0, end, key);
    }
}

// Puts the k-th smallest key of ix[0, n) at ix[k], smaller ones before it, larger after:
// three-way partitions around pivots from a fixed pseudo-random sequence (linear time
// expected, equal keys cost nothing), and should a mesh defeat the pivots, a sort of what is
// left after 2 log2 n + 16 rounds (so never worse than n log n).
static void select_kth(uint32_t *ix, size_t n, size_t k, const double *key, uint64_t *rng)
{
    size_t lo = 0, hi = n;
    int rounds = 16;
    for (size_t m = n; m > 1; m /= 2) rounds += 2;
    while (hi - lo > 1) {
        if (rounds-- == 0) {
            sort_by_key(ix + lo, hi - lo, key);
            return;
        }
        *rng = *rng * 6364136223846793005ull + 1442695040888963407ull;
        const double pivot = key[ix[lo + (size_t)((*rng >> 33) % (hi - lo))]];
        size_t lt = lo, i = lo, gt = hi;
        while (i < gt) {
            const double v = key[ix[i]];
            uint32_t t = ix[i];
            if (v < pivot) {
                ix[i++] = ix[lt];
                ix[lt++] = t;
            } else if (v > pivot) {
                ix[i] = ix[--gt];
                ix[gt] = t;
            } else {
                i++;
            }
        }
        if (k < lt) hi = lt;
        else if (k >= gt) lo = gt;
        else return;
    }
}

// Builds the hierarchy into nodes (room for 2 tc nodes) and order (tc). False when out of memory.
static bool bvh_build(const v3 *tri, uint32_t tc, bvh_node *nodes, uint32_t *order)
{
    double *cent = malloc(3 * (size_t)tc * sizeof *cent), *key = malloc((size_t)tc * sizeof *key);
    if (!cent || !key) {
        free(cent);
        free(key);
        return false;
    }
    for (uint32_t t = 0; t < tc; t++) {
        order[t] = t;
        for (int k = 0; k < 3; k++)
            cent[3 * t + k] = (axis_of(tri[4 * t], k) + axis_of(tri[4 * t + 1], k) + axis_of(tri[4 * t + 2], k)) / 3.0;
    }
    typedef struct task {
        uint32_t parent, first, count; // parent UINT32_MAX: the root, or a first child
    } task;
    task stack[BVH_STACK];
    int top = 0;
    stack[top++] = (task){ UINT32_MAX, 0, tc };
    uint32_t used = 0;
    uint64_t rng = 0x5eed;
    while (top > 0) {
        task w = stack[--top];
        uint32_t at = used++;
        if (w.parent != UINT32_MAX) nodes[w.parent].right = at;
        bvh_node *nd = &nodes[at];
        double clo[3] = { INFINITY, INFINITY, INFINITY }, chi[3] = { -INFINITY, -INFINITY, -INFINITY };
        for (int k = 0; k < 3; k++) {
            nd->lo[k] = INFINITY;
            nd->hi[k] = -INFINITY;
        }
        for (uint32_t i = w.first; i < w.first + w.count; i++) {
            uint32_t t = order[i];
            for (int c = 0; c < 3; c++)
                for (int k = 0; k < 3; k++) {
                    double v = axis_of(tri[4 * t + c], k);
                    nd->lo[k] = fmin(nd->lo[k], v);
                    nd->hi[k] = fmax(nd->hi[k], v);
                }
            for (int k = 0; k < 3; k++) {
                clo[k] = fmin(clo[k], cent[3 * t + k]);
                chi[k] = fmax(chi[k], cent[3 * t + k]);
            }
        }
        nd->first = w.first;
        nd->right = 0;
        if (w.count <= BVH_LEAF) {
            nd->count = w.count;
            continue;
        }
        nd->count = 0;
        int axis = 0;
        for (int k = 1; k < 3; k++)
            if (chi[k] - clo[k] > chi[axis] - clo[axis]) axis = k;
        for (uint32_t i = w.first; i < w.first + w.count; i++) key[order[i]] = cent[3 * order[i] + axis];
        uint32_t half = w.count / 2;
        select_kth(order + w.first, w.count, half, key, &rng);
        // The second child is pushed first, so the first is built next and sits at at + 1.
        stack[top++] = (task){ at, w.first + half, w.count - half };
        stack[top++] = (task){ UINT32_MAX, w.first, half };
    }
    free(cent);
    free(key);
    return true;
}

static double box_distance2(const bvh_node *nd, v3 p)
{
    double d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        double v = axis_of(p, k), e = fmax(fmax(nd->lo[k] - v, v - nd->hi[k]), 0.0);
        d2 += e * e;
    }
    return d2;
}

// The nearest triangles to a point so far: the squared distance, and the side of the one whose
// normal is most aligned with the direction to the point among (nearly) equally near ones
// (edges, corners).
typedef struct nearest {
    double best, best_align, sign;
    uint32_t triangle;
} nearest;

// Farther than the nearest so far by more than the tie margin, or not a number (the closest
// point of a degenerate triangle can be NaN): never taken.
static bool beyond(double d2, const nearest *n) { return !(d2 <= n->best * (1.0 + 1e-9) + 1e-18); }

static void consider(bake_tris *b, uint32_t t, v3 p, nearest *n)
{
    const v3 *tr = &b->tri[4 * (size_t)t];
    b->tests++;
    v3 dv = vsub(p, closest_on_triangle(p, tr[0], tr[1], tr[2]));
    double d2 = vdot(dv, dv);
    if (beyond(d2, n)) return;
    double d = sqrt(d2);
    double along = d > 0 ? vdot(dv, tr[3]) / d : 0.0;
    // An exact tie (duplicates, degenerate triangles) goes to the first triangle of the list,
    // whatever order the hierarchy visits them in.
    if (d2 < n->best * (1.0 - 1e-9) - 1e-18 || fabs(along) > n->best_align ||
        (fabs(along) == n->best_align && t < n->triangle)) {
        n->best = d2;
        n->best_align = fabs(along);
        n->sign = along >= 0 ? 1.0 : -1.0;
        n->triangle = t;
    }
}

// The nearest triangle to p within sqrt(within2) (n.triangle UINT32_MAX: none): the same
// triangle, distance and side as testing every triangle in the list's order. hint: a triangle
// near p (the last sample's nearest), tried first so that most of the hierarchy is pruned at
// once.
static nearest search(bake_tris *b, v3 p, uint32_t hint, double within2)
{
    nearest n = { within2, 0.0, 1.0, UINT32_MAX };
    if (hint != UINT32_MAX) consider(b, hint, p, &n);
    uint32_t stack[BVH_STACK];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const bvh_node *nd = &b->nodes[stack[--top]];
        if (beyond(box_distance2(nd, p), &n)) continue;
        if (nd->count > 0) {
            for (uint32_t i = nd->first; i < nd->first + nd->count; i++) consider(b, b->order[i], p, &n);
            continue;
        }
        uint32_t first = (uint32_t)(nd - b->nodes) + 1, second = nd->right;
        double d_first = box_distance2(&b->nodes[first], p), d_second = box_distance2(&b->nodes[second], p);
        bool first_nearer = d_first <= d_second;
        // The farther child is pushed first, so the nearer one is searched first.
        uint32_t near_child = first_nearer ? first : second, far_child = first_nearer ? second : first;
        if (!beyond(first_nearer ? d_second : d_first, &n)) stack[top++] = far_child;
        if (!beyond(first_nearer ? d_first : d_second, &n)) stack[top++] = near_child;
    }
    return n;
}

// Beyond the band only the side and a distance that grows the right way matter (the fluid
// reads the grid within a kernel of the surface; a particle deep inside a solid is pushed out
// along its gradient): the far samples take the chamfer distance from the band, the least
// over paths of steps to the 26 neighbours (1, sqrt 2 or sqrt 3 cells) of a band sample's
// distance plus the path's length. Never shorter than the true distance, at most 12.8 %
// longer (a direction between the steps'), and O(samples) where the exact search would test every facet near the middle of a
// round solid. Forward and backward raster sweeps until a sweep changes nothing (values only
// fall, so it ends): five or six for the meshes tried, the last changing nothing (a sweep
// passes values on along the 13 neighbours it has passed, so a path that turns against both
// orders takes more than two).
// Magnitudes only: far values stay positive here, their side comes after.
static void chamfer_far_field(float *values, const uint8_t *far, const uint32_t dims[3], double cell)
{
    const int64_t sx = 1, sy = dims[0], sz = (int64_t)dims[0] * dims[1];
    // A step's length by its squared length in cells (1, 2 or 3).
    const float step[4] = { 0.0f, (float)cell, (float)(cell * sqrt(2.0)), (float)(cell * sqrt(3.0)) };
    for (int sweep = 0;; sweep++) {
        bool changed = false;
        const int dir = sweep % 2 == 0 ? 1 : -1;
        for (int64_t zz = 0; zz < dims[2]; zz++)
            for (int64_t yy = 0; yy < dims[1]; yy++)
                for (int64_t xx = 0; xx < dims[0]; xx++) {
                    int64_t x = dir > 0 ? xx : dims[0] - 1 - xx, y = dir > 0 ? yy : dims[1] - 1 - yy,
                            z = dir > 0 ? zz : dims[2] - 1 - zz;
                    int64_t i = x * sx + y * sy + z * sz;
                    if (!far[i]) continue;
                    float best = values[i];
                    // The 13 neighbours the sweep has already passed: the previous plane, the
                    // previous row of this plane, the previous sample of this row.
                    for (int dz = -1; dz <= 0; dz++)
                        for (int dy = -1; dy <= 1; dy++)
                            for (int dx = -1; dx <= 1; dx++) {
                                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
                                int64_t qx = x + dir * dx, qy = y + dir * dy, qz = z + dir * dz;
                                if (qx < 0 || qy < 0 || qz < 0 || qx >= dims[0] || qy >= dims[1] || qz >= dims[2])
                                    continue;
                                float q = fabsf(values[qx * sx + qy * sy + qz * sz]) + step[dx * dx + dy * dy + dz * dz];
                                if (q < best) best = q;
                            }
                    if (best < values[i]) {
                        values[i] = best;
                        changed = true;
                    }
                }
        if (!changed && sweep > 0) break;
    }
}

// A closed mesh's far samples take the side of the samples they touch: a sample farther than
// the band from every triangle and its neighbour, a cell away, cannot lie on opposite sides
// (the distance changes by at most a cell between them, and the band is wider), so the side
// spreads from the exactly known samples (far[i] 0) to every far one, breadth first.
static bool spread_sides(float *values, uint8_t *far, const uint32_t dims[3])
{
    size_t n = (size_t)dims[0] * dims[1] * dims[2], head = 0, tail = 0;
    uint32_t *queue = malloc(n * sizeof *queue);
    if (!queue) return false;
    for (size_t i = 0; i < n; i++)
        if (!far[i]) queue[tail++] = (uint32_t)i;
    const size_t step[3] = { 1, dims[0], (size_t)dims[0] * dims[1] };
    while (head < tail) {
        size_t i = queue[head++];
        size_t at[3] = { i % dims[0], (i / dims[0]) % dims[1], i / step[2] };
        for (int k = 0; k < 3; k++)
            for (int dir = -1; dir <= 1; dir += 2) {
                if ((dir < 0 && at[k] == 0) || (dir > 0 && at[k] + 1 == dims[k])) continue;
                size_t j = dir < 0 ? i - step[k] : i + step[k];
                if (!far[j]) continue;
                values[j] = copysignf(fabsf(values[j]), values[i]);
                far[j] = 0;
                queue[tail++] = (uint32_t)j;
            }
    }
    free(queue);
    return true;
}

// The samples within `band` of the mesh, exactly (far[i] set, and INFINITY, for the others).
// shell: an open mesh's shell thickness, or negative for a closed mesh.
static void bake_band(bake_tris *b, v3 origin, double cell, const uint32_t dims[3], double band, double shell,
                      float *values, uint8_t *far)
{
    uint32_t hint = UINT32_MAX;
    for (uint32_t z = 0; z < dims[2]; z++)
        for (uint32_t y = 0; y < dims[1]; y++)
            for (uint32_t x = 0; x < dims[0]; x++) {
                v3 p = { origin.x + x * cell, origin.y + y * cell, origin.z + z * cell };
                size_t i = x + dims[0] * ((size_t)y + dims[1] * (size_t)z);
                nearest nn = search(b, p, hint, band * band);
                if (nn.triangle == UINT32_MAX) {
                    far[i] = 1;
                    values[i] = INFINITY;
                    continue;
                }
                hint = nn.triangle;
                double sd = nn.sign * sqrt(nn.best);
                // Behind an open mesh: inside its shell, then outside again past its back.
                if (shell >= 0.0 && sd < 0.0) sd = fmax(sd, -shell - sd);
                values[i] = (float)sd;
            }
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
    bvh_node *nodes = malloc(2 * tc * sizeof *nodes);
    uint32_t *order = malloc(tc * sizeof *order);
    uint8_t *far = calloc(n, 1); // 1: a sample beyond the band
    bool ok = values && tri && nodes && order && far;
    v3 origin = { lo.x - margin, lo.y - margin, lo.z - margin };
    if (ok) {
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
        ok = bvh_build(tri, (uint32_t)tc, nodes, order);
    }
    bake_tris b = { tri, nodes, order, 0 };
    if (ok) {
        // Exact within the band the fluid reads (a kernel past the surface, or past an open
        // mesh's shell, and two of the grid's cells for the interpolation), roughly beyond it.
        const double band = (closed ? h : shell + h) + 2.0 * cell;
        bake_band(&b, origin, cell, dims, band, closed ? -1.0 : shell, values, far);
        chamfer_far_field(values, far, dims, cell);
        ok = !closed || spread_sides(values, far, dims);
    }
    free(far);
    free(tri);
    free(nodes);
    free(order);
    if (!ok) {
        free(values);
        return false;
    }
    out->triangle_tests = b.tests;
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
