// Internals of the fluid world shared by its C files (not a public header).
#ifndef PBF_INTERNAL_H
#define PBF_INTERNAL_H

#include <epoxy/gl.h>

#include "fluid/pbf.h"
#include "fluid/pbf_uniforms.h"
#include "shaders/fluid/pbf_shared.h"

#define RING 8
#define MAX_SCAN_LEVELS 6

enum program_id {
    PROG_PREDICT,
    PROG_GRID_COUNT,
    PROG_SCAN_BLOCK,
    PROG_SCAN_ADD,
    PROG_GRID_SCATTER,
    PROG_GRID_SORT,
    PROG_REORDER,
    PROG_NEIGHBOURS,
    PROG_DENSITY,
    PROG_DELTA,
    PROG_COLLIDE,
    PROG_VELOCITY,
    PROG_VORTICITY,
    PROG_VISCOSITY,
    PROG_METRICS,
    PROG_METRICS_FINAL,
    PROG_LIVE_COUNT,
    PROG_APPEND,
    PROG_GRID_CLEAR,
    PROG_TENSION,
    PROG_TINT,
    PROG_LEVEL_DEPOSIT,
    PROG_LEVEL_PREPARE,
    PROG_LEVEL_SWEEP,
    PROG_COUNT
};

#define PBF_MAX_EMITTERS 16

typedef struct emitter_slot {
    bool used;
    uint16_t generation;
    pbf_emitter_def def;
    float basis_u[3], basis_v[3], dir[3];
    float *disc;        // 2D lattice points on the nozzle disc (u, v pairs), m
    int disc_count;
    int cursor;         // next disc point to use (rotates so partial layers spread out)
    double travel;      // m the last layer has moved since it left the nozzle
    double credit;      // particles owed
    bool tinted;        // pours particles of tint `tint` (pbf_world_set_emitter_tint)
    float tint;         // the w of that tint (pbf_tint_encode)
} emitter_slot;

typedef struct sink_slot {
    bool used;
    uint16_t generation;
    float min[3], max[3];
} sink_slot;

typedef struct collider_slot {
    bool used;
    uint16_t generation;
    int gpu_index; // index in the uploaded array, -1 when not uploaded
    pbf_gpu_collider gpu;
    float *data;        // hull planes or distance grid (CPU copy), NULL for analytic shapes
    uint32_t data_count;
    uint64_t added_step;  // step_index when it was added (earlier steps are not its own)
    float step_scale[RING]; // force scale it had in the step issued in each ring slot
    // Per-step reports read back, indexed by step % RING (valid when step matches).
    pbf_collider_report hist[RING];
} collider_slot;

typedef struct stats_slot {
    bool pending;
    uint64_t step;
    double time;
    uint64_t appended_total; // w->appended_total when this step was issued
    GLsync fence;
    int nq;
    GLuint *queries;    // nq timestamps; query 0 is the start
    uint8_t *stage_of;  // stage of the interval ending at query k
    int substeps;
    int collider_slot_of[PBF_MAX_COLLIDERS]; // gpu index -> slot, -1 none
    int colliders;
} stats_slot;

/// Called by the step after each stage's passes (tests that compare stages: pbf_world_set_stage_hook).
typedef void pbf_stage_hook_fn(void *user, pbf_stage stage, int substep, int iteration);

struct pbf_world {
    pbf_params params;
    uint32_t capacity;
    uint32_t max_neighbours;
    uint32_t cells_per_kernel;
    uint32_t count;            // particles as last known: stats count + appended since
    uint64_t appended_total;   // particles handed to the append pass so far
    uint64_t known_appended;   // appended_total when the latest stats' step was issued
    uint32_t known_count;      // live count of the latest step whose stats arrived
    uint64_t known_step;       // 1 + that step
    bool sinks_active;
    uint32_t next_id;
    float domain_min[3], domain_max[3];
    char shader_dir[512];
    pbf_log_fn *log;
    void *log_user;
    char error[512];

    // derived
    pbf_constants k;
    float grid_origin[3];
    uint32_t grid_dims[3], cells;

    GLuint programs[PROG_COUNT];
    GLint u_scan_n[2], u_frame, u_tint[4], u_relax[2], u_apply_level[2]; // u_relax, u_apply_level: delta, collide
    GLint u_level_parity;
    GLuint level;              // pbf_gpu_level_cell[level_dims[3]] (one cell while the level is off)
    uint32_t level_dims[4];    // xyz, w = all (0 while level_sweeps is 0)
    float level_cell[3];       // m
    GLuint pos[2], vel[2], pred[2], ids[2];
    int cur_pos, cur_vel, cur_pred, cur_ids;
    GLuint cell_of, cell_start, cell_fill, sorted, lambda, omega, tension, scan, colliders, forces,
        reduce, metrics, draw, params_ubo, nb_list, nb_count, state, stage_pos, stage_vel, stage_id, order;
    GLuint forces_ring;        // the forces of the last RING steps, read by the CPU (pbf_read_buffer)
    GLuint readback;           // pbf_download's buffer, grown on demand
    GLsizeiptr readback_size;
    uint32_t stage_cap;        // particles the staging buffers hold
    bool flush_timestamps; // llvmpipe records a timestamp only when its commands are flushed
    GLint ssbo_align;
    uint32_t max_groups;   // GL_MAX_COMPUTE_WORK_GROUP_COUNT[0]: work groups one dispatch may have
    struct { GLintptr offset; uint32_t n; } scan_level[MAX_SCAN_LEVELS];
    int scan_levels;
    GLintptr scan_dummy;

