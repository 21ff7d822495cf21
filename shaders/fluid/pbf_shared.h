// Constants and struct layouts shared by the C side (fluid/*.c) and the GLSL compute
// shaders (shaders/fluid/*.comp). This one file compiles as both: in GLSL (core profile)
// GL_core_profile is defined; in C it is not. Change a layout here and both sides follow;
// fluid/pbf_gpu.c pins the C sizes with _Static_assert.
#ifndef PBF_SHARED_H
#define PBF_SHARED_H

#ifdef GL_core_profile
#define PBF_VEC4 vec4
#define PBF_UVEC4 uvec4
#define PBF_IVEC4 ivec4
#define PBF_UINT uint
#define PBF_INT int
#define PBF_FLOAT float
#define PBF_STRUCT(name) struct name
#define PBF_END(name)
#else
#include <stdint.h>
typedef struct pbf_float4 { float x, y, z, w; } pbf_float4;
typedef struct pbf_uint4 { uint32_t x, y, z, w; } pbf_uint4;
typedef struct pbf_int4 { int32_t x, y, z, w; } pbf_int4;
#define PBF_VEC4 pbf_float4
#define PBF_UVEC4 pbf_uint4
#define PBF_IVEC4 pbf_int4
#define PBF_UINT uint32_t
#define PBF_INT int32_t
#define PBF_FLOAT float
#define PBF_STRUCT(name) typedef struct name
#define PBF_END(name) name
#endif

// Work-group sizes (threads per group) of the particle and cell passes.
#define PBF_WG 128
// Cells of more particles than this keep the scatter's order instead of the grid sort's
// (a rank among the cell's particles is quadratic in them; a cell holds 8-16 in water):
// only a pile (a diverged solve, particles spawned on one spot) is then not bit-reproducible.
#define PBF_SORT_RANK_MAX 256
// The neighbour search of one particle looks at no more than this many candidates per
// entry of its list (16 x max_neighbours: 1408 at the default 88; water at rest offers about
// 110, compressed twice 250): past that it stops and counts an overflow. A pile of
// particles that are not neighbours (a hash bucket crowded by a diverged solve, non-finite
// positions, which no comparison finds near anything) then costs a bounded search each.
#define PBF_CANDIDATES_PER_ENTRY 16u
// Set in a particle's neighbour count when its search stopped at that budget: the low bits
// still count the neighbours listed (what the passes walk), and the count as a whole is
// above max_neighbours, so the metrics count it as an overflow.
#define PBF_NB_CUT 0x80000000u
// The prefix scan: threads per group, consecutive elements per thread, elements per group.
#define PBF_SCAN_WG 64
#define PBF_SCAN_PER_THREAD 16
#define PBF_SCAN_BLOCK (PBF_SCAN_WG * PBF_SCAN_PER_THREAD)
// Maximum colliders (bodies; the container's planes are separate).
#define PBF_MAX_COLLIDERS 64
// Maximum container planes.
#define PBF_MAX_PLANES 6
// Maximum sinks (axis-aligned boxes that remove the particles entering them).
#define PBF_MAX_SINKS 8

// Shader storage binding points.
#define PBF_B_POS 0        // vec4[cap]: position (m), w = colour parameter in [0,1]
#define PBF_B_VEL 1        // vec4[cap]: velocity (m/s)
#define PBF_B_PRED 2       // vec4[cap]: predicted position x* (m)
#define PBF_B_ID 3         // uint[cap]: particle id (creation order)
#define PBF_B_POS_OUT 4    // the other half of each ping-pong pair
#define PBF_B_VEL_OUT 5
#define PBF_B_PRED_OUT 6
#define PBF_B_ID_OUT 7
#define PBF_B_CELL 8       // uint[cap]: cell of each particle
#define PBF_B_CELL_START 9 // uint[cells + 1]: counts, then exclusive prefix sums
#define PBF_B_CELL_FILL 10 // uint[cells]: scatter cursors
#define PBF_B_SORTED 11    // uint[cap]: new slot -> old slot
#define PBF_B_LAMBDA 12    // vec2[cap]: (lambda, density kg/m^3)
#define PBF_B_OMEGA 13     // vec4[cap]: vorticity (1/s)
#define PBF_B_SCAN 14      // uint[]: block sums of the scan
#define PBF_B_COLLIDERS 15 // pbf_gpu_collider[PBF_MAX_COLLIDERS]
#define PBF_B_FORCES 16    // int[PBF_MAX_COLLIDERS * PBF_FORCE_WORDS]: fixed-point force, torque, the water near it
#define PBF_B_REDUCE 17    // pbf_gpu_reduce[groups]: partial metrics
#define PBF_B_METRICS 18   // pbf_gpu_metrics[ring]: reduced metrics
#define PBF_B_DRAW 19      // uint[4]: DrawArraysIndirectCommand for the renderer
#define PBF_B_SCAN_DATA 20 // the array a scan level works on (a range of a buffer)
#define PBF_B_SCAN_SUMS 21 // its block sums
#define PBF_B_NB_LIST 22   // uint[cap * max_neighbours]: neighbour slots of each particle
#define PBF_B_NB_COUNT 23  // uint[cap]: neighbours found (> max_neighbours: an overflow; PBF_NB_CUT: the budget ran out)
#define PBF_B_STATE 24     // pbf_gpu_state: the live particle count, kept on the GPU
#define PBF_B_STAGE_POS 25 // vec4[]: particles waiting to be appended (emitters, blocks)
#define PBF_B_STAGE_VEL 26 // vec4[]
#define PBF_B_STAGE_ID 27  // uint[]
#define PBF_B_ORDER 28     // uint[cap]: new slot -> old slot, in deterministic order
#define PBF_B_TENSION 29   // vec4[cap]: surface tension acceleration (m/s^2) of the tension pass, added by the next predict
#define PBF_B_LEVEL 30     // pbf_gpu_level_cell[level cells]: the coarse level (level_sweeps > 0)

