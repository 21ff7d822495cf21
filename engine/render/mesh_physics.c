// Bullet shapes from a mesh (mesh_physics.h): hull points, hulls moved to their centre of
// mass, static triangle meshes.
#include "engine/render/mesh_physics.h"
#include "engine/core/log.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static bool check_mesh(const eng_mesh_data *m, const char *fn, char *err, size_t err_size)
{
    if (!m || !m->positions || !m->indices || m->vertex_count < 3 || !m->triangle_count)
        return eng_fail(err, err_size, "%s: mesh must be a loaded mesh (got %s)", fn, !m ? "NULL" : "an empty one");
    return true;
}

// ---- hull points ----------------------------------------------------------------------------

// Direction k of the sequence: the six axes, a cube's eight corners and twelve edges, then
// the R2 low-discrepancy sequence (Roberts 2018) mapped onto the sphere by equal areas.
static void direction(uint32_t k, double d[3])
{
    if (k < 6) { // +x, -x, +y, -y, +z, -z
        d[0] = d[1] = d[2] = 0.0;
        d[k / 2] = k % 2 ? -1.0 : 1.0;
        return;
    }
    if (k < 14) { // corners
        for (int a = 0; a < 3; a++) d[a] = (k - 6) >> a & 1 ? -1.0 : 1.0;
        return;
    }
    if (k < 26) { // edges: one axis 0, the other two +-1
        uint32_t e = k - 14, zero = e / 4;
        for (int a = 0, b = 0; a < 3; a++) d[a] = (uint32_t)a == zero ? 0.0 : e >> b++ & 1 ? -1.0 : 1.0;
        return;
    }
    const double g = 1.32471795724474602596; // plastic number
    double s = 0.5 + (double)(k - 26) / g, t = 0.5 + (double)(k - 26) / (g * g);
    s -= floor(s);
    t -= floor(t);
    double z = 1.0 - 2.0 * s, r = sqrt(fmax(0.0, 1.0 - z * z)), phi = 2.0 * 3.14159265358979323846 * t;
    d[0] = r * cos(phi);
    d[1] = r * sin(phi);
    d[2] = z;
}

bool eng_mesh_hull_points(const eng_mesh_data *m, uint32_t max_points, phys_vec3 **out_points, uint32_t *out_count,
                          char *err, size_t err_size)
{
    if (!out_points || !out_count)
        return eng_fail(err, err_size, "eng_mesh_hull_points: %s must not be NULL", !out_points ? "out_points" : "out_count");
    *out_points = NULL;
    *out_count = 0;
    if (!check_mesh(m, "eng_mesh_hull_points", err, err_size)) return false;
    if (max_points < ENG_MESH_HULL_MIN_POINTS || max_points > ENG_MESH_HULL_MAX_POINTS)
        return eng_fail(err, err_size, "mesh '%s': hull max_points must be in [%d, %d] (got %u)", m->name,
                    ENG_MESH_HULL_MIN_POINTS, ENG_MESH_HULL_MAX_POINTS, max_points);
    uint32_t n = m->vertex_count;
    phys_vec3 *pts = malloc((size_t)(n < max_points ? n : max_points) * sizeof *pts);
    if (!pts) return eng_fail(err, err_size, "mesh '%s': out of memory", m->name);
    uint32_t count = 0;
    if (n <= max_points) {
        for (uint32_t i = 0; i < n; i++)
            pts[count++] = (phys_vec3){ m->positions[3 * i], m->positions[3 * i + 1], m->positions[3 * i + 2] };
    } else {
        uint32_t *chosen = malloc((size_t)max_points * sizeof *chosen);
        if (!chosen) {
            free(pts);
            return eng_fail(err, err_size, "mesh '%s': out of memory", m->name);
        }
        // Extremes are taken about the bounds' centre (the directions do not care, the
        // rounding does).
        double c[3];
        for (int k = 0; k < 3; k++) c[k] = 0.5 * ((double)m->bounds_min[k] + m->bounds_max[k]);
        const uint32_t tries = 64u * max_points;
        for (uint32_t k = 0; k < tries && count < max_points; k++) {
            double d[3], best = -INFINITY;
            direction(k, d);
            uint32_t arg = 0;
            for (uint32_t i = 0; i < n; i++) {
                const float *p = m->positions + 3 * (size_t)i;
                double s = (p[0] - c[0]) * d[0] + (p[1] - c[1]) * d[1] + (p[2] - c[2]) * d[2];
                if (s > best) best = s, arg = i;
            }
            bool seen = false;
            for (uint32_t j = 0; j < count && !seen; j++) seen = chosen[j] == arg;
            if (seen) continue;
            chosen[count] = arg;
            const float *p = m->positions + 3 * (size_t)arg;
            pts[count++] = (phys_vec3){ p[0], p[1], p[2] };
        }
        free(chosen);
    }
    *out_points = pts;
    *out_count = count;
    return true;
}

