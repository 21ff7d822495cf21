// GPU meshes: shape builders, upload, and the generation-checked store. See mesh.h.
#include "engine/render/mesh.h"

#include <epoxy/gl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI_F 3.14159265358979323846f

struct eng_mesh_store {
    eng_mesh_store_def def;
    struct slot {
        eng_mesh_gpu gpu;
        uint32_t generation;
        bool live;
        int next_free; ///< next free slot index, -1 = none
    } *slots;
    int slot_count, slot_cap;
    int free_head;
    int live_count;
};

eng_mesh_store_def eng_default_mesh_store_def(void)
{
    eng_mesh_store_def d;
    memset(&d, 0, sizeof d);
    d.segments = 32;
    d.max_meshes = 4096;
    d.logger = eng_default_logger();
    return d;
}

eng_mesh_store *eng_mesh_store_create(const eng_mesh_store_def *def)
{
    if (def->segments < 6 || def->segments > 256) {
        eng_log(&def->logger, ENG_LOG_ERROR, "eng_mesh_store_def.segments must be 6..256 (got %d)", def->segments);
        return NULL;
    }
    if (def->max_meshes < 1 || def->max_meshes > 65536) {
        eng_log(&def->logger, ENG_LOG_ERROR, "eng_mesh_store_def.max_meshes must be 1..65536 (got %d)",
                def->max_meshes);
        return NULL;
    }
    eng_mesh_store *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->def = *def;
    s->free_head = -1;
    return s;
}

static void free_gpu(eng_mesh_gpu *g)
{
    glDeleteVertexArrays(1, &g->vao);
    glDeleteBuffers(1, &g->vbo);
    glDeleteBuffers(1, &g->ebo);
    memset(g, 0, sizeof *g);
}

void eng_mesh_store_destroy(eng_mesh_store *store)
{
    if (!store) return;
    for (int i = 0; i < store->slot_count; i++)
        if (store->slots[i].live) free_gpu(&store->slots[i].gpu);
    free(store->slots);
    free(store);
}

// ---- CPU-side building -------------------------------------------------------------

typedef struct builder {
    float *verts; ///< interleaved position (3) + normal (3)
    uint32_t *idx;
    int nv, cap_v, ni, cap_i;
    bool oom;
} builder;

static uint32_t put_vertex(builder *b, float px, float py, float pz, float nx, float ny, float nz)
{
    if (b->nv == b->cap_v) {
        int cap = b->cap_v ? b->cap_v * 2 : 64;
        float *v = realloc(b->verts, (size_t)cap * 6 * sizeof *v);
        if (!v) {
            b->oom = true;
            return 0;
        }
        b->verts = v;
        b->cap_v = cap;
    }
    float *v = b->verts + (size_t)b->nv * 6;
    v[0] = px, v[1] = py, v[2] = pz, v[3] = nx, v[4] = ny, v[5] = nz;
    return (uint32_t)b->nv++;
}

static void put_triangle(builder *b, uint32_t i0, uint32_t i1, uint32_t i2)
{
    if (b->oom) return;
    if (b->ni + 3 > b->cap_i) {
        int cap = b->cap_i ? b->cap_i * 2 : 192;
        uint32_t *v = realloc(b->idx, (size_t)cap * sizeof *v);
        if (!v) {
            b->oom = true;
            return;
        }
        b->idx = v;
        b->cap_i = cap;
    }
    b->idx[b->ni++] = i0;
    b->idx[b->ni++] = i1;
    b->idx[b->ni++] = i2;
}

static void builder_free(builder *b)
{
    free(b->verts);
    free(b->idx);
}

// A point of a profile turned around the Y axis: radius r and height y in m, with the
// surface normal (nr outward, ny up) in the profile plane.
typedef struct profile_point {
    float r, y, nr, ny;
} profile_point;

// Turns a profile (listed from top to bottom) around Y into a closed surface of
// revolution. Consecutive points at the same place only change the normal (a crease).
static void lathe(builder *b, const profile_point *p, int n, int segments)
{
    int ring = segments + 1; // the seam vertex is duplicated
    uint32_t base = (uint32_t)b->nv;
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < ring; j++) {
            float phi = 2.0f * PI_F * (float)(j % segments) / (float)segments;
            float s = sinf(phi), c = cosf(phi);
            put_vertex(b, p[i].r * s, p[i].y, p[i].r * c, p[i].nr * s, p[i].ny, p[i].nr * c);
        }
    }
    for (int i = 0; i + 1 < n; i++) {
        if (p[i].r == p[i + 1].r && p[i].y == p[i + 1].y) continue; // a crease, no area
        for (int j = 0; j < segments; j++) {
            uint32_t a = base + (uint32_t)(i * ring + j), d = a + 1;
            uint32_t bb = base + (uint32_t)((i + 1) * ring + j), c = bb + 1;
            // Counter-clockwise seen from outside (phi grows towards +x from +z).
            if (p[i + 1].r > 0.0f) put_triangle(b, a, bb, c);
            if (p[i].r > 0.0f) put_triangle(b, a, c, d);
        }
    }
}

