// Mesh files through assimp's C API, in a child process behind a guarded file system, and the
// mesh data every other mesh function takes (mesh_file.h): welding, degenerate triangles,
// winding, bounds, recentring, open edges.
#define _XOPEN_SOURCE 700 // realpath, RLIMIT_CORE
#include "engine/render/mesh_file.h"
#include "engine/core/log.h"

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

eng_mesh_file_options eng_default_mesh_file_options(void)
{
    eng_mesh_file_options o;
    memset(&o, 0, sizeof o);
    o.scale = 1.0f;
    o.centre = ENG_MESH_KEEP_ORIGIN;
    o.timeout_s = ENG_MESH_FILE_DEFAULT_TIMEOUT_S;
    o.root = NULL;
    o.memory_mb = ENG_MESH_FILE_DEFAULT_MEMORY_MB;
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

// ---- assimp, in a child process ----------------------------------------------------------------
//
// assimp runs in a forked child (import_child), so that a file that makes it loop for ever or
// crash costs a refusal, not the process: the parent (read_reply) waits at most timeout_s,
// kills the child when it runs over, and turns a signal or a malformed reply into a message
// naming the file. The child touches nothing but assimp, malloc and the pipe (the parent may
// hold a GL context and driver threads, which the child does not have), and ends with _exit.
// Every file assimp opens goes through guarded_open: regular files only, and with a root, only
// those whose real path lies inside it.
//
// The reply: a reply_header, then either message_length bytes of error message, or
// vertex_count * 3 floats (scaled, finite) and triangle_count * 3 uint32 indices. The parent
// trusts none of it: counts are checked against the limits before anything is allocated,
// indices against vertex_count, positions for finiteness.

#define REPLY_MAGIC 0x4d455348u // "MESH"
#define REPLY_MAX_MESSAGE 2048u

typedef struct reply_header {
    uint32_t magic;
    uint32_t message_length; // > 0: an error message follows instead of a mesh
    uint32_t vertex_count, triangle_count;
} reply_header;

// What the child's file system allows and what it refused (the first refusal, for the message).
typedef struct guarded_fs {
    const char *root_real; // NULL: any regular file
    const char *root;      // as given, for messages
    char refused[PATH_MAX];
} guarded_fs;

static bool path_inside(const char *real, const char *root_real)
{
    size_t n = strlen(root_real);
    if (n == 1 && root_real[0] == '/') return true;
    return strncmp(real, root_real, n) == 0 && (real[n] == '/' || real[n] == 0);
}

static size_t guarded_read(struct aiFile *f, char *buf, size_t size, size_t count)
{
    return fread(buf, size, count, (FILE *)(void *)f->UserData);
}

static size_t guarded_write(struct aiFile *f, const char *buf, size_t size, size_t count)
{
    (void)f, (void)buf, (void)size, (void)count;
    return 0; // opened for reading only
}

static size_t guarded_tell(struct aiFile *f)
{
    long at = ftell((FILE *)(void *)f->UserData);
    return at < 0 ? 0 : (size_t)at;
}

static size_t guarded_size(struct aiFile *f)
{
    struct stat st;
    if (fstat(fileno((FILE *)(void *)f->UserData), &st) != 0) return 0;
    return (size_t)st.st_size;
}

static enum aiReturn guarded_seek(struct aiFile *f, size_t offset, enum aiOrigin origin)
{
    int whence = origin == aiOrigin_SET ? SEEK_SET : origin == aiOrigin_CUR ? SEEK_CUR : SEEK_END;
    if (offset > (size_t)LONG_MAX) return aiReturn_FAILURE;
    return fseek((FILE *)(void *)f->UserData, (long)offset, whence) == 0 ? aiReturn_SUCCESS : aiReturn_FAILURE;
}

static void guarded_flush(struct aiFile *f) { (void)f; }

// A refusal: the same whether the file is missing, outside the root or not a regular file,
// so that a file cannot learn what lies outside its folder from how it fails.
static struct aiFile *refuse_open(guarded_fs *fs, const char *path)
{
    if (!fs->refused[0]) snprintf(fs->refused, sizeof fs->refused, "%s", path);
    return NULL;
}

static struct aiFile *guarded_open(struct aiFileIO *io, const char *path, const char *mode)
{
    guarded_fs *fs = (guarded_fs *)(void *)io->UserData;
    if (!path || !mode || mode[0] != 'r' || strchr(mode, '+')) return NULL; // reading only
    char real[PATH_MAX];
    if (!realpath(path, real)) return fs->root_real ? refuse_open(fs, path) : NULL; // missing: assimp says so
    if (fs->root_real && !path_inside(real, fs->root_real)) return refuse_open(fs, path);
    struct stat st;
    if (stat(real, &st) == 0 && S_ISDIR(st.st_mode)) return NULL; // assimp probing a folder: not worth a word
    if (stat(real, &st) != 0 || !S_ISREG(st.st_mode)) return refuse_open(fs, path); // no FIFOs, devices
    int fd = open(real, O_RDONLY | O_NOCTTY | O_NONBLOCK);
    if (fd < 0) return fs->root_real ? refuse_open(fs, path) : NULL;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) { // swapped since the stat
        close(fd);
        return refuse_open(fs, path);
    }
    FILE *file = fdopen(fd, "rb");
    struct aiFile *f = file ? malloc(sizeof *f) : NULL;
    if (!f) {
        if (file) fclose(file);
        else close(fd);
        return NULL;
    }
    f->ReadProc = guarded_read;
    f->WriteProc = guarded_write;
    f->TellProc = guarded_tell;
    f->FileSizeProc = guarded_size;
    f->SeekProc = guarded_seek;
    f->FlushProc = guarded_flush;
    f->UserData = (aiUserData)(void *)file;
    return f;
}

