// phys_world.cpp: the world of the C API (phys.h): create, destroy, step, gravity, the last
// error and result names, and fail() and the input checks that every part of the wrapper uses.

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

phys_result check_speed(phys_world* w, const char* fn, const char* field, phys_vec3 v, bool angular) {
    CHECK(check_vec3(w, fn, field, v));
    const double len = length_of(v);
    const double most = angular ? PHYS_MAX_ANGULAR_SPEED : PHYS_MAX_SPEED;
    if (len <= most) return PHYS_OK;
    return fail(w, PHYS_ERR_INVALID_ARG, "%s: %s must be at most %s = %g %s in size (got %g)", fn, field,
                angular ? "PHYS_MAX_ANGULAR_SPEED" : "PHYS_MAX_SPEED", most, angular ? "rad/s" : "m/s", len);
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

} // namespace phys_internal

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
    d.split_impulse_depth = 0.04f;
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
    const double glen = length_of(g[0], g[1], g[2]);
    if (glen > PHYS_MAX_GRAVITY) {
        std::snprintf(msg, sizeof msg,
                      "phys_world_create: phys_world_def.gravity must be at most PHYS_MAX_GRAVITY = %g m/s^2 in size "
                      "(got %g)", (double)PHYS_MAX_GRAVITY, glen);
        return reject(msg);
    }
    if (def->solver_iterations < 1 || def->solver_iterations > 1000) {
        std::snprintf(msg, sizeof msg,
                      "phys_world_create: phys_world_def.solver_iterations must be in [1, 1000] "
                      "(got %d)",
                      def->solver_iterations);
        return reject(msg);
    }
    if (!std::isfinite(def->split_impulse_depth) || def->split_impulse_depth < 0 ||
        def->split_impulse_depth > 1) {
        std::snprintf(msg, sizeof msg,
                      "phys_world_create: phys_world_def.split_impulse_depth must be finite and in "
                      "[0, 1] m (got %g)",
                      (double)def->split_impulse_depth);
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
        // Overlaps deeper than split_impulse_depth are pushed apart without velocity.
        w->dynamics->getSolverInfo().m_splitImpulse = 1;
        w->dynamics->getSolverInfo().m_splitImpulsePenetrationThreshold = -def->split_impulse_depth;
        // The world side of joints to the world: static (mass 0), no shape, at the origin.
        btRigidBody::btRigidBodyConstructionInfo fixed_info(0, nullptr, nullptr);
        w->fixed = std::make_unique<btRigidBody>(fixed_info);
        w->fixed->setUserIndex(-1);
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

// A warning through the log, the first time a body was held to the speed limits.
static void warn_once(phys_world* w, BodySlot& b, const char* fmt, ...) PRINTF_LIKE(3, 4);
static void warn_once(phys_world* w, BodySlot& b, const char* fmt, ...) {
    if (b.speed_held || !w->log) return;
    b.speed_held = true;
    char msg[320];
    va_list args;
    va_start(args, fmt);
    format_message(msg, sizeof msg, fmt, args);
    va_end(args);
    w->log(w->log_user, PHYS_LOG_WARNING, msg);
}

// Dynamic bodies faster than PHYS_MAX_SPEED / PHYS_MAX_ANGULAR_SPEED slowed to them (an impulse or
// a huge force or gravity): told once per body through the log.
static void hold_speeds(phys_world* w) {
    for (uint32_t i = 0; i < w->bodies.size(); ++i) {
        BodySlot& b = w->bodies[i];
        if (!b.alive || b.type != PHYS_BODY_DYNAMIC) continue;
        btRigidBody* rb = b.body.get();
        const btVector3 v = rb->getLinearVelocity(), a = rb->getAngularVelocity();
        const double lv = length_of(v), la = length_of(a);
        const bool fast = !(lv <= PHYS_MAX_SPEED), spin = !(la <= PHYS_MAX_ANGULAR_SPEED);
        if (!fast && !spin) continue;
        // A velocity that is no longer finite cannot be scaled: the body stops.
        if (fast) rb->setLinearVelocity(std::isfinite(lv) ? v * (btScalar)(PHYS_MAX_SPEED / lv) : btVector3(0, 0, 0));
        if (spin) rb->setAngularVelocity(std::isfinite(la) ? a * (btScalar)(PHYS_MAX_ANGULAR_SPEED / la) : btVector3(0, 0, 0));
        warn_once(w, b, "phys_world_step: body %u moved at %g m/s and turned at %g rad/s: held to PHYS_MAX_SPEED = %g "
                  "m/s and PHYS_MAX_ANGULAR_SPEED = %g rad/s (a huge force, impulse or gravity; said once per body)",
                  (unsigned)(i + 1), lv, la, (double)PHYS_MAX_SPEED, (double)PHYS_MAX_ANGULAR_SPEED);
    }
}

// The held forces (phys_body_set_held_force) join the step's one-step forces; then a force or
// torque that would change a body's speed by more than PHYS_MAX_SPEED (or its turning by more than
// PHYS_MAX_ANGULAR_SPEED) in this step is scaled down to that before Bullet integrates it: Bullet
// would put the whole change into the position in floats (3e38 N on a milligram is no number), and
// the speeds are held only between steps.
static void add_held_forces(phys_world* w, float dt) {
    for (uint32_t i = 0; i < w->bodies.size(); ++i) {
        BodySlot& b = w->bodies[i];
        if (!b.alive || b.type != PHYS_BODY_DYNAMIC) continue;
        btRigidBody* rb = b.body.get();
        if (!b.held_force.isZero() || !b.held_torque.isZero()) {
            rb->activate(true);
            rb->applyCentralForce(b.held_force);
            rb->applyTorque(b.held_torque);
        }
        btVector3 f = rb->getTotalForce(), t = rb->getTotalTorque();
        const btVector3 dw = rb->getInvInertiaTensorWorld() * t;  // may overflow: then not finite
        const double dv = length_of(f) * rb->getInvMass() * dt, dom = length_of(dw) * dt;
        const bool cut_f = !(dv <= PHYS_MAX_SPEED), cut_t = !(dom <= PHYS_MAX_ANGULAR_SPEED);
        if (!cut_f && !cut_t) continue;
        // Scale by what the limit allows (from the torque's own size where its product overflowed).
        if (cut_f) f *= (btScalar)(std::isfinite(dv) && dv > 0 ? PHYS_MAX_SPEED / dv : 0.0);
        if (cut_t) {
            const double per = std::isfinite(dom) && dom > 0 ? PHYS_MAX_ANGULAR_SPEED / dom : 0.0;
            t *= (btScalar)(std::isfinite(length_of(t)) ? per : 0.0);
        }
        rb->clearForces();
        rb->applyCentralForce(f);
        rb->applyTorque(t);
        warn_once(w, b, "phys_world_step: the force on body %u would change its speed by %g in one step: scaled to "
                  "PHYS_MAX_SPEED = %g m/s and PHYS_MAX_ANGULAR_SPEED = %g rad/s (said once per body)",
                  (unsigned)(i + 1), cut_f ? dv : dom, (double)PHYS_MAX_SPEED, (double)PHYS_MAX_ANGULAR_SPEED);
    }
}

phys_result phys_world_step(phys_world* world, float dt) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        if (!std::isfinite(dt) || dt < 1e-7f || dt > 10.0f) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: dt must be finite and in [1e-07, 10] s (got %g)", fn, (double)dt);
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
        hold_speeds(w);
        add_held_forces(w, dt);
        for (ConstraintSlot& c : w->constraints) {
            if (c.alive) c.constraint->m_setting.m_impulseClamp = c.max_force * dt;
        }
        prepare_joints(w, dt);
        // maxSubSteps = 0: Bullet's variable-step path, exactly one step of dt.
        w->dynamics->stepSimulation(dt, 0, dt);
        hold_speeds(w);
        w->last_dt = dt;
        for (BodySlot& b : w->bodies) b.has_target = false;
        sum_step_contacts(w);
        return PHYS_OK;
    });
}

phys_result phys_world_set_gravity(phys_world* world, phys_vec3 gravity) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "gravity", gravity));
        const double glen = length_of(gravity);
        if (glen > PHYS_MAX_GRAVITY) {
            return fail(world, PHYS_ERR_INVALID_ARG,
                        "%s: gravity must be at most PHYS_MAX_GRAVITY = %g m/s^2 in size (got %g)", fn,
                        (double)PHYS_MAX_GRAVITY, glen);
        }
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

} // extern "C"
