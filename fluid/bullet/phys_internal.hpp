// phys_internal.hpp: private to seiche_phys, shared by the phys_*.cpp files (C++17): the world
// and its slot tables, id helpers, the exception guard, input checks and cross-file prototypes.
//
// How it is put together:
// - phys_world owns one btDiscreteDynamicsWorld and four slot tables (shapes,
//   bodies, constraints, joints). A slot keeps its Bullet object in a unique_ptr,
//   a generation and an alive flag; freed slots go on a free list and their
//   generation moves on, which is what makes old ids detectably stale.
// - Every extern "C" entry point runs its body inside guarded(), which turns
//   any C++ exception into a phys_result and a message. Nothing is thrown into C.
// - Input checks run before anything is changed, so a failed call leaves the
//   world as it was.
// - Stepping calls stepSimulation(dt, 0): Bullet's variable-step path, which
//   runs exactly one internal step of dt with no accumulator. Kinematic bodies
//   are moved by writing their world transform just before the step; Bullet's
//   saveKinematicState then derives their velocity from the previous pose.
// - Joints to the world are two-body constraints whose second body is the
//   world's own `fixed` body: static, shapeless, at the origin, never added to
//   the dynamics world (Bullet's getFixedBody() is the same idea, but one object
//   for the whole process).
//
// The files: phys_world.cpp (world create/destroy, step, gravity, errors, input checks),
// phys_shape.cpp (shapes, compounds, mass properties), phys_body.cpp (bodies),
// phys_query.cpp (ray casts, point constraints), phys_joint.cpp (joints) and
// phys_contact.cpp (contact reports). Helpers two files share live in the
// namespace phys_internal, declared here; file-local ones are static.

#ifndef SEICHE_PHYS_INTERNAL_HPP
#define SEICHE_PHYS_INTERNAL_HPP

#include "phys.h"

#include <btBulletDynamicsCommon.h>

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <cmath>
#include <memory>
#include <new>
#include <stdexcept>
#include <vector>

static_assert(sizeof(phys_vec3) == 3 * sizeof(float), "phys_vec3 must be tightly packed");
static_assert(sizeof(btScalar) == sizeof(float), "this wrapper expects single-precision Bullet");
static_assert(sizeof(phys_body_type) == sizeof(int) && sizeof(phys_shape_type) == sizeof(int),
              "a C enum of the API is read as an int where a caller may have stored any value");

namespace phys_internal {

constexpr double kPi = 3.14159265358979323846;
constexpr float kUnitTolerance = 1e-3f;    // allowed |length - 1| for normals and quaternions
constexpr uint32_t kMaxHullPoints = 65536;
constexpr float kMaxMargin = 1.0f;
constexpr float kMaxFriction = 100.0f;

struct ShapeSlot {
    uint16_t generation = 1;
    bool alive = false;
    uint32_t use_count = 0;
    phys_shape_desc desc{};
    // Storage that desc points into (hull points/planes, mesh vertices/indices).
    std::vector<phys_vec3> points;
    std::vector<phys_hull_plane> planes;
    std::vector<uint32_t> indices;
    // Compounds: the children (each a slot of its own, never in the world's
    // table) and their stored descriptions, which desc.compound points into.
    std::vector<std::unique_ptr<ShapeSlot>> children;
    std::vector<phys_compound_child> child_descs;
    // Compounds: principal moments of inertia per kg of mass, m².
    btVector3 inertia_per_kg{0, 0, 0};
    // Declared before `shape` so the mesh shape is deleted before its mesh data
    // (and a compound before its children).
    std::unique_ptr<btTriangleIndexVertexArray> mesh;
    std::unique_ptr<btCollisionShape> shape;

