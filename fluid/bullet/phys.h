/// phys.h: Seiche's C API over the Bullet rigid-body engine (prefix `phys_`).
///
/// Bullet is C++; this header is plain C11 and includes no Bullet header. The
/// implementation (phys_*.cpp) catches every C++ exception at the boundary, so
/// nothing is ever thrown into C.
///
///     phys_world_def wd = phys_default_world_def();
///     phys_world *w = NULL;
///     if (phys_world_create(&wd, &w) != PHYS_OK) ...            // message went to wd.log
///     phys_box box = {{0.5f, 0.5f, 0.5f}};
///     phys_shape_id shape;
///     phys_shape_create_box(w, &box, &shape);
///     phys_body_def bd = phys_default_body_def();
///     bd.shape = shape;
///     bd.position = (phys_vec3){0, 2, 0};
///     phys_body_id body;
///     if (phys_body_create(w, &bd, &body) != PHYS_OK) puts(phys_world_last_error(w));
///     each substep: apply forces, then phys_world_step(w, dt);
///     phys_world_destroy(w);                                      // frees everything
///
/// Shape of the API (after Box2D v3):
/// - A world is an opaque pointer, `phys_world*`. It holds everything: bodies,
///   shapes, constraints, joints, the last error message and the log callback.
///   There is no process-wide state in this wrapper, which is why the world is
///   a pointer and not an index into a global table.
/// - Bodies, shapes, constraints and joints are ids passed by value. An id
///   carries a slot (`index1`, 1-based), a tag of the world that issued it
///   (`world0`) and a generation. The all-zero id is the null id. When an object is destroyed
///   its slot's generation moves on, so an old id is "stale" and every call
///   that takes it fails with PHYS_ERR_STALE_ID instead of touching freed memory.
/// - Creation takes a def struct filled by a default function
///   (`phys_default_body_def()`); zero is never a stand-in for "default".
/// - Calls that can fail return `phys_result`. The world keeps the message of
///   the most recent failure (`phys_world_last_error`) and also hands it to the
///   optional log callback. Messages name the field, the value given and what
///   is allowed. Input checks are always on (NaN and infinity included).
///
/// Units are SI throughout: metres, seconds, kilograms, kg/m³, newtons (N),
/// newton-metres (N·m), N·s for impulses, radians and rad/s for angles.
///
/// Frames and conventions:
/// - Right-handed, Y up by convention (gravity defaults to {0, -9.81, 0}).
/// - Orientation is a unit quaternion stored (x, y, z, w), w the scalar part,
///   Hamilton convention; it rotates body-local vectors into world space:
///   p_world = position + q * p_local * conj(q). Bullet uses the same layout.
/// - A body's centre of mass is its origin (`position`). Give hull and mesh
///   points around the point that should be the centre of mass. Compound
///   shapes are the exception that keeps the rule: their parts are given in a
///   frame of the caller's choosing and the wrapper moves them so that the
///   compound's centre of mass is the shape origin (see phys_compound).
/// - Capsules and cylinders have their axis along the body's local Y.
///
/// Stepping: `phys_world_step(world, dt)` runs exactly one Bullet step of dt
/// (no accumulator, no interpolation), so it stays in lockstep with the fluid
/// substeps. At the start of the step Bullet adds gravity (mass × g) to every
/// awake dynamic body; forces and torques applied through this API before the
/// call act during that one step only and are cleared when it returns.
///
/// Bullet facts worth knowing:
/// - Integration is semi-implicit Euler: v += (F/m + g) dt, then x += v dt.
/// - Bullet caps a body's rotation at π/2 per step (|ω| dt); faster spins are
///   scaled down.
/// - Inertia comes from Bullet: exact for boxes, spheres and cylinders; a
///   bounding-box estimate for capsules and hulls. Mass from density is exact.
/// - Sleep thresholds (0.8 m/s, 1 rad/s, 2 s) are Bullet's own.
#ifndef SEICHE_PHYS_H
#define SEICHE_PHYS_H

#include <stddef.h>
#include <stdbool.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/// A 3-vector; meaning and unit depend on the field (m, m/s, N, ...).
typedef struct phys_vec3 {
    float x, y, z;
} phys_vec3;

/// A rotation as a unit quaternion, stored (x, y, z, w); w is the scalar part.
/// The identity is {0, 0, 0, 1}. Inputs must have length 1 within 1e-3; they
/// are renormalised exactly before use.
typedef struct phys_quat {
    float x, y, z, w;
} phys_quat;

/// Result of every call that can fail. On anything but PHYS_OK the world's
/// last error message says why (see phys_world_last_error).
typedef enum phys_result {
    PHYS_OK = 0,
    PHYS_ERR_INVALID_ARG,   ///< an argument or def field is out of range, NaN/inf, or NULL
    PHYS_ERR_STALE_ID,      ///< the id names an object that was destroyed
    PHYS_ERR_OUT_OF_MEMORY, ///< an allocation failed
    PHYS_ERR_INTERNAL       ///< Bullet or the wrapper failed in a way that is a bug
} phys_result;

/// Severity of a message given to the log callback.
typedef enum phys_log_level {
    PHYS_LOG_ERROR = 0,
    PHYS_LOG_WARNING,
    PHYS_LOG_INFO
} phys_log_level;

/// Log callback. `message` is valid only during the call. Called from the
/// thread that made the failing phys_ call.
typedef void (*phys_log_fn)(void *user, phys_log_level level, const char *message);

/// The world: opaque, created by phys_world_create, freed by phys_world_destroy.
typedef struct phys_world phys_world;

/// Id of a body. All-zero is null. `index1` is the slot + 1, `world0` a tag
/// of the issuing world (never 0 for a real id; not an index), `generation`
/// counts reuses of the slot.
typedef struct phys_body_id {
    uint32_t index1;
    uint16_t world0;
    uint16_t generation;
} phys_body_id;

