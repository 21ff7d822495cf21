// Seiche fluid: Position Based Fluids (Macklin & Mueller 2013) on OpenGL 4.3 compute.
//
// This is the module another engine embeds. It needs a current OpenGL 4.3+ core
// context (made by the host) and libepoxy; nothing else: no window system, no Lua, no
// physics engine. All particle data stays on the GPU; the host draws straight from
// pbf_world_gpu_buffers() and reads small metrics late, without stalling.
//
// Units are SI throughout: metres, seconds, kilograms, kg/m^3.
//
//     pbf_world_def def = pbf_default_world_def();
//     def.capacity = 100000;
//     pbf_world *w = pbf_world_create(&def, err, sizeof err);   // NULL + message on error
//     pbf_world_set_container(w, lo, hi, true);
//     pbf_block_def b = pbf_default_block_def(); ... pbf_world_add_block(w, &b);
//     each frame: pbf_world_step(w, 1.0f / 60.0f);
//
// Every function that takes input checks it and returns PBF_OK or an error whose message
// (pbf_world_last_error) names the field, the value given and what is allowed. A NULL
// world or a NULL pointer where one is needed gives PBF_ERR_INVALID_ARG (functions that
// return a value give 0, NULL or false); sizes are computed in 64 bits and checked.
// Inside a step's substep hook (pbf_world_step_with) a host may set collider poses and
// strengths, add and remove colliders, sinks and emitters, and read; pbf_world_step, the
// calls that add particles or change parameters, pbf_world_tint_box, and pbf_world_clear,
// pbf_world_remove_container and pbf_world_destroy refuse (the last three return nothing:
// they are ignored, with the reason in pbf_world_last_error and the world's log).
//
// The calls that issue GL commands need the context the world was made in current on the
// calling thread: with none current, create, step, set_params, set_container, add_block,
// add_particles and read_fields return an error that says so (PBF_ERR_GL; read_particles
// and state_hash return 0) rather than doing nothing.
//
// GL state and synchronisation (the contract; docs/architecture.md has the reasons):
// - Calls that issue GL commands (create, destroy, set_params, set_container, add_*,
//   clear, step, collider and emitter calls, poll_stats, read_particles, state_hash)
//   change, and do not restore: the current program (glUseProgram), the indexed
//   GL_SHADER_STORAGE_BUFFER bindings 0..28 and 31 and GL_UNIFORM_BUFFER binding
//   PBF_U_PARAMS (shaders/fluid/pbf_shared.h), and the generic GL_SHADER_STORAGE_BUFFER,
//   GL_UNIFORM_BUFFER, GL_DISPATCH_INDIRECT_BUFFER, GL_COPY_READ_BUFFER and
//   GL_COPY_WRITE_BUFFER bindings. They touch no VAO, framebuffer, texture or raster state.
//   Rebind what your renderer relies on after them.
// - Inside a step every pass is followed by the barrier its consumer needs; the step ends
//   with GL_SHADER_STORAGE_BARRIER_BIT. Before drawing from pbf_world_gpu_buffers, issue
//   the bit of your use: GL_SHADER_STORAGE_BARRIER_BIT to read positions in a storage
//   block, GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT to read them as vertex attributes,
//   GL_COMMAND_BARRIER_BIT to draw with draw_indirect, GL_BUFFER_UPDATE_BARRIER_BIT before
//   copying or reading them back.
// - Nothing stalls: statistics and collider forces come back through fences, one or more
//   steps late. Only read_particles and state_hash (tests and tools) wait for the GPU.
// - Buffers the CPU uploads into are created with their data and never cleared on the GPU
//   (a driver may apply a GPU clear after a following upload). Run with
//   SEICHE_GL_STRICT=1 under the Seiche engine to have such ordering bugs caught.
#ifndef PBF_H
#define PBF_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/// The version of Seiche, semantic (major.minor.patch), defined here only: the build, the
/// pkg-config file, the shared library's soname, `seiche --version` and `seiche.version`
/// in Lua all read it from these lines.
#define PBF_VERSION_MAJOR 0
#define PBF_VERSION_MINOR 21
#define PBF_VERSION_PATCH 0
#define PBF_VERSION_STRING "0.21.0"

/// PBF_VERSION_STRING of the library actually linked (a host built against one header
/// and run with another shared library can tell).
const char *pbf_version(void);

typedef struct pbf_world pbf_world;

typedef enum pbf_result {
    PBF_OK = 0,
    PBF_ERR_INVALID_ARG,  ///< a parameter is out of range; see pbf_world_last_error
    PBF_ERR_CAPACITY,     ///< more particles than the world's capacity
    PBF_ERR_STALE_ID,     ///< a collider id that was removed
    PBF_ERR_GL,           ///< a GL resource or shader failed
    PBF_ERR_OUT_OF_MEMORY,
} pbf_result;

