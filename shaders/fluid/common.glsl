// Shared declarations of the fluid passes: buffers, kernels, grid, boundaries.
// Included by every shaders/fluid/*.comp after its #version line. A pass defines
// USE_<BUFFER> for each storage block it touches before including this file: std430
// blocks count against GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS even when unused. Blocks are
// `readonly` unless the pass also defines WRITE_<BUFFER> (WRITE_STATE for the state): the
// compiler then refuses a stray write, and the strict GL mode knows which passes write
// what (a barrier is owed only after a write).
#include "pbf_shared.h"

layout(std140, binding = PBF_U_PARAMS) uniform Params { pbf_gpu_params P; };
#ifdef WRITE_STATE
layout(std430, binding = PBF_B_STATE) buffer State { pbf_gpu_state state; };
#else
layout(std430, binding = PBF_B_STATE) readonly buffer State { pbf_gpu_state state; };
#endif

// Live particles (kept on the GPU; sinks and appends change it between passes).
uint particle_count() { return state.count; }

#ifdef USE_POS
#ifdef WRITE_POS
layout(std430, binding = PBF_B_POS) buffer PosIn { vec4 pos[]; };
#else
layout(std430, binding = PBF_B_POS) readonly buffer PosIn { vec4 pos[]; };
#endif
#endif
#ifdef USE_VEL
#ifdef WRITE_VEL
layout(std430, binding = PBF_B_VEL) buffer VelIn { vec4 vel[]; };
#else
layout(std430, binding = PBF_B_VEL) readonly buffer VelIn { vec4 vel[]; };
#endif
#endif
#ifdef USE_PRED
#ifdef WRITE_PRED
layout(std430, binding = PBF_B_PRED) buffer PredIn { vec4 pred[]; };
#else
layout(std430, binding = PBF_B_PRED) readonly buffer PredIn { vec4 pred[]; };
#endif
#endif
#ifdef USE_ID
#ifdef WRITE_ID
layout(std430, binding = PBF_B_ID) buffer IdIn { uint pid[]; };
#else
layout(std430, binding = PBF_B_ID) readonly buffer IdIn { uint pid[]; };
#endif
#endif
#ifdef USE_POS_OUT
#ifdef WRITE_POS_OUT
layout(std430, binding = PBF_B_POS_OUT) buffer PosOut { vec4 pos_out[]; };
#else
layout(std430, binding = PBF_B_POS_OUT) readonly buffer PosOut { vec4 pos_out[]; };
#endif
#endif
#ifdef USE_VEL_OUT
#ifdef WRITE_VEL_OUT
layout(std430, binding = PBF_B_VEL_OUT) buffer VelOut { vec4 vel_out[]; };
#else
layout(std430, binding = PBF_B_VEL_OUT) readonly buffer VelOut { vec4 vel_out[]; };
#endif
#endif
#ifdef USE_PRED_OUT
#ifdef WRITE_PRED_OUT
layout(std430, binding = PBF_B_PRED_OUT) buffer PredOut { vec4 pred_out[]; };
#else
layout(std430, binding = PBF_B_PRED_OUT) readonly buffer PredOut { vec4 pred_out[]; };
#endif
#endif
#ifdef USE_ID_OUT
#ifdef WRITE_ID_OUT
layout(std430, binding = PBF_B_ID_OUT) buffer IdOut { uint pid_out[]; };
#else
layout(std430, binding = PBF_B_ID_OUT) readonly buffer IdOut { uint pid_out[]; };
#endif
#endif
#ifdef USE_CELL
#ifdef WRITE_CELL
layout(std430, binding = PBF_B_CELL) buffer Cells { uint cell_of[]; };
#else
layout(std430, binding = PBF_B_CELL) readonly buffer Cells { uint cell_of[]; };
#endif
#endif
#ifdef USE_CELL_START
#ifdef WRITE_CELL_START
layout(std430, binding = PBF_B_CELL_START) buffer CellStart { uint cell_start[]; };
#else
layout(std430, binding = PBF_B_CELL_START) readonly buffer CellStart { uint cell_start[]; };
#endif
#endif
#ifdef USE_CELL_FILL
#ifdef WRITE_CELL_FILL
layout(std430, binding = PBF_B_CELL_FILL) buffer CellFill { uint cell_fill[]; };
#else
layout(std430, binding = PBF_B_CELL_FILL) readonly buffer CellFill { uint cell_fill[]; };
#endif
#endif
#ifdef USE_SORTED
#ifdef WRITE_SORTED
layout(std430, binding = PBF_B_SORTED) buffer Sorted { uint sorted_slot[]; };
#else
layout(std430, binding = PBF_B_SORTED) readonly buffer Sorted { uint sorted_slot[]; };
#endif
#endif
#ifdef USE_ORDER
#ifdef WRITE_ORDER
layout(std430, binding = PBF_B_ORDER) buffer Order { uint order[]; };
#else
layout(std430, binding = PBF_B_ORDER) readonly buffer Order { uint order[]; };
#endif
#endif
#ifdef USE_LAMBDA
#ifdef WRITE_LAMBDA
layout(std430, binding = PBF_B_LAMBDA) buffer Lambda { vec2 lambda_rho[]; };
#else
layout(std430, binding = PBF_B_LAMBDA) readonly buffer Lambda { vec2 lambda_rho[]; };
#endif
#endif
#ifdef USE_OMEGA
#ifdef WRITE_OMEGA
layout(std430, binding = PBF_B_OMEGA) buffer Omega { vec4 omega[]; };
#else
layout(std430, binding = PBF_B_OMEGA) readonly buffer Omega { vec4 omega[]; };
#endif
#endif
#ifdef USE_TENSION
#ifdef WRITE_TENSION
layout(std430, binding = PBF_B_TENSION) buffer Tension { vec4 tension[]; };
#else
layout(std430, binding = PBF_B_TENSION) readonly buffer Tension { vec4 tension[]; };
#endif
#endif
#ifdef USE_LEVEL
#ifdef WRITE_LEVEL
layout(std430, binding = PBF_B_LEVEL) buffer Level { pbf_gpu_level_cell level[]; };
#else
layout(std430, binding = PBF_B_LEVEL) readonly buffer Level { pbf_gpu_level_cell level[]; };
#endif
#endif
#ifdef USE_COLLIDERS
#ifdef WRITE_COLLIDERS
layout(std430, binding = PBF_B_COLLIDERS) buffer Colliders { pbf_gpu_collider colliders[]; };
#else
layout(std430, binding = PBF_B_COLLIDERS) readonly buffer Colliders { pbf_gpu_collider colliders[]; };
#endif
#endif
#ifdef USE_NB
#ifdef WRITE_NB
layout(std430, binding = PBF_B_NB_LIST) buffer NbList { uint nb_list[]; };
#else
layout(std430, binding = PBF_B_NB_LIST) readonly buffer NbList { uint nb_list[]; };
#endif
#ifdef WRITE_NB
layout(std430, binding = PBF_B_NB_COUNT) buffer NbCount { uint nb_count[]; };
#else
layout(std430, binding = PBF_B_NB_COUNT) readonly buffer NbCount { uint nb_count[]; };
#endif
// Neighbour j (a slot) of particle i, k < nb_len(i); the particle itself is not listed.
// The lists are interleaved: entry k of every particle, then entry k + 1 (index
// k * capacity + i), so the invocations of a work group, consecutive particles, read and
// write consecutive words at each k (coalesced on a GPU) instead of one word each from rows
// max_neighbours apart. The CPU reference keeps a row per particle; pbf_world_read_binding
// hands the lists back in that layout.
uint nb_index(uint i, uint k) { return k * P.capacity + i; }
uint nb_len(uint i) { return min(nb_count[i] & ~PBF_NB_CUT, P.max_neighbours); }
uint nb_at(uint i, uint k) { return nb_list[nb_index(i, k)]; }
#endif
#ifdef USE_FORCES
#ifdef WRITE_FORCES
layout(std430, binding = PBF_B_FORCES) buffer Forces { int forces[]; };
#else
layout(std430, binding = PBF_B_FORCES) readonly buffer Forces { int forces[]; };
#endif
#endif

