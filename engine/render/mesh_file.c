// Mesh files through assimp's C API, and the mesh data every other mesh function takes
// (mesh_file.h): welding, degenerate triangles, winding, bounds, recentring, open edges.
#include "engine/render/mesh_file.h"
#include "engine/core/log.h"

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

eng_mesh_file_options eng_default_mesh_file_options(void)
{
    eng_mesh_file_options o;
    memset(&o, 0, sizeof o);
    o.scale = 1.0f;
    o.centre = ENG_MESH_KEEP_ORIGIN;
    return o;
}

void eng_mesh_data_free(eng_mesh_data *m)
{
    if (!m) return;
    free(m->positions);
    free(m->indices);
    memset(m, 0, sizeof *m);
}

static bool check_options(const char *name, const eng_mesh_file_options *o, char *err, size_t err_size)
{
    if (!isfinite(o->scale) || !(o->scale > 0.0f) || o->scale > 1e6f)
        return eng_fail(err, err_size, "mesh '%s': eng_mesh_file_options.scale must be in (0, 1e6] (got %g)", name,
                    (double)o->scale);
    if (o->centre != ENG_MESH_KEEP_ORIGIN && o->centre != ENG_MESH_CENTRE_BOUNDS && o->centre != ENG_MESH_CENTRE_BASE)
        return eng_fail(err, err_size, "mesh '%s': eng_mesh_file_options.centre must be ENG_MESH_KEEP_ORIGIN, "
                    "ENG_MESH_CENTRE_BOUNDS or ENG_MESH_CENTRE_BASE (got %d)", name, (int)o->centre);
    return true;
}

// ---- welding: one vertex per position -------------------------------------------------------

static uint64_t hash_position(const float p[3])
{
    uint64_t h = 1469598103934665603ull;
    for (int k = 0; k < 3; k++) {
        float c = p[k] == 0.0f ? 0.0f : p[k]; // -0 and +0 weld
        uint32_t bits;
        memcpy(&bits, &c, sizeof bits);
        h = (h ^ bits) * 1099511628211ull;
        h ^= h >> 29;
    }
    return h;
}

// Welds positions in place: on return positions[0 .. *count) are distinct and remap[i] is
// the new index of old vertex i. Returns false when out of memory.
static bool weld(float *positions, uint32_t *count, uint32_t *remap)
{
    uint32_t n = *count;
    size_t cap = 16;
    while (cap < 2 * (size_t)n) cap *= 2;
    uint32_t *table = malloc(cap * sizeof *table); // new index + 1, 0 = empty
    if (!table) return false;
    memset(table, 0, cap * sizeof *table);
    uint32_t kept = 0;
    for (uint32_t i = 0; i < n; i++) {
        float p[3] = { positions[3 * i], positions[3 * i + 1], positions[3 * i + 2] };
        for (int k = 0; k < 3; k++)
            if (p[k] == 0.0f) p[k] = 0.0f;
        size_t slot = hash_position(p) & (cap - 1);
        for (;;) {
            uint32_t e = table[slot];
            if (e == 0) {
                table[slot] = kept + 1;
                memcpy(positions + 3 * (size_t)kept, p, sizeof p);
                remap[i] = kept++;
                break;
            }
            const float *q = positions + 3 * (size_t)(e - 1);
            if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) {
                remap[i] = e - 1;
                break;
            }
            slot = (slot + 1) & (cap - 1);
        }
    }
    free(table);
    *count = kept;
    return true;
}

// ---- topology and volume ----------------------------------------------------------------------

static int compare_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return x < y ? -1 : x > y;
}

uint32_t eng_mesh_open_edges(const eng_mesh_data *m)
{
    if (!m || !m->triangle_count) return 0;
    size_t n = 3 * (size_t)m->triangle_count;
    uint64_t *keys = malloc(n * sizeof *keys);
    if (!keys) return UINT32_MAX;
    size_t k = 0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *v = m->indices + 3 * (size_t)t;
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue; // no edges of its own
        for (int e = 0; e < 3; e++) {
            uint64_t a = v[e], b = v[(e + 1) % 3];
            keys[k++] = a < b ? a << 32 | b : b << 32 | a;
        }
    }
    qsort(keys, k, sizeof *keys, compare_u64);
    uint32_t open = 0;
    for (size_t i = 0; i < k;) {
        size_t j = i;
        while (j < k && keys[j] == keys[i]) j++;
        open += (j - i) & 1u;
        i = j;
    }
    free(keys);
    return open;
}

