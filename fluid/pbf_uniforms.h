// Filling the uniform block pbf_gpu_params (shaders/fluid/pbf_shared.h) from the world's
// settings: shared by the GPU step (pbf_world.c) and the CPU reference (pbf_cpu.c), so the
// two read the same numbers. Internal to the fluid module.
#ifndef PBF_UNIFORMS_H
#define PBF_UNIFORMS_H

#include "fluid/pbf.h"
#include "shaders/fluid/pbf_shared.h"

/// The solver's part: gravity, time step (s), kernel constants, masses, relaxation,
/// artificial pressure, vorticity, viscosity, damping, speed clamp, particle radius.
void pbf_uniforms_solver(pbf_gpu_params *g, const pbf_params *p, const pbf_constants *k, float dt);

/// k (1/(m^5 s^2)) of the cohesion pull k S(r) that gives the rest lattice's surface the
/// tension p->surface_tension (N/m), averaged over its orientations: pbf_kernels.h
/// cohesion_of, pbf_cohesion_lattice_ratio. 0 without tension or for a kernel that validation
/// refuses.
double pbf_cohesion_factor(const pbf_params *p);

/// The tension per unit k of a flat cut through the rest lattice (spacing units, one particle
/// per cubic spacing) along the face with integer normal `face`, the kernel `spacings` wide:
/// the Kirkwood-Buff sum over the surface's pairs of the pull K_ij S(r) (Akinci's spline and
/// density factor, the densities the spiky sum gives the layers under the face). 0 outside
/// (0, 5] spacings or for a zero normal.
double pbf_cohesion_face_stress(double spacings, const int face[3]);

/// The lattice's tension over the continuum's (pi/8) int_0^H u^4 S(u) du, averaged over the
/// faces 0 <= a <= b <= c <= 3 weighted by the share of directions nearest each: 1.32 at 2
/// spacings, 1.13 at 2.5, 1.24 at 3, 1.22 at 4 (Akinci's K at the surface's thin densities
/// raises it by 13-21 %). A kernel narrower than 2 spacings takes the value at 2 (its lattice
/// surface has too few neighbours: the sum falls to 0 at one spacing). 0 outside (0, 5].
double pbf_cohesion_lattice_ratio(double spacings);

/// The largest eigenvalue of the Jacobi iteration matrix A D^-1 on a filled cubic lattice at
/// h = 2 spacings (spiky kernel), which pbf_relaxation keeps stable: docs/solver.md,
/// "Under-relaxed Jacobi"; tests/test_solver.c computes it.
#define PBF_JACOBI_MU_MAX 2.8
/// The same, as pbf_jacobi_mu_max(2) finds it: a kernel whose pbf_constants.jacobi_mu_max is
/// larger scales the relaxation factors by this over its own (tests/test_solver.c checks it).
#define PBF_JACOBI_MU_LATTICE 2.8207

/// The eigenvalue up to which an even iteration count's pairs of factors still damp: water
/// compressed and disordered at depth reaches beyond PBF_JACOBI_MU_MAX (a 0.4 m column of
/// 1.25 cm particles boiled at its bottom with the constant 0.6, which is undamped from
/// 3.33): docs/solver.md, "Under-relaxed Jacobi".
#define PBF_JACOBI_MU_DEEP 4.0

/// The largest eigenvalue of the Jacobi iteration matrix A D^-1 on a filled cubic lattice
/// with the kernel `spacings` lattice spacings wide (spiky gradient): the largest over the
/// Brillouin zone of mu(q) = |sum_j grad W(r_j) sin(q . r_j)|^2 / sum_j |grad W(r_j)|^2,
/// searched on a grid and refined. 2.82 at 2 spacings, 3.38 at 2.25, 4.19 at 2.5, 6.72 at 3,
/// 14.4 at 4: it grows with the neighbourhood, and the factors tuned at 2 spacings leave the
/// modes above PBF_JACOBI_MU_DEEP growing (pbf_constants.jacobi_mu_max holds it for a set).
/// 0 outside (0, 5] (kernel_radius is at most 10 particle radii).
double pbf_jacobi_mu_max(double spacings);

/// The relaxation factor of iteration `it` (0-based) of p->iterations: the uniform `relax`
/// of delta.comp and collide.comp, the `relax` argument of the CPU reference's passes. For
/// a kernel wider than 2 spacings every factor is scaled by pbf_jacobi_mu_max(2) /
/// k->jacobi_mu_max, so each lattice mode is damped as the default kernel's mode of the same
/// rank is (a positive `sor`, a constant factor the caller chose, is taken as it is; k NULL
/// gives the unscaled factors, the default kernel's).
float pbf_relaxation(const pbf_params *p, const pbf_constants *k, int it);

/// The space's part: the grid (origin m, cells per axis, total cells, cell size m), the
/// domain (m) and the container planes (inward normal xyz, offset w).
void pbf_uniforms_space(pbf_gpu_params *g, const float grid_origin[3], const uint32_t grid_dims[3],
                        uint32_t cells, float cell_size, const float domain_min[3], const float domain_max[3],
                        const float (*planes)[4], uint32_t plane_count, uint32_t max_neighbours);

