// The meshes and scene nodes that draw a script's bodies: a mesh per shape (convex hulls and
// compounds triangulated here), the node's transform, and eng_script_sync_nodes.
#include "engine/script/script_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// ---- convex hulls ----------------------------------------------------------------------------

// A triangle mesh of a convex hull: each face's points in order around its normal.
static eng_mesh_id hull_mesh(eng_mesh_store *store, const phys_shape_desc *d)
{
    const phys_hull_desc *h = &d->hull;
    uint32_t np = h->point_count;
    float *pos = malloc((size_t)h->plane_count * np * 3 * sizeof(float) + 4);
    uint32_t *idx = malloc((size_t)h->plane_count * np * 3 * sizeof(uint32_t) + 4);
    uint32_t *face = malloc((size_t)np * sizeof(uint32_t) + 4);
    float *ang = malloc((size_t)np * sizeof(float) + 4);
    eng_mesh_id id = ENG_NULL_MESH;
    if (!pos || !idx || !face || !ang) goto done;
    float scale = 0;
    for (uint32_t i = 0; i < np; i++)
        scale = fmaxf(scale, fmaxf(fabsf(h->points[i].x), fmaxf(fabsf(h->points[i].y), fabsf(h->points[i].z))));
    float eps = 1e-4f * scale + 1e-6f;
    int nv = 0, ni = 0;
    for (uint32_t f = 0; f < h->plane_count; f++) {
        const phys_hull_plane *pl = &h->planes[f];
        float n[3] = { pl->normal.x, pl->normal.y, pl->normal.z };
        uint32_t k = 0;
        float c[3] = { 0, 0, 0 };
        for (uint32_t i = 0; i < np; i++) {
            const phys_vec3 *p = &h->points[i];
            if (fabsf(n[0] * p->x + n[1] * p->y + n[2] * p->z - pl->offset) <= eps) {
                face[k++] = i;
                c[0] += p->x, c[1] += p->y, c[2] += p->z;
            }
        }
        if (k < 3) continue;
        for (int a = 0; a < 3; a++) c[a] /= (float)k;
        float u[3] = { 1, 0, 0 };
        if (fabsf(n[0]) > 0.9f) u[0] = 0, u[1] = 1;
        float dn = u[0] * n[0] + u[1] * n[1] + u[2] * n[2];
        for (int a = 0; a < 3; a++) u[a] -= dn * n[a];
        float v[3] = { n[1] * u[2] - n[2] * u[1], n[2] * u[0] - n[0] * u[2], n[0] * u[1] - n[1] * u[0] };
        for (uint32_t i = 0; i < k; i++) {
            const phys_vec3 *p = &h->points[face[i]];
            float r[3] = { p->x - c[0], p->y - c[1], p->z - c[2] };
            ang[i] = atan2f(r[0] * v[0] + r[1] * v[1] + r[2] * v[2], r[0] * u[0] + r[1] * u[1] + r[2] * u[2]);
        }
        for (uint32_t i = 1; i < k; i++) // insertion sort by angle (faces are small)
            for (uint32_t j = i; j > 0 && ang[j - 1] > ang[j]; j--) {
                float ta = ang[j];
                ang[j] = ang[j - 1], ang[j - 1] = ta;
                uint32_t tf = face[j];
                face[j] = face[j - 1], face[j - 1] = tf;
            }
        int base = nv;
        for (uint32_t i = 0; i < k; i++) {
            const phys_vec3 *p = &h->points[face[i]];
            pos[3 * nv] = p->x, pos[3 * nv + 1] = p->y, pos[3 * nv + 2] = p->z;
            nv++;
        }
        for (uint32_t i = 1; i + 1 < k; i++) {
            idx[ni++] = (uint32_t)base;
            idx[ni++] = (uint32_t)base + i;
            idx[ni++] = (uint32_t)base + i + 1;
        }
    }
    if (ni > 0) id = eng_mesh_create_triangles(store, pos, nv, idx, ni);
done:
    free(pos);
    free(idx);
    free(face);
    free(ang);
    return id;
}

// ---- compound meshes: every part's triangles, in the body frame ---------------------------

typedef struct tri_builder {
    float *pos;
    uint32_t *idx;
    int nv, ni, cap_v, cap_i;
    bool failed;
} tri_builder;

static int tb_vertex(tri_builder *t, const float p[3])
{
    if (t->nv == t->cap_v) {
        int cap = t->cap_v ? 2 * t->cap_v : 256;
        float *n = realloc(t->pos, (size_t)cap * 3 * sizeof *n);
        if (!n) {
            t->failed = true;
            return 0;
        }
        t->pos = n;
        t->cap_v = cap;
    }
    memcpy(t->pos + 3 * t->nv, p, 3 * sizeof(float));
    return t->nv++;
}

