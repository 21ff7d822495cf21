// Seiche coupling: Bullet rigid bodies as two-way coupled fluid boundaries (prefix `cpl_`).
//
// A coupling links one phys_world (fluid/bullet/phys.h) and one pbf_world (fluid/pbf.h).
// Each registered body becomes a fluid collider of the same shape (plane, box, sphere,
// capsule, cylinder analytically; convex hulls by their face planes; triangle meshes by a
// signed distance grid baked once when the body is added; compounds as one collider per
// child, whose forces and torques, all about the body's centre of mass, are summed). cpl_step then runs Bullet in
// lockstep with the fluid: before every fluid substep it
//   1. applies to each dynamic two-way body the force and torque the fluid exerted on it
//      `force_latency` steps earlier (cpl_def; the GPU accumulates them, they are read
//      back through a fence),
//   2. steps Bullet by the substep's dt (one Bullet step per fluid substep),
//   3. hands each body's new pose (the previous one is kept, so the fluid sweeps the
//      motion), velocities and centre of mass to its collider.
// Static and kinematic bodies act on the fluid only (one-way); the fluid's force on them
// is measured (cpl_body_get_stats) for kinematic bodies and, when asked, static ones.
// Coupled dynamic bodies are kept awake (a sleeping body would ignore the fluid's forces).
//
//     cpl_def cd = cpl_default_def();
//     cd.phys = phys; cd.fluid = fluid;
//     cpl_coupling *c = cpl_create(&cd, err, sizeof err);   // NULL + message on error
//     cpl_add_body(c, crate, NULL);                          // NULL: cpl_default_body_def()
//     each frame: cpl_step(c, 1.0f / 60.0f);                 // instead of both worlds' steps
//
// Everything is in SI units (m, s, kg, N, N m). Every call that takes input checks it and
// returns CPL_OK or an error whose message (cpl_last_error) names the field, the value
// given and what is allowed. docs/coupling.md explains the model and its limits.
#ifndef SEICHE_COUPLING_H
#define SEICHE_COUPLING_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "fluid/bullet/phys.h"
#include "fluid/pbf.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct cpl_coupling cpl_coupling;

typedef enum cpl_result {
    CPL_OK = 0,
    CPL_ERR_INVALID_ARG,   ///< an argument or def field is out of range, NaN or NULL
    CPL_ERR_STALE_ID,      ///< the body was destroyed, or is not (or already) coupled
    CPL_ERR_CAPACITY,      ///< more colliders than the fluid has (64; a compound takes one per part)
    CPL_ERR_PHYS,          ///< a phys_ call failed (its message is in cpl_last_error)
    CPL_ERR_FLUID,         ///< a pbf_ call failed (its message is in cpl_last_error)
    CPL_ERR_OUT_OF_MEMORY,
} cpl_result;

typedef void cpl_log_fn(void *user, const char *message);