/// Id of a collision shape; same layout and rules as phys_body_id.
typedef struct phys_shape_id {
    uint32_t index1;
    uint16_t world0;
    uint16_t generation;
} phys_shape_id;

/// Id of a constraint; same layout and rules as phys_body_id.
typedef struct phys_constraint_id {
    uint32_t index1;
    uint16_t world0;
    uint16_t generation;
} phys_constraint_id;

/// Short fixed name of a result code, e.g. "PHYS_ERR_STALE_ID".
const char *phys_result_string(phys_result result);

// ---------------------------------------------------------------------------
// World
// ---------------------------------------------------------------------------

/// World settings. Fill with phys_default_world_def(), then change fields.
typedef struct phys_world_def {
    /// Gravitational acceleration, m/s². Default {0, -9.81, 0}. Finite, at most
    /// PHYS_MAX_GRAVITY in size.
    phys_vec3 gravity;
    /// Sequential-impulse solver iterations per step. Default 10. Range [1, 1000].
    int solver_iterations;
    /// Bullet collision margin for convex shapes, m. Default 0.04 (Bullet's).
    /// Range [0, 1]. Boxes and cylinders use at most 0.1 × their smallest
    /// half extent; hulls are shrunk by their margin (at most 0.25 × the
    /// distance from their centre to the nearest face) so that hull + margin
    /// has the faces you gave (see phys_shape_desc.margin).
    float collision_margin;
    /// How bodies that overlap are pushed apart, m, finite, in [0, 1]. Default 0.04
    /// (Bullet's). Overlaps deeper than this are moved apart without velocity (Bullet's
    /// split impulse); shallower ones get a velocity that removes a fifth of the overlap
    /// per step (Baumgarte), which then stays: a body landing at speed v overlaps by about
    /// v dt and so leaves again at about 0.2 v, whatever the restitution (a 2 kg crate
    /// landing at 2.8 m/s at dt = 1/240 s rose again at 0.58 m/s and landed a second time).
    /// 0 moves every overlap apart without velocity: landings do not hop, and a contact's
    /// impulse is the body's change of momentum (scene runner: 0).
    float split_impulse_depth;
    /// Optional log callback (NULL: none). Receives every error message.
    phys_log_fn log;
    /// Passed back to `log` unchanged.
    void *log_user;
} phys_world_def;

/// Defaults: gravity {0, -9.81, 0}, 10 iterations, margin 0.04 m, split impulse depth
/// 0.04 m, no log.
phys_world_def phys_default_world_def(void);

/// Create a world. On success *out_world is the new world. When the def is
/// invalid, *out_world is NULL, the result is PHYS_ERR_INVALID_ARG and the
/// message goes to def->log (there is no world to keep it).
phys_result phys_world_create(const phys_world_def *def, phys_world **out_world);

/// Destroy a world and everything in it (bodies, shapes, constraints,
/// joints); every id from it becomes meaningless. NULL is allowed and does nothing.
void phys_world_destroy(phys_world *world);

/// Advance the world by exactly one Bullet step of `dt` seconds.
/// dt must be finite and in [1e-7, 10] s. Gravity is added at the start of the
/// step; forces applied before the call act for this step and are then cleared.
/// Kinematic bodies move to their target (or by their velocity) during the step.
phys_result phys_world_step(phys_world *world, float dt);

/// Set gravity, m/s² (finite, at most PHYS_MAX_GRAVITY in size). Applies to all bodies
/// from the next step on.
phys_result phys_world_set_gravity(phys_world *world, phys_vec3 gravity);

/// Current gravity, m/s². Zero vector when world is NULL.
phys_vec3 phys_world_get_gravity(const phys_world *world);

/// Message of the most recent failed call on this world ("" if none failed).
/// Valid until the next failing call. Never NULL.
const char *phys_world_last_error(const phys_world *world);

/// Number of live bodies in the world (0 for NULL).
uint32_t phys_world_get_body_count(const phys_world *world);

/// Closest hit of a ray cast from `from` to `to` (world space, m).
typedef struct phys_ray_hit {
    bool hit;             ///< false: nothing between from and to; other fields zero
    phys_body_id body;    ///< the body hit
    phys_vec3 point;      ///< hit point, world space, m
    phys_vec3 normal;     ///< unit surface normal at the hit, world space (outward for solids;
                          ///< for a mesh triangle, on the side the ray came from)
    float fraction;       ///< where along the segment: point = from + fraction × (to - from), [0, 1]
} phys_ray_hit;

/// Cast a ray segment and report the closest body hit. `from` and `to` must be
/// finite and differ. A miss is PHYS_OK with out->hit false.
phys_result phys_world_ray_cast(phys_world *world, phys_vec3 from, phys_vec3 to,
                                phys_ray_hit *out);

// ---------------------------------------------------------------------------
// Shapes
//
// A shape is created once and may be used by any number of bodies. Its
// geometry is in body-local coordinates. Planes and triangle meshes have no
// finite volume and may only go on static or kinematic bodies.
// ---------------------------------------------------------------------------

/// Kind of shape.
typedef enum phys_shape_type {
    PHYS_SHAPE_PLANE = 1,
    PHYS_SHAPE_BOX,
    PHYS_SHAPE_SPHERE,
    PHYS_SHAPE_CAPSULE,
    PHYS_SHAPE_CYLINDER,
    PHYS_SHAPE_CONVEX_HULL,
    PHYS_SHAPE_TRIANGLE_MESH,
    PHYS_SHAPE_COMPOUND
} phys_shape_type;