    collider_slot slots[PBF_MAX_COLLIDERS];
    uint32_t gpu_colliders;
    bool colliders_dirty;
    bool in_step;         // inside pbf_world_step_with's substep hook: no nested step or edit
    bool collider_data_dirty;   // hull planes / grids changed: collider_data is rebuilt
    GLuint collider_data;       // float[]: PBF_B_COLLIDER_DATA (made on first use)
    GLsizeiptr collider_data_size;
    float planes[PBF_MAX_PLANES][4];
    int plane_count;
    emitter_slot emitters[PBF_MAX_EMITTERS];
    sink_slot sinks[PBF_MAX_SINKS];

    stats_slot ring[RING];
    pbf_step_stats done[RING]; // records read early because the ring was full, oldest first
    int done_count;
    int ring_head;   // next slot to fill
    int max_queries;
    uint64_t step_index;
    double time;

    // the time-step guard (params.cfl): speeds seen, by step
    float speed_of[PBF_GUARD_HISTORY];      // speed_max of step k at [k % PBF_GUARD_HISTORY] once read
    uint64_t speed_step[PBF_GUARD_HISTORY]; // 1 + the step each holds (0: none)
    float added_speed[PBF_GUARD_HISTORY];   // fastest particle appended before step k, same index
    bool guard_capped;          // the guard wanted more than max_substeps (warned once)
    bool tension_warned;        // the cohesion needed more than max_substeps (warned once)
    bool level_warned;          // the coarse level ran beside two-way bodies (warned once)
    bool warned_hang;           // a step's fence did not signal in PBF_STEP_WAIT_NS (said once)
    pbf_guard_seen seen_of[PBF_GUARD_HISTORY]; // step k's compression and substeps, same index as speed_of
    pbf_guard_state compression; // the compression guard's level and quiet count (pbf_guard_compression)
    bool compression_capped;    // it wanted more than max_substeps (warned once while it lasts)
    int step_substeps;          // substeps of the step being issued (or the next one)

    // latest forces read back, per slot (N, N m)
    float force[PBF_MAX_COLLIDERS][6];
    uint64_t force_step[PBF_MAX_COLLIDERS];

    pbf_stage_hook_fn *stage_hook; // NULL unless a test compares stages
    void *stage_hook_user;
};

// ---- pbf_base.c: services the world's parts share (below world, emitters, colliders) ----

/// Records an error message (and logs it); returns r.
/// True inside a step's substep hook, where `fn` may not run: the error is then set,
/// "FN: called from inside a step (the substep hook)" and `tail` (": ignored" for the calls
/// that return nothing).
bool pbf_refused_in_step(pbf_world *w, const char *fn, const char *tail);
/// True when no GL context is current on the calling thread: the error (PBF_ERR_GL) is then
/// set, naming `fn`.
bool pbf_without_context(pbf_world *w, const char *fn);