/// The solver's stages, in the order the step runs them. Each is timed on the GPU.
typedef enum pbf_stage {
    PBF_STAGE_PREDICT = 0, ///< external forces, damping, predicted position
    PBF_STAGE_GRID_COUNT,  ///< cell of each particle, particles per cell
    PBF_STAGE_GRID_SCAN,   ///< exclusive prefix sum over cells
    PBF_STAGE_GRID_SCATTER,///< slot of each particle in cell order
    PBF_STAGE_GRID_SORT,   ///< order inside each cell made deterministic
    PBF_STAGE_REORDER,     ///< particle data gathered into cell order
    PBF_STAGE_NEIGHBOURS,  ///< neighbour list of each particle (once per substep)
    PBF_STAGE_DENSITY,     ///< density and lambda (per iteration)
    PBF_STAGE_DELTA,       ///< position correction, container, collisions (per iteration)
    PBF_STAGE_COLLIDE,     ///< bodies' correction and swept collisions (per iteration, with bodies)
    PBF_STAGE_VELOCITY,    ///< v = (x* - x) / dt
    PBF_STAGE_VORTICITY,   ///< curl of the velocity field
    PBF_STAGE_VISCOSITY,   ///< vorticity confinement and XSPH viscosity
    PBF_STAGE_TENSION,     ///< the cohesion force (surface_tension > 0)
    PBF_STAGE_LEVEL,       ///< the coarse level's solve (level_sweeps > 0, once per substep)
    PBF_STAGE_METRICS,     ///< density statistics reduced on the GPU (once per step)
    PBF_STAGE_COUNT
} pbf_stage;

/// Short stage name as used in metrics columns ("density" -> "density_ms").
const char *pbf_stage_name(pbf_stage stage);

/// Solver parameters. Every field has a unit and a range; pbf_params_validate checks them.
typedef struct pbf_params {
    float particle_radius;  ///< m, (0.0005, 1]; particles sit 2 radii apart at rest
    float kernel_radius;    ///< h, m; (2 * particle_radius, 10 * particle_radius]
    float rest_density;     ///< rho0, kg/m^3, [1, 100000]
    int iterations;         ///< density solver iterations per substep, [1, 100]
    int substeps;           ///< substeps per step, [1, 64]
    float relaxation;       ///< epsilon in lambda, relative to sum |grad C|^2 of a filled
                            ///< neighbourhood (dimensionless), [0, 100]
    float sor;              ///< 0 (default): the per-iteration relaxation schedule (docs/solver.md);
                            ///< in (0, 2): that constant factor on every correction
    float scorr_k;          ///< artificial pressure strength k (dimensionless), [0, 1]
    float scorr_n;          ///< artificial pressure exponent n, [1, 8]
    float scorr_dq;         ///< artificial pressure reference distance dq as a fraction of h, (0, 1)
    float vorticity;        ///< vorticity confinement epsilon, m/s (acceleration per unit curl), [0, 10]
    float viscosity;        ///< XSPH viscosity c (dimensionless), [0, 1]
    float gravity[3];       ///< m/s^2, finite, each |g| <= 1000
    float damping;          ///< linear velocity damping, 1/s, [0, 100]
    float max_speed;        ///< velocity clamp, m/s, (0, 1000]
    float surface_tension;  ///< surface tension sigma, N/m, [0, 1000]: the strength of a
                            ///< cohesion force between particles (Akinci et al. 2013) set so
                            ///< that a flat surface of the rest lattice has this sigma; 0
                            ///< (the default) skips its pass (docs/solver.md, "Surface tension")
    float cfl;              ///< time-step guard: a step takes more substeps (up to
                            ///< max_substeps) when the fastest particle would move more than
                            ///< cfl particle spacings in one substep, [0, 10]; 0 turns it off
    int max_substeps;       ///< the most substeps the guard may take, [1, 64] (at least
                            ///< `substeps` are always taken)
    float guard_compression; ///< time-step guard on compression, [0, 1]: a step takes more
                            ///< substeps (up to max_substeps) while the latest measured step's
                            ///< worst density exceeded rho0 by more than this fraction, or its
                            ///< mean compression a tenth of it, and fewer again once well
                            ///< under; 0 turns it off (docs/solver.md, "The time-step guard")
    float wall_friction;    ///< skin-friction coefficient C_f of the container's walls and
                            ///< floor (dimensionless), [0, 1]: water sliding along a wall at
                            ///< speed u feels a shear stress rho C_f u^2 against its motion;
                            ///< 0 makes the walls frictionless (docs/solver.md)
    float surface_fill;     ///< how much of a free-surface particle's missing neighbourhood
                            ///< its density constraint counts, [0, 1]: the share is estimated
                            ///< from the density gradient, so a surface layer cannot crowd to
                            ///< rho0 within itself; 0 (default) off (docs/solver.md, "The
                            ///< free surface's missing share")
    int level_sweeps;       ///< the coarse level solve: red-black sweeps per substep of a
                            ///< pressure solve on a coarse grid over the domain that removes
                            ///< the compression of deep water the particle iterations leave,
                            ///< [0, 200]; 0 (default) off (docs/solver.md, "The coarse level")
    float level_cell;       ///< the coarse level's cell, in kernel radii, [1, 16]
    float level_tolerance;  ///< compression the coarse level leaves to the particle
                            ///< iterations (a share of rho0), [0, 0.1]: a cell's mean
                            ///< compression less this is what it removes
} pbf_params;