/// Infinite plane: the points x with dot(normal, x) = offset. The solid side is
/// dot(normal, x) < offset. normal: unit length (within 1e-3); offset: m, finite.
typedef struct phys_plane {
    phys_vec3 normal;
    float offset;
} phys_plane;

/// Box centred on the body origin. half_extents: m, each > 0 and finite.
typedef struct phys_box {
    phys_vec3 half_extents;
} phys_box;

/// Sphere centred on the body origin. radius: m, > 0 and finite.
typedef struct phys_sphere {
    float radius;
} phys_sphere;

/// Capsule along local Y: a cylinder of `half_height` (m, > 0) each side of the
/// origin with hemispherical caps of `radius` (m, > 0). Total height is
/// 2 × (half_height + radius).
typedef struct phys_capsule {
    float radius;
    float half_height;
} phys_capsule;

/// Solid cylinder along local Y, flat caps at y = ±half_height.
/// radius, half_height: m, each > 0 and finite.
typedef struct phys_cylinder {
    float radius;
    float half_height;
} phys_cylinder;

/// Convex hull of a point cloud (body-local, m). point_count in [4, 65536];
/// points finite and spanning a volume. Points inside the hull are dropped.
/// The data is copied; the caller keeps ownership of `points`.
typedef struct phys_convex_hull {
    const phys_vec3 *points;
    uint32_t point_count;
} phys_convex_hull;

/// Static triangle mesh (body-local, m): triangle i is vertices[indices[3i]],
/// vertices[indices[3i+1]], vertices[indices[3i+2]], counter-clockwise seen
/// from the front. vertex_count in [3, 2^31); triangle_count >= 1; every index
/// < vertex_count. The data is copied.
typedef struct phys_triangle_mesh {
    const phys_vec3 *vertices;
    uint32_t vertex_count;
    const uint32_t *indices;
    uint32_t triangle_count;
} phys_triangle_mesh;

/// One face plane of a convex hull, body-local: inside is dot(normal, x) <= offset.
typedef struct phys_hull_plane {
    phys_vec3 normal; ///< outward unit normal
    float offset;     ///< m
} phys_hull_plane;

/// A convex hull as stored: its corner points and face planes.
typedef struct phys_hull_desc {
    const phys_vec3 *points;       ///< hull vertices (only extreme points), body-local, m
    uint32_t point_count;
    const phys_hull_plane *planes; ///< one per face
    uint32_t plane_count;
} phys_hull_desc;

struct phys_compound_child;

/// A compound shape as stored (see phys_compound). Everything is in the
/// shape's own frame, whose origin is the compound's centre of mass and whose
/// axes are its principal axes of inertia.
typedef struct phys_compound_desc {
    /// child_count children: each one's description and its pose in the
    /// shape frame. World-owned, valid until the shape or world is destroyed.
    const struct phys_compound_child *children;
    uint32_t child_count;
    /// Where the shape frame sits in the frame the parts were given in
    /// (phys_compound.parts[i].position/rotation): its origin (the centre of
    /// mass, m) and its rotation (the principal axes; the identity whenever
    /// the parts' own axes already are principal, e.g. a symmetric wheel).
    /// A body with pose (P, Q) shows the parts frame at
    /// P + Q * (-conj(frame_rotation) * frame_origin), rotated Q * conj(frame_rotation).
    phys_vec3 frame_origin;
    phys_quat frame_rotation;
} phys_compound_desc;

/// Plain description of a shape, for building a signed-distance collider.
/// Pointers inside point into world-owned memory, valid until the shape or
/// the world is destroyed.
typedef struct phys_shape_desc {
    phys_shape_type type;
    phys_shape_id shape;
    /// Bullet's collision margin for this shape, m. For boxes and cylinders it
    /// lies inside the given extents (edges rounded by this radius); for hulls
    /// the Bullet hull is shrunk by it, so again the outer faces are the ones
    /// given; spheres and capsules are exact (reported 0); planes and meshes
    /// collide as given with this much extra skin.
    float margin;
    /// Volume, m³: exact for box, sphere, capsule, cylinder and hull;
    /// INFINITY for a plane; 0 for a triangle mesh; for a compound the sum
    /// of its children's volumes (overlaps count twice).
    float volume;
    union {
        phys_plane plane;
        phys_box box;
        phys_sphere sphere;
        phys_capsule capsule;
        phys_cylinder cylinder;
        phys_hull_desc hull;
        phys_triangle_mesh mesh;
        phys_compound_desc compound;
    };
} phys_shape_desc;

/// One child of a compound as stored: its description (type, margin,
/// volume, geometry; `shape` is the null id, children are not shapes of
/// their own) and its pose in the compound's shape frame.
typedef struct phys_compound_child {
    phys_shape_desc desc;
    phys_vec3 position;   ///< m, shape frame (relative to the centre of mass)
    phys_quat rotation;   ///< unit quaternion (x, y, z, w)
} phys_compound_child;

/// One part of a compound to create: a box, sphere, capsule, cylinder or
/// convex hull (set `type` and the matching union member; the same rules as
/// the shape of that type) placed at `position` (m) with `rotation` (unit
/// quaternion) in the parts frame.
typedef struct phys_compound_part {
    phys_shape_type type;
    union {
        phys_box box;
        phys_sphere sphere;
        phys_capsule capsule;
        phys_cylinder cylinder;
        phys_convex_hull hull;
    };
    phys_vec3 position;
    phys_quat rotation;
} phys_compound_part;

/// Maximum number of parts in one compound.
#define PHYS_MAX_COMPOUND_PARTS 256