// Profile of a capsule (half_height >= 0) or, with half_height = 0, a sphere.
static void build_capsule(builder *b, float radius, float half_height, int segments)
{
    int rings = segments / 4; // per hemisphere
    if (rings < 2) rings = 2;
    profile_point *p = malloc((size_t)(2 * rings + 2) * sizeof *p);
    if (!p) {
        b->oom = true;
        return;
    }
    int n = 0;
    for (int i = 0; i <= rings; i++) { // top hemisphere, pole to equator
        float t = 0.5f * PI_F * (float)i / (float)rings;
        float s = sinf(t), c = cosf(t);
        p[n++] = (profile_point){ radius * s, half_height + radius * c, s, c };
    }
    for (int i = 0; i <= rings; i++) { // bottom hemisphere, equator to pole
        float t = 0.5f * PI_F + 0.5f * PI_F * (float)i / (float)rings;
        float s = sinf(t), c = cosf(t);
        if (i == 0 && half_height == 0.0f) continue; // a sphere: the equator once
        p[n++] = (profile_point){ radius * s, -half_height + radius * c, s, c };
    }
    // Exact poles, so that triangle skipping sees r == 0.
    p[0].r = 0.0f;
    p[n - 1].r = 0.0f;
    lathe(b, p, n, segments);
    free(p);
}

static void build_cylinder(builder *b, float radius, float half_height, int segments)
{
    const profile_point p[] = {
        { 0.0f, half_height, 0.0f, 1.0f },     { radius, half_height, 0.0f, 1.0f },
        { radius, half_height, 1.0f, 0.0f },   { radius, -half_height, 1.0f, 0.0f },
        { radius, -half_height, 0.0f, -1.0f }, { 0.0f, -half_height, 0.0f, -1.0f },
    };
    lathe(b, p, 6, segments);
}

static void build_quad(builder *b, const float o[3], const float u[3], const float v[3])
{
    // Corners o, o+u, o+u+v, o+v; the normal u x v faces the viewer when u, v run CCW.
    float n[3] = { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0] };
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    n[0] /= len, n[1] /= len, n[2] /= len;
    uint32_t i0 = put_vertex(b, o[0], o[1], o[2], n[0], n[1], n[2]);
    uint32_t i1 = put_vertex(b, o[0] + u[0], o[1] + u[1], o[2] + u[2], n[0], n[1], n[2]);
    uint32_t i2 = put_vertex(b, o[0] + u[0] + v[0], o[1] + u[1] + v[1], o[2] + u[2] + v[2], n[0], n[1], n[2]);
    uint32_t i3 = put_vertex(b, o[0] + v[0], o[1] + v[1], o[2] + v[2], n[0], n[1], n[2]);
    put_triangle(b, i0, i1, i2);
    put_triangle(b, i0, i2, i3);
}

static void build_box(builder *b, const float h[3])
{
    const float x = h[0], y = h[1], z = h[2];
    // Each face: a corner and two edges running counter-clockwise seen from outside.
    build_quad(b, (const float[]){ x, -y, z }, (const float[]){ 0, 0, -2 * z }, (const float[]){ 0, 2 * y, 0 });   // +x
    build_quad(b, (const float[]){ -x, -y, -z }, (const float[]){ 0, 0, 2 * z }, (const float[]){ 0, 2 * y, 0 });  // -x
    build_quad(b, (const float[]){ -x, y, z }, (const float[]){ 2 * x, 0, 0 }, (const float[]){ 0, 0, -2 * z });   // +y
    build_quad(b, (const float[]){ -x, -y, -z }, (const float[]){ 2 * x, 0, 0 }, (const float[]){ 0, 0, 2 * z });  // -y
    build_quad(b, (const float[]){ -x, -y, z }, (const float[]){ 2 * x, 0, 0 }, (const float[]){ 0, 2 * y, 0 });   // +z
    build_quad(b, (const float[]){ x, -y, -z }, (const float[]){ -2 * x, 0, 0 }, (const float[]){ 0, 2 * y, 0 });  // -z
}

// ---- the store ---------------------------------------------------------------------