static void guarded_close(struct aiFileIO *io, struct aiFile *f)
{
    (void)io;
    if (!f) return;
    fclose((FILE *)(void *)f->UserData);
    free(f);
}

static bool write_all(int fd, const void *data, size_t n)
{
    const char *p = data;
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w < 0 && errno == EINTR) continue;
        if (w <= 0) return false;
        p += w;
        n -= (size_t)w;
    }
    return true;
}

// The child's error reply (the whole message, as the parent will give it).
static void child_fail(int fd, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

static void child_fail(int fd, const char *fmt, ...)
{
    char msg[REPLY_MAX_MESSAGE];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (n < 1) n = snprintf(msg, sizeof msg, "?");
    reply_header h = { REPLY_MAGIC, (uint32_t)strnlen(msg, sizeof msg - 1), 0, 0 };
    _exit(write_all(fd, &h, sizeof h) && write_all(fd, msg, h.message_length) ? 0 : 3);
}

// Why assimp could not read the file, with a word on the extension when assimp has no reader
// for it, and on a file it refers to that guarded_open refused.
static void child_assimp_failed(int fd, const char *path, const guarded_fs *fs, double memory_mb)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash : path, '.');
    const char *why = aiGetErrorString();
    if (!why || !*why) why = "no reason given";
    if (strstr(why, "bad_alloc"))
        child_fail(fd, "mesh file '%s': the importer ran out of its memory (%g MiB, eng_mesh_file_options.memory_mb; a "
                   "file can declare more vertices or faces than it holds): %s", path, memory_mb, why);
    if (!dot || !aiIsExtensionSupported(dot))
        child_fail(fd, "mesh file '%s' is not a mesh format assimp reads (extension '%s'; OBJ, glTF 2.0 .gltf/.glb and "
                   "the formats of aiGetExtensionList are): %s", path, dot ? dot : "", why);
    if (fs->refused[0] && fs->root_real)
        child_fail(fd, "mesh file '%s' could not be read: it refers to '%s', which is not a regular file inside '%s' "
                   "(a mesh file may only read files in that folder and below): %s", path, fs->refused, fs->root,
                   why);
    if (fs->refused[0])
        child_fail(fd, "mesh file '%s' could not be read: it refers to '%s', which is not a regular file: %s", path,
                   fs->refused, why);
    child_fail(fd, "mesh file '%s' could not be read: %s", path, why);
}