// Uniform block binding of pbf_gpu_params.
#define PBF_U_PARAMS 0

// Collider types.
// All in the collider's own frame (its pose maps it to the world).
#define PBF_COLLIDER_PLANE 0    // half-space: normal params.xyz, offset params.w; fluid on the +n side
#define PBF_COLLIDER_BOX 1      // half extents in params.xyz
#define PBF_COLLIDER_SPHERE 2   // radius in params.x
#define PBF_COLLIDER_CAPSULE 3  // radius params.x, half height params.y (along local Y)
#define PBF_COLLIDER_CYLINDER 4 // radius params.x, half height params.y (along local Y)
#define PBF_COLLIDER_HULL 5     // convex hull: info.w face planes (outward n xyz, offset w) at
                                // collider_data[info.z], 4 floats each; inside: dot(n, x) <= w
#define PBF_COLLIDER_GRID 6     // signed distance grid (triangle meshes): samples at
                                // collider_data[info.z], x fastest; dims packed in info.w
                                // (10 bits each, x lowest); first sample at params.xyz, spacing params.w
// Collider flags (pbf_gpu_collider.info.y).
#define PBF_COLLIDER_TWO_WAY 1u // accumulate the fluid's force and torque on it
#define PBF_COLLIDER_BLOCKS_SINKS 2u // sinks do not drain what it shields (pbf_collider_def.blocks_sinks)

// Force accumulators: PBF_B_FORCES[index * PBF_FORCE_WORDS + k], k = 0..2 force, 4..6
// torque, as fixed point int(f * scale) summed with atomicAdd (exact and order
// independent), where scale is the collider's own (pbf_gpu_collider.center_of_mass.w,
// units per N) chosen from its size so that the range is about 1000 times the weight of
// the fluid it can displace; k = 3 counts particle-boundary contacts, k = 7 particles
// pushed out from inside. k = 8..15: the water that pushes it, as four 64-bit sums (low
// word, taken as unsigned, then high word; add_wide carries): at k = 8, 10, 12 the sums of
// each particle's velocity (at most max_speed) times the magnitude of its push |f| (the
// boundary's share of its correction, as in the force), and at k = 14 the sum of |f|, in
// the force's scale (units per N m/s, per N). The magnitudes add up where the forces cancel
// (pressure from every side), times a speed: 64 bits leave them room.
// Colliders without a size of their own (planes) use PBF_FORCE_SCALE.
#define PBF_FORCE_WORDS 16
#define PBF_WIDE_MAX 2147483520.0f // 2^31 - 128, the largest float below 2^31: one particle's share
#define PBF_FORCE_SCALE 1024.0
// Fastest a particle found inside a collider is moved out of it, m/s.
#define PBF_PUSH_OUT_SPEED 0.5
// The swept collision keeps a particle's centre this fraction of its radius off a body's
// surface: a backstop against tunnelling. The boundary share holds it at its rest distance,
// about a radius; a hard contact at the whole radius (before 0.13.0) made a body a rigid,
// inelastic wall that took the water's push in place of the share, and a sphere driven
// through water felt four times its drag (docs/coupling.md, "Collisions").
#define PBF_CONTACT_MARGIN 0.1f
// A body's boundary share over the lattice calibration (pbf_gpu_params.boundary_scale):
// the liquid's first layer is spread over [s/2, s] from a wall where the lattice's sits at
// s/2, so the lattice's share lets a liquid pack closer. 1.2 makes a body held under water
// feel its buoyancy (0.075 m box and 0.05 m ball, 2.5 cm particles: within 1-2 %; 1 gave
// 11-12 % less), the factor that also balanced the container's wall strips when they took
// this share (docs/validation.md, "Volume and walls").
#define PBF_BODY_SHARE 1.2f
// The vorticity's corrected gradient inverts (A + d I) / (1 + d) (corrected_curl,
// pbf_kernels.h): a neighbourhood's A reads 1 inside, about 0.5 across a free surface.
#define PBF_CURL_REGULARISATION 0.05f
// Storage of hull planes and distance grids (float[]), see PBF_COLLIDER_HULL / _GRID.
#define PBF_B_COLLIDER_DATA 31 // (kept apart from the fluid's bindings, which count up from 0)