static bool upload(eng_mesh_gpu *g, const builder *b)
{
    memset(g, 0, sizeof *g);
    g->vertex_count = b->nv;
    g->index_count = b->ni;
    for (int k = 0; k < 3; k++) {
        g->bounds_min[k] = b->nv ? INFINITY : 0.0f;
        g->bounds_max[k] = b->nv ? -INFINITY : 0.0f;
    }
    for (int i = 0; i < b->nv; i++)
        for (int k = 0; k < 3; k++) {
            float v = b->verts[(size_t)i * 6 + (size_t)k];
            if (v < g->bounds_min[k]) g->bounds_min[k] = v;
            if (v > g->bounds_max[k]) g->bounds_max[k] = v;
        }
    glGenVertexArrays(1, &g->vao);
    glGenBuffers(1, &g->vbo);
    glGenBuffers(1, &g->ebo);
    glBindVertexArray(g->vao);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)((size_t)b->nv * 6 * sizeof(float)), b->verts, GL_STATIC_DRAW);
    glObjectLabel(GL_BUFFER, g->vbo, -1, "eng.mesh_vertices");
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ebo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)((size_t)b->ni * sizeof(uint32_t)), b->idx, GL_STATIC_DRAW);
    glObjectLabel(GL_BUFFER, g->ebo, -1, "eng.mesh_indices");
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (const void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (const void *)(3 * sizeof(float)));
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    return true;
}

static eng_mesh_id add(eng_mesh_store *s, builder *b, const char *what)
{
    eng_mesh_id id = ENG_NULL_MESH;
    if (b->oom) {
        eng_log(&s->def.logger, ENG_LOG_ERROR, "%s: out of memory", what);
        builder_free(b);
        return id;
    }
    int slot = s->free_head;
    if (slot >= 0) {
        s->free_head = s->slots[slot].next_free;
    } else {
        if (s->slot_count >= s->def.max_meshes) {
            eng_log(&s->def.logger, ENG_LOG_ERROR, "%s: the mesh store is full (eng_mesh_store_def.max_meshes = %d)",
                    what, s->def.max_meshes);
            builder_free(b);
            return id;
        }
        if (s->slot_count == s->slot_cap) {
            int cap = s->slot_cap ? s->slot_cap * 2 : 16;
            if (cap > s->def.max_meshes) cap = s->def.max_meshes;
            struct slot *n = realloc(s->slots, (size_t)cap * sizeof *n);
            if (!n) {
                eng_log(&s->def.logger, ENG_LOG_ERROR, "%s: out of memory", what);
                builder_free(b);
                return id;
            }
            s->slots = n;
            s->slot_cap = cap;
        }
        slot = s->slot_count++;
        s->slots[slot].generation = 0;
    }
    struct slot *sl = &s->slots[slot];
    upload(&sl->gpu, b);
    builder_free(b);
    sl->live = true;
    sl->next_free = -1;
    sl->generation++;
    if (sl->generation == 0) sl->generation = 1; // zero is reserved for null ids
    s->live_count++;
    id.index1 = (uint32_t)slot + 1;
    id.generation = sl->generation;
    return id;
}

static bool check_positive(const eng_mesh_store *s, const char *fn, const char *field, float v)
{
    if (v > 0.0f && isfinite(v)) return true;
    eng_log(&s->def.logger, ENG_LOG_ERROR, "%s: %s must be a finite length > 0 m (got %g)", fn, field, (double)v);
    return false;
}

eng_mesh_id eng_mesh_create_plane(eng_mesh_store *store, float size_x, float size_z)
{
    const char *fn = "eng_mesh_create_plane";
    if (!check_positive(store, fn, "size_x", size_x) || !check_positive(store, fn, "size_z", size_z))
        return ENG_NULL_MESH;
    builder b = { 0 };
    float hx = 0.5f * size_x, hz = 0.5f * size_z;
    build_quad(&b, (const float[]){ -hx, 0, hz }, (const float[]){ size_x, 0, 0 }, (const float[]){ 0, 0, -size_z });
    return add(store, &b, fn);
}

eng_mesh_id eng_mesh_create_box(eng_mesh_store *store, const float half_extents[3])
{
    const char *fn = "eng_mesh_create_box";
    if (!check_positive(store, fn, "half_extents[0]", half_extents[0]) ||
        !check_positive(store, fn, "half_extents[1]", half_extents[1]) ||
        !check_positive(store, fn, "half_extents[2]", half_extents[2]))
        return ENG_NULL_MESH;
    builder b = { 0 };
    build_box(&b, half_extents);
    return add(store, &b, fn);
}

eng_mesh_id eng_mesh_create_sphere(eng_mesh_store *store, float radius)
{
    const char *fn = "eng_mesh_create_sphere";
    if (!check_positive(store, fn, "radius", radius)) return ENG_NULL_MESH;
    builder b = { 0 };
    build_capsule(&b, radius, 0.0f, store->def.segments);
    return add(store, &b, fn);
}

