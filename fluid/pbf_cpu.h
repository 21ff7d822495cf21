// Seiche fluid, CPU reference: the GPU step of pbf_world.c and shaders/fluid/*.comp
// redone in plain C, float32, one thread, for small scenes (tests, tools, debugging).
//
// It is a second implementation of the same specification, not a port of a port: the
// stages are the same (per substep: predict, grid count, scan, scatter and sort, reorder,
// neighbours with the first iteration's density, iterations x {density (from the second),
// delta, collide (only with colliders)}, velocity, then vorticity (eps > 0) and viscosity
// when either is on), each a function that reads and writes the arrays its shader binds, in
// the same layout; the constants come from pbf_derive_constants, and the per-particle
// arithmetic is written in the shaders' order. The neighbour grid is the GPU's (cell size
// h, same origin and dimensions, a stable counting sort each substep), so neighbour lists
// come in the same order and the sums run in the same order too; what remains is the shader
// compiler's freedom (fused multiply-adds, sqrt/pow precision). tests/test_mirror.c runs
// each stage on both from the same input and compares them (pbf_cpu_internal.h's hook).
//
// Colliders are mirrored with colliders.glsl's shapes (hulls and distance grids included),
// poses (a pose set between steps is interpolated substep by substep), boundary share,
// swept collisions, push-out and the fixed-point reaction forces; the host side mirrors
// pbf_colliders.c for poses set between steps (there is no substep hook here).
// Not mirrored: emitters, sinks, stage timers.
// All positions in metres, velocities in m/s, densities in kg/m^3, times in seconds.
//
//     pbf_cpu_world *w = pbf_cpu_world_create(&params, 4096, lo, hi, err, sizeof err);
//     pbf_cpu_world_set_container(w, lo, hi, false);
//     pbf_cpu_world_add_block(w, &block, NULL);
//     pbf_cpu_world_step(w, 1.0f / 120.0f);
//     pbf_cpu_world_read_particles(w, pos4, vel4, NULL, n);
#ifndef PBF_CPU_H
#define PBF_CPU_H

#include "fluid/pbf.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct pbf_cpu_world pbf_cpu_world;

/// Density statistics of the current state, computed as metrics.comp does: poly6 over the
/// neighbour list of the last substep at the final positions, plus the boundaries' share.
typedef struct pbf_cpu_stats {
    uint32_t particles;
    float density_avg;       ///< kg/m^3, mean over particles with finite state
    float density_max;       ///< kg/m^3
    float density_error_avg; ///< mean of max(rho / rho0 - 1, 0)
    uint32_t nan_count;      ///< particles with a non-finite position or velocity
    uint32_t outside_count;  ///< particles outside the domain
    uint32_t overflow_count; ///< particles with more neighbours than max_neighbours
} pbf_cpu_stats;

/// Creates a world for up to `capacity` particles ([1, 2^20]) in the domain [min, max]
/// (m; the hashed neighbour grid covers it, at most 65536 cells per axis). Parameters
/// are checked by pbf_params_validate. max_neighbours starts at pbf_suggest_max_neighbours,
/// as in pbf_default_world_def. Returns NULL and a message naming the field on error.
pbf_cpu_world *pbf_cpu_world_create(const pbf_params *params, uint32_t capacity, const float domain_min[3],
                                    const float domain_max[3], char *err, size_t err_size);
void pbf_cpu_world_destroy(pbf_cpu_world *world);
/// Message of the latest failed call ("" if none).
const char *pbf_cpu_world_last_error(const pbf_cpu_world *world);
const pbf_params *pbf_cpu_world_params(const pbf_cpu_world *world);
/// Changes parameters between steps (validated; on error nothing changes), as
/// pbf_world_set_params: a new kernel radius re-lays the grid over the same domain.
pbf_result pbf_cpu_world_set_params(pbf_cpu_world *world, const pbf_params *params);
/// Neighbour list length per particle, [8, 512], as pbf_world_def.max_neighbours: a
/// particle keeps the first max_neighbours found, in grid order, like the GPU.
pbf_result pbf_cpu_world_set_max_neighbours(pbf_cpu_world *world, uint32_t max_neighbours);

/// The same inward planes as pbf_world_set_container: floor, -x, +x, -z, +z walls, and
/// the lid when closed_top. Must lie inside the domain.
pbf_result pbf_cpu_world_set_container(pbf_cpu_world *world, const float min[3], const float max[3],
                                       bool closed_top);
void pbf_cpu_world_remove_container(pbf_cpu_world *world);