/// The coarse level's grid (docs/solver.md, "The coarse level"): cells of about level_cell
/// kernel radii that divide the domain exactly along each axis, so its walls are cell faces;
/// dims[3] the cell count, all zero while level_sweeps is 0. More than PBF_LEVEL_MAX_CELLS
/// is an error that names the fields.
#define PBF_LEVEL_MAX_CELLS (1u << 22)
pbf_result pbf_level_layout(const pbf_params *p, const float domain_min[3], const float domain_max[3], uint32_t dims[4],
                            float cell[3], char *err, size_t err_size);
/// The level's fields of the parameter block.
void pbf_uniforms_level(pbf_gpu_params *g, const pbf_params *p, const uint32_t dims[4], const float cell[3]);
/// The iteration of a substep in whose delta pass the coarse level acts (the last: the ones
/// before have taken out the short modes, which its cells cannot represent), or -1 while
/// level_sweeps is 0. Both worlds run the level's passes just before that delta.
int pbf_level_iteration(const pbf_params *p);

/// The neighbour grid over [domain_min - h, domain_max + h] in cells of h / cells_per_kernel:
/// origin (m) and cells per axis; returns the total number of cells. The grid is virtual:
/// cells map to pbf_hash_buckets buckets (pbf_grid_bucket), so nothing is stored per cell.
uint64_t pbf_grid_geometry(const float domain_min[3], const float domain_max[3], float h,
                           uint32_t cells_per_kernel, float origin[3], uint32_t dims[3]);

/// Steps the time-step guard looks back: it takes the fastest speed of step (now -
/// PBF_GUARD_LATENCY), which a GPU has normally finished, so the guard neither stalls nor
/// depends on timing (the same substeps on every machine).
#define PBF_GUARD_LATENCY 2

/// Steps of history the guard keeps (speeds per step, at [step % PBF_GUARD_HISTORY]).
#define PBF_GUARD_HISTORY 8

/// The time-step guard (pbf_params.cfl): the substeps step `step`, of dt seconds, takes.
/// `seen` is the fastest particle speed of step (step - PBF_GUARD_LATENCY), m/s, negative
/// when there is none yet (then taken as 0); `added` holds the fastest particle added
/// before each step, at [k % PBF_GUARD_HISTORY]: those of the steps since count. The speed expected is
/// seen + |g| dt PBF_GUARD_LATENCY (what gravity adds meanwhile) or `added`, whichever is
/// larger, clamped to max_speed; the step takes enough substeps that it covers at most cfl
/// spacings in one, at least params.substeps and at most max(substeps, max_substeps).
/// *capped (may be NULL) says whether more were needed than allowed. Shared by the GPU and
/// CPU worlds.
/// Measured on droplets (docs/solver.md, "Surface tension"): a pair's strongest cohesion pull
/// times a substep squared, in kernel radii, that keeps a droplet quiet (0.075 still held one,
/// 0.19 blew it up; 0.00125 until the pull was taken at the predicted positions).
#define PBF_TENSION_STIFFNESS 0.01
/// The fewest substeps of a step dt (s) that keep the cohesion force stable (1 without it).
int pbf_tension_substeps(const pbf_params *p, float dt);
/// The most substeps a step may take: max(substeps, max_substeps). Any of the guards
/// (pbf_guard_substeps, pbf_guard_compression) and the tension's floor may go up to it,
/// whether or not cfl is on.
int pbf_most_substeps(const pbf_params *p);
int pbf_guard_substeps(const pbf_params *p, float spacing, float dt, uint64_t step, float seen,
                       const float added[PBF_GUARD_HISTORY], bool *capped);

/// What a finished step measured, for the compression guard: its worst density over rho0
/// minus 1, its mean compression (a fraction) and the substeps it took (0: no record).
typedef struct pbf_guard_seen {
    float density_error_max;
    float density_error_avg;
    int substeps;
} pbf_guard_seen;

/// Steps of quiet (compression under a quarter of the target) before the compression guard
/// takes one substep fewer: a change of substeps changes how far the water is compressed,
/// so the guard changes them seldom (every change is a small change of volume).
#define PBF_GUARD_QUIET_STEPS 60

/// What the compression guard keeps from step to step (zeroed: nothing asked yet).
typedef struct pbf_guard_state {
    int level; ///< the substeps it asks for (0: params.substeps)
    int quiet; ///< steps in a row measured under a quarter of the target
} pbf_guard_state;