eng_mesh_id eng_mesh_create_capsule(eng_mesh_store *store, float radius, float half_height)
{
    const char *fn = "eng_mesh_create_capsule";
    if (!check_positive(store, fn, "radius", radius)) return ENG_NULL_MESH;
    if (!(half_height >= 0.0f) || !isfinite(half_height)) {
        eng_log(&store->def.logger, ENG_LOG_ERROR, "%s: half_height must be a finite length >= 0 m (got %g)", fn,
                (double)half_height);
        return ENG_NULL_MESH;
    }
    builder b = { 0 };
    build_capsule(&b, radius, half_height, store->def.segments);
    return add(store, &b, fn);
}

eng_mesh_id eng_mesh_create_cylinder(eng_mesh_store *store, float radius, float half_height)
{
    const char *fn = "eng_mesh_create_cylinder";
    if (!check_positive(store, fn, "radius", radius) || !check_positive(store, fn, "half_height", half_height))
        return ENG_NULL_MESH;
    builder b = { 0 };
    build_cylinder(&b, radius, half_height, store->def.segments);
    return add(store, &b, fn);
}

eng_mesh_id eng_mesh_create_triangles(eng_mesh_store *store, const float *positions, int vertex_count,
                                      const uint32_t *indices, int index_count)
{
    const char *fn = "eng_mesh_create_triangles";
    const eng_logger *log = &store->def.logger;
    if (vertex_count < 3 || !positions) {
        eng_log(log, ENG_LOG_ERROR, "%s: vertex_count must be >= 3 with non-NULL positions (got %d, positions %s)",
                fn, vertex_count, positions ? "set" : "NULL");
        return ENG_NULL_MESH;
    }
    if (index_count < 3 || index_count % 3 != 0 || !indices) {
        eng_log(log, ENG_LOG_ERROR, "%s: index_count must be a positive multiple of 3 with non-NULL indices (got %d)",
                fn, index_count);
        return ENG_NULL_MESH;
    }
    for (int i = 0; i < vertex_count * 3; i++) {
        if (!isfinite(positions[i])) {
            eng_log(log, ENG_LOG_ERROR, "%s: positions[%d] must be finite (got %g)", fn, i, (double)positions[i]);
            return ENG_NULL_MESH;
        }
    }
    for (int i = 0; i < index_count; i++) {
        if (indices[i] >= (uint32_t)vertex_count) {
            eng_log(log, ENG_LOG_ERROR, "%s: indices[%d] must be < vertex_count %d (got %u)", fn, i, vertex_count,
                    (unsigned)indices[i]);
            return ENG_NULL_MESH;
        }
    }
    builder b = { 0 };
    for (int t = 0; t < index_count; t += 3) {
        const float *p0 = positions + 3 * (size_t)indices[t];
        const float *p1 = positions + 3 * (size_t)indices[t + 1];
        const float *p2 = positions + 3 * (size_t)indices[t + 2];
        float u[3] = { p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2] };
        float v[3] = { p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2] };
        float n[3] = { u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0] };
        float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (len > 0.0f) n[0] /= len, n[1] /= len, n[2] /= len;
        else n[0] = 0.0f, n[1] = 1.0f, n[2] = 0.0f; // degenerate: any normal will do
        uint32_t i0 = put_vertex(&b, p0[0], p0[1], p0[2], n[0], n[1], n[2]);
        uint32_t i1 = put_vertex(&b, p1[0], p1[1], p1[2], n[0], n[1], n[2]);
        uint32_t i2 = put_vertex(&b, p2[0], p2[1], p2[2], n[0], n[1], n[2]);
        put_triangle(&b, i0, i1, i2);
    }
    return add(store, &b, fn);
}

static struct slot *lookup(const eng_mesh_store *s, eng_mesh_id id)
{
    if (!s || id.index1 == 0 || id.index1 > (uint32_t)s->slot_count) return NULL;
    struct slot *sl = &s->slots[id.index1 - 1];
    return sl->live && sl->generation == id.generation ? sl : NULL;
}

void eng_mesh_destroy(eng_mesh_store *store, eng_mesh_id id)
{
    struct slot *sl = lookup(store, id);
    if (!sl) {
        if (id.index1 != 0)
            eng_log(&store->def.logger, ENG_LOG_WARN,
                    "eng_mesh_destroy: attempt to destroy a destroyed mesh (index %u, generation %u)",
                    (unsigned)id.index1, (unsigned)id.generation);
        return;
    }
    free_gpu(&sl->gpu);
    sl->live = false;
    int slot = (int)id.index1 - 1;
    sl->next_free = store->free_head;
    store->free_head = slot;
    store->live_count--;
}

bool eng_mesh_is_valid(const eng_mesh_store *store, eng_mesh_id id) { return lookup(store, id) != NULL; }

const eng_mesh_gpu *eng_mesh_get_gpu(const eng_mesh_store *store, eng_mesh_id id)
{
    struct slot *sl = lookup(store, id);
    return sl ? &sl->gpu : NULL;
}

int eng_mesh_store_count(const eng_mesh_store *store) { return store->live_count; }
