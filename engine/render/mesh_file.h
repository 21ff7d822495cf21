// Meshes from files: OBJ, glTF 2.0 (.gltf with its buffers, .glb) and the other formats
// assimp reads, as one list of positions and triangles (eng_mesh_data); and what the engine
// does with such a mesh: draw it (eng_mesh_create_triangles, mesh.h), make Bullet shapes of it
// (mesh_physics.h: a convex hull for a dynamic body, a triangle mesh for a static one, which
// fluid/bullet/coupling.c turns into the fluid's collider), fill its inside with water
// (eng_mesh_fill_points, here).
//
//     eng_mesh_file_options o = eng_default_mesh_file_options();
//     o.centre = ENG_MESH_CENTRE_BASE;                 // stand it on y = 0
//     eng_mesh_data m;
//     char err[512];
//     if (!eng_mesh_file_load("cup.obj", &o, &m, err, sizeof err)) ...   // err names the file
//     eng_mesh_id gpu = eng_mesh_create_triangles(store, m.positions, (int)m.vertex_count,
//                                                 m.indices, 3 * (int)m.triangle_count);
//     float *xyz; uint32_t n;
//     if (eng_mesh_fill_points(&m, 2 * radius, NULL, &xyz, &n, err, sizeof err))
//         pbf_world_add_particles(fluid, xyz, NULL, n), free(xyz);
//     eng_mesh_data_free(&m);
//
// Loading (assimp's C API): every mesh of the file is placed by its node (pre-transformed)
// and merged into one list; faces are triangulated; points and lines are dropped. Only
// positions are kept, each once: vertices at the same position are welded whatever their
// normals or texture coordinates, so the triangles of a closed surface share their edges
// (eng_mesh_create_triangles computes flat normals again for drawing). Triangles whose
// corners weld together are dropped. A closed mesh whose triangles wind inwards (negative
// enclosed volume) is turned outside out, so that triangles are counter-clockwise seen from
// outside, the winding phys.h and the fluid's distance grids expect. Units: the file's units
// times `scale` are metres; glTF's are metres already, OBJ has none.
//
// Closed and open: a mesh is closed when every edge is used by an even number of triangles
// (two for an ordinary surface). Open edges (used once, or an odd number of times) mean a
// hole: the mesh has no inside. eng_mesh_fill_points refuses open meshes, naming the file and
// the number of open edges; Bullet's triangle meshes and hulls take them.
//
// Hostile files (docs/meshes.md): assimp runs in a child process (fork) that hands back the
// positions and triangles through a pipe; the parent kills it after options.timeout_s and
// refuses a file that hung or crashed it, naming the file. Every file assimp opens (the file,
// a .gltf's buffers, an .obj's materials) must be a regular file, and with options.root set,
// one whose real path lies in that folder or below; others look missing to assimp.
//
// Errors: functions that can fail return false and write one message into err (which may be
// NULL), naming the file and what is wrong, and leave *out zeroed (free is still safe).
#ifndef ENG_MESH_FILE_H
#define ENG_MESH_FILE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/// The most vertices a mesh file may hold (as assimp hands them over, after it joins
/// identical vertices; summed over its meshes): 2^20. Larger files are refused.
#define ENG_MESH_FILE_MAX_VERTICES (1u << 20)
/// The most triangles a mesh file may hold (after triangulation): 2^21.
#define ENG_MESH_FILE_MAX_TRIANGLES (1u << 21)

/// Where the loaded mesh's origin goes.
typedef enum eng_mesh_centre {
    ENG_MESH_KEEP_ORIGIN = 0, ///< the file's origin stays the origin
    ENG_MESH_CENTRE_BOUNDS,   ///< the centre of the bounding box moves to the origin
    ENG_MESH_CENTRE_BASE,     ///< the bottom centre of the box (centre in x and z, lowest y) does
} eng_mesh_centre;

