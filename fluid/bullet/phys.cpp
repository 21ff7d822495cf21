// phys.cpp: the C API of phys.h over Bullet (C++17). What the parts share (the world, its
// slots, id helpers, input checks, the exception guard) is in phys_internal.hpp.

#include "phys_internal.hpp"

#include <cmath>
#include <cstdarg>
#include <cstdio>

using namespace phys_internal;

static void format_message(char* buf, size_t size, const char* fmt, va_list args) noexcept {
    if (std::vsnprintf(buf, size, fmt, args) < 0) {
        std::snprintf(buf, size, "(unformattable error message)");
    }
}

namespace phys_internal {

phys_result fail(phys_world* w, phys_result result, const char* fmt, ...) {
    va_list args;
    va_start(args, fmt);
    format_message(w->last_error, sizeof w->last_error, fmt, args);
    va_end(args);
    if (w->log) w->log(w->log_user, PHYS_LOG_ERROR, w->last_error);
    return result;
}

// ---- input checks ---------------------------------------------------------

phys_result check_ptr(phys_world* w, const char* fn, const char* name, const void* p) {
    if (p) return PHYS_OK;
    return fail(w, PHYS_ERR_INVALID_ARG, "%s: %s must not be NULL", fn, name);
}

phys_result check_finite(phys_world* w, const char* fn, const char* field, float v) {
    if (std::isfinite(v)) return PHYS_OK;
    return fail(w, PHYS_ERR_INVALID_ARG, "%s: %s must be finite (got %g)", fn, field, (double)v);
}

phys_result check_vec3(phys_world* w, const char* fn, const char* field, phys_vec3 v) {
    const float c[3] = {v.x, v.y, v.z};
    const char* axis[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(c[i])) {
            return fail(w, PHYS_ERR_INVALID_ARG, "%s: %s.%s must be finite (got %g)", fn, field,
                        axis[i], (double)c[i]);
        }
    }
    return PHYS_OK;
}

phys_result check_positive(phys_world* w, const char* fn, const char* field, float v) {
    CHECK(check_finite(w, fn, field, v));
    if (v > 0) return PHYS_OK;
    return fail(w, PHYS_ERR_INVALID_ARG, "%s: %s must be > 0 (got %g)", fn, field, (double)v);
}

phys_result check_range(phys_world* w, const char* fn, const char* field, float v, float lo,
                        float hi) {
    if (std::isfinite(v) && v >= lo && v <= hi) return PHYS_OK;
    return fail(w, PHYS_ERR_INVALID_ARG, "%s: %s must be finite and in [%g, %g] (got %g)", fn,
                field, (double)lo, (double)hi, (double)v);
}

phys_result check_quat(phys_world* w, const char* fn, const char* field, phys_quat q,
                       btQuaternion* out) {
    const float c[4] = {q.x, q.y, q.z, q.w};
    const char* axis[4] = {"x", "y", "z", "w"};
    for (int i = 0; i < 4; ++i) {
        if (!std::isfinite(c[i])) {
            return fail(w, PHYS_ERR_INVALID_ARG, "%s: %s.%s must be finite (got %g)", fn, field,
                        axis[i], (double)c[i]);
        }
    }
    const double len = std::sqrt((double)q.x * q.x + (double)q.y * q.y + (double)q.z * q.z +
                                 (double)q.w * q.w);
    if (std::fabs(len - 1.0) > kUnitTolerance) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: %s must be a unit quaternion (x, y, z, w), length 1 within %g (got "
                    "length %g)",
                    fn, field, (double)kUnitTolerance, len);
    }
    *out = btQuaternion(q.x, q.y, q.z, q.w);
    out->normalize();
    return PHYS_OK;
}

const char* body_type_name(phys_body_type t) {
    switch (t) {
    case PHYS_BODY_STATIC: return "PHYS_BODY_STATIC";
    case PHYS_BODY_KINEMATIC: return "PHYS_BODY_KINEMATIC";
    case PHYS_BODY_DYNAMIC: return "PHYS_BODY_DYNAMIC";
    }
    return "unknown";
}

void destroy_constraint_slot(phys_world* w, uint32_t slot) {
    ConstraintSlot& c = w->constraints[slot];
    w->dynamics->removeConstraint(c.constraint.get());
    c.constraint.reset();
    c.alive = false;
    c.generation = next_generation(c.generation);
    BodySlot& b = w->bodies[c.body_slot];
    if (b.constraint_count > 0) --b.constraint_count;
    if (b.alive && b.constraint_count == 0 && b.allow_sleep) {
        b.body->forceActivationState(ACTIVE_TAG);
        b.body->setDeactivationTime(0);
    }
    w->free_constraints.push_back(slot);
}

} // namespace phys_internal