/// A rigid union of parts: one shape that need not be convex (a paddle wheel,
/// a table, a hook). part_count in [1, PHYS_MAX_COMPOUND_PARTS]; the parts
/// array and any hull points are copied, the caller keeps ownership.
///
/// Mass and centre of mass: the parts share one density, so the compound's
/// volume is the sum of the parts' volumes (overlaps count twice) and its
/// centre of mass the volume-weighted mean of the parts' centres. Inertia is
/// the sum of the parts' inertias moved to that centre (parallel axis;
/// Bullet's btCompoundShape::calculatePrincipalAxisTransform), diagonalised:
/// exact for boxes, spheres and cylinders, a bounding-box estimate for
/// capsules and hulls as for single shapes.
///
/// Frames: to keep "the centre of mass is the body origin", the wrapper
/// moves the parts into the shape frame, whose origin is the centre of mass
/// and whose axes are the principal axes (phys_compound_desc.frame_origin and
/// frame_rotation say where that frame lies in the parts frame). A body's
/// pose is the pose of the shape frame: to place the parts frame at (P, Q),
/// give the body position P + Q * frame_origin and orientation
/// Q * frame_rotation.
typedef struct phys_compound {
    const phys_compound_part *parts;
    uint32_t part_count;
} phys_compound;

/// A convex hull measured without a world: its corner and face counts and its
/// volume, as phys_shape_create_convex_hull would make it (the same checks, the
/// same exact hull, without Bullet's margin-shrunk copy, which costs ten times
/// more). A host that must refuse a hull early (the fluid's hull collider takes
/// at most PBF_MAX_HULL_PLANES faces) can ask first, cheaply.
typedef struct phys_hull_info {
    uint32_t vertex_count; ///< the hull's corners (points inside it dropped)
    uint32_t plane_count;  ///< its faces (coplanar triangles merged)
    float volume;          ///< m³
} phys_hull_info;

/// Checks `hull` and measures it into *out. On failure *out is untouched and,
/// when message is not NULL, it holds why (naming the field, as the world's
/// last error would), cut to message_size bytes with a terminating NUL.
phys_result phys_convex_hull_measure(const phys_convex_hull *hull, phys_hull_info *out, char *message,
                                     size_t message_size);

/// Create shapes. On success *out is the new shape id; on failure *out is
/// untouched and the message names the offending field.
phys_result phys_shape_create_plane(phys_world *world, const phys_plane *plane, phys_shape_id *out);
phys_result phys_shape_create_box(phys_world *world, const phys_box *box, phys_shape_id *out);
phys_result phys_shape_create_sphere(phys_world *world, const phys_sphere *sphere, phys_shape_id *out);
phys_result phys_shape_create_capsule(phys_world *world, const phys_capsule *capsule, phys_shape_id *out);
phys_result phys_shape_create_cylinder(phys_world *world, const phys_cylinder *cylinder, phys_shape_id *out);
phys_result phys_shape_create_convex_hull(phys_world *world, const phys_convex_hull *hull, phys_shape_id *out);
phys_result phys_shape_create_triangle_mesh(phys_world *world, const phys_triangle_mesh *mesh, phys_shape_id *out);
phys_result phys_shape_create_compound(phys_world *world, const phys_compound *compound, phys_shape_id *out);

/// Destroy a shape (a compound with all its children). Fails with
/// PHYS_ERR_INVALID_ARG while a body uses it.
phys_result phys_shape_destroy(phys_world *world, phys_shape_id shape);

/// True when `shape` names a live shape of this world. Never sets an error.
bool phys_shape_is_valid(const phys_world *world, phys_shape_id shape);

/// Describe a shape (see phys_shape_desc).
phys_result phys_shape_get_desc(phys_world *world, phys_shape_id shape, phys_shape_desc *out);

/// Volume of a shape, m³ (INFINITY for planes, 0 for triangle meshes).
phys_result phys_shape_get_volume(phys_world *world, phys_shape_id shape, float *out_volume);

// ---------------------------------------------------------------------------
// Bodies
// ---------------------------------------------------------------------------

/// How a body moves.
typedef enum phys_body_type {
    PHYS_BODY_STATIC = 0,    ///< never moves by itself; infinite mass
    PHYS_BODY_KINEMATIC = 1, ///< moved by the caller (target pose or velocity); infinite mass; pushes dynamic bodies
    PHYS_BODY_DYNAMIC = 2    ///< moved by forces and contacts
} phys_body_type;

/// The heaviest dynamic body, kg. Bullet's contact solver lets a body of about
/// 1.5e7 kg or more fall straight through a static floor (measured with Bullet
/// 3.24: 1e7 kg rests, 1.5e7 kg falls), so bodies are held an order below that.
#define PHYS_MAX_MASS 1.0e6f

/// The lightest dynamic body, kg (1 mg). Bullet keeps 1/mass and 1/inertia in
/// floats: a body of a denormal mass (1e-41 kg from a density of 1e-37 kg/m³)
/// came out of its first step as NaN.
#define PHYS_MIN_MASS 1.0e-6f

/// The fastest a body may move, m/s and rad/s. A velocity over these (in a body def,
/// phys_body_set_linear_velocity / _angular_velocity) is refused; a dynamic body that
/// forces, impulses or gravity drive faster is held to them before and after each
/// phys_world_step, and the log is told once per body (a warning). Bullet integrates
/// in floats: a body given 3.6e27 m/s was NaN two steps later.
#define PHYS_MAX_SPEED 1.0e5f
#define PHYS_MAX_ANGULAR_SPEED 1.0e5f
/// The strongest gravity, m/s² in size (about 1000 g); more is refused. A force or
/// torque that would change a body's speed by more than the limits above in one step is
/// scaled down to that before the step (and said once per body in the log).
#define PHYS_MAX_GRAVITY 1.0e4f