// The child's address space now, bytes (0 when it cannot be read): what it shares with the
// parent, on top of which it may take the memory limit.
static uint64_t child_address_space(void)
{
    char text[128];
    int fd = open("/proc/self/statm", O_RDONLY | O_CLOEXEC);
    if (fd < 0) return 0;
    ssize_t n = read(fd, text, sizeof text - 1);
    close(fd);
    if (n <= 0) return 0;
    text[n] = 0;
    long page = sysconf(_SC_PAGESIZE);
    return strtoull(text, NULL, 10) * (uint64_t)(page > 0 ? page : 4096);
}

// The child's memory limit: its address space as it was at the fork plus `mb` MiB (RLIMIT_AS,
// never raised above a limit the caller already had). False when it could not be set.
static bool limit_child_memory(double mb)
{
    uint64_t now = child_address_space();
    if (now == 0) return false;
    uint64_t reach = now + (uint64_t)(mb * 1048576.0);
    struct rlimit as;
    if (getrlimit(RLIMIT_AS, &as) != 0) return false;
    if (as.rlim_cur != RLIM_INFINITY && as.rlim_cur <= reach) return true;
    as.rlim_cur = (rlim_t)reach;
    if (as.rlim_max != RLIM_INFINITY && as.rlim_cur > as.rlim_max) as.rlim_cur = as.rlim_max;
    return setrlimit(RLIMIT_AS, &as) == 0;
}

// The child: imports, replies through fd, and ends. Never returns.
static void import_child(int fd, const char *path, const eng_mesh_file_options *o, const char *root_real,
                         double timeout_s)
{
    // The parent's crash handlers and masks are not ours: die of what kills us, leave no core.
    static const int defaults[] = { SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT, SIGPIPE, SIGALRM, SIGTERM };
    struct sigaction dfl;
    memset(&dfl, 0, sizeof dfl);
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    for (size_t i = 0; i < sizeof defaults / sizeof defaults[0]; i++) sigaction(defaults[i], &dfl, NULL);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, NULL);
    struct rlimit no_core = { 0, 0 };
    setrlimit(RLIMIT_CORE, &no_core);
    alarm((unsigned)timeout_s + 2); // ends the child should the parent die and not kill it
    if (!limit_child_memory(o->memory_mb))
        child_fail(fd, "mesh file '%s': cannot limit the importer's memory to %g MiB (RLIMIT_AS: %s)", path,
                   o->memory_mb, strerror(errno));

    guarded_fs fs;
    memset(&fs, 0, sizeof fs);
    fs.root_real = root_real;
    fs.root = o->root;
    struct aiFileIO io = { guarded_open, guarded_close, (aiUserData)(void *)&fs };
    // No normals asked for: only positions are kept (eng_mesh_create_triangles makes flat
    // normals), and generated normals would keep assimp from joining a corner's vertices.
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_PreTransformVertices |
                           aiProcess_ValidateDataStructure;
    const struct aiScene *scene = aiImportFileEx(path, flags, &io);
    if (!scene) child_assimp_failed(fd, path, &fs, o->memory_mb);
    if (scene->mNumMeshes == 0)
        child_fail(fd, "mesh file '%s' holds no meshes (assimp read it, but found no geometry in it)", path);
    uint64_t nv = 0, nt = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; i++) {
        const struct aiMesh *m = scene->mMeshes[i];
        nv += m->mNumVertices;
        for (unsigned f = 0; f < m->mNumFaces; f++) nt += m->mFaces[f].mNumIndices == 3;
    }
    if (nt == 0)
        child_fail(fd, "mesh file '%s' has no triangles (%u meshes of points or lines only)", path, scene->mNumMeshes);
    if (nv > ENG_MESH_FILE_MAX_VERTICES || nt > ENG_MESH_FILE_MAX_TRIANGLES)
        child_fail(fd, "mesh file '%s' is too big: %llu vertices and %llu triangles, at most %u and %u (simplify it)",
                   path, (unsigned long long)nv, (unsigned long long)nt, ENG_MESH_FILE_MAX_VERTICES,
                   ENG_MESH_FILE_MAX_TRIANGLES);
    for (unsigned i = 0; i < scene->mNumMeshes; i++) { // finite, scaled: checked before anything is sent
        const struct aiMesh *m = scene->mMeshes[i];
        for (unsigned k = 0; k < m->mNumVertices; k++) {
            const float p[3] = { (float)m->mVertices[k].x, (float)m->mVertices[k].y, (float)m->mVertices[k].z };
            for (int a = 0; a < 3; a++)
                if (!isfinite(p[a] * o->scale))
                    child_fail(fd, "mesh file '%s': mesh %u, vertex %u is not finite (%g, %g, %g; scale %g)", path, i,
                               k, (double)p[0], (double)p[1], (double)p[2], (double)o->scale);
        }
    }
    reply_header h = { REPLY_MAGIC, 0, (uint32_t)nv, (uint32_t)nt };
    if (!write_all(fd, &h, sizeof h)) _exit(3);
    float chunk[3 * 1024];
    size_t used = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; i++) {
        const struct aiMesh *m = scene->mMeshes[i];
        for (unsigned k = 0; k < m->mNumVertices; k++) {
            chunk[used++] = (float)m->mVertices[k].x * o->scale;
            chunk[used++] = (float)m->mVertices[k].y * o->scale;
            chunk[used++] = (float)m->mVertices[k].z * o->scale;
            if (used == sizeof chunk / sizeof chunk[0]) {
                if (!write_all(fd, chunk, sizeof chunk)) _exit(3);
                used = 0;
            }
        }
    }
    if (used && !write_all(fd, chunk, used * sizeof chunk[0])) _exit(3);
    uint32_t tri[3 * 1024];
    size_t base = 0;
    used = 0;
    for (unsigned i = 0; i < scene->mNumMeshes; i++) {
        const struct aiMesh *m = scene->mMeshes[i];
        for (unsigned f = 0; f < m->mNumFaces; f++) {
            const struct aiFace *face = &m->mFaces[f];
            if (face->mNumIndices != 3) continue; // points and lines
            for (int a = 0; a < 3; a++) tri[used++] = (uint32_t)(base + face->mIndices[a]);
            if (used == sizeof tri / sizeof tri[0]) {
                if (!write_all(fd, tri, sizeof tri)) _exit(3);
                used = 0;
            }
        }
        base += m->mNumVertices;
    }
    if (used && !write_all(fd, tri, used * sizeof tri[0])) _exit(3);
    _exit(0); // no aiReleaseImport, no atexit handlers, no stdio flush: the process ends here
}

