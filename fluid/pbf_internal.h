// Internals of the fluid world shared by its C files (not a public header).
#ifndef PBF_INTERNAL_H
#define PBF_INTERNAL_H

#include <epoxy/gl.h>

#include "fluid/pbf.h"
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
    PROG_VELOCITY,
    PROG_VORTICITY,
    PROG_VISCOSITY,
    PROG_METRICS,
    PROG_METRICS_FINAL,
    PROG_COUNT
};

typedef struct collider_slot {
    bool used;
    uint16_t generation;
    int gpu_index; // index in the uploaded array, -1 when not uploaded
    pbf_gpu_collider gpu;
} collider_slot;

typedef struct stats_slot {
    bool pending;
    uint64_t step;
    double time;
    uint32_t count;
    GLsync fence;
    int nq;
    GLuint *queries;    // nq timestamps; query 0 is the start
    uint8_t *stage_of;  // stage of the interval ending at query k
    int substeps;
    int collider_slot_of[PBF_MAX_COLLIDERS]; // gpu index -> slot, -1 none
    int colliders;
} stats_slot;

struct pbf_world {
    pbf_params params;
    uint32_t capacity;
    uint32_t max_neighbours;
    uint32_t count;
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
    GLint u_scan_n[2], u_groups, u_frame;
    GLuint pos[2], vel[2], pred[2], ids[2];
    int cur_pos, cur_vel, cur_pred, cur_ids;
    GLuint cell_of, cell_start, cell_fill, sorted, lambda, omega, scan, colliders, forces,
        reduce, metrics, draw, params_ubo, nb_list, nb_count;
    bool flush_timestamps; // llvmpipe records a timestamp only when its commands are flushed
    GLint ssbo_align;
    struct { GLintptr offset; uint32_t n; } scan_level[MAX_SCAN_LEVELS];
    int scan_levels;
    GLintptr scan_dummy;

    collider_slot slots[PBF_MAX_COLLIDERS];
    uint32_t gpu_colliders;
    bool colliders_dirty;
    float planes[PBF_MAX_PLANES][4];
    int plane_count;

    stats_slot ring[RING];
    int ring_head;   // next slot to fill
    int max_queries;
    uint64_t step_index;
    double time;

    // latest forces read back, per slot (N, N m)
    float force[PBF_MAX_COLLIDERS][6];
    uint64_t force_step[PBF_MAX_COLLIDERS];
};

/// Records an error message (and logs it); returns r.
pbf_result pbf_fail(pbf_world *w, pbf_result r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/// Colliders (pbf_colliders.c): upload before a step, read forces after.
void pbf_colliders_upload(pbf_world *w);
void pbf_colliders_begin_step(pbf_world *w, stats_slot *slot);
void pbf_colliders_end_step(pbf_world *w);
void pbf_colliders_read_forces(pbf_world *w, const stats_slot *r);

#endif