/// What looks and measures best (water at 2.5 cm particles; see docs/solver.md).
pbf_params pbf_default_params(void);
/// The parameters of the 2025 OpenGL reproduction in ../shared/seed (h = 2.5 r with its r
/// read as the particle spacing, 1 substep, 3 iterations, rho0 = 125, vorticity 0.008,
/// XSPH 0.01, s_corr k = 0.1, n = 4). Read as half the spacing (our particle_radius), a
/// kernel of 2.5 r holds 6 neighbours and the solver does not converge (a dam break boils,
/// +360 % maximum density), so the report's r is taken as the spacing its particles sit at.
pbf_params pbf_seed_params(void);
/// Checks every field; on error writes "pbf_params.<field> must be <rule> (got <value>)".
pbf_result pbf_params_validate(const pbf_params *p, char *err, size_t err_size);

/// Parameters by name, for scripts, command lines and panels: every pbf_params field
/// except gravity (a vector; see pbf_params.gravity).
typedef struct pbf_param_info {
    const char *name;        ///< "iterations", "viscosity", ...
    const char *unit;        ///< "m", "kg/m^3", "1/s", "" for dimensionless
    const char *description;
    bool is_int;
    double min, max;         ///< documented range (see pbf_params_validate for open ends)
    size_t offset;           ///< of the float or int field in pbf_params
} pbf_param_info;
/// The table; `count` receives its length.
const pbf_param_info *pbf_param_table(int *count);
/// Looks a parameter up by name; NULL when there is none.
const pbf_param_info *pbf_param_find(const char *name);
/// Sets one parameter by name (the whole set is validated); on error nothing changes and
/// err says which name or value was wrong.
pbf_result pbf_params_set(pbf_params *params, const char *name, double value, char *err, size_t err_size);
/// Sets `count` parameters by name at once, then validates the set as a whole, so any
/// consistent combination is accepted whatever each field's old value (a scene table or
/// several --set options). Given particle_radius without kernel_radius, the kernel keeps
/// its size in particle radii (4 r with the defaults). On error nothing changes and err
/// names the field and value that break the set.
pbf_result pbf_params_apply(pbf_params *params, const char *const *names, const double *values, int count,
                            char *err, size_t err_size);
double pbf_params_get(const pbf_params *params, const pbf_param_info *info);

/// Constants derived from the parameters (shared by the GPU step and the CPU reference).
typedef struct pbf_constants {
    float spacing;        ///< m, 2 * particle_radius
    float mass;           ///< kg, physical mass of a particle: rest_density * spacing^3
    float mass_density;   ///< kg, mass in the density sum, calibrated so that a particle in a
                          ///< filled rest lattice has density rest_density exactly
    float lattice_grad2;  ///< 1/m^2, sum |grad C|^2 of a filled rest neighbourhood
    float epsilon;        ///< 1/m^2, relaxation * lattice_grad2
    float poly6;          ///< 315 / (64 pi h^9) (the XSPH viscosity's weight)
    float spiky_grad;     ///< -45 / (pi h^6); the density kernel is W_spiky = -spiky_grad / 3 (h - r)^3
    float scorr_inv_wdq;  ///< 1 / W_spiky(scorr_dq * h)
    float boundary_scale; ///< a body's share V(d) and its gradient are multiplied by this:
                          ///< the missing share of a rest lattice whose first layer sits half
                          ///< a spacing from a flat side, over the continuous V(spacing / 2), so
                          ///< a block placed against it starts in balance (docs/solver.md; the
                          ///< container's walls are mirrors and need no calibration)
    float scorr_scale;    ///< m^2, 1 / lattice_grad2: the artificial pressure term is
                          ///< -k (W / W(dq))^n * scorr_scale, so k reads as a constraint
                          ///< violation (k = 0.1 pushes like a 10 % compression)
    float jacobi_mu_max;  ///< the largest eigenvalue of one Jacobi sweep's A D^-1 on a filled
                          ///< rest lattice at this kernel: 2.82 at h = 2 spacings, 6.7 at 3.
                          ///< A kernel wider than 2 spacings scales the relaxation factors by
                          ///< 2.82 / jacobi_mu_max (docs/solver.md, "Under-relaxed Jacobi")
} pbf_constants;
/// All zeros for a set that pbf_params_validate refuses (or NULL).
pbf_constants pbf_derive_constants(const pbf_params *params);