/// Body settings. Fill with phys_default_body_def(), then change fields.
typedef struct phys_body_def {
    phys_body_type type;         ///< default PHYS_BODY_DYNAMIC
    phys_shape_id shape;         ///< required; planes and meshes only on static/kinematic bodies
    phys_vec3 position;          ///< m, world; default origin
    phys_quat orientation;       ///< unit quaternion (x, y, z, w); default identity
    phys_vec3 linear_velocity;   ///< m/s; default 0; must be 0 for static bodies
    phys_vec3 angular_velocity;  ///< rad/s, world axes; default 0; must be 0 for static bodies
    /// kg, finite: 0, or in [PHYS_MIN_MASS, PHYS_MAX_MASS]. Dynamic bodies only:
    /// if mass > 0 it wins and `density` is ignored; if mass == 0 the mass is
    /// density × shape volume, which must lie in that range too. Ignored (but
    /// still checked) for static and kinematic bodies. A body too small for its
    /// mass to have a moment of inertia a float can invert is refused.
    float mass;
    /// kg/m³, finite; must be > 0 when used (dynamic, mass == 0). Default 1000.
    float density;
    /// Coulomb coefficient, [0, 100]; default 0.5. Bullet uses the product
    /// of the two bodies' values for a contact (0.5 against 0.5 gives 0.25).
    float friction;
    /// Bounciness, [0, 1]; default 0. A contact uses the product of the two.
    float restitution;
    /// Fraction of linear velocity removed per second, [0, 1]; Bullet applies
    /// v *= (1 - linear_damping)^dt each step. Default 0.
    float linear_damping;
    float angular_damping;       ///< as linear_damping, for angular velocity; default 0
    /// Whether the body may fall asleep when slow (Bullet: below 0.8 m/s and
    /// 1 rad/s for 2 s). Default true. Set false for bodies in fluid.
    bool allow_sleep;
    void *user_data;             ///< caller's pointer, returned by phys_body_get_user_data
} phys_body_def;

/// Defaults: dynamic, null shape, at the origin, identity orientation, at rest,
/// mass 0 (use density), density 1000 kg/m³, friction 0.5, restitution 0,
/// no damping, sleep allowed, user_data NULL.
phys_body_def phys_default_body_def(void);

/// Create a body. On success *out is its id.
phys_result phys_body_create(phys_world *world, const phys_body_def *def, phys_body_id *out);

/// Destroy a body. Constraints and joints attached to it are destroyed with it
/// (their ids become stale; the other body of a joint is woken). The shape is
/// not destroyed.
phys_result phys_body_destroy(phys_world *world, phys_body_id body);

/// True when `body` names a live body of this world. Never sets an error.
bool phys_body_is_valid(const phys_world *world, phys_body_id body);

/// The body's type.
phys_result phys_body_get_type(phys_world *world, phys_body_id body, phys_body_type *out);

/// Describe the body's shape (same as phys_shape_get_desc on its shape).
/// For a compound the children's poses are relative to the body pose:
/// child world pose = body pose × child pose.
phys_result phys_body_get_shape(phys_world *world, phys_body_id body, phys_shape_desc *out);

/// Teleport a body: position (m) and orientation. No velocity is derived and a
/// pending kinematic target is dropped. Wakes the body.
phys_result phys_body_set_pose(phys_world *world, phys_body_id body, phys_vec3 position, phys_quat orientation);

/// Current pose. Either output may be NULL.
phys_result phys_body_get_pose(phys_world *world, phys_body_id body, phys_vec3 *out_position, phys_quat *out_orientation);

/// Kinematic bodies only: reach this pose at the end of the next step. The body
/// moves with velocity (target - current) / dt during that step, which is
/// what contacts see, and stops there unless a new target is set. Setting a
/// target also clears a velocity set with phys_body_set_linear_velocity.
phys_result phys_body_set_kinematic_target(phys_world *world, phys_body_id body, phys_vec3 position, phys_quat orientation);

/// Linear velocity of the centre of mass, m/s. Dynamic: takes effect at once.
/// Kinematic: the body keeps moving with it every step until changed or a
/// target is set; it cancels a pending target. Static: rejected. Wakes the body.
phys_result phys_body_set_linear_velocity(phys_world *world, phys_body_id body, phys_vec3 velocity);
phys_result phys_body_get_linear_velocity(phys_world *world, phys_body_id body, phys_vec3 *out);

/// Size of the body's world-axis bounding box at its current pose, m (Bullet's, margins
/// included: tight along each axis for boxes, spheres, capsules and cylinders).
phys_result phys_body_get_extent(phys_world *world, phys_body_id body, phys_vec3 *out);

/// Angular velocity, rad/s about world axes; same rules as linear velocity.
phys_result phys_body_set_angular_velocity(phys_world *world, phys_body_id body, phys_vec3 velocity);
phys_result phys_body_get_angular_velocity(phys_world *world, phys_body_id body, phys_vec3 *out);

/// Velocity of the material point of the body at world point `point` (m):
/// v + ω × (point - centre of mass), m/s.
phys_result phys_body_get_velocity_at_point(phys_world *world, phys_body_id body, phys_vec3 point, phys_vec3 *out);

/// Forces and impulses. All vectors in world space. Forces (N) and torques
/// (N·m) act during the next phys_world_step only. Impulses (N·s) and angular
/// impulses (N·m·s) change the velocity at once. With wake = true a sleeping
/// body is woken first; with wake = false the call has no effect on a sleeping
/// body. Static and kinematic bodies accept the calls and do not respond.
phys_result phys_body_apply_force(phys_world *world, phys_body_id body, phys_vec3 force, bool wake);
phys_result phys_body_apply_force_at_point(phys_world *world, phys_body_id body, phys_vec3 force, phys_vec3 point, bool wake);
phys_result phys_body_apply_torque(phys_world *world, phys_body_id body, phys_vec3 torque, bool wake);
phys_result phys_body_apply_impulse(phys_world *world, phys_body_id body, phys_vec3 impulse, bool wake);
phys_result phys_body_apply_impulse_at_point(phys_world *world, phys_body_id body, phys_vec3 impulse, phys_vec3 point, bool wake);
phys_result phys_body_apply_angular_impulse(phys_world *world, phys_body_id body, phys_vec3 impulse, bool wake);