typedef struct cpl_def {
    phys_world *phys;       ///< required; the coupling does not own it
    pbf_world *fluid;       ///< required; the coupling does not own it
    /// Steps between the fluid step that measured a force and the step that applies it,
    /// [1, 7]. Default 1. The readback waits for that step's fence when the GPU has not
    /// finished it yet, so the coupling is deterministic; with 1 that can stall the CPU
    /// for the rest of the previous GPU step, with 2 a GPU normally has finished it.
    int force_latency;
    /// Share of the previous step's applied force kept when the next one arrives, [0, 0.95];
    /// default 0.5. The measured force is noisy from step to step (particles arrive and
    /// leave a body in bursts), and a late, noisy force makes light bodies jitter; an
    /// exponential average keeps the mean (buoyancy) and removes the noise, at the cost of
    /// keep / (1 - keep) steps of extra lag (1 step at 0.5).
    float force_smoothing;
    /// Bound on the fluid's push on a dynamic body per step, as a multiple of the
    /// acceleration full submersion gives it plus a quarter of g, g (rho_fluid / rho_body
    /// + 1/4), [0, 100]; default 1. Per step the fluid may take away the body's velocity
    /// against the force and add at most that acceleration times dt; 0 turns the bound off.
    /// Without it the one-step-late force (measured while a light body plunged in, applied
    /// after) throws light bodies out of the water faster than they hit it (docs/coupling.md).
    /// Beyond that, the water may bring a body up to the speed of the water that pushes it
    /// (pbf_collider_report.fluid_velocity), once it has not been stopping the body for a few
    /// steps: so water pushes bodies in zero gravity too. The torque is not bounded.
    float impulse_limit;
    /// Heave damping that cancels what the force's lag does to a floating body, as a
    /// multiple of that lag's negative damping, [0, 4]; default 1.5 (1 cancels it for small
    /// heaves; the half more settles a light body thrown up by its fall or its creation);
    /// 0 off. A restoring force that arrives tau late acts like the spring plus a damping
    /// of -k tau: a light, flat body (a high heave frequency, sqrt(g / draft)) then bounces
    /// for ever. The coupling adds -lag_damping k tau v along gravity, k = rho g V / H (the
    /// waterplane stiffness of a body of volume V and height H along gravity: exact for
    /// upright boxes and cylinders), tau = (force_latency + 1/2 + the smoothing's lag)
    /// steps, only while the body floats (the measured lift between none and full
    /// submersion's), at most what stops the body in a step (docs/coupling.md).
    float lag_damping;
    /// Added-mass coefficient C_a of the lag's correction, [0, 2]; default 0.5 (a sphere's
    /// in potential flow); 0 off. The water's answer to a body's acceleration (the inertia of
    /// the water it must move, C_a rho V_submerged) is in the measured force, but tau late: a
    /// heavy body let go in water fell at (1 - rho / rho_body) g until it came. The coupling
    /// integrates a dynamic body as one of mass m + m_a, m_a = C_a rho V (the submerged share
    /// from the measured lift), under gravity, the applied force and m_a a_lag, the body's
    /// own acceleration in the step the force was measured in (smoothed as the force is, at
    /// most g: an impact's jolt is answered by a slam, not by the water's inertia alone):
    /// where the acceleration holds still that is exactly the force, and from a release it is
    /// potential flow's (rho_body - rho) g / (rho_body + C_a rho) until the measured answer
    /// arrives (docs/coupling.md, "Added mass"). Linear motion only.
    float added_mass;
    /// Sample spacing of the distance grid baked for triangle meshes, m, (0, 1].
    /// Default 0: not allowed; cpl_default_def() sets 0.02 m. Grids hold at most 128
    /// samples per axis; a finer spacing is coarsened to fit (and logged).
    float mesh_cell;
    cpl_log_fn *log;        ///< NULL: messages go nowhere (errors still come back as results)
    void *log_user;
} cpl_def;

/// Defaults: no worlds, force_latency 1, force_smoothing 0.5, impulse_limit 1, lag_damping 1.5,
/// added_mass 0.5, mesh_cell 0.02 m, no log.
cpl_def cpl_default_def(void);

/// The numeric settings of cpl_def by name, for scripts and command lines (seiche.coupling,
/// --set coupling.NAME): force_latency, force_smoothing, impulse_limit, lag_damping, added_mass,
/// mesh_cell.
typedef struct cpl_setting_info {
    const char *name;
    double min, max;    ///< allowed range, inclusive except min where open_min
    bool open_min;      ///< min itself is not allowed (mesh_cell: (0, 1])
    bool is_int;
    const char *unit;   ///< "steps", "m", "" ...
} cpl_setting_info;
/// The table of settings; *count receives its length. Never NULL.
const cpl_setting_info *cpl_setting_table(int *count);
/// The setting called `name`, or NULL.
const cpl_setting_info *cpl_setting_find(const char *name);
/// Sets one setting of a def after checking it (name known, value in range and whole where
/// it must be); on error def is unchanged and err names the setting, value and range.
cpl_result cpl_def_set(cpl_def *def, const char *name, double value, char *err, size_t err_size);
/// The value of one setting of a def.
double cpl_def_get(const cpl_def *def, const cpl_setting_info *info);
/// Checks every setting of a def (not its worlds): CPL_OK, or CPL_ERR_INVALID_ARG and a
/// message naming the setting, the value and the range.
cpl_result cpl_def_check(const cpl_def *def, char *err, size_t err_size);

/// Creates a coupling. Returns NULL and a message naming the field on bad input. A body
/// belongs to one coupling at most: two couplings of the same worlds must not share a body
/// (not checked: each would add the fluid's force).
cpl_coupling *cpl_create(const cpl_def *def, char *err, size_t err_size);
/// The def a coupling was created with (worlds, settings, log). CPL_ERR_INVALID_ARG on NULL.
cpl_result cpl_get_def(const cpl_coupling *coupling, cpl_def *out);
/// Removes the colliders the coupling made; bodies and worlds stay. NULL does nothing.
/// Destroy the coupling before the fluid world; where the fluid world went first its
/// colliders went with it, cpl_destroy only frees the coupling, and every other call refuses
/// with CPL_ERR_FLUID (pbf_world_alive tells).
void cpl_destroy(cpl_coupling *coupling);

