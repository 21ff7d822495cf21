// phys_body.cpp: bodies of the C API (phys.h): create and destroy, type and shape, poses and
// kinematic targets, velocities, forces and impulses, mass data, axis factors, sleep, user data.

#include "phys_internal.hpp"

#include <cmath>
#include <cstring>

using namespace phys_internal;

namespace phys_internal {

const char* body_type_name(phys_body_type t) {
    switch (t) {
    case PHYS_BODY_STATIC: return "PHYS_BODY_STATIC";
    case PHYS_BODY_KINEMATIC: return "PHYS_BODY_KINEMATIC";
    case PHYS_BODY_DYNAMIC: return "PHYS_BODY_DYNAMIC";
    }
    return "unknown";
}

void hold_awake(BodySlot& b) {
    if (!b.alive || b.type != PHYS_BODY_DYNAMIC) return;
    ++b.awake_holds;
    b.body->forceActivationState(DISABLE_DEACTIVATION);
}

void release_awake(BodySlot& b) {
    if (!b.alive || b.type != PHYS_BODY_DYNAMIC) return;
    if (b.awake_holds > 0) --b.awake_holds;
    if (b.awake_holds == 0 && b.allow_sleep) {
        b.body->forceActivationState(ACTIVE_TAG);
        b.body->setDeactivationTime(0);
    }
}

} // namespace phys_internal

static phys_result get_body(phys_world* w, const char* fn, phys_body_id id, BodySlot** out) {
    uint32_t slot = 0;
    CHECK(lookup(w, fn, "phys_body_id", "body", w->bodies, id, &slot));
    *out = &w->bodies[slot];
    return PHYS_OK;
}

// The shared path of the getters: checks `out` and the id, then `*out = read(slot)`.
template <class T, class F>
static phys_result read_body(phys_world* w, const char* func, phys_body_id id, T* out, F&& read) {
    return guarded(w, func, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(w, fn, "out", out));
        BodySlot* b = nullptr;
        CHECK(get_body(w, fn, id, &b));
        *out = read(*b);
        return PHYS_OK;
    });
}

// Shared path of the force/impulse calls: checks, then `apply` on an awake
// dynamic body.
template <class F>
static phys_result apply_to_body(phys_world* w, const char* fn, phys_body_id id, bool wake, F&& apply) {
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

static phys_result set_velocity(phys_world* w, const char* fn, phys_body_id id, phys_vec3 v,
                                bool angular) {
    CHECK(check_speed(w, fn, "velocity", v, angular));
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

extern "C" {

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
        // A C caller may store any int in the enum: read it as one (loading an enum object
        // that holds no enumerator is undefined in C++).
        int type_value;
        std::memcpy(&type_value, &d.type, sizeof type_value);
        if (type_value != PHYS_BODY_STATIC && type_value != PHYS_BODY_KINEMATIC &&
            type_value != PHYS_BODY_DYNAMIC) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_body_def.type must be PHYS_BODY_STATIC, PHYS_BODY_KINEMATIC or "
                        "PHYS_BODY_DYNAMIC (got %d)",
                        fn, type_value);
        }
        uint32_t shape_slot = 0;
        CHECK(lookup(w, fn, "phys_body_def.shape", "shape", w->shapes, d.shape, &shape_slot));
        CHECK(check_vec3(w, fn, "phys_body_def.position", d.position));
        btQuaternion q;
        CHECK(check_quat(w, fn, "phys_body_def.orientation", d.orientation, &q));
        CHECK(check_speed(w, fn, "phys_body_def.linear_velocity", d.linear_velocity, false));
        CHECK(check_speed(w, fn, "phys_body_def.angular_velocity", d.angular_velocity, true));
        if (!std::isfinite(d.mass) || d.mass < 0) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_body_def.mass must be >= 0 and finite (got %g)", fn,
                        (double)d.mass);
        }
        if (d.mass > 0 && d.mass < PHYS_MIN_MASS) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_body_def.mass must be 0 (from the density) or at least PHYS_MIN_MASS = %g kg "
                        "(got %g)",
                        fn, (double)PHYS_MIN_MASS, (double)d.mass);
        }
        if (d.mass > PHYS_MAX_MASS) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_body_def.mass must be at most PHYS_MAX_MASS = %g kg (got %g): "
                        "Bullet lets heavier bodies fall through static ones",
                        fn, (double)PHYS_MAX_MASS, (double)d.mass);
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
                if (!std::isfinite(mass) || !(mass >= PHYS_MIN_MASS) || mass > PHYS_MAX_MASS) {
                    return fail(w, PHYS_ERR_INVALID_ARG,
                                "%s: phys_body_def.density %g times the %s volume %g m^3 gives "
                                "mass %g kg; it must be in [PHYS_MIN_MASS = %g, PHYS_MAX_MASS = %g kg]",
                                fn, (double)d.density, shape_name(st), (double)shape.desc.volume,
                                (double)mass, (double)PHYS_MIN_MASS, (double)PHYS_MAX_MASS);
                }
            }
            if (st == PHYS_SHAPE_COMPOUND) {
                inertia = shape.inertia_per_kg * mass;  // Bullet's own is a bounding-box guess
            } else {
                shape.shape->calculateLocalInertia(mass, inertia);
            }
            // Bullet inverts the inertia in floats (0 stays 0: no turning about that axis).
            for (int k = 0; k < 3; ++k) {
                if (!std::isfinite(inertia[k]) || inertia[k] < 0 ||
                    (inertia[k] > 0 && !std::isfinite(1.0f / inertia[k]))) {
                    return fail(w, PHYS_ERR_INVALID_ARG,
                                "%s: a %s of mass %g kg has a moment of inertia of %g kg m^2 about its %c "
                                "axis, too small to invert in a float: make the shape larger",
                                fn, shape_name(st), (double)mass, (double)inertia[k], "xyz"[k]);
                }
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
        b.awake_holds = 0;
        b.user_data = d.user_data;
        b.kin_linear = d.type == PHYS_BODY_KINEMATIC ? to_bt(d.linear_velocity) : btVector3(0, 0, 0);
        b.kin_angular = d.type == PHYS_BODY_KINEMATIC ? to_bt(d.angular_velocity) : btVector3(0, 0, 0);
        b.held_force = btVector3(0, 0, 0);
        b.held_torque = btVector3(0, 0, 0);
        b.speed_held = false;
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
        destroy_body_joints(w, slot);
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
    return read_body(world, __func__, body, out, [](const BodySlot& b) {
        return b.type;
    });
}