/// A force (N, through the centre of mass) and a torque (N·m), world space, held on
/// a body: applied in every phys_world_step from now on, until set again (zero
/// releases it), on top of the one-step forces above. For a host that steps the
/// world several times per frame (the coupling steps it once per fluid substep)
/// and has a force for the whole frame: a steady push then acts evenly over the
/// frame instead of as one impulse at its start. Wakes the body while non-zero.
/// Static and kinematic bodies accept it and do not respond.
phys_result phys_body_set_held_force(phys_world *world, phys_body_id body, phys_vec3 force, phys_vec3 torque);
/// The force and torque held on a body (zero when none). Either output may be NULL.
phys_result phys_body_get_held_force(phys_world *world, phys_body_id body, phys_vec3 *out_force, phys_vec3 *out_torque);

/// Mass properties. Static and kinematic bodies report mass 0 and all inverse
/// quantities 0 (infinite mass).
typedef struct phys_mass_data {
    float mass;                   ///< kg (0 for static/kinematic)
    float inv_mass;               ///< 1/kg
    phys_vec3 inertia_local;      ///< principal moments about the body axes, kg·m²
    float inv_inertia_world[9];   ///< inverse inertia tensor in world axes, row-major, 1/(kg·m²)
    phys_vec3 center_of_mass;     ///< world, m (the body position)
} phys_mass_data;

/// Mass, inertia and centre of mass of a body.
phys_result phys_body_get_mass_data(phys_world *world, phys_body_id body, phys_mass_data *out);

/// Per-axis factors on a dynamic body's motion, world axes, each component
/// finite and in [0, 1]; default {1, 1, 1}. Forces, gravity, contacts and
/// impulses change the linear velocity only along axes with a non-zero
/// factor (scaled by it), the angular velocity likewise. Linear factor
/// {0, 0, 0} pins the centre of mass; with angular factor {0, 0, 1} as well
/// the body is a wheel on a fixed axle along world z through its centre of
/// mass. Setting a factor zeroes the velocity along axes whose factor is 0.
/// Static and kinematic bodies accept the calls and are not affected.
phys_result phys_body_set_linear_factor(phys_world *world, phys_body_id body, phys_vec3 factor);
phys_result phys_body_set_angular_factor(phys_world *world, phys_body_id body, phys_vec3 factor);
phys_result phys_body_get_linear_factor(phys_world *world, phys_body_id body, phys_vec3 *out);
phys_result phys_body_get_angular_factor(phys_world *world, phys_body_id body, phys_vec3 *out);

/// Allow or forbid sleeping. Forbidding also wakes the body.
phys_result phys_body_set_sleep_enabled(phys_world *world, phys_body_id body, bool enabled);

/// Wake a sleeping body (and restart its sleep timer).
phys_result phys_body_wake(phys_world *world, phys_body_id body);

/// Whether the body is awake (simulated). Static bodies report false.
phys_result phys_body_is_awake(phys_world *world, phys_body_id body, bool *out);

/// The caller's pointer from the def, or as set later.
phys_result phys_body_set_user_data(phys_world *world, phys_body_id body, void *user_data);
phys_result phys_body_get_user_data(phys_world *world, phys_body_id body, void **out);

// ---------------------------------------------------------------------------
// Point constraint (mouse drag)
// ---------------------------------------------------------------------------

/// Pins a point of a dynamic body to a world pivot that the caller moves.
typedef struct phys_point_constraint_def {
    phys_body_id body;       ///< a dynamic body
    phys_vec3 pivot;         ///< world point, m; attached to the body where it is at creation
    /// Largest force the constraint may apply, N, > 0 and finite. Default 1e6.
    float max_force;
    /// Fraction of the pivot error removed per step, (0, 1]. Default 0.3.
    float error_reduction;
} phys_point_constraint_def;

/// Defaults: null body, pivot at origin, max_force 1e6 N, error_reduction 0.3.
phys_point_constraint_def phys_default_point_constraint_def(void);

/// Create the constraint. The body is kept awake while it exists.
phys_result phys_point_constraint_create(phys_world *world, const phys_point_constraint_def *def, phys_constraint_id *out);

/// Move the world pivot, m. Wakes the body.
phys_result phys_point_constraint_set_pivot(phys_world *world, phys_constraint_id constraint, phys_vec3 pivot);

/// Destroy a constraint. The body may sleep again if its def allowed it.
phys_result phys_constraint_destroy(phys_world *world, phys_constraint_id constraint);

/// True when `constraint` names a live constraint of this world.
bool phys_constraint_is_valid(const phys_world *world, phys_constraint_id constraint);