namespace {

// ---- bodies -----------------------------------------------------------------

phys_result get_body(phys_world* w, const char* fn, phys_body_id id, BodySlot** out) {
    uint32_t slot = 0;
    CHECK(lookup(w, fn, "phys_body_id", "body", w->bodies, id, &slot));
    *out = &w->bodies[slot];
    return PHYS_OK;
}

// Shared path of the force/impulse calls: checks, then `apply` on an awake
// dynamic body.
template <class F>
phys_result apply_to_body(phys_world* w, const char* fn, phys_body_id id, bool wake, F&& apply) {
    BodySlot* b = nullptr;
    CHECK(get_body(w, fn, id, &b));
    if (b->type != PHYS_BODY_DYNAMIC) return PHYS_OK;  // infinite mass: no response
    btRigidBody* rb = b->body.get();
    if (!rb->isActive()) {
        if (!wake) return PHYS_OK;
        rb->activate(true);
    }
    apply(rb);
    return PHYS_OK;
}

phys_result set_velocity(phys_world* w, const char* fn, phys_body_id id, phys_vec3 v,
                         bool angular) {
    CHECK(check_vec3(w, fn, "velocity", v));
    BodySlot* b = nullptr;
    CHECK(get_body(w, fn, id, &b));
    if (b->type == PHYS_BODY_STATIC) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: body is PHYS_BODY_STATIC; static bodies cannot be given a velocity "
                    "(use a kinematic body)",
                    fn);
    }
    btRigidBody* rb = b->body.get();
    if (b->type == PHYS_BODY_KINEMATIC) {
        (angular ? b->kin_angular : b->kin_linear) = to_bt(v);
        b->has_target = false;
    }
    if (angular) {
        rb->setAngularVelocity(to_bt(v));
    } else {
        rb->setLinearVelocity(to_bt(v));
    }
    rb->activate(true);
    return PHYS_OK;
}

phys_result get_vector(phys_world* w, const char* fn, phys_body_id id, phys_vec3* out,
                       bool angular) {
    CHECK(check_ptr(w, fn, "out", out));
    BodySlot* b = nullptr;
    CHECK(get_body(w, fn, id, &b));
    *out = from_bt(angular ? b->body->getAngularVelocity() : b->body->getLinearVelocity());
    return PHYS_OK;
}

} // namespace

// =============================================================================
// extern "C" entry points
// =============================================================================