typedef void pbf_log_fn(void *user, int level, const char *message); ///< level: 0 debug .. 3 error

typedef struct pbf_world_def {
    pbf_params params;
    uint32_t capacity;      ///< maximum live particles, [1, 2^26], and at most 128 x the GL's
                            ///< GL_MAX_COMPUTE_WORK_GROUP_COUNT (8.4M where that is GL's 65535)
    uint32_t max_neighbours;///< neighbour list length per particle, [8, 512]; 0 is not
                            ///< allowed: the default sizes it from kernel_radius / spacing
    uint32_t grid_cells_per_kernel; ///< neighbour grid cells per kernel radius, [1, 4]:
                            ///< cells of h / this. Finer cells mean fewer candidates per
                            ///< neighbour search and more cells to count and scan; the
                            ///< default PBF_GRID_CELLS_PER_KERNEL (2) measured best
    float domain_min[3];    ///< m: particles are kept inside [min, max] (the outermost wall);
    float domain_max[3];    ///< the neighbour grid is hashed, so a large domain costs no
                            ///< memory, but each axis may hold at most 65536 grid cells
    const char *shader_dir; ///< NULL: the shaders embedded in the library (the default unless
                            ///< SEICHE_SHADER_DIR is set); else a directory holding
                            ///< fluid/*.comp, read at pbf_world_create (shader development)
    pbf_log_fn *log;        ///< NULL: messages go nowhere (errors still come back as results)
    void *log_user;
} pbf_world_def;

/// The default grid_cells_per_kernel (docs/performance.md has the measurement).
#define PBF_GRID_CELLS_PER_KERNEL 2u

pbf_world_def pbf_default_world_def(void);
/// A neighbour list length that holds twice a rest neighbourhood for these parameters, in
/// [8, 512] whatever the parameters.
uint32_t pbf_suggest_max_neighbours(const pbf_params *params);

/// GPU memory the world of this def allocates, bytes (particle buffers, neighbour lists,
/// the grid, the coarse level), for checking a capacity against what the GPU has before creating it.
uint64_t pbf_world_def_memory(const pbf_world_def *def);

/// Creates a world in the current GL context. Returns NULL and a message on bad
/// parameters, missing GL 4.3 compute, or a shader that fails (file:line in the message).
pbf_world *pbf_world_create(const pbf_world_def *def, char *err, size_t err_size);
void pbf_world_destroy(pbf_world *world);

/// A number no other world of this process has had or will have (0 for NULL or a world
/// already destroyed), and whether the world that had it is still alive: for a holder that
/// does not own the world and may outlive it (the Bullet coupling keeps both).
uint64_t pbf_world_serial(const pbf_world *world);
bool pbf_world_alive(const pbf_world *world, uint64_t serial);

const char *pbf_world_last_error(const pbf_world *world);
const pbf_params *pbf_world_params(const pbf_world *world);
/// Changes parameters between steps (validated; on error nothing changes). A new kernel
/// radius rebuilds the grid, and the neighbour lists grow when the new parameters need
/// longer ones (pbf_suggest_max_neighbours). A new particle_radius is refused while the
/// world holds particles (their mass and lattice spacing come from it; the steps in flight
/// are read first, so water a sink has just drained does not count): set it before adding
/// water, or after pbf_world_clear.
pbf_result pbf_world_set_params(pbf_world *world, const pbf_params *params);

/// An axis-aligned container: floor, four walls and optionally a lid, as boundaries
/// that contribute density (no stacking). Must lie inside the domain.
pbf_result pbf_world_set_container(pbf_world *world, const float min[3], const float max[3],
                                   bool closed_top);

void pbf_world_remove_container(pbf_world *world);

/// A block of particles on a lattice of spacing 2 * particle_radius filling [min, max].
typedef struct pbf_block_def {
    float min[3], max[3];   ///< m, inside the domain, min < max
    float velocity[3];      ///< m/s initial velocity
} pbf_block_def;
pbf_block_def pbf_default_block_def(void);
/// Adds the block; returns the number of particles added through `added` (may be NULL).
/// PBF_ERR_CAPACITY when it does not fit the capacity (nothing added). Room is judged on the
/// exact live count: where the kept count (pbf_world_particle_count, an upper bound with
/// sinks) says it does not fit, the steps still in flight are waited for and read first
/// (their records stay for pbf_world_poll_stats). The same for pbf_world_add_particles.
pbf_result pbf_world_add_block(pbf_world *world, const pbf_block_def *block, uint32_t *added);
/// Adds particles at given positions (xyz triples, m) and velocities (may be NULL).
pbf_result pbf_world_add_particles(pbf_world *world, const float *positions, const float *velocities,
                                   uint32_t count);