/// The same lattice, order (x fastest, then y, then z) and colour parameter as
/// pbf_world_add_block. `added` (may be NULL) receives the number of particles.
pbf_result pbf_cpu_world_add_block(pbf_cpu_world *world, const pbf_block_def *block, uint32_t *added);
/// Adds particles at xyz triples (m) with velocities (m/s; NULL: at rest), ids in order.
pbf_result pbf_cpu_world_add_particles(pbf_cpu_world *world, const float *positions, const float *velocities,
                                       uint32_t count);
/// Adds a collider of any pbf_collider_type (hull planes and distance grid samples are
/// copied) at def->position and rotation, checked like pbf_world_add_collider, with the
/// same derived data (normalised rotation and plane normal, bounding radius, force scale).
/// `index` (may be NULL) receives its 0-based index, in the order of addition.
pbf_result pbf_cpu_world_add_collider(pbf_cpu_world *world, const pbf_collider_def *def, uint32_t *index);
/// pbf_world_set_collider_pose called between steps: the collider reaches this pose at the
/// end of the next step, moving from the one it has along the path the GPU interpolates
/// (linear in position, normalised-linear in rotation, substep by substep).
/// center_of_mass (m, may be NULL: the position) is where torque is taken about.
pbf_result pbf_cpu_world_set_collider_pose(pbf_cpu_world *world, uint32_t index, const float position[3],
                                           const float rotation[4], const float center_of_mass[3]);
/// The fluid's force and torque on two-way collider `index` during the latest step, from the
/// same fixed-point accumulators as the GPU (averaged over substeps), its contacts and
/// push-outs: pbf_world_collider_report with steps_back 1 (ready is false before a step).
pbf_result pbf_cpu_world_collider_report(const pbf_cpu_world *world, uint32_t index, pbf_collider_report *out);
uint32_t pbf_cpu_world_particle_count(const pbf_cpu_world *world);

/// Advances by dt seconds ((0, 1]) in params.substeps substeps, as pbf_world_step.
pbf_result pbf_cpu_world_step(pbf_cpu_world *world, float dt);

/// Copies up to max particles in id order: positions (xyz m, w colour parameter) and
/// velocities (xyz m/s, w 0) as xyzw, like pbf_world_read_particles. Any may be NULL.
uint32_t pbf_cpu_world_read_particles(const pbf_cpu_world *world, float *positions, float *velocities,
                                      uint32_t *ids, uint32_t max);
/// 64-bit FNV-1a of positions then velocities (xyzw, id order), defined as pbf_world_state_hash.
uint64_t pbf_cpu_world_state_hash(const pbf_cpu_world *world);
/// The substeps the last step took (the time-step guard may take more than params.substeps,
/// as pbf_step_stats.substeps says of a GPU step); 0 before the first step.
int pbf_cpu_world_last_substeps(const pbf_cpu_world *world);
/// Density statistics as metrics.comp computes them after a step. Before the first step
/// (or after particles were added) the neighbour lists are first built at the positions.
pbf_cpu_stats pbf_cpu_world_density_stats(pbf_cpu_world *world);
/// The vorticity omega = curl v (1/s) at the current positions and velocities, as
/// vorticity.comp computes it (neighbour lists rebuilt at the positions, densities as in
/// the stats), written as xyzw (w = |omega|) in id order for up to max particles.
uint32_t pbf_cpu_world_vorticity(pbf_cpu_world *world, float *omega, uint32_t max);

/// Share of a filled neighbourhood taken by a half-space at distance d (m) from the
/// particle, for kernel radius h (m): V(d) = integral over z > d of W_spiky (dimensionless;
/// V(0) = 1/2, V(h) = 0). The closed form of common.glsl's boundary_volume.
float pbf_cpu_boundary_volume(float d, float h);
/// G(d) = integral over z > d of |grad W_spiky| z / r (1/m; G(0) = 1.5 / h, G(h) = 0):
/// the magnitude of the boundary's density-gradient term. common.glsl's boundary_gradient.
float pbf_cpu_boundary_gradient(float d, float h);
/// The colliders' share of a filled neighbourhood at x (m; dimensionless, what they add to
/// rho / rho0) and its gradient with respect to x (1/m, into grad), at their poses: what
/// the density pass adds for them (colliders.glsl's colliders_density).
float pbf_cpu_world_collider_share(pbf_cpu_world *world, const float x[3], float grad[3]);
/// The same share and gradient (into *G, 1/m) for a ball of radius R (m) at distance d
/// from its surface: pbf_kernels.h's pbf_curved_boundary, which spheres and capsules take.
float pbf_cpu_curved_boundary(float d, float h, float R, float *G);

#ifdef __cplusplus
}
#endif
#endif