double eng_mesh_volume(const eng_mesh_data *m)
{
    if (!m) return 0.0;
    double v = 0.0;
    for (uint32_t t = 0; t < m->triangle_count; t++) {
        const float *a = m->positions + 3 * (size_t)m->indices[3 * (size_t)t];
        const float *b = m->positions + 3 * (size_t)m->indices[3 * (size_t)t + 1];
        const float *c = m->positions + 3 * (size_t)m->indices[3 * (size_t)t + 2];
        v += (double)a[0] * ((double)b[1] * c[2] - (double)b[2] * c[1]) -
             (double)a[1] * ((double)b[0] * c[2] - (double)b[2] * c[0]) +
             (double)a[2] * ((double)b[0] * c[1] - (double)b[1] * c[0]);
    }
    return v / 6.0;
}

static void compute_bounds(eng_mesh_data *m)
{
    for (int k = 0; k < 3; k++) {
        m->bounds_min[k] = INFINITY;
        m->bounds_max[k] = -INFINITY;
    }
    for (uint32_t i = 0; i < m->vertex_count; i++)
        for (int k = 0; k < 3; k++) {
            float c = m->positions[3 * (size_t)i + k];
            if (c < m->bounds_min[k]) m->bounds_min[k] = c;
            if (c > m->bounds_max[k]) m->bounds_max[k] = c;
        }
}

void eng_mesh_data_translate(eng_mesh_data *m, const float d[3])
{
    if (!m || !d) return;
    for (uint32_t i = 0; i < m->vertex_count; i++)
        for (int k = 0; k < 3; k++) m->positions[3 * (size_t)i + k] += d[k];
    for (int k = 0; k < 3; k++) {
        m->bounds_min[k] += d[k];
        m->bounds_max[k] += d[k];
        m->origin[k] += d[k];
    }
}

// Takes ownership of raw positions (scaled already) and indices (checked < vertex_count) and
// makes the mesh data of them: weld, drop degenerate triangles, orient, bounds, recentre.
static bool finish(const char *name, float *pos, uint32_t nv, uint32_t *idx, uint32_t nt,
                   const eng_mesh_file_options *o, eng_mesh_data *out, char *err, size_t err_size)
{
    uint32_t *remap = malloc((size_t)nv * sizeof *remap + 4);
    if (!remap || !weld(pos, &nv, remap)) {
        free(remap);
        free(pos);
        free(idx);
        return eng_fail(err, err_size, "mesh '%s': out of memory welding its vertices", name);
    }
    uint32_t kept = 0;
    for (uint32_t t = 0; t < nt; t++) {
        uint32_t a = remap[idx[3 * (size_t)t]], b = remap[idx[3 * (size_t)t + 1]], c = remap[idx[3 * (size_t)t + 2]];
        if (a == b || b == c || c == a) continue; // its corners welded together
        idx[3 * (size_t)kept] = a;
        idx[3 * (size_t)kept + 1] = b;
        idx[3 * (size_t)kept + 2] = c;
        kept++;
    }
    free(remap);
    float *shrunk = realloc(pos, 3 * (size_t)nv * sizeof *pos);
    if (shrunk) pos = shrunk;
    if (kept == 0) {
        free(pos);
        free(idx);
        return eng_fail(err, err_size, "mesh '%s' has no triangles with an area (all %u are degenerate)", name, nt);
    }
    memset(out, 0, sizeof *out);
    out->positions = pos;
    out->indices = idx;
    out->vertex_count = nv;
    out->triangle_count = kept;
    snprintf(out->name, sizeof out->name, "%s", name);
    out->open_edges = eng_mesh_open_edges(out);
    out->volume = eng_mesh_volume(out);
    if (out->open_edges == 0 && out->volume < 0.0) { // closed and inside out: turn it
        for (uint32_t t = 0; t < kept; t++) {
            uint32_t s = idx[3 * (size_t)t + 1];
            idx[3 * (size_t)t + 1] = idx[3 * (size_t)t + 2];
            idx[3 * (size_t)t + 2] = s;
        }
        out->volume = -out->volume;
    }
    compute_bounds(out);
    float d[3] = { 0.0f, 0.0f, 0.0f };
    if (o->centre != ENG_MESH_KEEP_ORIGIN) {
        for (int k = 0; k < 3; k++) d[k] = -0.5f * (out->bounds_min[k] + out->bounds_max[k]);
        if (o->centre == ENG_MESH_CENTRE_BASE) d[1] = -out->bounds_min[1];
        eng_mesh_data_translate(out, d);
    }
    return true;
}