// Everything a pass needs to know, one uniform block (std140: vec4s first, then scalars
// in groups of four so C and GLSL agree without padding rules).
PBF_STRUCT(pbf_gpu_params) {
    PBF_VEC4 gravity;        // xyz m/s^2
    PBF_VEC4 grid_origin;    // xyz m: corner of cell (0,0,0)
    PBF_UVEC4 grid_dims;     // xyz cells, w = total cells
    PBF_VEC4 domain_min;     // xyz m: particles are kept inside [min, max]
    PBF_VEC4 domain_max;
    PBF_VEC4 planes[PBF_MAX_PLANES]; // container: inward normal xyz, offset w (n.x >= w inside)
    PBF_VEC4 sink_min[PBF_MAX_SINKS]; // sinks: boxes [min, max], m
    PBF_VEC4 sink_max[PBF_MAX_SINKS];
    PBF_FLOAT dt;            // s, one substep
    PBF_FLOAT inv_dt;
    PBF_FLOAT h;             // kernel radius, m
    PBF_FLOAT inv_cell;      // 1 / cell size (cell size = h)
    PBF_FLOAT poly6;         // 315 / (64 pi h^9)
    PBF_FLOAT spiky_grad;    // -45 / (pi h^6)
    PBF_FLOAT rest_density;  // kg/m^3
    PBF_FLOAT inv_rest_density;
    PBF_FLOAT mass_density;  // kg: mass used by the density sum (calibrated to the lattice)
    PBF_FLOAT mass;          // kg: physical mass of one particle (rest_density * spacing^3)
    PBF_FLOAT epsilon;       // 1/m^2: relaxation added to sum |grad C|^2
    PBF_UINT row_stride;     // buckets from one row of the grid's curve to the next (pbf_row_stride)
    PBF_FLOAT scorr_k;
    PBF_FLOAT scorr_n;
    PBF_FLOAT scorr_inv_wdq; // 1 / W(dq)
    PBF_FLOAT vorticity;     // m/s
    PBF_FLOAT viscosity;     // XSPH c, dimensionless
    PBF_FLOAT damping;       // 1/s
    PBF_FLOAT max_speed;     // m/s
    PBF_FLOAT radius;        // particle radius, m (collision distance)
    PBF_UINT count;          // live particles as the CPU last knew them (the passes read
                             // the exact count from pbf_gpu_state on the GPU)
    PBF_UINT collider_count;
    PBF_UINT metrics_slot;   // ring slot the metrics pass writes
    PBF_UINT substep;        // 0-based substep index in this step
    PBF_UINT plane_count;
    PBF_UINT max_neighbours; // length of each particle's neighbour list
    PBF_UINT sink_count;
    PBF_UINT capacity;       // particle capacity
    PBF_UINT append_count;   // particles in the staging buffers for the append pass
    PBF_UINT count_mode;     // count pass: 0 after sinks removed particles, 1 after an append
    PBF_FLOAT scorr_scale;   // m^2: s_corr is -k (W / W(dq))^n * scorr_scale, a multiplier
                             // of the size a constraint violated by k would get
    PBF_FLOAT boundary_scale;// calibrates the bodies' continuous wall model to the particle lattice
    PBF_FLOAT surface_tension; // gamma, m/s^2 (0: the tension passes do not run)
    PBF_FLOAT cohesion_norm; // k, 1/(m^5 s^2): a pair's pull is k S(r) (pbf_cohesion_factor, from sigma)
    PBF_FLOAT wall_friction; // skin-friction coefficient C_f of the container's planes
    PBF_FLOAT surface_fill;  // share of the free surface's missing neighbourhood counted in C (0 off)
    PBF_UVEC4 level_dims;    // the coarse level's cells along xyz, w = all of them (0: off)
    PBF_VEC4 level_cell;     // xyz its cell's size (m), w = spacing^3 / the cell's volume
    PBF_VEC4 level_solve;    // x = level_tolerance, y = the sweeps' over-relaxation, zw unused
} PBF_END(pbf_gpu_params);