typedef struct eng_mesh_file_options {
    /// Uniform factor from the file's units to metres, finite, in (0, 1e6]. Default 1.
    float scale;
    /// Recentring, applied after scaling. Default ENG_MESH_KEEP_ORIGIN.
    eng_mesh_centre centre;
    /// s, finite, in (0, ENG_MESH_FILE_MAX_TIMEOUT_S]: the most eng_mesh_file_load waits for the
    /// importer, which runs in a child process and is killed when it runs over (a broken file can
    /// keep assimp busy for ever). Default ENG_MESH_FILE_DEFAULT_TIMEOUT_S. Not used by
    /// eng_mesh_data_from_arrays.
    double timeout_s;
    /// The folder the importer may read from, or NULL (default): any regular file. With a root,
    /// the file and every file it refers to (a .gltf's buffers, an .obj's materials) must be
    /// regular files whose real path (links followed) lies in root or below; others are refused
    /// as if missing, whether or not they exist. Not used by eng_mesh_data_from_arrays.
    const char *root;
    /// MiB, in [ENG_MESH_FILE_MIN_MEMORY_MB, ENG_MESH_FILE_MAX_MEMORY_MB]: the most memory the
    /// importer's child process may take on top of what it shares with the caller (its address
    /// space, RLIMIT_AS): a file of a few hundred bytes can declare billions of vertices and
    /// make assimp allocate until the machine runs out. Going over is refused as "the importer
    /// ran out of its memory (N MiB ...)". Default ENG_MESH_FILE_DEFAULT_MEMORY_MB. Not used by
    /// eng_mesh_data_from_arrays.
    double memory_mb;
} eng_mesh_file_options;

/// The default eng_mesh_file_options.timeout_s, s: three times what the largest file allowed
/// (a 60 MB OBJ of 2^20 vertices) takes on two cores.
#define ENG_MESH_FILE_DEFAULT_TIMEOUT_S 30.0
/// The largest eng_mesh_file_options.timeout_s, s.
#define ENG_MESH_FILE_MAX_TIMEOUT_S 3600.0
/// The default eng_mesh_file_options.memory_mb, MiB: 1.6 times the address space the largest
/// file allowed took (a 70 MB OBJ of 2^20 vertices and 2^21 triangles: 2.6 GB, 1.2 GB of it
/// resident; a 40 MB binary PLY of the same needs under 1 GB).
#define ENG_MESH_FILE_DEFAULT_MEMORY_MB 4096.0
/// The range of eng_mesh_file_options.memory_mb, MiB.
#define ENG_MESH_FILE_MIN_MEMORY_MB 64.0
#define ENG_MESH_FILE_MAX_MEMORY_MB 1048576.0

/// Defaults: scale 1, the file's origin kept, timeout ENG_MESH_FILE_DEFAULT_TIMEOUT_S, no root,
/// memory ENG_MESH_FILE_DEFAULT_MEMORY_MB.
eng_mesh_file_options eng_default_mesh_file_options(void);

/// A triangle mesh in memory (positions and indices; no GL). Owned: eng_mesh_data_free.
typedef struct eng_mesh_data {
    float *positions;         ///< vertex_count positions, xyz each, m; every position once
    uint32_t *indices;        ///< triangle_count triangles, 3 indices each (< vertex_count)
    uint32_t vertex_count;
    uint32_t triangle_count;
    float bounds_min[3];      ///< m, axis-aligned bounds of the positions
    float bounds_max[3];
    /// m: where the file's origin lies in this mesh's frame (the translation recentring and
    /// eng_mesh_data_translate applied). {0, 0, 0} with ENG_MESH_KEEP_ORIGIN.
    float origin[3];
    uint32_t open_edges;      ///< as loaded: edges used by an odd number of triangles (0: closed)
    double volume;            ///< as loaded: enclosed volume, m^3 (meaningful when closed)
    char name[256];           ///< the path it was loaded from (or the name given), for messages
} eng_mesh_data;

/// Loads every mesh of the file at `path` into *out (see the top of this header). options
/// may be NULL (defaults). On failure returns false, *out is zeroed and err says which file
/// and why: not found (or unreadable, or not a regular file), outside options->root, not a
/// format assimp reads, a file it refers to refused (named), no meshes, no triangles, more
/// than ENG_MESH_FILE_MAX_VERTICES vertices or ENG_MESH_FILE_MAX_TRIANGLES triangles, a
/// position that is not finite, a bad option, "the importer did not finish within N s", "the
/// importer crashed (signal N, ...)". Time: assimp's parsing dominates; a 60 MB OBJ of a
/// million vertices takes about 10 s on two cores; the child process adds a fork and its
/// page faults (a few ms to tens of ms; docs/meshes.md).
bool eng_mesh_file_load(const char *path, const eng_mesh_file_options *options, eng_mesh_data *out, char *err,
                        size_t err_size);