bool eng_mesh_data_from_arrays(const float *positions, uint32_t nv, const uint32_t *indices, uint32_t nt,
                               const char *name, const eng_mesh_file_options *options, eng_mesh_data *out, char *err,
                               size_t err_size)
{
    if (!name) name = "mesh";
    if (!out) return eng_fail(err, err_size, "mesh '%s': eng_mesh_data_from_arrays: out must not be NULL", name);
    memset(out, 0, sizeof *out);
    eng_mesh_file_options o = options ? *options : eng_default_mesh_file_options();
    if (!check_options(name, &o, err, err_size)) return false;
    if (!positions || !indices)
        return eng_fail(err, err_size, "mesh '%s': %s must not be NULL", name, !positions ? "positions" : "indices");
    if (nv < 3 || nv > ENG_MESH_FILE_MAX_VERTICES)
        return eng_fail(err, err_size, "mesh '%s': vertex_count must be in [3, %u] (got %u)", name,
                    ENG_MESH_FILE_MAX_VERTICES, nv);
    if (nt < 1 || nt > ENG_MESH_FILE_MAX_TRIANGLES)
        return eng_fail(err, err_size, "mesh '%s': triangle_count must be in [1, %u] (got %u)", name,
                    ENG_MESH_FILE_MAX_TRIANGLES, nt);
    for (size_t i = 0; i < 3 * (size_t)nv; i++)
        if (!isfinite(positions[i] * o.scale))
            return eng_fail(err, err_size, "mesh '%s': positions[%zu] must be finite (got %g, scale %g)", name, i,
                        (double)positions[i], (double)o.scale);
    for (size_t i = 0; i < 3 * (size_t)nt; i++)
        if (indices[i] >= nv)
            return eng_fail(err, err_size, "mesh '%s': indices[%zu] must be < vertex_count %u (got %u)", name, i, nv,
                        indices[i]);
    float *pos = malloc(3 * (size_t)nv * sizeof *pos);
    uint32_t *idx = malloc(3 * (size_t)nt * sizeof *idx);
    if (!pos || !idx) {
        free(pos);
        free(idx);
        return eng_fail(err, err_size, "mesh '%s': out of memory", name);
    }
    for (size_t i = 0; i < 3 * (size_t)nv; i++) pos[i] = positions[i] * o.scale;
    memcpy(idx, indices, 3 * (size_t)nt * sizeof *idx);
    return finish(name, pos, nv, idx, nt, &o, out, err, err_size);
}

// ---- assimp --------------------------------------------------------------------------------

// Why assimp could not read the file, with a word on the extension when assimp has no reader
// for it.
static bool assimp_failed(const char *path, char *err, size_t err_size)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash : path, '.');
    const char *why = aiGetErrorString();
    if (!why || !*why) why = "no reason given";
    if (!dot || !aiIsExtensionSupported(dot))
        return eng_fail(err, err_size, "mesh file '%s' is not a mesh format assimp reads (extension '%s'; OBJ, glTF 2.0 "
                    ".gltf/.glb and the formats of aiGetExtensionList are): %s", path, dot ? dot : "", why);
    return eng_fail(err, err_size, "mesh file '%s' could not be read: %s", path, why);
}