// A collider on the GPU: a shape in a rigid frame at two poses (previous and current
// substep end) so moving walls sweep; forces land in PBF_B_FORCES[index * PBF_FORCE_WORDS ...].
PBF_STRUCT(pbf_gpu_collider) {
    PBF_VEC4 position;       // xyz m, w = bounding radius about position (m)
    PBF_VEC4 rotation;       // quaternion xyzw (body to world)
    PBF_VEC4 prev_position;  // pose at the start of the substep (w = bounding radius)
    PBF_VEC4 prev_rotation;
    PBF_VEC4 params;         // shape sizes (see PBF_COLLIDER_*)
    PBF_VEC4 linear_velocity;  // m/s
    PBF_VEC4 angular_velocity; // xyz rad/s; w = boundary strength in [0, 1]: the share of the
                               // density and push it gives the water (1; less while placed)
    PBF_VEC4 center_of_mass;   // xyz m (world), torque is taken about it; w = force scale (1/N)
    PBF_UVEC4 info;          // x = type, y = flags (PBF_COLLIDER_TWO_WAY), z = data offset
                             // (floats), w = hull plane count or packed grid dims
} PBF_END(pbf_gpu_collider);

// A cell of the coarse level (docs/solver.md, "The coarse level"): the particles' trilinear
// weights and their weighted compression, summed in fixed point (PBF_LEVEL_FIXED), then the
// cell's compression E (a share of its volume) and the pressure-like potential p (m^2)
// whose gradient is the correction.
PBF_STRUCT(pbf_gpu_level_cell) {
    PBF_INT weight;          // sum w, fixed point
    PBF_INT excess;          // sum w (rho / rho0 - 1), fixed point
    PBF_FLOAT e;             // sum w (rho / rho0 - 1) s^3 / V_cell; -1e30 for an empty cell (air)
    PBF_FLOAT p;             // m^2
} PBF_END(pbf_gpu_level_cell);
#define PBF_LEVEL_FIXED 65536.0f
#define PBF_LEVEL_AIR (-1e30f) // E of a cell the water fills less than half of
#define PBF_LEVEL_OMEGA 1.8f   // the sweeps' over-relaxation (docs/solver.md, "The coarse level")

// The live particle count and the indirect dispatch size of the particle passes, kept on
// the GPU so that sinks can remove particles without a read-back.
PBF_STRUCT(pbf_gpu_state) {
    PBF_UINT count;          // live particles, in slots [0, count)
    PBF_UINT groups_x;       // ceil(count / PBF_WG): DispatchIndirectCommand at byte 4
    PBF_UINT groups_y;       // 1
    PBF_UINT groups_z;       // 1
    PBF_UINT removed;        // particles removed by sinks so far
    PBF_UINT dropped;        // particles that did not fit the capacity when appended
    PBF_UINT pad0, pad1;
} PBF_END(pbf_gpu_state);

// Partial metrics of one work group, then the reduced metrics of a frame.
PBF_STRUCT(pbf_gpu_reduce) {
    PBF_FLOAT density_sum;   // kg/m^3, summed over the group
    PBF_FLOAT density_max;
    PBF_UINT nan_count;      // particles with a non-finite position or velocity
    PBF_UINT outside_count;  // particles outside the domain
    PBF_UINT overflow_count; // particles with more neighbours than their list holds
    PBF_FLOAT error_sum;     // sum of max(rho / rho0 - 1, 0): the compression error
    PBF_FLOAT kinetic_sum;   // J: sum of m |v|^2 / 2 (finite particles)
    PBF_FLOAT speed_max;     // m/s
    PBF_VEC4 momentum_sum;   // xyz kg m/s: sum of m v
    PBF_VEC4 position_sum;   // xyz m: sum of x (centre of mass = sum / count, equal masses)
} PBF_END(pbf_gpu_reduce);

PBF_STRUCT(pbf_gpu_metrics) {
    PBF_FLOAT density_avg;   // kg/m^3
    PBF_FLOAT density_max;
    PBF_UINT nan_count;
    PBF_UINT outside_count;
    PBF_UINT count;
    PBF_UINT frame;
    PBF_UINT overflow_count;
    PBF_FLOAT error_avg;     // mean of max(rho / rho0 - 1, 0) over the particles
    PBF_VEC4 momentum;       // xyz kg m/s, w = kinetic energy J
    PBF_VEC4 center_of_mass; // xyz m, w = largest speed m/s
} PBF_END(pbf_gpu_metrics);

#endif