// ---------------------------------------------------------------------------
// Joints (Bullet's constraints)
//
// A joint ties `body_a`, which must be PHYS_BODY_DYNAMIC, to `body_b`: another
// body of any type, or the world when body_b is the null id. Pivots and axes
// are given in world space at creation and fixed to each body there, so
// create the joint with the bodies where they belong relative to each other.
//
// What a joint measures is body_a relative to body_b (or the world):
// - hinge angle: rotation of body_a relative to body_b about the axis, rad,
//   right-hand rule, 0 at creation, wrapped to [-π, π];
// - slider position: displacement of body_a relative to body_b along the
//   axis, m, 0 at creation.
// Limits bound that measure. A motor drives its rate towards a target
// velocity (rad/s, m/s) with at most a given torque (N·m) or force (N);
// Bullet reduces the motor's push near a limit and the limit wins.
//
// Limits are inelastic: a hinge stops a door at its limit (Bullet's hinge
// limit has a restitution by default; the wrapper sets it to 0).
//
// Joints are soft, like contacts: Bullet's sequential-impulse solver removes
// a fraction of the error each step, so under load a pivot stretches by
// millimetres and a body driven into a limit overshoots it briefly. The
// solver runs phys_world_def.solver_iterations over all rows; it converges
// slowly when a pivot is far from the centre of a body with little inertia
// about its own centre: a ball on a point joint 1 m away swings slower than
// it should (radius 5 cm: period +1.7% at dt 1/240 s, +8% at 1/60 s; radius
// 10 cm at 1/120 s: +0.2%). More iterations, a shorter dt, or the arm as a
// body of its own fix that.
//
// The two bodies of a joint do not collide with each other unless the def's
// collide_connected is true. Destroying either body destroys its joints (their
// ids become stale); destroying the world frees them all. Creating, changing
// or destroying a joint wakes its bodies; a joint with an enabled motor, or
// one whose body_b is kinematic, keeps its dynamic bodies awake.
// ---------------------------------------------------------------------------

/// Id of a joint; same layout and rules as phys_body_id.
typedef struct phys_joint_id {
    uint32_t index1;
    uint16_t world0;
    uint16_t generation;
} phys_joint_id;

/// Kind of joint.
typedef enum phys_joint_type {
    PHYS_JOINT_HINGE = 1, ///< one rotation about an axis (door, wheel)
    PHYS_JOINT_SLIDER,    ///< one translation along an axis, no rotation (piston, lock gate)
    PHYS_JOINT_FIXED,     ///< none: a weld that keeps the relative pose at creation
    PHYS_JOINT_POINT      ///< three rotations about a pivot (ball socket, chain link)
} phys_joint_type;

/// A hinge (Bullet's btHingeConstraint): body_a turns about the line through
/// `pivot` along `axis`, relative to body_b. Fill with phys_default_hinge_joint_def().
/// Limit and motor fields are checked even while disabled.
typedef struct phys_hinge_joint_def {
    phys_body_id body_a;     ///< a PHYS_BODY_DYNAMIC body
    phys_body_id body_b;     ///< another body, or the null id for the world (default)
    phys_vec3 pivot;         ///< world point on the axis, m; default origin
    phys_vec3 axis;          ///< world direction, any non-zero length (normalised); default {0, 0, 1}
    bool enable_limit;       ///< default false
    float lower_angle;       ///< rad, in [-π, π] and <= upper_angle; default 0
    float upper_angle;       ///< rad, in [-π, π]; default 0 (equal limits lock the hinge)
    bool enable_motor;       ///< default false
    float motor_speed;       ///< target rate of the angle, rad/s, finite; default 0
    float max_motor_torque;  ///< N·m, finite and >= 0; default 0
    bool collide_connected;  ///< whether body_a and body_b collide; default false
} phys_hinge_joint_def;

/// A slider (Bullet's btSliderConstraint): body_a moves along the line through
/// `anchor` along `axis`, relative to body_b, and does not rotate relative to
/// it. Fill with phys_default_slider_joint_def(). Limit and motor fields are
/// checked even while disabled.
typedef struct phys_slider_joint_def {
    phys_body_id body_a;     ///< a PHYS_BODY_DYNAMIC body
    phys_body_id body_b;     ///< another body, or the null id for the world (default)
    phys_vec3 anchor;        ///< world point on the line, m; default origin
    phys_vec3 axis;          ///< world direction, any non-zero length (normalised); default {1, 0, 0}
    bool enable_limit;       ///< default false
    float lower_translation; ///< m, finite and <= upper_translation; default 0
    float upper_translation; ///< m, finite; default 0
    bool enable_motor;       ///< default false
    float motor_speed;       ///< target rate of the position, m/s, finite; default 0
    float max_motor_force;   ///< N, finite and >= 0; default 0
    bool collide_connected;  ///< default false
} phys_slider_joint_def;

/// A weld (Bullet's btFixedConstraint): keeps body_a's pose relative to
/// body_b (or the world) as it is at creation. Fill with phys_default_fixed_joint_def().
typedef struct phys_fixed_joint_def {
    phys_body_id body_a;     ///< a PHYS_BODY_DYNAMIC body
    phys_body_id body_b;     ///< another body, or the null id for the world (default)
    bool collide_connected;  ///< default false
} phys_fixed_joint_def;

/// A ball socket (Bullet's btPoint2PointConstraint): the material points of
/// body_a and body_b at world `pivot` at creation stay together; rotation is
/// free. Fill with phys_default_point_joint_def().
typedef struct phys_point_joint_def {
    phys_body_id body_a;     ///< a PHYS_BODY_DYNAMIC body
    phys_body_id body_b;     ///< another body, or the null id for the world (default)
    phys_vec3 pivot;         ///< world point, m; default origin
    bool collide_connected;  ///< default false
} phys_point_joint_def;

/// Defaults: null bodies (body_b null = the world), pivot/anchor at the origin,
/// hinge axis {0, 0, 1}, slider axis {1, 0, 0}, limits and motor off with all
/// their values 0, collide_connected false.
phys_hinge_joint_def phys_default_hinge_joint_def(void);
phys_slider_joint_def phys_default_slider_joint_def(void);
phys_fixed_joint_def phys_default_fixed_joint_def(void);
phys_point_joint_def phys_default_point_joint_def(void);