// ---- the hull's centre of mass ----------------------------------------------------------------

// Volume and centroid of a convex hull from its corners and face planes: each face's corners
// in order around its normal, fanned into tetrahedra with an inner point.
static bool hull_centroid(const phys_hull_desc *h, double centroid[3], double *volume)
{
    uint32_t np = h->point_count;
    uint32_t *face = malloc((size_t)np * sizeof *face + 4);
    double *ang = malloc((size_t)np * sizeof *ang + 8);
    if (!face || !ang) {
        free(face);
        free(ang);
        return false;
    }
    double o[3] = { 0, 0, 0 }, scale = 0.0;
    for (uint32_t i = 0; i < np; i++) {
        const double p[3] = { h->points[i].x, h->points[i].y, h->points[i].z };
        for (int k = 0; k < 3; k++) o[k] += p[k] / np;
    }
    for (uint32_t i = 0; i < np; i++)
        scale = fmax(scale, fmax(fabs(h->points[i].x - o[0]), fmax(fabs(h->points[i].y - o[1]), fabs(h->points[i].z - o[2]))));
    double eps = 1e-4 * scale + 1e-9, vol = 0.0, acc[3] = { 0, 0, 0 };
    for (uint32_t f = 0; f < h->plane_count; f++) {
        const double n[3] = { h->planes[f].normal.x, h->planes[f].normal.y, h->planes[f].normal.z };
        uint32_t k = 0;
        double c[3] = { 0, 0, 0 };
        for (uint32_t i = 0; i < np; i++) {
            const phys_vec3 *p = &h->points[i];
            if (fabs(n[0] * p->x + n[1] * p->y + n[2] * p->z - h->planes[f].offset) > eps) continue;
            face[k++] = i;
            c[0] += p->x, c[1] += p->y, c[2] += p->z;
        }
        if (k < 3) continue;
        for (int a = 0; a < 3; a++) c[a] /= k;
        // A frame (e1, e2) in the face's plane, angles of the corners about its centre.
        double e1[3] = { 1, 0, 0 };
        if (fabs(n[0]) > 0.9) e1[0] = 0, e1[1] = 1;
        double dn = e1[0] * n[0] + e1[1] * n[1] + e1[2] * n[2];
        for (int a = 0; a < 3; a++) e1[a] -= dn * n[a];
        double e2[3] = { n[1] * e1[2] - n[2] * e1[1], n[2] * e1[0] - n[0] * e1[2], n[0] * e1[1] - n[1] * e1[0] };
        for (uint32_t i = 0; i < k; i++) {
            const phys_vec3 *p = &h->points[face[i]];
            double r[3] = { p->x - c[0], p->y - c[1], p->z - c[2] };
            ang[i] = atan2(r[0] * e2[0] + r[1] * e2[1] + r[2] * e2[2], r[0] * e1[0] + r[1] * e1[1] + r[2] * e1[2]);
        }
        for (uint32_t i = 1; i < k; i++) // insertion sort by angle (faces are small)
            for (uint32_t j = i; j > 0 && ang[j - 1] > ang[j]; j--) {
                double ta = ang[j];
                ang[j] = ang[j - 1], ang[j - 1] = ta;
                uint32_t tf = face[j];
                face[j] = face[j - 1], face[j - 1] = tf;
            }
        const phys_vec3 *a = &h->points[face[0]];
        for (uint32_t i = 1; i + 1 < k; i++) {
            const phys_vec3 *b = &h->points[face[i]], *d = &h->points[face[i + 1]];
            double u[3] = { a->x - o[0], a->y - o[1], a->z - o[2] }, v[3] = { b->x - o[0], b->y - o[1], b->z - o[2] },
                   w[3] = { d->x - o[0], d->y - o[1], d->z - o[2] };
            double t = fabs(u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                            u[2] * (v[0] * w[1] - v[1] * w[0])) / 6.0;
            vol += t;
            acc[0] += t * (o[0] + a->x + b->x + d->x) / 4.0;
            acc[1] += t * (o[1] + a->y + b->y + d->y) / 4.0;
            acc[2] += t * (o[2] + a->z + b->z + d->z) / 4.0;
        }
    }
    free(face);
    free(ang);
    if (!(vol > 0.0)) return false;
    for (int k = 0; k < 3; k++) centroid[k] = acc[k] / vol;
    *volume = vol;
    return true;
}