/// Removes every particle (capacity and parameters stay). Ignored inside a substep hook.
void pbf_world_clear(pbf_world *world);

/// ---- emitters and sinks -----------------------------------------------------------
/// An emitter pours particles from a round nozzle: layers of a lattice of spacing 2r on a
/// disc of `radius` around `position`, perpendicular to `direction`, each layer leaving
/// when the previous one has moved one spacing, so emitted particles never overlap. `rate`
/// particles per second are taken from those layers (at most the full layers' rate,
/// speed * disc points / spacing: pbf_emitter_max_rate).
typedef struct pbf_emitter_def {
    float position[3];    ///< m, centre of the nozzle, inside the domain
    float direction[3];   ///< direction of the jet (normalised here; not zero)
    float speed;          ///< m/s, (0, 100] and at most the world's max_speed (the solver's clamp)
    float rate;           ///< particles/s, [0, pbf_emitter_max_rate]
    float radius;         ///< m, nozzle radius, [particle_radius, 10 m], and a layer of at most
                          ///< PBF_MAX_EMITTER_POINTS particles (about 578 spacings 2r); the disc
                          ///< across the jet must lie inside the domain (a particle radius over
                          ///< is allowed: a nozzle set in a wall)
    bool enabled;         ///< off: emits nothing (and owes nothing)
} pbf_emitter_def;
pbf_emitter_def pbf_default_emitter_def(void);
/// Particles in one layer of a nozzle at most (one layer is generated at once).
#define PBF_MAX_EMITTER_POINTS (1 << 20)

typedef struct pbf_emitter_id {
    uint16_t index1;      ///< slot + 1; 0 is the null id
    uint16_t generation;
} pbf_emitter_id;

/// The most particles per second an emitter of this speed and radius can pour.
float pbf_emitter_max_rate(const pbf_world *world, float speed, float radius);
/// At most 16 emitters at once (PBF_ERR_CAPACITY beyond). pbf_default_emitter_def has rate 0
/// (pours nothing, as the most depends on the world's spacing) and sits at the origin: set
/// position, direction, speed, radius and rate (at most pbf_emitter_max_rate).
pbf_result pbf_world_add_emitter(pbf_world *world, const pbf_emitter_def *def, pbf_emitter_id *out);
/// Changes an emitter (position, direction, speed, rate, radius, on/off).
pbf_result pbf_world_set_emitter(pbf_world *world, pbf_emitter_id id, const pbf_emitter_def *def);
pbf_result pbf_world_remove_emitter(pbf_world *world, pbf_emitter_id id);
bool pbf_emitter_is_valid(const pbf_world *world, pbf_emitter_id id);

/// ---- tints: per-particle colour on the GPU ------------------------------------------
/// A particle's colour lives in the w of its position (pbf_gpu_buffers.positions), which
/// the solver carries with the particle wherever it sorts it: w in [0, 1] is the colour
/// parameter (the initial height, the renderer's height map; every particle starts so); a
/// tinted particle has w = -(1 + R * 65536 + G * 256 + B) with R, G, B in 0..255, an
/// integer-valued float (exact: at most 2^24), so w <= -1 means "tinted". Nothing changes
/// for a world that never tints (no ABI change: new functions only).
/// The w of a tint of rgb (each in [0, 1], clamped; rounded to 8 bits).
float pbf_tint_encode(const float rgb[3]);
/// True when w is a tint (-1 - 0xFFFFFF <= w <= -1, the range pbf_tint_encode writes), with
/// its colour in rgb (may be NULL); false otherwise (w is the height parameter, or below that
/// range: not a tint; rgb untouched).
bool pbf_tint_decode(float w, float rgb[3]);
/// Tints every live particle inside the box [min, max] (m): rgb each in [0, 1]; NULL gives
/// the particles back their height parameter. A compute pass over the particles on the
/// GPU, nothing read back; the tint then travels with each particle.
pbf_result pbf_world_tint_box(pbf_world *world, const float min[3], const float max[3], const float rgb[3]);
/// The tint of the particles an emitter pours from now on (rgb each in [0, 1]; NULL: the
/// height parameter, the default). Kept through pbf_world_set_emitter.
pbf_result pbf_world_set_emitter_tint(pbf_world *world, pbf_emitter_id id, const float rgb[3]);