// ---- kernels, boundaries, rigid frames: shared with the CPU reference ----------------
#include "pbf_kernels.h"

#if defined(USE_POS) && defined(USE_NB)
// The walls' share of the density at particle i's step-end position xi (next to a wall
// only): its nn listed neighbours' images and its own, added to sum_w. For the passes that
// sum the final positions' density (viscosity.comp, and metrics.comp when that one did not run).
void add_final_wall_images(uint i, vec3 xi, uint nn, inout float sum_w)
{
    vec3 twice;
    uint mask = mirror_mask(xi, twice);
    if (mask == 0u) return;
    vec3 unused_grad = vec3(0.0);
    float unused_grad2 = 0.0;
    for (uint q = 0u; q < nn; q++)
        density_add_images(xi, pos[nb_at(i, q)].xyz, mask, twice, sum_w, unused_grad, unused_grad2);
    density_add_self_images(xi, mask, twice, sum_w, unused_grad, unused_grad2);
}
#endif

// ---- grid ---------------------------------------------------------------------------
ivec3 cell_coord(vec3 x)
{
    ivec3 c = ivec3(floor((x - P.grid_origin.xyz) * P.inv_cell));
    return clamp(c, ivec3(0), ivec3(P.grid_dims.xyz) - 1);
}

// The grid is virtual (cells of 1 / P.inv_cell over the domain, P.grid_dims.xyz of them);
// cells go to P.grid_dims.w buckets (a power of two, a few per particle). A row of cells
// (fixed y, z) takes consecutive buckets, so the cells a kernel reaches in a row are one run
// of buckets (two where it wraps) and, particles being stored in bucket order, one or two
// contiguous ranges of slots. The rows follow each other along a Morton curve of (y, z),
// each P.row_stride buckets after the last (at least dims_x; pbf_row_stride spreads the
// rows evenly where the curve wraps at the bucket count): rows that are near each other are
// near in memory, so the neighbours a work group gathers lie in a few stretches instead of
// one per row (an NVIDIA H200, 4 iterations: 1M particles 2.13 -> 1.87 ms a step, 4M 9.63 ->
// 7.25, against a hash of the row; docs/performance.md). Rows that share buckets are told
// apart by row_of (pbf_uniforms.h pbf_hash_buckets; grid_row and grid_bucket are
// pbf_kernels.h's, shared with the CPU reference).
uint row_of(ivec3 c) { return grid_row(uint(c.y), uint(c.z)); }

uint bucket_of(ivec3 c) { return grid_bucket(uint(c.x), uint(c.y), uint(c.z)); }