extern "C" {

const char* phys_result_string(phys_result result) {
    switch (result) {
    case PHYS_OK: return "PHYS_OK";
    case PHYS_ERR_INVALID_ARG: return "PHYS_ERR_INVALID_ARG";
    case PHYS_ERR_STALE_ID: return "PHYS_ERR_STALE_ID";
    case PHYS_ERR_OUT_OF_MEMORY: return "PHYS_ERR_OUT_OF_MEMORY";
    case PHYS_ERR_INTERNAL: return "PHYS_ERR_INTERNAL";
    }
    return "PHYS_ERR_UNKNOWN";
}

phys_world_def phys_default_world_def(void) {
    phys_world_def d;
    d.gravity = phys_vec3{0.0f, -9.81f, 0.0f};
    d.solver_iterations = 10;
    d.collision_margin = 0.04f;
    d.log = nullptr;
    d.log_user = nullptr;
    return d;
}

phys_result phys_world_create(const phys_world_def* def, phys_world** out_world) {
    if (out_world) *out_world = nullptr;
    if (!def) return PHYS_ERR_INVALID_ARG;
    auto reject = [def](const char* msg) {
        if (def->log) def->log(def->log_user, PHYS_LOG_ERROR, msg);
        return PHYS_ERR_INVALID_ARG;
    };
    char msg[512];
    if (!out_world) return reject("phys_world_create: out_world must not be NULL");
    const float g[3] = {def->gravity.x, def->gravity.y, def->gravity.z};
    const char* axis[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(g[i])) {
            std::snprintf(msg, sizeof msg,
                          "phys_world_create: phys_world_def.gravity.%s must be finite (got %g)",
                          axis[i], (double)g[i]);
            return reject(msg);
        }
    }
    if (def->solver_iterations < 1 || def->solver_iterations > 1000) {
        std::snprintf(msg, sizeof msg,
                      "phys_world_create: phys_world_def.solver_iterations must be in [1, 1000] "
                      "(got %d)",
                      def->solver_iterations);
        return reject(msg);
    }
    if (!std::isfinite(def->collision_margin) || def->collision_margin < 0 ||
        def->collision_margin > kMaxMargin) {
        std::snprintf(msg, sizeof msg,
                      "phys_world_create: phys_world_def.collision_margin must be finite and in "
                      "[0, %g] m (got %g)",
                      (double)kMaxMargin, (double)def->collision_margin);
        return reject(msg);
    }
    try {
        auto w = std::make_unique<phys_world>();
        w->log = def->log;
        w->log_user = def->log_user;
        w->margin = def->collision_margin;
        // A tag for ids from this world: a hash of its address, never 0.
        const uintptr_t a = reinterpret_cast<uintptr_t>(w.get());
        uint16_t tag = (uint16_t)(((uint64_t)a * 0x9E3779B97F4A7C15ull) >> 48);
        w->tag = tag == 0 ? 1 : tag;
        w->config = std::make_unique<btDefaultCollisionConfiguration>();
        w->dispatcher = std::make_unique<btCollisionDispatcher>(w->config.get());
        w->broadphase = std::make_unique<btDbvtBroadphase>();
        w->solver = std::make_unique<btSequentialImpulseConstraintSolver>();
        w->dynamics = std::make_unique<btDiscreteDynamicsWorld>(
            w->dispatcher.get(), w->broadphase.get(), w->solver.get(), w->config.get());
        w->dynamics->setGravity(to_bt(def->gravity));
        w->dynamics->getSolverInfo().m_numIterations = def->solver_iterations;
        *out_world = w.release();
        return PHYS_OK;
    } catch (const std::bad_alloc&) {
        if (def->log) def->log(def->log_user, PHYS_LOG_ERROR, "phys_world_create: out of memory");
        return PHYS_ERR_OUT_OF_MEMORY;
    } catch (...) {
        if (def->log) {
            def->log(def->log_user, PHYS_LOG_ERROR, "phys_world_create: internal error");
        }
        return PHYS_ERR_INTERNAL;
    }
}

void phys_world_destroy(phys_world* world) {
    try {
        delete world;
    } catch (...) {
        // Destructors do not throw; nothing may escape into C regardless.
    }
}

phys_result phys_world_step(phys_world* world, float dt) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        if (!std::isfinite(dt) || dt < 1e-6f || dt > 10.0f) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: dt must be finite and in [1e-06, 10] s (got %g)", fn, (double)dt);
        }
        // Kinematic bodies: write where they must be at the end of the step;
        // Bullet derives their velocity from the previous pose.
        for (BodySlot& b : w->bodies) {
            if (!b.alive || b.type != PHYS_BODY_KINEMATIC) continue;
            btRigidBody* rb = b.body.get();
            if (b.has_target) {
                rb->setWorldTransform(b.target);
            } else if (!b.kin_linear.fuzzyZero() || !b.kin_angular.fuzzyZero()) {
                btTransform next;
                btTransformUtil::integrateTransform(rb->getWorldTransform(), b.kin_linear,
                                                    b.kin_angular, dt, next);
                rb->setWorldTransform(next);
            }
        }
        for (ConstraintSlot& c : w->constraints) {
            if (c.alive) c.constraint->m_setting.m_impulseClamp = c.max_force * dt;
        }
        // maxSubSteps = 0: Bullet's variable-step path, exactly one step of dt.
        w->dynamics->stepSimulation(dt, 0, dt);
        for (BodySlot& b : w->bodies) b.has_target = false;
        return PHYS_OK;
    });
}

phys_result phys_world_set_gravity(phys_world* world, phys_vec3 gravity) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "gravity", gravity));
        world->dynamics->setGravity(to_bt(gravity));
        return PHYS_OK;
    });
}

phys_vec3 phys_world_get_gravity(const phys_world* world) {
    if (!world) return phys_vec3{0, 0, 0};
    return from_bt(world->dynamics->getGravity());
}

const char* phys_world_last_error(const phys_world* world) {
    if (!world) return "phys_world is NULL";
    return world->last_error;
}

uint32_t phys_world_get_body_count(const phys_world* world) {
    return world ? world->body_count : 0;
}