/// A mesh from arrays (procedural meshes, tests): `vertex_count` positions (xyz, m, finite)
/// and `triangle_count` triangles (3 indices each, < vertex_count), treated as a loaded file
/// is (welded, degenerate triangles dropped, turned outward when closed, recentred and
/// scaled by options, which may be NULL). The arrays are copied. `name` (may be NULL: "mesh")
/// names the mesh in messages. Same failures as eng_mesh_file_load, file errors aside.
bool eng_mesh_data_from_arrays(const float *positions, uint32_t vertex_count, const uint32_t *indices,
                               uint32_t triangle_count, const char *name, const eng_mesh_file_options *options,
                               eng_mesh_data *out, char *err, size_t err_size);

/// Frees what the mesh owns and zeroes it. NULL and a zeroed mesh are allowed.
void eng_mesh_data_free(eng_mesh_data *mesh);

/// Moves every position by `offset` (m), the bounds and `origin` with them (e.g. by minus the
/// centre of mass a hull reports, so the drawn mesh sits on its body: mesh_physics.h).
void eng_mesh_data_translate(eng_mesh_data *mesh, const float offset[3]);

/// Edges used by an odd number of triangles, counted now (0: closed; see the top).
uint32_t eng_mesh_open_edges(const eng_mesh_data *mesh);
/// Enclosed volume, m^3, counted now: the signed sum over triangles (positive for a closed
/// mesh wound outward; meaningless for an open one).
double eng_mesh_volume(const eng_mesh_data *mesh);

/// ---- filling the inside with water ------------------------------------------------------

/// The largest lattice eng_mesh_fill_points scans: sites over the mesh's bounds, 2^27.
#define ENG_MESH_FILL_MAX_SITES (1u << 27)

typedef struct eng_mesh_fill_options {
    /// m, >= 0, finite: sites nearer than this to the surface are left out. Default 0 (every
    /// site strictly inside). spacing / 2 keeps the water as far from the surface as a
    /// block's lattice keeps it from the block's faces.
    float clearance;
    /// The most points to return, >= 1: a fill holding more is refused with both numbers
    /// (e.g. the fluid's free capacity). Default ENG_MESH_FILL_MAX_SITES.
    uint32_t max_points;
    /// Pose of the mesh: points come out as position + rotation * (mesh point). m and a unit
    /// quaternion x, y, z, w (length 1 within 1e-3). Default: origin, identity.
    float position[3];
    float rotation[4];
} eng_mesh_fill_options;

/// Defaults: clearance 0, max_points ENG_MESH_FILL_MAX_SITES, at the origin, not rotated.
eng_mesh_fill_options eng_default_mesh_fill_options(void);

/// The sites of a lattice of `spacing` m (finite, > 0; 2 * particle_radius for water at
/// rest) that lie strictly inside the closed mesh, as *out_count xyz triples in *out_points
/// (malloc'd; free() them; NULL when the count is 0), ready for pbf_world_add_particles.
/// The lattice is a block's (pbf_block_def) over the mesh's bounds: sites at
/// bounds_min + spacing * (i + 1/2) for i < floor(extent / spacing), at least one per axis,
/// so a box-shaped mesh fills exactly like a block of its size. options may be NULL.
///
/// Inside is decided by ray parity, row by row along x: each row of sites is crossed with
/// every triangle (edges and corners shared by two triangles count once, by a consistent
/// tie rule), and a site is inside when an odd number of crossings lie beyond it. Sites on
/// the surface are outside. Nested shells (a hollow ball) and touching parts work; overlapping
/// parts (two boxes through each other) are inside where an odd number of them overlap.
///
/// Refused (false, with a message naming the mesh): an open mesh ("... has 4 open edges:
/// no inside to fill"), a bad spacing or option, a lattice of more than
/// ENG_MESH_FILL_MAX_SITES sites, more inside points than options->max_points.
bool eng_mesh_fill_points(const eng_mesh_data *mesh, float spacing, const eng_mesh_fill_options *options,
                          float **out_points, uint32_t *out_count, char *err, size_t err_size);

#endif
