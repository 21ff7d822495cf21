// Internals of the CPU reference shared by its files (pbf_cpu.c: the world and the step;
// pbf_cpu_passes.c: the passes of shaders/fluid/*.comp; pbf_cpu_colliders.c: colliders.glsl).
#ifndef PBF_CPU_INTERNAL_H
#define PBF_CPU_INTERNAL_H

#include "fluid/pbf_cpu.h"
#include "fluid/pbf_uniforms.h"
#include "shaders/fluid/pbf_shared.h"
// The formulas the shaders use (kernels, boundaries, frames, the density constraint) and
// the vector vocabulary they are written in (pbf_vec3, pbf_add, pbf_scale, ...).
#include "shaders/fluid/pbf_kernels.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

/// Called by the step after each stage, at the point where pbf_world.c calls its stage hook
/// (pbf_internal.h): `substep` counts from 0, `iteration` is the solver iteration of the
/// density, delta and collide stages and -1 for the others.
typedef void pbf_cpu_stage_hook_fn(void *user, pbf_stage stage, int substep, int iteration);

/// Sets the stage hook (NULL: none, the default); for tests that compare stages.
void pbf_cpu_world_set_stage_hook(pbf_cpu_world *world, pbf_cpu_stage_hook_fn *fn, void *user);

/// The array that mirrors the GPU buffer at storage binding `binding` (PBF_B_POS ...), in
/// slot order and the GPU's layout, as the passes see it now (the ping-pong pairs as the
/// step has them flipped); *bytes receives its live size (count particles, cells + 2 cell
/// starts, gpu colliders x 8 force accumulators). NULL for a binding with no twin here.
void *pbf_cpu_world_binding(pbf_cpu_world *world, int binding, size_t *bytes);

struct pbf_cpu_world {
    pbf_params params;
    pbf_constants k;
    uint32_t capacity, count, max_neighbours;
    uint32_t cells_per_kernel; // the GPU's default: the same grid, so the same sums in the same order
    float domain_min[3], domain_max[3];
    float grid_origin[3];
    uint32_t grid_dims[3], cells;
    float planes[PBF_MAX_PLANES][4];
    uint32_t plane_count;
    // Colliders as pbf_colliders.c keeps them (`colliders`, the host's copy, whose previous
    // pose catches up at the end of a step) and as the passes see them (`gpu`, uploaded at
    // the start of each step with the span of the poses set since), hull planes and grid
    // samples packed in `collider_data` (info.z offsets), and the step's fixed-point
    // force accumulators (PBF_B_FORCES: force xyz, contacts, torque xyz, push-outs).
    pbf_gpu_collider colliders[PBF_MAX_COLLIDERS], gpu[PBF_MAX_COLLIDERS];
    uint32_t collider_count, gpu_count;
    float *collider_data;
    uint32_t collider_data_count;
    int32_t forces[PBF_MAX_COLLIDERS][PBF_FORCE_WORDS];
    uint64_t steps;          // steps taken (the latest report's step is steps - 1)
    bool stepping;           // inside pbf_cpu_world_step: gpu[] holds the substep's colliders
    uint32_t report_substeps;// substeps of the latest step (forces are averaged over them)
    uint32_t last_substep;   // P.substep of the latest substep (the metrics pass sees it)
    // The time-step guard, as pbf_world.c keeps it: the fastest speed at the end of step k
    // at [k % PBF_GUARD_HISTORY], the fastest particle added before step k at the same index.
    float speed_of[PBF_GUARD_HISTORY], added_speed[PBF_GUARD_HISTORY];
    pbf_guard_seen seen_of[PBF_GUARD_HISTORY]; // as the GPU world's (pbf_guard_compression)
    pbf_guard_state compression;