static void tb_triangle(tri_builder *t, int a, int b, int c)
{
    if (t->failed) return;
    if (t->ni + 3 > t->cap_i) {
        int cap = t->cap_i ? 2 * t->cap_i : 768;
        uint32_t *n = realloc(t->idx, (size_t)cap * sizeof *n);
        if (!n) {
            t->failed = true;
            return;
        }
        t->idx = n;
        t->cap_i = cap;
    }
    t->idx[t->ni++] = (uint32_t)a;
    t->idx[t->ni++] = (uint32_t)b;
    t->idx[t->ni++] = (uint32_t)c;
}

// A point of a part (its own frame) moved into the body frame.
static void part_point(const float pos[3], const float rot[4], float x, float y, float z, float out[3])
{
    float l[3] = { x, y, z }, w[3];
    scr_quat_rotate(rot, l, w);
    for (int k = 0; k < 3; k++) out[k] = pos[k] + w[k];
}

// A solid of revolution about the part's y axis from a profile of (radius, y) pairs, bottom
// to top; counter-clockwise seen from outside.
static void tb_lathe(tri_builder *t, const float pos[3], const float rot[4], const float (*prof)[2], int np)
{
    enum { SEG = 20 };
    int base = t->nv;
    for (int j = 0; j < np; j++)
        for (int i = 0; i < SEG; i++) {
            float a = 2.0f * (float)PI * (float)i / SEG, p[3];
            part_point(pos, rot, prof[j][0] * cosf(a), prof[j][1], prof[j][0] * sinf(a), p);
            tb_vertex(t, p);
        }
    for (int j = 0; j + 1 < np; j++)
        for (int i = 0; i < SEG; i++) {
            int a = base + j * SEG + i, b = base + j * SEG + (i + 1) % SEG;
            int c = base + (j + 1) * SEG + (i + 1) % SEG, d = base + (j + 1) * SEG + i;
            if (prof[j][0] > 0.0f) tb_triangle(t, a, d, b);
            if (prof[j + 1][0] > 0.0f) tb_triangle(t, b, d, c);
        }
}

static void tb_part(tri_builder *t, const phys_shape_desc *d, const float pos[3], const float rot[4])
{
    enum { RINGS = 8 };
    float prof[2 * RINGS + 4][2];
    int np = 0;
    switch (d->type) {
    case PHYS_SHAPE_BOX: {
        const float h[3] = { d->box.half_extents.x, d->box.half_extents.y, d->box.half_extents.z };
        for (int a = 0; a < 3; a++)
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                int u = (a + 1) % 3, v = (a + 2) % 3, first = t->nv;
                static const float cu[4] = { -1, 1, 1, -1 }, cv[4] = { -1, -1, 1, 1 };
                for (int k = 0; k < 4; k++) {
                    float l[3], p[3];
                    l[a] = (float)sgn * h[a];
                    l[u] = cu[k] * h[u];
                    l[v] = cv[k] * h[v];
                    part_point(pos, rot, l[0], l[1], l[2], p);
                    tb_vertex(t, p);
                }
                if (sgn > 0) {
                    tb_triangle(t, first, first + 1, first + 2);
                    tb_triangle(t, first, first + 2, first + 3);
                } else {
                    tb_triangle(t, first, first + 2, first + 1);
                    tb_triangle(t, first, first + 3, first + 2);
                }
            }
        return;
    }
    case PHYS_SHAPE_CYLINDER: {
        float r = d->cylinder.radius, hh = d->cylinder.half_height;
        const float cyl[4][2] = { { 0, -hh }, { r, -hh }, { r, hh }, { 0, hh } };
        tb_lathe(t, pos, rot, cyl, 4);
        return;
    }
    case PHYS_SHAPE_SPHERE:
    case PHYS_SHAPE_CAPSULE: {
        float r = d->type == PHYS_SHAPE_SPHERE ? d->sphere.radius : d->capsule.radius;
        float hh = d->type == PHYS_SHAPE_SPHERE ? 0.0f : d->capsule.half_height;
        for (int j = 0; j <= RINGS; j++) { // bottom cap, from the pole up to the equator
            float phi = 0.5f * (float)PI * (float)j / RINGS;
            prof[np][0] = r * sinf(phi);
            prof[np][1] = -hh - r * cosf(phi);
            np++;
        }
        for (int j = hh > 0.0f ? 0 : 1; j <= RINGS; j++) { // top cap, from the equator to the pole
            float phi = 0.5f * (float)PI * (float)j / RINGS;
            prof[np][0] = r * cosf(phi);
            prof[np][1] = hh + r * sinf(phi);
            np++;
        }
        prof[RINGS][0] = r;
        prof[np - 1][0] = 0.0f;
        prof[0][0] = 0.0f;
        tb_lathe(t, pos, rot, (const float(*)[2])prof, np);
        return;
    }
    default: return; // hull parts are not made from scripts
    }
}