phys_result phys_world_ray_cast(phys_world* world, phys_vec3 from, phys_vec3 to,
                                phys_ray_hit* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        *out = phys_ray_hit{};
        CHECK(check_vec3(world, fn, "from", from));
        CHECK(check_vec3(world, fn, "to", to));
        const btVector3 a = to_bt(from), b = to_bt(to);
        if (a == b) {
            return fail(world, PHYS_ERR_INVALID_ARG,
                        "%s: from and to must differ (both are %g, %g, %g)", fn, (double)from.x,
                        (double)from.y, (double)from.z);
        }
        btCollisionWorld::ClosestRayResultCallback cb(a, b);
        world->dynamics->rayTest(a, b, cb);
        if (!cb.hasHit()) return PHYS_OK;
        const int slot = cb.m_collisionObject->getUserIndex();
        if (slot < 0 || (size_t)slot >= world->bodies.size() || !world->bodies[(size_t)slot].alive) {
            return fail(world, PHYS_ERR_INTERNAL, "%s: hit an object that is not a live body", fn);
        }
        out->hit = true;
        out->body = make_id<phys_body_id>(world, (uint32_t)slot, world->bodies[(size_t)slot].generation);
        out->point = from_bt(cb.m_hitPointWorld);
        btVector3 n = cb.m_hitNormalWorld;
        if (n.length2() > 0) n.normalize();
        out->normal = from_bt(n);
        out->fraction = cb.m_closestHitFraction;
        return PHYS_OK;
    });
}

// ---- bodies --------------------------------------------------------------------

phys_body_def phys_default_body_def(void) {
    phys_body_def d;
    d.type = PHYS_BODY_DYNAMIC;
    d.shape = phys_shape_id{0, 0, 0};
    d.position = phys_vec3{0, 0, 0};
    d.orientation = phys_quat{0, 0, 0, 1};
    d.linear_velocity = phys_vec3{0, 0, 0};
    d.angular_velocity = phys_vec3{0, 0, 0};
    d.mass = 0.0f;
    d.density = 1000.0f;
    d.friction = 0.5f;
    d.restitution = 0.0f;
    d.linear_damping = 0.0f;
    d.angular_damping = 0.0f;
    d.allow_sleep = true;
    d.user_data = nullptr;
    return d;
}