/// A sink removes every particle that enters the box [min, max] (m), on the GPU, except
/// those a collider with blocks_sinks shields (inside it, or behind it as seen from the
/// sink's centre): water held in a static basin is not drained by a sink below it.
typedef struct pbf_sink_id {
    uint16_t index1;
    uint16_t generation;
} pbf_sink_id;
/// At most 8 sinks at once (PBF_ERR_CAPACITY beyond); `out` must not be NULL.
pbf_result pbf_world_add_sink(pbf_world *world, const float min[3], const float max[3], pbf_sink_id *out);
pbf_result pbf_world_remove_sink(pbf_world *world, pbf_sink_id id);
bool pbf_sink_is_valid(const pbf_world *world, pbf_sink_id id);

/// Live particles. The exact count lives on the GPU (sinks remove particles there); this is
/// the count of the latest step whose statistics reached the CPU plus the particles added
/// since, so with sinks it can be a step or two behind (an upper bound). The per-step
/// count in pbf_step_stats is exact.
uint32_t pbf_world_particle_count(const pbf_world *world);
uint32_t pbf_world_capacity(const pbf_world *world);
/// Mass of one particle (rest_density * (2 r)^3), kg.
float pbf_world_particle_mass(const pbf_world *world);

/// Advances by dt seconds ([PBF_MIN_DT, 1]), in params.substeps substeps. Everything runs
/// on the GPU; nothing is read back here.
pbf_result pbf_world_step(pbf_world *world, float dt);
/// The shortest step, s: a denormal dt would give substeps of length 0 and an infinite 1/dt.
#define PBF_MIN_DT 1e-6f

/// Called before each substep with the substep's index and length (s): a host that steps
/// a rigid-body engine in lockstep with the fluid steps it here and sets the colliders'
/// poses (pbf_world_set_collider_pose), which the substep then uses.
typedef void pbf_substep_fn(void *user, pbf_world *world, int substep, float dt);
/// pbf_world_step with a hook before every substep (NULL: none).
pbf_result pbf_world_step_with(pbf_world *world, float dt, pbf_substep_fn *hook, void *user);

/// ---- colliders: the generic boundary interface (the container uses it too) ----------
/// A collider is a rigid shape in a moving frame. Each particle near it sees it as a
/// half-space at its signed distance (boundary density and correction, like the
/// container), is kept a particle radius outside it, and is swept along when the collider
/// moves (previous pose -> current pose within each substep, so thin or fast walls do not
/// let fluid through). Particles found inside at the start of a substep are moved out
/// gently (at 0.5 m/s at most). Two-way colliders accumulate the
/// fluid's force and torque on the GPU. fluid/bullet/coupling.h drives this from Bullet.
typedef enum pbf_collider_type {
    PBF_SHAPE_PLANE = 0,  ///< size: normal xyz, offset w (fluid on the +normal side), collider frame
    PBF_SHAPE_BOX,        ///< size: half extents xyz, m
    PBF_SHAPE_SPHERE,     ///< size: radius x, m
    PBF_SHAPE_CAPSULE,    ///< size: radius x, half height y (local Y axis), m
    PBF_SHAPE_CYLINDER,   ///< size: radius x, half height y (local Y axis), m
    PBF_SHAPE_CONVEX_HULL,///< planes: the face planes (size unused)
    PBF_SHAPE_SDF,        ///< grid: a signed distance grid (size unused), e.g. a triangle mesh
} pbf_collider_type;

/// A signed distance grid in the collider's frame: value = distance to the surface, m,
/// positive outside the solid (where fluid may be). Outside the grid the distance grows
/// with the distance to the grid's box, so give a margin of at least kernel_radius.
typedef struct pbf_sdf_grid {
    const float *values;  ///< dims[0] * dims[1] * dims[2] samples, x fastest, then y, z; m
    uint32_t dims[3];     ///< samples per axis, [2, 1023]
    float origin[3];      ///< m, collider frame: where sample (0, 0, 0) lies
    float cell;           ///< m, spacing of the samples, > 0
} pbf_sdf_grid;

typedef struct pbf_collider_id {
    uint16_t index1;     ///< slot + 1; 0 is the null id
    uint16_t generation;
} pbf_collider_id;