/// The compression guard (pbf_params.guard_compression): the substeps the density error
/// asks for, from the records of steps now - 2 (`seen`) and now - 3 (`before`), NULL when
/// missing. It sees two steps late, so a worst that rose since `before` (at the same
/// substeps) is carried on at that pace over those two steps. With r the larger of that
/// worst / guard_compression and the mean / (guard_compression / 10), and n the substeps
/// `seen` took, the substeps that would bring that step to half the target are
/// ceil(n sqrt(2 r)) (compression falls as 1/substeps^2). r > 1: it asks for those at once,
/// at most max(substeps, max_substeps) (*capped, may be NULL, set when that is not
/// enough). r < 1/4 for PBF_GUARD_QUIET_STEPS steps in a row: one substep fewer, down to
/// params.substeps. Else it holds. Returns the level; shared by the GPU and CPU worlds,
/// which keep `state`.
int pbf_guard_compression(const pbf_params *p, pbf_guard_state *state, const pbf_guard_seen *seen,
                          const pbf_guard_seen *before, bool *capped);

/// The most cells the virtual grid may have along one axis (rows, y + dims_y * z, must fit
/// 32 bits).
#define PBF_GRID_MAX_AXIS_CELLS 65536u

/// Buckets of the grid for a world of `capacity` particles: a power of two, at least 4 per
/// particle (few rows share a bucket) and at least 4096. Cell (x, y, z) goes to bucket
/// (morton(y, z) stride + x) mod buckets, so a row's consecutive cells are consecutive
/// buckets and rows near each other are near (common.glsl bucket_of).
uint32_t pbf_hash_buckets(uint32_t capacity);

/// The stride of the grid's rows (pbf_gpu_params.row_stride): the odd number at least dims_x
/// (within 2048 above it) whose (-buckets) mod stride is closest to a golden fraction of it,
/// so that the curve's rows interleave evenly each time it wraps around the buckets.
uint32_t pbf_row_stride(uint32_t dims_x, uint32_t buckets);

/// The bucket of cell (x, y, z) under the space uniforms P (pbf_kernels.h grid_bucket, which
/// the shaders' bucket_of and the CPU reference's grid use).
uint32_t pbf_grid_bucket(const pbf_gpu_params *P, int x, int y, int z);

/// The container's planes (inward normal xyz, offset w: floor, -x, +x, -z, +z walls, lid)
/// for the box [min, max], which must lie in [domain_min, domain_max]. Returns the number of
/// planes (5, or 6 with a lid), or 0 with a message in err naming the coordinate.
int pbf_container_planes(const float min[3], const float max[3], bool closed_top, const float domain_min[3],
                         const float domain_max[3], float planes[PBF_MAX_PLANES][4], char *err, size_t err_size);

/// Checks a block against the domain and lays out its lattice: particles at the centres of
/// cells of `spacing` from min, x fastest; n receives the particles per axis and *total all
/// of them. PBF_ERR_INVALID_ARG with a message in err naming the field, or PBF_ERR_CAPACITY
/// when they do not fit in a world with `in_use` of `capacity` particles taken.
pbf_result pbf_block_lattice(const pbf_block_def *b, float spacing, const float domain_min[3],
                             const float domain_max[3], uint32_t in_use, uint32_t capacity, uint32_t n[3],
                             uint64_t *total, char *err, size_t err_size);
/// Position of lattice point (x, y, z) of the block, m.
void pbf_block_point(const pbf_block_def *b, float spacing, uint32_t x, uint32_t y, uint32_t z, float out[3]);

/// Checks a list of n particles (xyz triples, m; velocities m/s or NULL): every position
/// finite and inside [domain_min, domain_max], every velocity finite. Returns false with a
/// message in err that starts with `fn` and names the index and value.
bool pbf_points_check(const char *fn, const float *positions, const float *velocities, uint32_t n,
                      const float domain_min[3], const float domain_max[3], char *err, size_t err_size);

/// A collider's bounding radius about its origin, m (pbf_gpu_collider.position.w).
float pbf_collider_bounding_radius(const pbf_collider_def *d);

/// A 64-bit sum of the force accumulators (add_wide, colliders.glsl): words[0] the low half,
/// taken as unsigned, words[1] the high.
double pbf_wide_sum(const int32_t *words);
/// A report's fluid_velocity and fluid_push from a collider's accumulators (`words`, its
/// PBF_FORCE_WORDS: the 64-bit sums at 8..15) of a step of `substeps` at the force scale it
/// had (units per N).
void pbf_water_of_sums(const int32_t *words, float force_scale, int substeps, pbf_collider_report *rep);

/// Floats of collider data a collider takes: a hull's planes (4 each) and its faces'
/// exponents (1 each), a grid's samples, none otherwise.
uint32_t pbf_collider_data_count(const pbf_collider_def *d);

/// Fills out (pbf_collider_data_count floats) with the collider's data: a hull's planes,
/// then each face's exponent in the boundary share (pbf_shapes.h, collider_boundary_of):
/// 1 / sum_g max(n_f . n_g, 0)^8, so a face with no neighbour near its direction counts
/// fully (a box's, where the product of the faces' shares is exact) and a cluster of
/// nearly parallel faces (a finely faceted hull) counts about once; a grid's samples.
void pbf_collider_data_fill(const pbf_collider_def *d, float *out);

#endif