phys_result phys_body_create(phys_world* world, const phys_body_def* def, phys_body_id* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        CHECK(check_ptr(w, fn, "def", def));
        CHECK(check_ptr(w, fn, "out", out));
        const phys_body_def& d = *def;
        if (d.type != PHYS_BODY_STATIC && d.type != PHYS_BODY_KINEMATIC &&
            d.type != PHYS_BODY_DYNAMIC) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_body_def.type must be PHYS_BODY_STATIC, PHYS_BODY_KINEMATIC or "
                        "PHYS_BODY_DYNAMIC (got %d)",
                        fn, (int)d.type);
        }
        uint32_t shape_slot = 0;
        CHECK(lookup(w, fn, "phys_body_def.shape", "shape", w->shapes, d.shape, &shape_slot));
        CHECK(check_vec3(w, fn, "phys_body_def.position", d.position));
        btQuaternion q;
        CHECK(check_quat(w, fn, "phys_body_def.orientation", d.orientation, &q));
        CHECK(check_vec3(w, fn, "phys_body_def.linear_velocity", d.linear_velocity));
        CHECK(check_vec3(w, fn, "phys_body_def.angular_velocity", d.angular_velocity));
        if (!std::isfinite(d.mass) || d.mass < 0) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_body_def.mass must be >= 0 and finite (got %g)", fn,
                        (double)d.mass);
        }
        CHECK(check_finite(w, fn, "phys_body_def.density", d.density));
        CHECK(check_range(w, fn, "phys_body_def.friction", d.friction, 0, kMaxFriction));
        CHECK(check_range(w, fn, "phys_body_def.restitution", d.restitution, 0, 1));
        CHECK(check_range(w, fn, "phys_body_def.linear_damping", d.linear_damping, 0, 1));
        CHECK(check_range(w, fn, "phys_body_def.angular_damping", d.angular_damping, 0, 1));

        ShapeSlot& shape = w->shapes[shape_slot];
        if (d.type == PHYS_BODY_STATIC &&
            (!to_bt(d.linear_velocity).isZero() || !to_bt(d.angular_velocity).isZero())) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_body_def.linear_velocity and angular_velocity must be zero for "
                        "a PHYS_BODY_STATIC body (got %g, %g, %g and %g, %g, %g)",
                        fn, (double)d.linear_velocity.x, (double)d.linear_velocity.y,
                        (double)d.linear_velocity.z, (double)d.angular_velocity.x,
                        (double)d.angular_velocity.y, (double)d.angular_velocity.z);
        }
        float mass = 0;
        btVector3 inertia(0, 0, 0);
        if (d.type == PHYS_BODY_DYNAMIC) {
            const phys_shape_type st = shape.desc.type;
            if (st == PHYS_SHAPE_PLANE || st == PHYS_SHAPE_TRIANGLE_MESH) {
                return fail(w, PHYS_ERR_INVALID_ARG,
                            "%s: phys_body_def.type is PHYS_BODY_DYNAMIC but phys_body_def.shape "
                            "is a %s, which has no finite volume: planes and triangle meshes "
                            "only go on PHYS_BODY_STATIC or PHYS_BODY_KINEMATIC bodies",
                            fn, shape_name(st));
            }
            if (d.mass > 0) {
                mass = d.mass;
            } else {
                if (!(d.density > 0)) {
                    return fail(w, PHYS_ERR_INVALID_ARG,
                                "%s: phys_body_def.density must be > 0 and finite when "
                                "phys_body_def.mass is 0 (got %g)",
                                fn, (double)d.density);
                }
                mass = d.density * shape.desc.volume;
                if (!std::isfinite(mass) || !(mass > 0)) {
                    return fail(w, PHYS_ERR_INVALID_ARG,
                                "%s: phys_body_def.density %g times the %s volume %g m^3 gives "
                                "mass %g kg; it must be > 0 and finite",
                                fn, (double)d.density, shape_name(st), (double)shape.desc.volume,
                                (double)mass);
                }
            }
            if (st == PHYS_SHAPE_COMPOUND) {
                inertia = shape.inertia_per_kg * mass;  // Bullet's own is a bounding-box guess
            } else {
                shape.shape->calculateLocalInertia(mass, inertia);
            }
        }

        const uint32_t slot = reserve_slot(w->bodies, w->free_bodies);
        BodySlot& b = w->bodies[slot];
        btRigidBody::btRigidBodyConstructionInfo ci(mass, nullptr, shape.shape.get(), inertia);
        ci.m_startWorldTransform = btTransform(q, to_bt(d.position));
        ci.m_friction = d.friction;
        ci.m_restitution = d.restitution;
        ci.m_linearDamping = d.linear_damping;
        ci.m_angularDamping = d.angular_damping;
        auto rb = std::make_unique<btRigidBody>(ci);
        if (d.type == PHYS_BODY_KINEMATIC) {
            rb->setCollisionFlags((rb->getCollisionFlags() & ~btCollisionObject::CF_STATIC_OBJECT) |
                                  btCollisionObject::CF_KINEMATIC_OBJECT);
            rb->setActivationState(DISABLE_DEACTIVATION);  // Bullet skips sleeping kinematics
        }
        if (d.type != PHYS_BODY_STATIC) {
            rb->setLinearVelocity(to_bt(d.linear_velocity));
            rb->setAngularVelocity(to_bt(d.angular_velocity));
        }
        if (d.type == PHYS_BODY_DYNAMIC && !d.allow_sleep) {
            rb->setActivationState(DISABLE_DEACTIVATION);
        }
        rb->setUserIndex((int)slot);
        w->dynamics->addRigidBody(rb.get());

        b.body = std::move(rb);
        b.type = d.type;
        b.allow_sleep = d.allow_sleep;
        b.has_target = false;
        b.shape_slot = shape_slot;
        b.constraint_count = 0;
        b.user_data = d.user_data;
        b.kin_linear = d.type == PHYS_BODY_KINEMATIC ? to_bt(d.linear_velocity) : btVector3(0, 0, 0);
        b.kin_angular = d.type == PHYS_BODY_KINEMATIC ? to_bt(d.angular_velocity) : btVector3(0, 0, 0);
        b.alive = true;
        claim_slot(w->free_bodies, slot);
        ++shape.use_count;
        ++w->body_count;
        *out = make_id<phys_body_id>(w, slot, b.generation);
        return PHYS_OK;
    });
}

phys_result phys_body_destroy(phys_world* world, phys_body_id body) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        uint32_t slot = 0;
        CHECK(lookup(w, fn, "phys_body_id", "body", w->bodies, body, &slot));
        for (uint32_t c = 0; c < w->constraints.size(); ++c) {
            if (w->constraints[c].alive && w->constraints[c].body_slot == slot) {
                destroy_constraint_slot(w, c);
            }
        }
        BodySlot& b = w->bodies[slot];
        w->dynamics->removeRigidBody(b.body.get());
        b.body.reset();
        --w->shapes[b.shape_slot].use_count;
        b.alive = false;
        b.user_data = nullptr;
        b.generation = next_generation(b.generation);
        w->free_bodies.push_back(slot);
        --w->body_count;
        return PHYS_OK;
    });
}