    void clear() {
        shape.reset();
        mesh.reset();
        children.clear();
        child_descs.clear();
        points.clear();
        planes.clear();
        indices.clear();
        inertia_per_kg.setZero();
    }
};

struct BodySlot {
    uint16_t generation = 1;
    bool alive = false;
    phys_body_type type = PHYS_BODY_STATIC;
    bool allow_sleep = true;
    bool has_target = false;
    uint32_t shape_slot = 0;
    // Point constraints and motorised (or kinematic-driven) joints holding the
    // body awake: while > 0 a dynamic body does not sleep.
    uint32_t awake_holds = 0;
    void* user_data = nullptr;
    btTransform target;         // kinematic target for the next step
    btVector3 kin_linear{0, 0, 0};  // kinematic velocity set by the caller
    btVector3 kin_angular{0, 0, 0};
    btVector3 held_force{0, 0, 0};   // phys_body_set_held_force: applied in every step
    btVector3 held_torque{0, 0, 0};
    bool speed_held = false;         // PHYS_MAX_SPEED held it once (warned)
    std::unique_ptr<btRigidBody> body;
};

struct ConstraintSlot {
    uint16_t generation = 1;
    bool alive = false;
    uint32_t body_slot = 0;
    float max_force = 0;
    std::unique_ptr<btPoint2PointConstraint> constraint;
};

// body_b of a joint to the world.
constexpr uint32_t kWorldSlot = std::numeric_limits<uint32_t>::max();

struct JointSlot {
    uint16_t generation = 1;
    bool alive = false;
    phys_joint_type type = PHYS_JOINT_HINGE;
    uint32_t body_a = 0;
    uint32_t body_b = kWorldSlot;
    bool holds_awake = false;    // counted in the bodies' awake_holds
    bool motor = false;
    float motor_speed = 0;       // rad/s or m/s
    float max_motor = 0;         // N·m (hinge: made an impulse at each step) or N (slider)
    bool limit = false;
    float lower = 0, upper = 0;  // rad or m
    // Heap-allocated: Bullet keeps a pointer to it, and the slot moves when the table grows.
    std::unique_ptr<btJointFeedback> feedback;
    std::unique_ptr<btTypedConstraint> constraint;
};

// One body pair's contacts summed over steps (phys_world_set_contact_sums).
struct ContactSum {
    uint32_t a = 0, b = 0;            // body slots, a < b
    uint16_t gen_a = 0, gen_b = 0;    // their generations at the step that last touched
    double impulse = 0;               // N·s
    btVector3 point{0, 0, 0};         // sum of impulse × point
    btVector3 normal{0, 0, 0};        // sum of impulse × normal (a towards b)
};

inline uint16_t next_generation(uint16_t g) {
    ++g;
    return g == 0 ? 1 : g;
}

inline btVector3 to_bt(phys_vec3 v) { return btVector3(v.x, v.y, v.z); }
inline phys_vec3 from_bt(const btVector3& v) { return phys_vec3{v.x(), v.y(), v.z()}; }
inline phys_quat from_bt(const btQuaternion& q) { return phys_quat{q.x(), q.y(), q.z(), q.w()}; }

// A vector's length in doubles: a float's square overflows from about 1.8e19, and the speed and
// gravity limits must see a huge value as huge, not as infinity.
inline double length_of(double x, double y, double z) { return std::sqrt(x * x + y * y + z * z); }
inline double length_of(const btVector3& v) { return length_of(v.x(), v.y(), v.z()); }
inline double length_of(phys_vec3 v) { return length_of(v.x, v.y, v.z); }

} // namespace phys_internal