/// Create a joint. On success *out is its id; on failure *out is untouched and
/// the message names the field (a stale or null body, body_a == body_b,
/// body_a not dynamic, a zero axis, lower > upper, ...).
phys_result phys_joint_create_hinge(phys_world *world, const phys_hinge_joint_def *def, phys_joint_id *out);
phys_result phys_joint_create_slider(phys_world *world, const phys_slider_joint_def *def, phys_joint_id *out);
phys_result phys_joint_create_fixed(phys_world *world, const phys_fixed_joint_def *def, phys_joint_id *out);
phys_result phys_joint_create_point(phys_world *world, const phys_point_joint_def *def, phys_joint_id *out);

/// Destroy a joint. Its bodies are woken and collide with each other again.
phys_result phys_joint_destroy(phys_world *world, phys_joint_id joint);

/// True when `joint` names a live joint of this world. Never sets an error.
bool phys_joint_is_valid(const phys_world *world, phys_joint_id joint);

/// The joint's type.
phys_result phys_joint_get_type(phys_world *world, phys_joint_id joint, phys_joint_type *out);

/// Hinges and sliders: turn the motor on or off. target_velocity: rad/s
/// (hinge) or m/s (slider), finite; max_force: the most the motor may apply,
/// N·m (hinge) or N (slider), finite and >= 0. Both are checked and stored
/// even when enabled is false.
phys_result phys_joint_set_motor(phys_world *world, phys_joint_id joint, bool enabled,
                                 float target_velocity, float max_force);

/// Hinges and sliders: turn the limits on or off. lower <= upper; rad in
/// [-π, π] for a hinge, m (finite) for a slider. Checked even when enabled is false.
phys_result phys_joint_set_limits(phys_world *world, phys_joint_id joint, bool enabled,
                                  float lower, float upper);

/// Hinges: the current angle, rad in [-π, π] (see the section's top). For the
/// total turn of a wheel, add up the wrapped differences from step to step.
phys_result phys_joint_get_angle(phys_world *world, phys_joint_id joint, float *out);

/// Sliders: the current position, m (see the section's top).
phys_result phys_joint_get_position(phys_world *world, phys_joint_id joint, float *out);

/// What the joint did to body_a during the last step: the impulse, N·s, and
/// the angular impulse about body_a's centre of mass, N·m·s, both world axes
/// (body_b got the opposite impulse). Divide by dt for the force (N) and
/// torque (N·m): a body hanging still from a joint reports {0, m g dt, 0}.
/// Zero before the first step and while both bodies sleep. Either output may be NULL.
phys_result phys_joint_get_applied_impulse(phys_world *world, phys_joint_id joint,
                                           phys_vec3 *out_impulse, phys_vec3 *out_angular_impulse);

// ---------------------------------------------------------------------------
// Contact reports
// ---------------------------------------------------------------------------

/// One touching pair of bodies after a step (all contact points of the pair
/// merged).
typedef struct phys_contact {
    phys_body_id a, b;   ///< the two bodies, a.index1 < b.index1; either may be static
    /// World, m: the mean of the contact points (each midway between the two
    /// surfaces) weighted by their impulses.
    phys_vec3 point;
    /// World, unit: from a towards b, the direction of the impulse on b
    /// (impulse-weighted mean of the points' normals).
    phys_vec3 normal;
    /// N·s: the normal impulse of the last step, summed over the pair's
    /// contact points; > 0. Friction is not included.
    float impulse;
} phys_contact;

/// The body pairs whose contact impulse in the last phys_world_step exceeded
/// `min_impulse` (N·s, finite, >= 0), sorted by a.index1 then b.index1.
///
/// The threshold is an impulse per step, not a force: a body of mass m
/// resting on another pushes m·g·dt every step (0.16 N·s for 1 kg at
/// dt = 1/60 s), while one that stops from speed v in a hit gives about m·v
/// (a restitution e gives (1 + e)·m·v). So a threshold a few times m·g·dt
/// reports hits and not resting contact, and one of 0 reports every pair
/// that pushed at all. Pairs whose bodies all sleep were not solved and are
/// not reported.
///
/// How Bullet shapes a hit: a box landing flat on a box gets its whole face
/// in the first step and stops there; the report is a little over m·v, as
/// it also carries that step's gravity and the push out of the penetration
/// (+12% for a 0.4 m box falling 0.5 m at dt = 1/60 s). On a plane Bullet
/// adds one contact point per step, so the box lands on one corner, tips,
/// and its hit is spread over several steps at moving points.
///
/// *count receives the number of pairs found, which may exceed `max`; the
/// first min(max, *count) go to out. max >= 0; out may be NULL when max is 0.
phys_result phys_world_get_contacts(phys_world *world, float min_impulse, phys_contact *out,
                                    int max, int *count);

/// Contact sums over several steps, for a host that steps the world more than
/// once per frame (the coupling steps it once per fluid substep) and wants the
/// frame's hits. While sums are on (they are off in a new world), every
/// phys_world_step adds each of its pairs, as phys_world_get_contacts(0)
/// would report them after that step, to a running sum per pair: impulses
/// add, point and normal become the impulse-weighted means over the steps.
/// Turning sums off (or on again) empties them.
phys_result phys_world_set_contact_sums(phys_world *world, bool enabled);

/// The pairs summed since the sums were turned on or last taken whose summed
/// impulse exceeds `min_impulse` (N·s, finite, >= 0), sorted by a.index1 then
/// b.index1, as phys_world_get_contacts fills them; then empties the sums (all
/// of them, also the pairs at or below the threshold). A pair's ids are those
/// of its bodies at the step that last touched; a body destroyed since makes
/// its ids stale. *count and max as in phys_world_get_contacts. Refused
/// (PHYS_ERR_INVALID_ARG) while sums are off.
phys_result phys_world_take_contact_sums(phys_world *world, float min_impulse, phys_contact *out,
                                         int max, int *count);

#ifdef __cplusplus
}
#endif

#endif // SEICHE_PHYS_H