typedef struct pbf_collider_def {
    pbf_collider_type type;
    float size[4];
    /// PBF_SHAPE_CONVEX_HULL: plane_count face planes, 4 floats each (outward unit normal
    /// xyz, offset w, m; inside is dot(n, x) <= w), collider frame; [4, PBF_MAX_HULL_PLANES].
    const float *planes;
    uint32_t plane_count;
    pbf_sdf_grid grid;   ///< PBF_SHAPE_SDF only; the data is copied
    float position[3];   ///< m
    float rotation[4];   ///< unit quaternion x, y, z, w
    bool two_way;        ///< accumulate the fluid's force and torque on it
    bool blocks_sinks;   ///< a wall for sinks: a sink leaves the particles this collider
                         ///< separates from the sink's centre (inside it, or behind it on the
                         ///< straight line to the centre); a collider that holds the centre
                         ///< (a drain set into a floor) does not block it. The coupling sets it
                         ///< for static bodies. Default false.
} pbf_collider_def;
#define PBF_MAX_HULL_PLANES 256
pbf_collider_def pbf_default_collider_def(void);

/// At most 64 colliders at once, the container's included (PBF_ERR_CAPACITY beyond); `out`
/// must not be NULL.
pbf_result pbf_world_add_collider(pbf_world *world, const pbf_collider_def *def, pbf_collider_id *out);
pbf_result pbf_world_remove_collider(pbf_world *world, pbf_collider_id id);
bool pbf_collider_is_valid(const pbf_world *world, pbf_collider_id id);
/// Sets the pose the collider reaches at the end of the next substep (the pose it had is
/// kept as the previous one, which the substep sweeps from), its velocities and its centre
/// of mass (torque is taken about it; NULL: the position). Velocities may be NULL (kept).
pbf_result pbf_world_set_collider_pose(pbf_world *world, pbf_collider_id id, const float position[3],
                                       const float rotation[4], const float linear_velocity[3],
                                       const float angular_velocity[3], const float center_of_mass[3]);
/// How much of its boundary the collider gives the water, in [0, 1] (1 when added): its
/// share of each nearby particle's density and the push that comes with it are scaled by
/// `strength`, so the water's force on it too; collisions and the push-out of particles
/// inside it are not. A body made overlapping water grows its boundary in over a few steps
/// (cpl, "placing") instead of throwing the water out at once. Takes effect from the next step.
pbf_result pbf_world_set_collider_strength(pbf_world *world, pbf_collider_id id, float strength);
/// Force (N) and torque (N m) the fluid exerted on a two-way collider, averaged over the
/// substeps of the latest step whose results have reached the CPU (one or two steps of
/// latency). Never blocks.
pbf_result pbf_world_collider_force(pbf_world *world, pbf_collider_id id, float force[3], float torque[3]);

/// The fluid's force on a two-way collider during one given step, for hosts that want a
/// fixed latency (deterministic coupling): `steps_back` = 1 is the step issued last, 2 the
/// one before, up to 7. With `wait` it waits for that step's fence if the GPU has not
/// finished it (a stall; with steps_back >= 2 the GPU has normally finished); without,
/// *ready says whether the numbers were there (force and torque are zero when not).
/// `contacts` (may be NULL) receives the particle-boundary contacts summed over the step's
/// solver iterations and substeps.
typedef struct pbf_collider_report {
    float force[3];       ///< N, averaged over the step's substeps
    float torque[3];      ///< N m about the centre of mass given with the pose
    uint32_t contacts;    ///< particle-boundary contacts, summed over iterations and substeps
    uint32_t pushed_out;  ///< particles moved out from inside it, summed over iterations and substeps
    /// The water that pushes it (two-way colliders; zero for others): the velocity (m/s) of
    /// the particles whose pressure pushed it, each weighted by the magnitude of its push (zero
    /// when none did), and the sum of those magnitudes (N, averaged over the substeps as force
    /// is: at least |force|; pressure from every side makes it larger). The coupling lets the
    /// water bring a body up to the pushing water's speed.
    float fluid_velocity[3];
    float fluid_push;
    uint64_t step;        ///< 0-based index of the step these belong to
    bool ready;           ///< false: not complete yet (everything else zero)
    bool existed;         ///< the collider took part in that step (false: it was added
                          ///< later, so nothing was measured and the force is zero; true
                          ///< also while that step is not ready)
} pbf_collider_report;
pbf_result pbf_world_collider_report(pbf_world *world, pbf_collider_id id, int steps_back, bool wait,
                                     pbf_collider_report *out);