bool eng_mesh_file_load(const char *path, const eng_mesh_file_options *options, eng_mesh_data *out, char *err,
                        size_t err_size)
{
    if (!out) return eng_fail(err, err_size, "eng_mesh_file_load: out must not be NULL");
    memset(out, 0, sizeof *out);
    if (!path || !*path) return eng_fail(err, err_size, "eng_mesh_file_load: path must be a file name (got %s)",
                                     path ? "\"\"" : "NULL");
    eng_mesh_file_options o = options ? *options : eng_default_mesh_file_options();
    if (!check_options(path, &o, err, err_size)) return false;
    // Opened here first, so that a missing file reads as one (assimp's message is vaguer).
    FILE *probe = fopen(path, "rb");
    if (!probe) {
        int e = errno;
        if (e == ENOENT) return eng_fail(err, err_size, "mesh file '%s' not found", path);
        return eng_fail(err, err_size, "mesh file '%s' cannot be opened: %s", path, strerror(e));
    }
    fclose(probe);
    // No normals asked for: only positions are kept (eng_mesh_create_triangles makes flat
    // normals), and generated normals would keep assimp from joining a corner's vertices.
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices |
                           aiProcess_ValidateDataStructure;
    const struct aiScene *scene = aiImportFile(path, flags);
    if (!scene) return assimp_failed(path, err, err_size);
    if (scene->mNumMeshes == 0) {
        aiReleaseImport(scene);
        return eng_fail(err, err_size, "mesh file '%s' holds no meshes (assimp read it, but found no geometry in it)",
                    path);
    }
    uint64_t nv = 0, nt = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; i++) {
        const struct aiMesh *m = scene->mMeshes[i];
        nv += m->mNumVertices;
        for (unsigned f = 0; f < m->mNumFaces; f++) nt += m->mFaces[f].mNumIndices == 3;
    }
    if (nt == 0) {
        aiReleaseImport(scene);
        return eng_fail(err, err_size, "mesh file '%s' has no triangles (%u meshes of points or lines only)", path,
                    scene->mNumMeshes);
    }
    if (nv > ENG_MESH_FILE_MAX_VERTICES || nt > ENG_MESH_FILE_MAX_TRIANGLES) {
        aiReleaseImport(scene);
        return eng_fail(err, err_size, "mesh file '%s' is too big: %llu vertices and %llu triangles, at most %u and %u "
                    "(simplify it)", path, (unsigned long long)nv, (unsigned long long)nt, ENG_MESH_FILE_MAX_VERTICES,
                    ENG_MESH_FILE_MAX_TRIANGLES);
    }
    float *pos = malloc(3 * (size_t)nv * sizeof *pos);
    uint32_t *idx = malloc(3 * (size_t)nt * sizeof *idx);
    if (!pos || !idx) {
        free(pos);
        free(idx);
        aiReleaseImport(scene);
        return eng_fail(err, err_size, "mesh file '%s': out of memory for %llu vertices", path, (unsigned long long)nv);
    }
    size_t v = 0, t = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; i++) {
        const struct aiMesh *m = scene->mMeshes[i];
        size_t base = v;
        for (unsigned k = 0; k < m->mNumVertices; k++, v++) {
            const float p[3] = { (float)m->mVertices[k].x, (float)m->mVertices[k].y, (float)m->mVertices[k].z };
            for (int a = 0; a < 3; a++) {
                pos[3 * v + a] = p[a] * o.scale;
                if (!isfinite(pos[3 * v + a])) {
                    free(pos);
                    free(idx);
                    aiReleaseImport(scene);
                    return eng_fail(err, err_size, "mesh file '%s': mesh %u, vertex %u is not finite (%g, %g, %g; scale %g)",
                                path, i, k, (double)p[0], (double)p[1], (double)p[2], (double)o.scale);
                }
            }
        }
        for (unsigned f = 0; f < m->mNumFaces; f++) {
            const struct aiFace *face = &m->mFaces[f];
            if (face->mNumIndices != 3) continue; // points and lines
            for (int a = 0; a < 3; a++) idx[3 * t + a] = (uint32_t)(base + face->mIndices[a]);
            t++;
        }
    }
    aiReleaseImport(scene);
    return finish(path, pos, (uint32_t)nv, idx, (uint32_t)nt, &o, out, err, err_size);
}
