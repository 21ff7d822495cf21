// phys_query.cpp: queries and grabs of the C API (phys.h): ray casts, and the point constraint
// that holds a body by a pivot for a mouse drag (create, move the pivot, destroy).

#include "phys_internal.hpp"

#include <cmath>

using namespace phys_internal;

namespace phys_internal {

void destroy_constraint_slot(phys_world* w, uint32_t slot) {
    ConstraintSlot& c = w->constraints[slot];
    w->dynamics->removeConstraint(c.constraint.get());
    c.constraint.reset();
    c.alive = false;
    c.generation = next_generation(c.generation);
    release_awake(w->bodies[c.body_slot]);
    w->free_constraints.push_back(slot);
}

} // namespace phys_internal

extern "C" {

// ---- queries ------------------------------------------------------------------

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
        hold_awake(b);
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