/// ---- measurements ---------------------------------------------------------------------
typedef struct pbf_step_stats {
    uint64_t step;            ///< 0-based index of the step these numbers belong to
    double time;              ///< s, simulated time at the end of that step
    uint32_t particles;
    float rest_density;       ///< kg/m^3
    float density_avg;        ///< kg/m^3, mean over particles (boundary share included)
    float density_max;
    float density_error_avg;  ///< mean over particles of max(rho / rho0 - 1, 0): compression
                              ///< only (free-surface particles are not counted as errors)
    uint32_t nan_count;       ///< particles with a non-finite position or velocity
    uint32_t outside_count;   ///< particles outside the domain
    uint32_t overflow_count;  ///< particles with more neighbours than their list holds
    double mass;              ///< kg: particles × the mass of one (rest_density × spacing^3)
    double kinetic_energy;    ///< J: sum of m |v|^2 / 2 over the finite particles
    double momentum[3];       ///< kg m/s: sum of m v
    double center_of_mass[3]; ///< m: mean position of the finite particles (equal masses)
    float speed_max;          ///< m/s: the largest particle speed
    double stage_ms[PBF_STAGE_COUNT]; ///< GPU time per stage (all substeps and iterations)
    double step_ms;           ///< GPU time of the whole step (sum of stages but metrics)
    int substeps;             ///< substeps the step took (params.substeps, or more by the
                              ///< time-step guard: params.cfl)
} pbf_step_stats;

/// Returns up to `max` completed step records, oldest first, each once. The world keeps the
/// records of the latest 8 steps: a host that steps more than 8 times between polls gets the
/// latest 8 (each record's `step` says which), and a step whose slot was needed again while
/// the GPU had not finished it 10 s later is skipped (its record is dropped,
/// docs/architecture.md rule 3). With `wait`, waits
/// for every step issued so far (use at the end of a run); otherwise never blocks.
int pbf_world_poll_stats(pbf_world *world, pbf_step_stats *out, int max, bool wait);

/// ---- GPU buffers for drawing ---------------------------------------------------------
/// Written by compute shaders: issue the barrier bit of your use before reading them (see
/// the contract at the top of this header). The positions and velocities buffers swap
/// each step: ask again after every step.
typedef struct pbf_gpu_buffers {
    unsigned positions;   ///< SSBO of vec4: xyz m, w = colour parameter (initial height) in [0,1],
                          ///< or a tint (w <= -1: pbf_tint_decode)
    unsigned velocities;  ///< SSBO of vec4: xyz m/s, w the particle's volume m^3 (mass / density
                          ///< of the step's last density pass; 0 for particles added since the step)
    unsigned draw_indirect; ///< DrawArraysIndirectCommand {4, particles, 0, 0}, written on the GPU
    uint32_t count;       ///< pbf_world_particle_count (draw with draw_indirect, not this)
} pbf_gpu_buffers;
pbf_gpu_buffers pbf_world_gpu_buffers(const pbf_world *world);

/// ---- slow paths for tests and tools (download the particle state) --------------------
/// Copies up to max particles in id order: positions and velocities as xyzw (may be NULL).
uint32_t pbf_world_read_particles(pbf_world *world, float *positions, float *velocities,
                                  uint32_t *ids, uint32_t max);
/// 64-bit FNV-1a hash of positions and velocities in id order, bit exact.
uint64_t pbf_world_state_hash(pbf_world *world);

/// The particles inside the box [box_min, box_max] (m; both NULL: every particle), in id
/// order: positions and velocities as xyz triples (3 floats each) and densities (kg/m^3, from
/// the step's last density pass, so before its last position correction; 0 for particles
/// added since the last step). Any of the three outputs may be NULL; at most `max` particles
/// are copied and *count (may be NULL) receives how many are in the box. Downloads the state.
pbf_result pbf_world_read_fields(pbf_world *world, const float box_min[3], const float box_max[3],
                                 float *positions, float *velocities, float *densities, uint32_t max,
                                 uint32_t *count);

/// What the particles inside a box add up to.
typedef struct pbf_region_stats {
    uint32_t particles;       ///< particles in the box
    uint32_t with_density;    ///< of those, particles with a density (not added since the last step)
    double mass;              ///< kg: particles × the mass of one
    double density_avg;       ///< kg/m^3, over the particles with a density (0: none)
    double density_max;
    double velocity[3];       ///< m/s, mean
    double momentum[3];       ///< kg m/s
    double kinetic_energy;    ///< J
    double center_of_mass[3]; ///< m (0 when empty)
    double speed_max;         ///< m/s
} pbf_region_stats;
/// Sums `count` particles given as arrays in the layout of pbf_world_read_fields (positions
/// required; velocities and densities may be NULL), each of mass `particle_mass` (kg), over
/// those inside [box_min, box_max] (both NULL: all). No GL: usable on data read once.
pbf_result pbf_region_stats_of(const float *positions, const float *velocities, const float *densities,
                               uint32_t count, float particle_mass, const float box_min[3],
                               const float box_max[3], pbf_region_stats *out);
/// pbf_world_read_fields then pbf_region_stats_of for one box. Downloads the state.
pbf_result pbf_world_region_stats(pbf_world *world, const float box_min[3], const float box_max[3],
                                  pbf_region_stats *out);

#ifdef __cplusplus
}
#endif
#endif