bool phys_body_is_valid(const phys_world* world, phys_body_id body) {
    return world && id_is_live(world, world->bodies, body);
}

phys_result phys_body_get_type(phys_world* world, phys_body_id body, phys_body_type* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        *out = b->type;
        return PHYS_OK;
    });
}

phys_result phys_body_get_shape(phys_world* world, phys_body_id body, phys_shape_desc* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        *out = world->shapes[b->shape_slot].desc;
        return PHYS_OK;
    });
}

phys_result phys_body_set_pose(phys_world* world, phys_body_id body, phys_vec3 position,
                               phys_quat orientation) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "position", position));
        btQuaternion q;
        CHECK(check_quat(world, fn, "orientation", orientation, &q));
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        btRigidBody* rb = b->body.get();
        const btTransform t(q, to_bt(position));
        // Set both transforms so no velocity is derived from the jump.
        rb->setWorldTransform(t);
        rb->setInterpolationWorldTransform(t);
        rb->updateInertiaTensor();
        b->has_target = false;
        if (b->type == PHYS_BODY_DYNAMIC) rb->activate(true);
        world->dynamics->updateSingleAabb(rb);
        return PHYS_OK;
    });
}

phys_result phys_body_get_pose(phys_world* world, phys_body_id body, phys_vec3* out_position,
                               phys_quat* out_orientation) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        const btTransform& t = b->body->getWorldTransform();
        if (out_position) *out_position = from_bt(t.getOrigin());
        if (out_orientation) *out_orientation = from_bt(t.getRotation());
        return PHYS_OK;
    });
}

phys_result phys_body_set_kinematic_target(phys_world* world, phys_body_id body,
                                           phys_vec3 position, phys_quat orientation) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "position", position));
        btQuaternion q;
        CHECK(check_quat(world, fn, "orientation", orientation, &q));
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        if (b->type != PHYS_BODY_KINEMATIC) {
            return fail(world, PHYS_ERR_INVALID_ARG,
                        "%s: body must be PHYS_BODY_KINEMATIC (got %s); use phys_body_set_pose "
                        "to move other bodies",
                        fn, body_type_name(b->type));
        }
        b->target = btTransform(q, to_bt(position));
        b->has_target = true;
        b->kin_linear.setZero();
        b->kin_angular.setZero();
        return PHYS_OK;
    });
}

phys_result phys_body_set_linear_velocity(phys_world* world, phys_body_id body, phys_vec3 velocity) {
    return guarded(world, __func__, [&](const char* fn) {
        return set_velocity(world, fn, body, velocity, false);
    });
}

phys_result phys_body_get_linear_velocity(phys_world* world, phys_body_id body, phys_vec3* out) {
    return guarded(world, __func__, [&](const char* fn) {
        return get_vector(world, fn, body, out, false);
    });
}

phys_result phys_body_set_angular_velocity(phys_world* world, phys_body_id body, phys_vec3 velocity) {
    return guarded(world, __func__, [&](const char* fn) {
        return set_velocity(world, fn, body, velocity, true);
    });
}

phys_result phys_body_get_angular_velocity(phys_world* world, phys_body_id body, phys_vec3* out) {
    return guarded(world, __func__, [&](const char* fn) {
        return get_vector(world, fn, body, out, true);
    });
}

phys_result phys_body_get_velocity_at_point(phys_world* world, phys_body_id body, phys_vec3 point,
                                            phys_vec3* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        CHECK(check_vec3(world, fn, "point", point));
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        const btRigidBody* rb = b->body.get();
        *out = from_bt(rb->getVelocityInLocalPoint(to_bt(point) - rb->getCenterOfMassPosition()));
        return PHYS_OK;
    });
}

phys_result phys_body_apply_force(phys_world* world, phys_body_id body, phys_vec3 force, bool wake) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "force", force));
        return apply_to_body(world, fn, body, wake,
                             [&](btRigidBody* rb) { rb->applyCentralForce(to_bt(force)); });
    });
}

phys_result phys_body_apply_force_at_point(phys_world* world, phys_body_id body, phys_vec3 force,
                                           phys_vec3 point, bool wake) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "force", force));
        CHECK(check_vec3(world, fn, "point", point));
        return apply_to_body(world, fn, body, wake, [&](btRigidBody* rb) {
            rb->applyForce(to_bt(force), to_bt(point) - rb->getCenterOfMassPosition());
        });
    });
}