    // Particle slots in the GPU's layout (each array is the twin of a storage buffer, see
    // pbf_cpu_world_binding); the second of each pair is the ping-pong partner, flipped by
    // the step where pbf_world.c flips its bindings. pred.w carries lambda after the density
    // pass, vel.w the particle's volume m / rho after the velocity pass, as on the GPU.
    pbf_float4 *pos, *pos_out, *vel, *vel_out, *pred, *pred_out, *omega, *tension;
    uint32_t *id, *id_out;
    float *lambda_rho; // (lambda, rho kg/m^3) pairs: PBF_B_LAMBDA
    // Grid (cells + 2 starts: the cells, the removed cell of sinks, the total) and lists.
    uint32_t *cell_of, *cell_start, *cell_fill, *sorted, *order;
    uint32_t *nb_list, *nb_count;
    pbf_gpu_level_cell *level; // the coarse level's cells (NULL while level_sweeps is 0): PBF_B_LEVEL
    uint32_t level_dims[4];
    float level_cell[3];
    bool nb_valid; // the lists belong to the current slots and positions
    pbf_cpu_stage_hook_fn *hook; // called after each stage (tests); NULL: none
    void *hook_user;
    char error[512];
};

static inline bool pbf_cpu_finite3(pbf_vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

/// Records an error message; returns r.
pbf_result pbf_cpu_fail(pbf_cpu_world *w, pbf_result r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

// ---- pbf_cpu_passes.c: the passes, each named for the shader it mirrors ----------------
// Each runs over the live particles (w->count) and reads and writes the arrays its shader
// binds, ping-pong partners included; none flips a pair (the step does).
void pbf_cpu_predict(pbf_cpu_world *w, const pbf_gpu_params *P);
/// grid_count.comp at positions x (pred in the step), after the clear the step does first.
void pbf_cpu_grid_count(pbf_cpu_world *w, const pbf_gpu_params *P, const pbf_float4 *x);
void pbf_cpu_grid_scan(pbf_cpu_world *w);
void pbf_cpu_grid_scatter(pbf_cpu_world *w);
void pbf_cpu_grid_sort(pbf_cpu_world *w);
void pbf_cpu_reorder(pbf_cpu_world *w);
/// neighbours.comp at positions x. `place` maps a place in cell order to its slot (NULL:
/// the slots are in cell order, as after reorder). With `solve`, the first iteration's
/// density and lambda as well, as the shader computes them.
void pbf_cpu_neighbours(pbf_cpu_world *w, const pbf_gpu_params *P, const pbf_float4 *x, const uint32_t *place,
                        bool solve);
void pbf_cpu_density(pbf_cpu_world *w, const pbf_gpu_params *P);
void pbf_cpu_delta(pbf_cpu_world *w, const pbf_gpu_params *P, float relax, bool apply_level);
void pbf_cpu_collide(pbf_cpu_world *w, const pbf_gpu_params *P, float relax, bool apply_level);
void pbf_cpu_velocity(pbf_cpu_world *w, const pbf_gpu_params *P);
void pbf_cpu_vorticity(pbf_cpu_world *w, const pbf_gpu_params *P);
void pbf_cpu_viscosity(pbf_cpu_world *w, const pbf_gpu_params *P);
void pbf_cpu_tension(pbf_cpu_world *w, const pbf_gpu_params *P);
void pbf_cpu_level(pbf_cpu_world *w, const pbf_gpu_params *P);
/// metrics.comp's density of slot i at its position (kg/m^3).
float pbf_cpu_density_at(const pbf_cpu_world *w, const pbf_gpu_params *P, uint32_t i);

// ---- pbf_cpu_colliders.c: colliders.glsl and pbf_colliders.c's step bookkeeping ---------
void pbf_cpu_colliders_density(const pbf_cpu_world *w, const pbf_gpu_params *P, pbf_vec3 x, float *rho, pbf_vec3 *grad_i);
void pbf_cpu_colliders_delta(pbf_cpu_world *w, const pbf_gpu_params *P, pbf_vec3 x, float lambda, float relax,
                             float level_lambda, pbf_vec3 xs, pbf_vec3 *dp);
pbf_vec3 pbf_cpu_colliders_collide(pbf_cpu_world *w, const pbf_gpu_params *P, pbf_vec3 xs, pbf_vec3 x);
void pbf_cpu_colliders_begin_step(pbf_cpu_world *w);
void pbf_cpu_colliders_end_step(pbf_cpu_world *w);

#endif
