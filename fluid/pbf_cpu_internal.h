// Internals of the CPU reference shared by its files (pbf_cpu.c: the world and the step;
// pbf_cpu_passes.c: the passes of shaders/fluid/*.comp; pbf_cpu_colliders.c: colliders.glsl).
#ifndef PBF_CPU_INTERNAL_H
#define PBF_CPU_INTERNAL_H

#include "fluid/pbf_cpu.h"
#include "shaders/fluid/pbf_shared.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>

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
    int32_t forces[PBF_MAX_COLLIDERS][8];
    uint64_t steps;          // steps taken (the latest report's step is steps - 1)
    uint32_t report_substeps;// substeps of the latest step (forces are averaged over them)
    uint32_t last_substep;   // P.substep of the latest substep (the metrics pass sees it)

    // Particle slots; the second of each pair is the ping-pong partner.
    pbf_float4 *pos, *pos_out, *vel, *vel_out, *pred, *pred_out, *omega;
    uint32_t *id, *id_out;
    float *lambda, *rho;
    // Grid and neighbour lists.
    uint32_t *cell_of, *cell_start, *cell_fill, *sorted;
    uint32_t *nb_list, *nb_count;
    bool nb_valid; // the lists belong to the current slots and positions
    char error[512];
};

// ---- small vector helpers (float, evaluated in the order the shaders write) ----------

typedef struct v3 {
    float x, y, z;
} v3;

static inline v3 xyz(pbf_float4 a) { return (v3){ a.x, a.y, a.z }; }
static inline v3 add(v3 a, v3 b) { return (v3){ a.x + b.x, a.y + b.y, a.z + b.z }; }
static inline v3 sub(v3 a, v3 b) { return (v3){ a.x - b.x, a.y - b.y, a.z - b.z }; }
static inline v3 scale(float s, v3 a) { return (v3){ s * a.x, s * a.y, s * a.z }; }
static inline v3 divide(v3 a, float s) { return (v3){ a.x / s, a.y / s, a.z / s }; }
static inline float dot(v3 a, v3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline float length(v3 a) { return sqrtf(dot(a, a)); }
static inline v3 cross(v3 a, v3 b)
{
    return (v3){ a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y };
}
static inline float clampf(float x, float lo, float hi) { return fminf(fmaxf(x, lo), hi); }
static inline float signf(float x) { return x > 0.0f ? 1.0f : x < 0.0f ? -1.0f : 0.0f; }
static inline bool finite3(v3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }

/// Records an error message; returns r.
pbf_result pbf_cpu_fail(pbf_cpu_world *w, pbf_result r, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

// ---- pbf_cpu_passes.c: the passes, each named for the shader it mirrors ----------------
float pbf_cpu_poly6(const pbf_gpu_params *P, float r2);
v3 pbf_cpu_grad_spiky(const pbf_gpu_params *P, v3 r);
float pbf_cpu_wall_volume(const pbf_gpu_params *P, float d);
float pbf_cpu_wall_gradient(const pbf_gpu_params *P, float d);
float pbf_cpu_container_boundary(const pbf_gpu_params *P, v3 x, v3 *grad);
void pbf_cpu_swap4(pbf_float4 **a, pbf_float4 **b);
void pbf_cpu_predict(pbf_cpu_world *w, const pbf_gpu_params *P);
void pbf_cpu_build_grid(pbf_cpu_world *w, const pbf_float4 *x, const pbf_gpu_params *P);
void pbf_cpu_reorder(pbf_cpu_world *w);
void pbf_cpu_find_neighbours(pbf_cpu_world *w, const pbf_float4 *x, const pbf_gpu_params *P);
void pbf_cpu_density(pbf_cpu_world *w, const pbf_gpu_params *P);
void pbf_cpu_delta(pbf_cpu_world *w, const pbf_gpu_params *P);
void pbf_cpu_collide(pbf_cpu_world *w, const pbf_gpu_params *P);
void pbf_cpu_velocity(pbf_cpu_world *w, const pbf_gpu_params *P);
void pbf_cpu_vorticity(pbf_cpu_world *w, const pbf_gpu_params *P);
void pbf_cpu_viscosity(pbf_cpu_world *w, const pbf_gpu_params *P);
float pbf_cpu_density_at(const pbf_cpu_world *w, const pbf_gpu_params *P, uint32_t i);

// ---- pbf_cpu_colliders.c: colliders.glsl and pbf_colliders.c's step bookkeeping ---------
void pbf_cpu_colliders_density(const pbf_cpu_world *w, const pbf_gpu_params *P, v3 x, float *rho, v3 *grad_i);
void pbf_cpu_colliders_delta(pbf_cpu_world *w, const pbf_gpu_params *P, v3 x, float lambda, v3 *dp);
v3 pbf_cpu_colliders_collide(pbf_cpu_world *w, const pbf_gpu_params *P, v3 xs, v3 x);
void pbf_cpu_colliders_begin_step(pbf_cpu_world *w);
void pbf_cpu_colliders_end_step(pbf_cpu_world *w);

#endif