// ---- the parent's side -------------------------------------------------------------------------

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

typedef enum read_result { READ_OK, READ_EOF, READ_TIMEOUT, READ_ERROR } read_result;

// Reads exactly n bytes before `deadline` (now_s's clock).
static read_result read_until(int fd, void *data, size_t n, double deadline)
{
    char *p = data;
    while (n > 0) {
        double left = deadline - now_s();
        if (left <= 0.0) return READ_TIMEOUT;
        struct pollfd pfd = { fd, POLLIN, 0 };
        int r = poll(&pfd, 1, (int)(left * 1000.0) + 1);
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) return READ_ERROR;
        if (r == 0) continue; // the loop's deadline check decides
        ssize_t got = read(fd, p, n);
        if (got < 0 && (errno == EINTR || errno == EAGAIN)) continue;
        if (got < 0) return READ_ERROR;
        if (got == 0) return READ_EOF;
        p += got;
        n -= (size_t)got;
    }
    return READ_OK;
}

// Waits for the child until `deadline`, then kills it. *status: waitpid's; false when it had
// to be killed (or cannot be waited for: SIGCHLD ignored by the program).
static bool reap_child(pid_t pid, double deadline, int *status)
{
    long pause_ns = 20000; // the child is usually ending as its reply arrives: look again soon
    for (;;) {
        pid_t r = waitpid(pid, status, WNOHANG);
        if (r == pid) return true;
        if (r < 0 && errno == EINTR) continue;
        if (r < 0) { // ECHILD: already reaped (SIGCHLD ignored); exit status unknown
            *status = 0;
            return true;
        }
        if (now_s() >= deadline) break;
        struct timespec pause = { 0, pause_ns };
        nanosleep(&pause, NULL);
        if (pause_ns < 2000000) pause_ns *= 2;
    }
    kill(pid, SIGKILL);
    while (waitpid(pid, status, 0) < 0 && errno == EINTR) {}
    return false;
}

// Makes an error message from the child printable (it may quote bytes of the file).
static void printable(char *s)
{
    for (; *s; s++)
        if ((unsigned char)*s < 0x20 || *s == 0x7f) *s = '?';
}