phys_result phys_body_apply_torque(phys_world* world, phys_body_id body, phys_vec3 torque, bool wake) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "torque", torque));
        return apply_to_body(world, fn, body, wake,
                             [&](btRigidBody* rb) { rb->applyTorque(to_bt(torque)); });
    });
}

phys_result phys_body_apply_impulse(phys_world* world, phys_body_id body, phys_vec3 impulse, bool wake) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "impulse", impulse));
        return apply_to_body(world, fn, body, wake,
                             [&](btRigidBody* rb) { rb->applyCentralImpulse(to_bt(impulse)); });
    });
}

phys_result phys_body_apply_impulse_at_point(phys_world* world, phys_body_id body,
                                             phys_vec3 impulse, phys_vec3 point, bool wake) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "impulse", impulse));
        CHECK(check_vec3(world, fn, "point", point));
        return apply_to_body(world, fn, body, wake, [&](btRigidBody* rb) {
            rb->applyImpulse(to_bt(impulse), to_bt(point) - rb->getCenterOfMassPosition());
        });
    });
}

phys_result phys_body_apply_angular_impulse(phys_world* world, phys_body_id body,
                                            phys_vec3 impulse, bool wake) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "impulse", impulse));
        return apply_to_body(world, fn, body, wake,
                             [&](btRigidBody* rb) { rb->applyTorqueImpulse(to_bt(impulse)); });
    });
}

phys_result phys_body_get_mass_data(phys_world* world, phys_body_id body, phys_mass_data* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        const btRigidBody* rb = b->body.get();
        *out = phys_mass_data{};
        out->center_of_mass = from_bt(rb->getCenterOfMassPosition());
        if (b->type != PHYS_BODY_DYNAMIC) return PHYS_OK;
        out->inv_mass = rb->getInvMass();
        out->mass = out->inv_mass > 0 ? 1.0f / out->inv_mass : 0.0f;
        out->inertia_local = from_bt(rb->getLocalInertia());
        const btMatrix3x3& m = rb->getInvInertiaTensorWorld();
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) out->inv_inertia_world[r * 3 + c] = m[r][c];
        }
        return PHYS_OK;
    });
}

static phys_result set_factor(phys_world* w, const char* fn, phys_body_id id, phys_vec3 f, bool angular) {
    const float c[3] = {f.x, f.y, f.z};
    const char* axis[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
        if (!std::isfinite(c[i]) || c[i] < 0 || c[i] > 1) {
            return fail(w, PHYS_ERR_INVALID_ARG, "%s: factor.%s must be finite and in [0, 1] (got %g)", fn,
                        axis[i], (double)c[i]);
        }
    }
    BodySlot* b = nullptr;
    CHECK(get_body(w, fn, id, &b));
    btRigidBody* rb = b->body.get();
    const btVector3 keep(f.x != 0 ? 1 : 0, f.y != 0 ? 1 : 0, f.z != 0 ? 1 : 0);
    if (angular) {
        rb->setAngularFactor(to_bt(f));
        if (b->type == PHYS_BODY_DYNAMIC) rb->setAngularVelocity(rb->getAngularVelocity() * keep);
    } else {
        rb->setLinearFactor(to_bt(f));
        if (b->type == PHYS_BODY_DYNAMIC) rb->setLinearVelocity(rb->getLinearVelocity() * keep);
    }
    return PHYS_OK;
}

phys_result phys_body_set_linear_factor(phys_world* world, phys_body_id body, phys_vec3 factor) {
    return guarded(world, __func__, [&](const char* fn) {
        return set_factor(world, fn, body, factor, false);
    });
}

phys_result phys_body_set_angular_factor(phys_world* world, phys_body_id body, phys_vec3 factor) {
    return guarded(world, __func__, [&](const char* fn) {
        return set_factor(world, fn, body, factor, true);
    });
}

phys_result phys_body_get_linear_factor(phys_world* world, phys_body_id body, phys_vec3* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        *out = from_bt(b->body->getLinearFactor());
        return PHYS_OK;
    });
}

phys_result phys_body_get_angular_factor(phys_world* world, phys_body_id body, phys_vec3* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        *out = from_bt(b->body->getAngularFactor());
        return PHYS_OK;
    });
}