static eng_mesh_id compound_mesh(eng_script *s, body_rec *b)
{
    phys_shape_desc d;
    if (phys_shape_get_desc(s->host.phys, b->shape_id, &d) != PHYS_OK) return ENG_NULL_MESH;
    tri_builder t;
    memset(&t, 0, sizeof t);
    for (uint32_t i = 0; i < d.compound.child_count; i++) {
        const phys_compound_child *c = &d.compound.children[i];
        float pos[3] = { c->position.x, c->position.y, c->position.z };
        float rot[4] = { c->rotation.x, c->rotation.y, c->rotation.z, c->rotation.w };
        tb_part(&t, &c->desc, pos, rot);
    }
    eng_mesh_id id = ENG_NULL_MESH;
    if (!t.failed && t.ni > 0) id = eng_mesh_create_triangles(s->host.meshes, t.pos, t.nv, t.idx, t.ni);
    free(t.pos);
    free(t.idx);
    return id;
}

eng_mesh_id scr_body_mesh(eng_script *s, body_rec *b)
{
    eng_mesh_store *m = s->host.meshes;
    if (b->file)
        return eng_mesh_create_triangles(m, b->file->positions, (int)b->file->vertex_count, b->file->indices,
                                         3 * (int)b->file->triangle_count);
    switch (b->shape) {
    case SHAPE_BOX: return eng_mesh_create_box(m, b->dims);
    case SHAPE_SPHERE: return eng_mesh_create_sphere(m, b->dims[0]);
    case SHAPE_CAPSULE: return eng_mesh_create_capsule(m, b->dims[0], b->dims[1]);
    case SHAPE_CYLINDER: return eng_mesh_create_cylinder(m, b->dims[0], b->dims[1]);
    case SHAPE_PLANE: return eng_mesh_create_plane(m, 10.0f, 10.0f);
    case SHAPE_MESH:
        return eng_mesh_create_triangles(m, b->points, (int)b->point_count, b->indices, (int)b->index_count);
    case SHAPE_HULL: {
        phys_shape_desc d;
        if (phys_shape_get_desc(s->host.phys, b->shape_id, &d) != PHYS_OK) return ENG_NULL_MESH;
        return hull_mesh(m, &d);
    }
    case SHAPE_COMPOUND: return compound_mesh(s, b);
    default: return ENG_NULL_MESH;
    }
}

// ---- scene nodes ------------------------------------------------------------------------------

// The rotation taking +Y to the unit vector n.
static void quat_from_y(const float n[3], float q[4])
{
    float d = n[1];
    if (d < -0.999999f) {
        q[0] = 1, q[1] = 0, q[2] = 0, q[3] = 0;
        return;
    }
    // axis = y x n = (n.z, 0, -n.x), q = (axis, 1 + d) normalised
    float x = n[2], z = -n[0], w = 1.0f + d;
    float len = sqrtf(x * x + z * z + w * w);
    q[0] = x / len, q[1] = 0.0f, q[2] = z / len, q[3] = w / len;
}

void scr_body_transform(const body_rec *b, const float pos[3], const float rot[4], eng_transform *t)
{
    *t = eng_identity_transform();
    if (b->shape == SHAPE_PLANE) {
        float qa[4], off[3] = { b->dims[0] * b->dims[3], b->dims[1] * b->dims[3], b->dims[2] * b->dims[3] }, w[3];
        quat_from_y(b->dims, qa);
        scr_quat_mul(rot, qa, t->rotation);
        scr_quat_rotate(rot, off, w);
        for (int k = 0; k < 3; k++) t->translation[k] = pos[k] + w[k];
    } else {
        memcpy(t->translation, pos, 3 * sizeof(float));
        memcpy(t->rotation, rot, 4 * sizeof(float));
    }
    float len = sqrtf(t->rotation[0] * t->rotation[0] + t->rotation[1] * t->rotation[1] + t->rotation[2] * t->rotation[2] +
                      t->rotation[3] * t->rotation[3]);
    for (int k = 0; k < 4; k++) t->rotation[k] /= len;
}

void eng_script_sync_nodes(eng_script *s)
{
    if (!s->host.scene || !s->host.phys) return;
    for (uint32_t i = 0; i < s->obj_count; i++) {
        obj *o = &s->objs[i];
        if (o->state != OBJ_LIVE || o->kind != OBJ_BODY || !o->u.body.node.index1) continue;
        float pos[3], rot[4];
        scr_body_state(s, o, pos, rot, NULL, NULL);
        eng_transform t;
        scr_body_transform(&o->u.body, pos, rot, &t);
        eng_node_set_local(s->host.scene, o->u.body.node, &t);
    }
}