phys_result phys_body_get_shape(phys_world* world, phys_body_id body, phys_shape_desc* out) {
    return read_body(world, __func__, body, out, [&](const BodySlot& b) {
        return world->shapes[b.shape_slot].desc;
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
    return read_body(world, __func__, body, out, [](const BodySlot& b) {
        return from_bt(b.body->getLinearVelocity());
    });
}

phys_result phys_body_get_extent(phys_world* world, phys_body_id body, phys_vec3* out) {
    return read_body(world, __func__, body, out, [](const BodySlot& b) {
        btVector3 lo, hi;
        b.body->getCollisionShape()->getAabb(b.body->getWorldTransform(), lo, hi);
        return from_bt(hi - lo);
    });
}

phys_result phys_body_set_angular_velocity(phys_world* world, phys_body_id body, phys_vec3 velocity) {
    return guarded(world, __func__, [&](const char* fn) {
        return set_velocity(world, fn, body, velocity, true);
    });
}

phys_result phys_body_get_angular_velocity(phys_world* world, phys_body_id body, phys_vec3* out) {
    return read_body(world, __func__, body, out, [](const BodySlot& b) {
        return from_bt(b.body->getAngularVelocity());
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

phys_result phys_body_set_held_force(phys_world* world, phys_body_id body, phys_vec3 force, phys_vec3 torque) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_vec3(world, fn, "force", force));
        CHECK(check_vec3(world, fn, "torque", torque));
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        b->held_force = to_bt(force);
        b->held_torque = to_bt(torque);
        if (b->type == PHYS_BODY_DYNAMIC && !(b->held_force.isZero() && b->held_torque.isZero()))
            b->body->activate(true);
        return PHYS_OK;
    });
}

phys_result phys_body_get_held_force(phys_world* world, phys_body_id body, phys_vec3* out_force,
                                     phys_vec3* out_torque) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        if (out_force) *out_force = from_bt(b->held_force);
        if (out_torque) *out_torque = from_bt(b->held_torque);
        return PHYS_OK;
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
    return read_body(world, __func__, body, out, [](const BodySlot& b) {
        return from_bt(b.body->getLinearFactor());
    });
}

phys_result phys_body_get_angular_factor(phys_world* world, phys_body_id body, phys_vec3* out) {
    return read_body(world, __func__, body, out, [](const BodySlot& b) {
        return from_bt(b.body->getAngularFactor());
    });
}

phys_result phys_body_set_sleep_enabled(phys_world* world, phys_body_id body, bool enabled) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        BodySlot* b = nullptr;
        CHECK(get_body(world, fn, body, &b));
        b->allow_sleep = enabled;
        // Kinematic bodies never sleep; static bodies never move.
        if (b->type != PHYS_BODY_DYNAMIC) return PHYS_OK;
        if (!enabled || b->awake_holds > 0) {
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
    return read_body(world, __func__, body, out, [](const BodySlot& b) {
        return b.type != PHYS_BODY_STATIC && b.body->isActive();
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
    return read_body(world, __func__, body, out, [](const BodySlot& b) {
        return b.user_data;
    });
}

} // extern "C"