// Reads the child's reply into *pos / *idx (malloc'd) or into err. Returns false with a
// message in err; *timed_out when the time ran out first.
static bool read_reply(int fd, double deadline, float **pos, uint32_t **idx, reply_header *h,
                       bool *timed_out, char *err, size_t err_size)
{
    *pos = NULL;
    *idx = NULL;
    *timed_out = false;
    read_result r = read_until(fd, h, sizeof *h, deadline);
    if (r == READ_OK && h->magic != REPLY_MAGIC) return eng_fail(err, err_size, "bad magic %#x", h->magic);
    if (r == READ_OK && h->message_length > 0) {
        if (h->message_length >= REPLY_MAX_MESSAGE)
            return eng_fail(err, err_size, "an error message of %u bytes", h->message_length);
        char msg[REPLY_MAX_MESSAGE];
        r = read_until(fd, msg, h->message_length, deadline);
        if (r == READ_OK) {
            msg[h->message_length] = 0;
            printable(msg);
            eng_fail(err, err_size, "%s", msg);
            return true; // a reply: the child's own refusal
        }
    } else if (r == READ_OK) {
        if (h->vertex_count < 1 || h->vertex_count > ENG_MESH_FILE_MAX_VERTICES || h->triangle_count < 1 ||
            h->triangle_count > ENG_MESH_FILE_MAX_TRIANGLES)
            return eng_fail(err, err_size, "%u vertices and %u triangles (allowed: [1, %u] and [1, %u])",
                            h->vertex_count, h->triangle_count, ENG_MESH_FILE_MAX_VERTICES,
                            ENG_MESH_FILE_MAX_TRIANGLES);
        *pos = malloc(3 * (size_t)h->vertex_count * sizeof **pos);
        *idx = malloc(3 * (size_t)h->triangle_count * sizeof **idx);
        if (!*pos || !*idx)
            return eng_fail(err, err_size, "out of memory for %u vertices", h->vertex_count);
        r = read_until(fd, *pos, 3 * (size_t)h->vertex_count * sizeof **pos, deadline);
        if (r == READ_OK) r = read_until(fd, *idx, 3 * (size_t)h->triangle_count * sizeof **idx, deadline);
        if (r == READ_OK) {
            for (size_t i = 0; i < 3 * (size_t)h->vertex_count; i++)
                if (!isfinite((*pos)[i])) return eng_fail(err, err_size, "position %zu is not finite", i / 3);
            for (size_t i = 0; i < 3 * (size_t)h->triangle_count; i++)
                if ((*idx)[i] >= h->vertex_count)
                    return eng_fail(err, err_size, "index %u of %u vertices", (*idx)[i], h->vertex_count);
            return true;
        }
    }
    *timed_out = r == READ_TIMEOUT;
    return eng_fail(err, err_size, "%s", r == READ_EOF ? "it ended early" : r == READ_TIMEOUT ? "time" : "read error");
}