/// Message of the most recent failed call ("" if none). Never NULL.
const char *cpl_last_error(const cpl_coupling *coupling);

typedef struct cpl_body_def {
    /// Whether the fluid pushes the body back (dynamic bodies). Default true. Static and
    /// kinematic bodies are always one-way (their mass is infinite); it is ignored there.
    bool two_way;
    /// Measure the fluid's force and torque on a body the fluid does not push (static
    /// bodies, one-way dynamic ones) for cpl_body_get_stats. Default false; kinematic and
    /// two-way bodies are always measured. It costs GPU atomics per particle in contact, so
    /// a large static floor is best left unmeasured.
    bool measure_force;
} cpl_body_def;

cpl_body_def cpl_default_body_def(void);

/// Couples a live body: creates its collider at the body's current pose (fluid that
/// starts inside it is moved out gently over the next substeps). def may be NULL (two-way
/// for dynamic bodies, one-way otherwise). Triangle meshes are baked into a distance
/// grid here (once; a few ms for small meshes, more for large ones).
cpl_result cpl_add_body(cpl_coupling *coupling, phys_body_id body, const cpl_body_def *def);
/// Uncouples a body (removes its collider). The body itself stays in the phys_world.
cpl_result cpl_remove_body(cpl_coupling *coupling, phys_body_id body);
/// True when the body is coupled.
bool cpl_has_body(const cpl_coupling *coupling, phys_body_id body);
/// The fluid collider made for a coupled body (for pbf_world_collider_report); for a
/// compound, the collider of its first child.
cpl_result cpl_body_collider(cpl_coupling *coupling, phys_body_id body, pbf_collider_id *out);

/// Teleports a coupled body (position m, orientation unit quaternion x, y, z, w, both
/// finite): the body and its collider jump there without sweeping fluid along the way.
cpl_result cpl_teleport_body(cpl_coupling *coupling, phys_body_id body, phys_vec3 position, phys_quat orientation);

/// Advances both worlds by dt seconds (in [CPL_MIN_SUBSTEP_DT x n, 1], n the larger of the
/// fluid's substeps and max_substeps: 3.2e-6 s at the defaults): the fluid in its params.substeps
/// substeps, Bullet by one step per substep, forces and poses exchanged between them as
/// described at the top. Bodies destroyed in the phys_world since the last step are
/// uncoupled here (and logged). Use this instead of pbf_world_step and phys_world_step.
cpl_result cpl_step(cpl_coupling *coupling, float dt);
/// Bullet's shortest step, s (phys_world_step): a coupled step shorter than that per substep
/// the fluid may take (its time-step guard may go up to max_substeps) is refused before
/// either world moves, so the two never fall out of lockstep.
#define CPL_MIN_SUBSTEP_DT 1e-7f

/// What the coupling did to one body in the latest cpl_step. A two-way body's force is
/// that of `force_latency` steps ago; a measured one-way body's of max(force_latency, 2)
/// steps ago (read without a stall on a GPU that keeps up).
typedef struct cpl_body_stats {
    float force[3];         ///< N, the fluid's force on the body as measured in force_step
    float torque[3];        ///< N m, about the centre of mass
    uint64_t force_step;    ///< the fluid step (0-based) in which that force was measured
    uint32_t contacts;      ///< particle-boundary contacts in that step (all iterations)
    uint32_t pushed_out;    ///< particles moved out from inside the body in that step
    float fluid_velocity[3]; ///< m/s, the velocity of the water that pushed it in that step, each
                             ///< particle weighted by its push (pbf_collider_report; 0: none did)
    float fluid_push;       ///< N, the sum of those pushes' magnitudes (at least |force|)
    uint64_t limited_steps; ///< steps whose applied force the impulse limit scaled down
    bool two_way;           ///< the fluid pushes the body
    bool measured;          ///< force, torque, contacts and pushed_out are measured (else zero)
    pbf_collider_id collider;
} cpl_body_stats;

cpl_result cpl_body_get_stats(cpl_coupling *coupling, phys_body_id body, cpl_body_stats *out);

/// Number of coupled bodies.
uint32_t cpl_body_count(const cpl_coupling *coupling);
/// Steps taken by cpl_step so far.
uint64_t cpl_step_count(const cpl_coupling *coupling);

#ifdef __cplusplus
}
#endif
#endif