/// Bytes of one collider's force accumulators, and of a step's (pbf.forces; a slot of pbf.forces_ring).
#define PBF_COLLIDER_FORCE_BYTES (PBF_FORCE_WORDS * 4)
#define PBF_FORCES_BYTES (PBF_MAX_COLLIDERS * PBF_COLLIDER_FORCE_BYTES)
pbf_result pbf_fail(pbf_world *w, pbf_result r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/// A buffer only the GPU writes, zeroed on the GPU once (pbf_world.c explains the two kinds).
GLuint pbf_gpu_buffer(GLsizeiptr size, const char *label);
/// A buffer the CPU uploads into: made with `data` (NULL: zeros from the CPU), never cleared
/// on the GPU. 0 if the zeros could not be allocated.
GLuint pbf_cpu_buffer(GLsizeiptr size, const void *data, const char *label);
/// A buffer the CPU reads (GL_STREAM_READ): only copies and single records are written
/// into it on the GPU, so a driver may keep it in host memory. Zeroed on the GPU once.
GLuint pbf_read_buffer(GLsizeiptr size, const char *label);
/// Copies `size` bytes at `offset` of `src` into the world's read-back buffer on the GPU
/// (after the barrier shader writes need) and reads them into dst: the passes' own buffers
/// are never read by the CPU (pbf_base.c). False if the read-back buffer could not grow.
bool pbf_download(pbf_world *w, GLuint src, GLintptr offset, GLsizeiptr size, void *dst);

/// Appends particles (xyzw positions with w the colour parameter, xyzw velocities) through
/// the staging buffers and the append pass; ids are assigned here.
pbf_result pbf_append(pbf_world *w, const float *pos4, const float *vel4, uint32_t n);
/// Writes the params uniform block (a substep, or a pass outside the step: append).
void pbf_write_params(pbf_world *w, float dt, int substep, int slot);
/// Binds the particle ping-pong pairs (current as input, other as output).
void pbf_bind_particles(pbf_world *w);
/// Binds every world buffer and the params block (not the colliders' data:
/// pbf_colliders_bind) and the state buffer as the indirect dispatch buffer.
void pbf_bind_all(pbf_world *w);
/// Colour parameter of a particle at height y: its place in the domain's height, [0, 1].
float pbf_colour_of(const pbf_world *w, float y);
/// Looks up the tint pass's uniforms (pbf_tint.c), once its program is built.
void pbf_tint_locate(pbf_world *w);
/// Emitters (pbf_emitters.c): particles they owe for a step of dt, appended.
pbf_result pbf_emitters_emit(pbf_world *w, float dt);
void pbf_emitters_free(pbf_world *w);

/// How long a wait for a step's fence may take before the GPU counts as hung (ns).
#define PBF_STEP_WAIT_NS 10000000000ull
/// True once step record r's fence has signalled; with `wait`, after waiting up to
/// PBF_STEP_WAIT_NS; a GPU that has not finished by then is reported (a warning through the
/// world's log, once per world) and the caller goes on without that record.
bool pbf_step_done(pbf_world *w, const stats_slot *r, bool wait);
/// The step records' ring (pbf_stats.c): the live count made exact by reading every step in
/// flight (true when one was read); a pending record read now and kept for the next poll;
/// the fastest particle speed of a finished step (-1 when its record is gone).
bool pbf_count_settle(pbf_world *w);
/// The registry of worlds alive (pbf_base.c): false when out of memory.
bool pbf_live_add(const pbf_world *w);
void pbf_live_remove(const pbf_world *w);
void pbf_read_early(pbf_world *w, stats_slot *slot);
float pbf_speed_of_step(pbf_world *w, uint64_t step);
/// Colliders (pbf_colliders.c): upload before a step, read forces after.
void pbf_colliders_upload(pbf_world *w);
void pbf_colliders_begin_step(pbf_world *w, stats_slot *slot);
void pbf_colliders_end_step(pbf_world *w);
void pbf_colliders_read_forces(pbf_world *w, const stats_slot *r);
/// Particles in id order (see pbf_world_read_particles); `volumes` receives vel.w, the volume
/// of the step's last density pass (0 for particles added since). Any output may be NULL.
uint32_t pbf_read_sorted(pbf_world *w, float *positions, float *velocities, float *volumes, uint32_t *ids,
                         uint32_t max);
/// Binds the collider data buffer (call where the step binds its buffers).
void pbf_colliders_bind(pbf_world *w);
/// Frees the colliders' CPU copies and GL buffers (pbf_world_destroy).
void pbf_colliders_free(pbf_world *w);

// ---- pbf_inspect.c: looking inside a step (tests/test_mirror.c) ---------------------------

/// Calls fn after each stage of every step (NULL, the default: none; unset, it costs the
/// step one pointer test per stage). It runs right after the stage's passes were
/// issued, before the step flips a ping-pong pair, so a stage's results are where its
/// passes wrote them: reorder, delta, collide and viscosity in the *_OUT bindings. `substep`
/// counts from 0; `iteration` is the solver iteration of the density, delta and collide
/// stages (density is called from 1: the neighbours stage computes iteration 0's) and -1
/// for the others. The metrics stage is reported once per step, after the last substep.
/// The CPU reference (pbf_cpu_internal.h) calls its hook at the same points.
void pbf_world_set_stage_hook(pbf_world *w, pbf_stage_hook_fn *fn, void *user);

/// Reads `bytes` from the start of the buffer the passes see at storage binding `binding`
/// (PBF_B_POS ... PBF_B_COLLIDER_DATA, the ping-pong pairs as currently bound), which
/// holds its data in slot order; waits for the GPU (a GL_BUFFER_UPDATE barrier, then
/// glGetBufferSubData). For tests and tools only: it stalls the pipeline. The neighbour
/// lists (PBF_B_NB_LIST), interleaved on the GPU, come back a row of max_neighbours
/// entries per particle, as the CPU reference holds them.
pbf_result pbf_world_read_binding(pbf_world *w, int binding, size_t bytes, void *out);

#endif