// The file itself, checked here so that the common refusals read plainly (and a FIFO does
// not block the probe). root_real: the root resolved, or NULL.
static bool probe_file(const char *path, const char *root, char *root_real, bool *has_root, char *err,
                       size_t err_size)
{
    *has_root = false;
    if (root) {
        struct stat st;
        if (!realpath(root, root_real))
            return eng_fail(err, err_size, "mesh file '%s': eng_mesh_file_options.root '%s' must be a folder (%s)",
                            path, root, strerror(errno));
        if (stat(root_real, &st) != 0 || !S_ISDIR(st.st_mode))
            return eng_fail(err, err_size, "mesh file '%s': eng_mesh_file_options.root '%s' must be a folder (it is "
                            "not one)", path, root);
        *has_root = true;
        char real[PATH_MAX];
        if (!realpath(path, real)) {
            if (errno == ENOENT) return eng_fail(err, err_size, "mesh file '%s' not found", path);
            return eng_fail(err, err_size, "mesh file '%s' cannot be opened: %s", path, strerror(errno));
        }
        if (!path_inside(real, root_real))
            return eng_fail(err, err_size, "mesh file '%s' lies outside '%s', the folder mesh files may be read from "
                            "(eng_mesh_file_options.root)", path, root);
    }
    struct stat st;
    if (stat(path, &st) != 0) {
        int e = errno;
        if (e == ENOENT) return eng_fail(err, err_size, "mesh file '%s' not found", path);
        return eng_fail(err, err_size, "mesh file '%s' cannot be opened: %s", path, strerror(e));
    }
    if (!S_ISREG(st.st_mode)) return eng_fail(err, err_size, "mesh file '%s' is not a regular file", path);
    int fd = open(path, O_RDONLY | O_NOCTTY | O_NONBLOCK);
    if (fd < 0) return eng_fail(err, err_size, "mesh file '%s' cannot be opened: %s", path, strerror(errno));
    close(fd);
    return true;
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
    if (!isfinite(o.timeout_s) || !(o.timeout_s > 0.0) || o.timeout_s > ENG_MESH_FILE_MAX_TIMEOUT_S)
        return eng_fail(err, err_size, "mesh '%s': eng_mesh_file_options.timeout_s must be in (0, %g] s (got %g)", path,
                        ENG_MESH_FILE_MAX_TIMEOUT_S, o.timeout_s);
    if (o.root && !*o.root)
        return eng_fail(err, err_size, "mesh '%s': eng_mesh_file_options.root must be a folder or NULL (got \"\")", path);
    if (!isfinite(o.memory_mb) || !(o.memory_mb >= ENG_MESH_FILE_MIN_MEMORY_MB) ||
        o.memory_mb > ENG_MESH_FILE_MAX_MEMORY_MB)
        return eng_fail(err, err_size, "mesh '%s': eng_mesh_file_options.memory_mb must be in [%.0f, %.0f] MiB (got %g)",
                        path, ENG_MESH_FILE_MIN_MEMORY_MB, ENG_MESH_FILE_MAX_MEMORY_MB, o.memory_mb);
    char root_real[PATH_MAX];
    bool has_root;
    if (!probe_file(path, o.root, root_real, &has_root, err, err_size)) return false;

    const double deadline = now_s() + o.timeout_s;
    int fds[2];
    if (pipe(fds) != 0)
        return eng_fail(err, err_size, "mesh file '%s': cannot start the importer (pipe: %s)", path, strerror(errno));
    fcntl(fds[0], F_SETFD, FD_CLOEXEC);
    fcntl(fds[1], F_SETFD, FD_CLOEXEC);
    pid_t pid = fork();
    if (pid < 0) {
        int e = errno;
        close(fds[0]);
        close(fds[1]);
        return eng_fail(err, err_size, "mesh file '%s': cannot start the importer (fork: %s)", path, strerror(e));
    }
    if (pid == 0) {
        close(fds[0]);
        import_child(fds[1], path, &o, has_root ? root_real : NULL, o.timeout_s);
    }
    close(fds[1]);
    float *pos;
    uint32_t *idx;
    reply_header h = { 0, 0, 0, 0 };
    bool timed_out;
    char why[REPLY_MAX_MESSAGE];
    bool replied = read_reply(fds[0], deadline, &pos, &idx, &h, &timed_out, why, sizeof why);
    close(fds[0]);
    int status = 0;
    bool ended = reap_child(pid, timed_out ? 0.0 : deadline, &status);
    if (!replied || h.message_length > 0 || !ended || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        free(pos);
        free(idx);
    }
    if (timed_out || !ended)
        return eng_fail(err, err_size, "mesh file '%s': the importer did not finish within %g s (a broken or hostile "
                        "file can keep assimp busy for ever; eng_mesh_file_options.timeout_s)", path, o.timeout_s);
    if (WIFSIGNALED(status))
        return eng_fail(err, err_size, "mesh file '%s': the importer crashed (signal %d, %s): the file is broken or "
                        "hostile", path, WTERMSIG(status), strsignal(WTERMSIG(status)));
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
        return eng_fail(err, err_size, "mesh file '%s': the importer failed (exit status %d)", path,
                        WIFEXITED(status) ? WEXITSTATUS(status) : -1);
    if (!replied)
        return eng_fail(err, err_size, "mesh file '%s': the importer's reply is malformed (%s)", path, why);
    if (h.message_length > 0) return eng_fail(err, err_size, "%s", why);
    return finish(path, pos, h.vertex_count, idx, h.triangle_count, &o, out, err, err_size);
}