phys_result phys_body_set_sleep_enabled(phys_world* world, phys_body_id body, bool enabled) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        b->allow_sleep = enabled;
        // Kinematic bodies never sleep; static bodies never move.
        if (b->type != PHYS_BODY_DYNAMIC) return PHYS_OK;
        if (!enabled || b->constraint_count > 0) {
            b->body->forceActivationState(DISABLE_DEACTIVATION);
        } else {
            b->body->forceActivationState(ACTIVE_TAG);
            b->body->setDeactivationTime(0);
        }
        return PHYS_OK;
    });
}

phys_result phys_body_wake(phys_world* world, phys_body_id body) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        if (b->type == PHYS_BODY_DYNAMIC) b->body->activate(true);
        return PHYS_OK;
    });
}

phys_result phys_body_is_awake(phys_world* world, phys_body_id body, bool* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        *out = b->type != PHYS_BODY_STATIC && b->body->isActive();
        return PHYS_OK;
    });
}

phys_result phys_body_set_user_data(phys_world* world, phys_body_id body, void* user_data) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        b->user_data = user_data;
        return PHYS_OK;
    });
}

phys_result phys_body_get_user_data(phys_world* world, phys_body_id body, void** out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        *out = b->user_data;
        return PHYS_OK;
    });
}

// ---- constraints -----------------------------------------------------------------

phys_point_constraint_def phys_default_point_constraint_def(void) {
    phys_point_constraint_def d;
    d.body = phys_body_id{0, 0, 0};
    d.pivot = phys_vec3{0, 0, 0};
    d.max_force = 1.0e6f;
    d.error_reduction = 0.3f;
    return d;
}

phys_result phys_point_constraint_create(phys_world* world, const phys_point_constraint_def* def,
                                         phys_constraint_id* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        CHECK(check_ptr(w, fn, "def", def));
        CHECK(check_ptr(w, fn, "out", out));
        uint32_t body_slot = 0;
        CHECK(lookup(w, fn, "phys_point_constraint_def.body", "body", w->bodies, def->body,
                     &body_slot));
        CHECK(check_vec3(w, fn, "phys_point_constraint_def.pivot", def->pivot));
        CHECK(check_positive(w, fn, "phys_point_constraint_def.max_force", def->max_force));
        if (!std::isfinite(def->error_reduction) || !(def->error_reduction > 0) ||
            def->error_reduction > 1) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_point_constraint_def.error_reduction must be finite and in "
                        "(0, 1] (got %g)",
                        fn, (double)def->error_reduction);
        }
        BodySlot& b = w->bodies[body_slot];
        if (b.type != PHYS_BODY_DYNAMIC) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_point_constraint_def.body must be PHYS_BODY_DYNAMIC (got %s)", fn,
                        body_type_name(b.type));
        }
        const uint32_t slot = reserve_slot(w->constraints, w->free_constraints);
        ConstraintSlot& c = w->constraints[slot];
        btRigidBody* rb = b.body.get();
        const btVector3 local = rb->getCenterOfMassTransform().inverse() * to_bt(def->pivot);
        auto p2p = std::make_unique<btPoint2PointConstraint>(*rb, local);
        p2p->m_setting.m_tau = def->error_reduction;
        p2p->m_setting.m_impulseClamp = def->max_force / 60.0f;  // reset from dt at each step
        w->dynamics->addConstraint(p2p.get(), true);
        c.constraint = std::move(p2p);
        c.body_slot = body_slot;
        c.max_force = def->max_force;
        c.alive = true;
        claim_slot(w->free_constraints, slot);
        ++b.constraint_count;
        rb->forceActivationState(DISABLE_DEACTIVATION);
        *out = make_id<phys_constraint_id>(w, slot, c.generation);
        return PHYS_OK;
    });
}

phys_result phys_point_constraint_set_pivot(phys_world* world, phys_constraint_id constraint,
                                            phys_vec3 pivot) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "pivot", pivot));
        uint32_t slot = 0;
        CHECK(lookup(world, fn, "phys_constraint_id", "constraint", world->constraints, constraint,
                     &slot));
        ConstraintSlot& c = world->constraints[slot];
        c.constraint->setPivotB(to_bt(pivot));
        world->bodies[c.body_slot].body->activate(true);
        return PHYS_OK;
    });
}

phys_result phys_constraint_destroy(phys_world* world, phys_constraint_id constraint) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        uint32_t slot = 0;
        CHECK(lookup(world, fn, "phys_constraint_id", "constraint",
                     world->constraints, constraint, &slot));
        destroy_constraint_slot(world, slot);
        return PHYS_OK;
    });
}

bool phys_constraint_is_valid(const phys_world* world, phys_constraint_id constraint) {
    return world && id_is_live(world, world->constraints, constraint);
}

} // extern "C"