struct phys_world {
    phys_log_fn log = nullptr;
    void* log_user = nullptr;
    uint16_t tag = 1;
    float margin = 0.04f;
    std::unique_ptr<btDefaultCollisionConfiguration> config;
    std::unique_ptr<btCollisionDispatcher> dispatcher;
    std::unique_ptr<btBroadphaseInterface> broadphase;
    std::unique_ptr<btSequentialImpulseConstraintSolver> solver;
    std::unique_ptr<btDiscreteDynamicsWorld> dynamics;
    std::vector<phys_internal::ShapeSlot> shapes;
    std::vector<phys_internal::BodySlot> bodies;
    std::vector<phys_internal::ConstraintSlot> constraints;
    std::vector<phys_internal::JointSlot> joints;
    std::vector<uint32_t> free_shapes, free_bodies, free_constraints, free_joints;
    // The other body of joints to the world (see the top of this file).
    std::unique_ptr<btRigidBody> fixed;
    float last_dt = 0;  // s, of the last phys_world_step (0 before the first)
    bool sum_contacts = false;                        // phys_world_set_contact_sums
    std::vector<phys_internal::ContactSum> contact_sums; // sorted by (a, b)
    uint32_t body_count = 0;
    char last_error[512] = {0};

    ~phys_world() {
        // Bullet keeps raw pointers: take constraints and bodies out of the
        // dynamics world before deleting them, and delete shapes last.
        if (dynamics) {
            for (phys_internal::ConstraintSlot& c : constraints) {
                if (c.alive) dynamics->removeConstraint(c.constraint.get());
            }
            for (phys_internal::JointSlot& j : joints) {
                if (j.alive) dynamics->removeConstraint(j.constraint.get());
            }
            for (phys_internal::BodySlot& b : bodies) {
                if (b.alive) dynamics->removeRigidBody(b.body.get());
            }
        }
        constraints.clear();
        joints.clear();
        bodies.clear();
        fixed.reset();
        dynamics.reset();
        solver.reset();
        broadphase.reset();
        dispatcher.reset();
        config.reset();
        shapes.clear();
    }
};

#if defined(__GNUC__)
#define PRINTF_LIKE(f, a) __attribute__((format(printf, f, a)))
#else
#define PRINTF_LIKE(f, a)
#endif

#define CHECK(expr)                              \
    do {                                         \
        const phys_result check_r_ = (expr);     \
        if (check_r_ != PHYS_OK) return check_r_; \
    } while (0)

namespace phys_internal {

// Record an error on the world, hand it to the log callback, return `result` (phys_world.cpp).
phys_result fail(phys_world* w, phys_result result, const char* fmt, ...) PRINTF_LIKE(3, 4);

// Run an entry point's body, turning every exception into a result.
// `body` gets the entry point's name for its messages.
template <class F>
phys_result guarded(phys_world* w, const char* fn, F&& body) noexcept {
    if (!w) return PHYS_ERR_INVALID_ARG;
    try {
        return body(fn);
    } catch (const std::bad_alloc&) {
        return fail(w, PHYS_ERR_OUT_OF_MEMORY, "%s: out of memory", fn);
    } catch (const std::exception& e) {
        return fail(w, PHYS_ERR_INTERNAL, "%s: internal error: %s", fn, e.what());
    } catch (...) {
        return fail(w, PHYS_ERR_INTERNAL, "%s: internal error (unknown exception)", fn);
    }
}

// ---- input checks (phys_world.cpp) -------------------------------------------

phys_result check_ptr(phys_world* w, const char* fn, const char* name, const void* p);
phys_result check_finite(phys_world* w, const char* fn, const char* field, float v);
phys_result check_vec3(phys_world* w, const char* fn, const char* field, phys_vec3 v);
phys_result check_positive(phys_world* w, const char* fn, const char* field, float v);
phys_result check_range(phys_world* w, const char* fn, const char* field, float v, float lo,
                        float hi);
phys_result check_quat(phys_world* w, const char* fn, const char* field, phys_quat q,
                       btQuaternion* out);
// A velocity within PHYS_MAX_SPEED (angular: PHYS_MAX_ANGULAR_SPEED), finite.
phys_result check_speed(phys_world* w, const char* fn, const char* field, phys_vec3 v, bool angular);

// ---- id lookup ---------------------------------------------------------------

template <class Slot, class Id>
bool id_is_live(const phys_world* w, const std::vector<Slot>& slots, Id id) {
    return w && id.index1 != 0 && id.world0 == w->tag && id.index1 <= slots.size() &&
           slots[id.index1 - 1].alive && slots[id.index1 - 1].generation == id.generation;
}

// Find the slot of `id`. `label` names the argument or field in messages and
// `noun` the kind of object ("body").
template <class Slot, class Id>
phys_result lookup(phys_world* w, const char* fn, const char* label, const char* noun,
                   const std::vector<Slot>& slots, Id id, uint32_t* out_slot) {
    if (id.index1 == 0 && id.world0 == 0 && id.generation == 0) {
        return fail(w, PHYS_ERR_INVALID_ARG, "%s: %s is the null id (all zero): no %s given", fn,
                    label, noun);
    }
    if (id.world0 != w->tag) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: %s.world0 is %u but this world's tag is %u: the id comes from another "
                    "world",
                    fn, label, (unsigned)id.world0, (unsigned)w->tag);
    }
    if (id.index1 == 0 || id.index1 > slots.size()) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: %s.index1 must be in [1, %zu] for this world (got %u)", fn, label,
                    slots.size(), (unsigned)id.index1);
    }
    const Slot& s = slots[id.index1 - 1];
    if (!s.alive || s.generation != id.generation) {
        return fail(w, PHYS_ERR_STALE_ID,
                    "%s: %s is stale (index1 %u, generation %u, current %u): attempt to use a "
                    "destroyed %s",
                    fn, label, (unsigned)id.index1, (unsigned)id.generation,
                    (unsigned)s.generation, noun);
    }
    *out_slot = id.index1 - 1;
    return PHYS_OK;
}