bool eng_mesh_create_hull(phys_world *w, const eng_mesh_data *m, uint32_t max_points, eng_mesh_hull *out, char *err,
                          size_t err_size)
{
    if (!w || !out) return eng_fail(err, err_size, "eng_mesh_create_hull: %s must not be NULL", !w ? "world" : "out");
    memset(out, 0, sizeof *out);
    phys_vec3 *pts;
    uint32_t n;
    if (!eng_mesh_hull_points(m, max_points, &pts, &n, err, err_size)) return false;
    phys_convex_hull hull = { pts, n };
    phys_shape_id shape;
    if (phys_shape_create_convex_hull(w, &hull, &shape) != PHYS_OK) {
        free(pts);
        return eng_fail(err, err_size, "mesh '%s': no convex hull: %s", m->name, phys_world_last_error(w));
    }
    phys_shape_desc d;
    double com[3], vol;
    if (phys_shape_get_desc(w, shape, &d) != PHYS_OK || !hull_centroid(&d.hull, com, &vol)) {
        phys_shape_destroy(w, shape);
        free(pts);
        return eng_fail(err, err_size, "mesh '%s': the convex hull's centre of mass could not be found (%s)", m->name,
                    phys_world_last_error(w));
    }
    // Made again around its centre of mass (the first one only told where that is).
    phys_shape_destroy(w, shape);
    for (uint32_t i = 0; i < n; i++) {
        pts[i].x = (float)(pts[i].x - com[0]);
        pts[i].y = (float)(pts[i].y - com[1]);
        pts[i].z = (float)(pts[i].z - com[2]);
    }
    phys_result r = phys_shape_create_convex_hull(w, &hull, &shape);
    free(pts);
    if (r != PHYS_OK || phys_shape_get_desc(w, shape, &d) != PHYS_OK)
        return eng_fail(err, err_size, "mesh '%s': no convex hull: %s", m->name, phys_world_last_error(w));
    if (d.hull.plane_count > PBF_MAX_HULL_PLANES) { // 2 n - 4 faces at most: cannot happen
        phys_shape_destroy(w, shape);
        return eng_fail(err, err_size, "mesh '%s': its hull has %u faces, more than the fluid's %d", m->name,
                    d.hull.plane_count, PBF_MAX_HULL_PLANES);
    }
    out->shape = shape;
    for (int k = 0; k < 3; k++) out->centre_of_mass[k] = (float)com[k];
    out->volume = d.volume;
    out->point_count = d.hull.point_count;
    out->face_count = d.hull.plane_count;
    return true;
}

// ---- static triangle meshes --------------------------------------------------------------------

bool eng_mesh_create_static_shape(phys_world *w, const eng_mesh_data *m, phys_shape_id *out, char *err,
                                  size_t err_size)
{
    if (!w || !out)
        return eng_fail(err, err_size, "eng_mesh_create_static_shape: %s must not be NULL", !w ? "world" : "out");
    if (!check_mesh(m, "eng_mesh_create_static_shape", err, err_size)) return false;
    phys_vec3 *v = malloc((size_t)m->vertex_count * sizeof *v);
    if (!v) return eng_fail(err, err_size, "mesh '%s': out of memory", m->name);
    for (uint32_t i = 0; i < m->vertex_count; i++)
        v[i] = (phys_vec3){ m->positions[3 * (size_t)i], m->positions[3 * (size_t)i + 1], m->positions[3 * (size_t)i + 2] };
    phys_triangle_mesh tm = { v, m->vertex_count, m->indices, m->triangle_count };
    phys_result r = phys_shape_create_triangle_mesh(w, &tm, out);
    free(v);
    if (r != PHYS_OK) return eng_fail(err, err_size, "mesh '%s': no triangle mesh shape: %s", m->name, phys_world_last_error(w));
    return true;
}