template <class Id>
Id make_id(const phys_world* w, uint32_t slot, uint16_t generation) {
    Id id;
    id.index1 = slot + 1;
    id.world0 = w->tag;
    id.generation = generation;
    return id;
}

// Take a free slot or append one; the caller fills it and marks it alive.
template <class Slot>
uint32_t reserve_slot(std::vector<Slot>& slots, std::vector<uint32_t>& free_list) {
    if (!free_list.empty()) return free_list.back();
    if (slots.size() >= (size_t)std::numeric_limits<int32_t>::max()) {
        throw std::length_error("too many objects in one world");
    }
    slots.emplace_back();
    // The free list can always hold every slot, so releasing one never throws.
    free_list.reserve(slots.size());
    free_list.push_back((uint32_t)(slots.size() - 1));
    return free_list.back();
}

// Mark the slot from reserve_slot as taken, once the object is in it.
inline void claim_slot(std::vector<uint32_t>& free_list, uint32_t slot) {
    assert(!free_list.empty() && free_list.back() == slot);
    (void)slot;
    free_list.pop_back();
}

// ---- names for messages, and what one area asks of another ----------------------

const char* shape_name(phys_shape_type t);         // phys_shape.cpp
const char* body_type_name(phys_body_type t);      // phys_body.cpp

// Take a constraint out of the world, free its slot and let its body sleep again
// (phys_query.cpp; phys_body_destroy calls it for the body's constraints).
void destroy_constraint_slot(phys_world* w, uint32_t slot);

// Hold a dynamic body awake, or let go of a hold; the last one to let go lets it sleep
// again if its def allows (phys_body.cpp). Both do nothing for other body types.
void hold_awake(BodySlot& b);
void release_awake(BodySlot& b);

// Destroy every joint of a body (phys_joint.cpp; phys_body_destroy calls it).
void destroy_body_joints(phys_world* w, uint32_t body_slot);

// Before a step of dt: turn hinge motor torques into impulses (phys_joint.cpp).
void prepare_joints(phys_world* w, float dt);

// After a step: add its contact pairs to the sums when they are on (phys_contact.cpp).
void sum_step_contacts(phys_world* w);

} // namespace phys_internal

#endif // SEICHE_PHYS_INTERNAL_HPP
