// phys_joint.cpp: joints of the C API (phys.h): hinge, slider, fixed and point joints between two
// bodies or a body and the world; motors, limits, hinge angle, slider position, applied impulses.
//
// Every joint is a two-body Bullet constraint: Bullet's A is body_a, Bullet's B is body_b or,
// for the world, phys_world::fixed. Frames are built from the world-space def at creation
// (hinge: local z is the axis; slider: local x is the axis), so the measures start at 0.
// Bullet's own sign conventions were checked against ours (tests/test_phys_joints.c):
// - btHingeConstraint::getHingeAngle (useReferenceFrameA = false) is the rotation of A
//   relative to B about the axis, and its motor drives that angle's rate: our convention.
// - btSliderConstraint (useLinearReferenceFrameA = false) measures (pivot A - pivot B) along
//   A's x axis: our position. Its limits bound that, its motor drives its rate.
// Bullet's hinge limit bounces by default: its relaxation factor (1) is used as a restitution
// at the stop. A 10 kg trapdoor hitting its stop at 5 rad/s then rebounds 0.02 rad and its
// pivot stretches 22 mm, against 0.0006 rad and 6.5 mm with 0, which the wrapper passes.

#include "phys_internal.hpp"

#include <cmath>
#include <cstdio>

using namespace phys_internal;

namespace {

constexpr float kPiF = (float)kPi;
constexpr float kMinAxisLength = 1e-6f;
// Hinge motor impulses are set from the torque at every step (prepare_joints); this dt is
// only what they hold before the first step.
constexpr float kFirstDt = 1.0f / 60.0f;

const char* joint_type_name(phys_joint_type t) {
    switch (t) {
    case PHYS_JOINT_HINGE: return "PHYS_JOINT_HINGE";
    case PHYS_JOINT_SLIDER: return "PHYS_JOINT_SLIDER";
    case PHYS_JOINT_FIXED: return "PHYS_JOINT_FIXED";
    case PHYS_JOINT_POINT: return "PHYS_JOINT_POINT";
    }
    return "unknown";
}

// The two bodies of a joint, checked.
struct JointBodies {
    uint32_t a = 0;
    uint32_t b = kWorldSlot;
    btRigidBody* rb_a = nullptr;
    btRigidBody* rb_b = nullptr;
};

bool is_null(phys_body_id id) { return id.index1 == 0 && id.world0 == 0 && id.generation == 0; }

// body_a: a live dynamic body; body_b: another live body, or null for the world.
phys_result check_bodies(phys_world* w, const char* fn, const char* def, phys_body_id a,
                         phys_body_id b, JointBodies* out) {
    char label[96];
    std::snprintf(label, sizeof label, "%s.body_a", def);
    CHECK(lookup(w, fn, label, "body", w->bodies, a, &out->a));
    const BodySlot& body_a = w->bodies[out->a];
    if (body_a.type != PHYS_BODY_DYNAMIC) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: %s.body_a must be PHYS_BODY_DYNAMIC (got %s): a joint moves body_a; "
                    "put a static or kinematic body in body_b, or leave body_b null for the world",
                    fn, def, body_type_name(body_a.type));
    }
    out->rb_a = body_a.body.get();
    if (is_null(b)) {
        out->b = kWorldSlot;
        out->rb_b = w->fixed.get();
        return PHYS_OK;
    }
    std::snprintf(label, sizeof label, "%s.body_b", def);
    CHECK(lookup(w, fn, label, "body", w->bodies, b, &out->b));
    if (out->b == out->a) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: %s.body_a and body_b are the same body (index1 %u): a joint needs two "
                    "bodies, or the null id in body_b for the world",
                    fn, def, (unsigned)a.index1);
    }
    out->rb_b = w->bodies[out->b].body.get();
    return PHYS_OK;
}

// A direction: finite, not (near) zero; *out is it normalised.
phys_result check_axis(phys_world* w, const char* fn, const char* field, phys_vec3 v,
                       btVector3* out) {
    CHECK(check_vec3(w, fn, field, v));
    const double len = length_of(v);
    if (!(len >= kMinAxisLength)) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: %s must be a direction of length >= %g (got %g, %g, %g)", fn, field,
                    (double)kMinAxisLength, (double)v.x, (double)v.y, (double)v.z);
    }
    *out = btVector3((float)(v.x / len), (float)(v.y / len), (float)(v.z / len));
    return PHYS_OK;
}

// Limits of a hinge (rad, [-π, π]) or slider (m, finite), lower <= upper.
phys_result check_limits(phys_world* w, const char* fn, phys_joint_type type, const char* lo_name,
                         float lo, const char* hi_name, float hi) {
    if (type == PHYS_JOINT_HINGE) {
        CHECK(check_range(w, fn, lo_name, lo, -kPiF, kPiF));
        CHECK(check_range(w, fn, hi_name, hi, -kPiF, kPiF));
    } else {
        CHECK(check_finite(w, fn, lo_name, lo));
        CHECK(check_finite(w, fn, hi_name, hi));
    }
    if (lo > hi) {
        return fail(w, PHYS_ERR_INVALID_ARG, "%s: %s (%g) must be <= %s (%g)", fn, lo_name,
                    (double)lo, hi_name, (double)hi);
    }
    return PHYS_OK;
}

phys_result check_motor(phys_world* w, const char* fn, const char* speed_name, float speed,
                        const char* max_name, float max) {
    CHECK(check_finite(w, fn, speed_name, speed));
    if (!std::isfinite(max) || max < 0) {
        return fail(w, PHYS_ERR_INVALID_ARG, "%s: %s must be finite and >= 0 (got %g)", fn,
                    max_name, (double)max);
    }
    return PHYS_OK;
}

// A world frame at `origin` whose column `column` is the unit `axis`; right-handed.
btTransform frame_along(const btVector3& origin, const btVector3& axis, int column) {
    btVector3 p, q;
    btPlaneSpace1(axis, p, q);  // q = axis × p
    // Columns (p, q, axis) for z = axis; (axis, p, q) for x = axis.
    const btVector3 c0 = column == 2 ? p : axis;
    const btVector3 c1 = column == 2 ? q : p;
    const btVector3 c2 = column == 2 ? axis : q;
    btMatrix3x3 m(c0.x(), c1.x(), c2.x(), c0.y(), c1.y(), c2.y(), c0.z(), c1.z(), c2.z());
    return btTransform(m, origin);
}

void apply_limits(JointSlot& j) {
    if (j.type == PHYS_JOINT_HINGE) {
        auto* h = static_cast<btHingeConstraint*>(j.constraint.get());
        // softness and bias are Bullet's defaults (unused by its hinge); relaxation 0: no bounce.
        if (j.limit) {
            h->setLimit(j.lower, j.upper, 0.9f, 0.3f, 0.0f);
        } else {
            h->setLimit(1.0f, -1.0f);  // lower > upper: free
        }
    } else if (j.type == PHYS_JOINT_SLIDER) {
        auto* s = static_cast<btSliderConstraint*>(j.constraint.get());
        s->setLowerLinLimit(j.limit ? j.lower : 1.0f);  // lower > upper: free
        s->setUpperLinLimit(j.limit ? j.upper : -1.0f);
    }
}

void apply_motor(JointSlot& j, float dt) {
    if (j.type == PHYS_JOINT_HINGE) {
        auto* h = static_cast<btHingeConstraint*>(j.constraint.get());
        h->enableAngularMotor(j.motor, j.motor_speed, j.max_motor * dt);
    } else if (j.type == PHYS_JOINT_SLIDER) {
        auto* s = static_cast<btSliderConstraint*>(j.constraint.get());
        s->setPoweredLinMotor(j.motor);
        s->setTargetLinMotorVelocity(j.motor_speed);
        s->setMaxLinMotorForce(j.max_motor);  // Bullet turns it into an impulse itself
    }
}

void wake(phys_world* w, const JointSlot& j) {
    BodySlot& a = w->bodies[j.body_a];
    if (a.alive) a.body->activate(true);
    if (j.body_b == kWorldSlot) return;
    BodySlot& b = w->bodies[j.body_b];
    if (b.alive && b.type == PHYS_BODY_DYNAMIC) b.body->activate(true);
}

// Take or let go of the joint's hold on its dynamic bodies' sleep.
void set_holds(phys_world* w, JointSlot& j, bool want) {
    if (want == j.holds_awake) return;
    j.holds_awake = want;
    BodySlot* bodies[2] = {&w->bodies[j.body_a],
                           j.body_b == kWorldSlot ? nullptr : &w->bodies[j.body_b]};
    for (BodySlot* b : bodies) {
        if (!b) continue;
        if (want) {
            hold_awake(*b);
        } else {
            release_awake(*b);
        }
    }
}

// Keep the joint's dynamic bodies awake while it has a motor on or a kinematic body_b
// (Bullet would otherwise let body_a sleep while the motor or the kinematic body pushes).
void update_holds(phys_world* w, JointSlot& j) {
    const bool kinematic_b =
        j.body_b != kWorldSlot && w->bodies[j.body_b].type == PHYS_BODY_KINEMATIC;
    set_holds(w, j, j.motor || kinematic_b);
}

void destroy_joint_slot(phys_world* w, uint32_t slot) {
    JointSlot& j = w->joints[slot];
    w->dynamics->removeConstraint(j.constraint.get());
    set_holds(w, j, false);
    wake(w, j);
    j.constraint.reset();
    j.feedback.reset();
    j.alive = false;
    j.generation = next_generation(j.generation);
    w->free_joints.push_back(slot);
}

// The common end of the create calls: take a slot, add the constraint to the world.
struct JointSettings {
    phys_joint_type type;
    bool collide_connected;
    bool limit = false;
    float lower = 0, upper = 0;
    bool motor = false;
    float motor_speed = 0, max_motor = 0;
};

phys_result add_joint(phys_world* w, const JointBodies& jb, const JointSettings& s,
                      std::unique_ptr<btTypedConstraint> constraint, phys_joint_id* out) {
    auto feedback = std::make_unique<btJointFeedback>();
    feedback->m_appliedForceBodyA.setZero();
    feedback->m_appliedTorqueBodyA.setZero();
    feedback->m_appliedForceBodyB.setZero();
    feedback->m_appliedTorqueBodyB.setZero();
    const uint32_t slot = reserve_slot(w->joints, w->free_joints);
    JointSlot& j = w->joints[slot];
    j.type = s.type;
    j.body_a = jb.a;
    j.body_b = jb.b;
    j.holds_awake = false;
    j.limit = s.limit;
    j.lower = s.lower;
    j.upper = s.upper;
    j.motor = s.motor;
    j.motor_speed = s.motor_speed;
    j.max_motor = s.max_motor;
    j.feedback = std::move(feedback);
    j.constraint = std::move(constraint);
    j.constraint->setJointFeedback(j.feedback.get());
    apply_limits(j);
    apply_motor(j, w->last_dt > 0 ? w->last_dt : kFirstDt);

    const bool to_body = jb.b != kWorldSlot;
    const bool no_collision = to_body && !s.collide_connected;
    w->dynamics->addConstraint(j.constraint.get(), no_collision);
    if (no_collision) {
        // Bullet checks the bodies' constraint list only before it makes a contact
        // algorithm: drop one that exists already, or its contacts would live on.
        btBroadphaseProxy* pa = jb.rb_a->getBroadphaseHandle();
        btBroadphaseProxy* pb = jb.rb_b->getBroadphaseHandle();
        btOverlappingPairCache* cache = w->dynamics->getPairCache();
        if (pa && pb) {
            if (btBroadphasePair* pair = cache->findPair(pa, pb)) {
                cache->cleanOverlappingPair(*pair, w->dispatcher.get());
            }
        }
    }
    j.alive = true;
    claim_slot(w->free_joints, slot);
    update_holds(w, j);
    wake(w, j);
    *out = make_id<phys_joint_id>(w, slot, j.generation);
    return PHYS_OK;
}

phys_result get_joint(phys_world* w, const char* fn, phys_joint_id id, JointSlot** out) {
    uint32_t slot = 0;
    CHECK(lookup(w, fn, "phys_joint_id", "joint", w->joints, id, &slot));
    *out = &w->joints[slot];
    return PHYS_OK;
}

// Hinge and slider calls refuse other types, naming the one given.
phys_result need_type(phys_world* w, const char* fn, const JointSlot& j, bool hinge, bool slider,
                      const char* what) {
    if ((hinge && j.type == PHYS_JOINT_HINGE) || (slider && j.type == PHYS_JOINT_SLIDER)) {
        return PHYS_OK;
    }
    return fail(w, PHYS_ERR_INVALID_ARG, "%s: the joint is a %s; %s", fn, joint_type_name(j.type),
                what);
}

} // namespace

namespace phys_internal {

void destroy_body_joints(phys_world* w, uint32_t body_slot) {
    for (uint32_t i = 0; i < w->joints.size(); ++i) {
        const JointSlot& j = w->joints[i];
        if (j.alive && (j.body_a == body_slot || j.body_b == body_slot)) destroy_joint_slot(w, i);
    }
}

void prepare_joints(phys_world* w, float dt) {
    for (JointSlot& j : w->joints) {
        if (j.alive && j.motor && j.type == PHYS_JOINT_HINGE) {
            static_cast<btHingeConstraint*>(j.constraint.get())->setMaxMotorImpulse(j.max_motor * dt);
        }
    }
}

} // namespace phys_internal

extern "C" {

// ---- defaults ------------------------------------------------------------------

phys_hinge_joint_def phys_default_hinge_joint_def(void) {
    phys_hinge_joint_def d;
    d.body_a = phys_body_id{0, 0, 0};
    d.body_b = phys_body_id{0, 0, 0};
    d.pivot = phys_vec3{0, 0, 0};
    d.axis = phys_vec3{0, 0, 1};
    d.enable_limit = false;
    d.lower_angle = 0;
    d.upper_angle = 0;
    d.enable_motor = false;
    d.motor_speed = 0;
    d.max_motor_torque = 0;
    d.collide_connected = false;
    return d;
}

phys_slider_joint_def phys_default_slider_joint_def(void) {
    phys_slider_joint_def d;
    d.body_a = phys_body_id{0, 0, 0};
    d.body_b = phys_body_id{0, 0, 0};
    d.anchor = phys_vec3{0, 0, 0};
    d.axis = phys_vec3{1, 0, 0};
    d.enable_limit = false;
    d.lower_translation = 0;
    d.upper_translation = 0;
    d.enable_motor = false;
    d.motor_speed = 0;
    d.max_motor_force = 0;
    d.collide_connected = false;
    return d;
}

phys_fixed_joint_def phys_default_fixed_joint_def(void) {
    phys_fixed_joint_def d;
    d.body_a = phys_body_id{0, 0, 0};
    d.body_b = phys_body_id{0, 0, 0};
    d.collide_connected = false;
    return d;
}

phys_point_joint_def phys_default_point_joint_def(void) {
    phys_point_joint_def d;
    d.body_a = phys_body_id{0, 0, 0};
    d.body_b = phys_body_id{0, 0, 0};
    d.pivot = phys_vec3{0, 0, 0};
    d.collide_connected = false;
    return d;
}

// ---- creation --------------------------------------------------------------------

phys_result phys_joint_create_hinge(phys_world* world, const phys_hinge_joint_def* def,
                                    phys_joint_id* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        CHECK(check_ptr(w, fn, "def", def));
        CHECK(check_ptr(w, fn, "out", out));
        JointBodies jb;
        CHECK(check_bodies(w, fn, "phys_hinge_joint_def", def->body_a, def->body_b, &jb));
        CHECK(check_vec3(w, fn, "phys_hinge_joint_def.pivot", def->pivot));
        btVector3 axis;
        CHECK(check_axis(w, fn, "phys_hinge_joint_def.axis", def->axis, &axis));
        CHECK(check_limits(w, fn, PHYS_JOINT_HINGE, "phys_hinge_joint_def.lower_angle",
                           def->lower_angle, "phys_hinge_joint_def.upper_angle", def->upper_angle));
        CHECK(check_motor(w, fn, "phys_hinge_joint_def.motor_speed", def->motor_speed,
                          "phys_hinge_joint_def.max_motor_torque", def->max_motor_torque));
        const btTransform frame = frame_along(to_bt(def->pivot), axis, 2);
        auto hinge = std::make_unique<btHingeConstraint>(
            *jb.rb_a, *jb.rb_b, jb.rb_a->getCenterOfMassTransform().inverse() * frame,
            jb.rb_b->getCenterOfMassTransform().inverse() * frame, false);
        JointSettings s{PHYS_JOINT_HINGE, def->collide_connected};
        s.limit = def->enable_limit;
        s.lower = def->lower_angle;
        s.upper = def->upper_angle;
        s.motor = def->enable_motor;
        s.motor_speed = def->motor_speed;
        s.max_motor = def->max_motor_torque;
        return add_joint(w, jb, s, std::move(hinge), out);
    });
}

phys_result phys_joint_create_slider(phys_world* world, const phys_slider_joint_def* def,
                                     phys_joint_id* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        CHECK(check_ptr(w, fn, "def", def));
        CHECK(check_ptr(w, fn, "out", out));
        JointBodies jb;
        CHECK(check_bodies(w, fn, "phys_slider_joint_def", def->body_a, def->body_b, &jb));
        CHECK(check_vec3(w, fn, "phys_slider_joint_def.anchor", def->anchor));
        btVector3 axis;
        CHECK(check_axis(w, fn, "phys_slider_joint_def.axis", def->axis, &axis));
        CHECK(check_limits(w, fn, PHYS_JOINT_SLIDER, "phys_slider_joint_def.lower_translation",
                           def->lower_translation, "phys_slider_joint_def.upper_translation",
                           def->upper_translation));
        CHECK(check_motor(w, fn, "phys_slider_joint_def.motor_speed", def->motor_speed,
                          "phys_slider_joint_def.max_motor_force", def->max_motor_force));
        const btTransform frame = frame_along(to_bt(def->anchor), axis, 0);
        auto slider = std::make_unique<btSliderConstraint>(
            *jb.rb_a, *jb.rb_b, jb.rb_a->getCenterOfMassTransform().inverse() * frame,
            jb.rb_b->getCenterOfMassTransform().inverse() * frame, false);
        // Bullet's defaults lock the rotation about the axis (angular limits 0, 0): kept.
        JointSettings s{PHYS_JOINT_SLIDER, def->collide_connected};
        s.limit = def->enable_limit;
        s.lower = def->lower_translation;
        s.upper = def->upper_translation;
        s.motor = def->enable_motor;
        s.motor_speed = def->motor_speed;
        s.max_motor = def->max_motor_force;
        return add_joint(w, jb, s, std::move(slider), out);
    });
}

phys_result phys_joint_create_fixed(phys_world* world, const phys_fixed_joint_def* def,
                                    phys_joint_id* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        CHECK(check_ptr(w, fn, "def", def));
        CHECK(check_ptr(w, fn, "out", out));
        JointBodies jb;
        CHECK(check_bodies(w, fn, "phys_fixed_joint_def", def->body_a, def->body_b, &jb));
        // The joint frame is body_a's own: identity in A, A's pose seen from B.
        const btTransform a = jb.rb_a->getCenterOfMassTransform();
        auto fixed = std::make_unique<btFixedConstraint>(
            *jb.rb_a, *jb.rb_b, btTransform::getIdentity(),
            jb.rb_b->getCenterOfMassTransform().inverse() * a);
        JointSettings s{PHYS_JOINT_FIXED, def->collide_connected};
        return add_joint(w, jb, s, std::move(fixed), out);
    });
}

phys_result phys_joint_create_point(phys_world* world, const phys_point_joint_def* def,
                                    phys_joint_id* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        CHECK(check_ptr(w, fn, "def", def));
        CHECK(check_ptr(w, fn, "out", out));
        JointBodies jb;
        CHECK(check_bodies(w, fn, "phys_point_joint_def", def->body_a, def->body_b, &jb));
        CHECK(check_vec3(w, fn, "phys_point_joint_def.pivot", def->pivot));
        const btVector3 pivot = to_bt(def->pivot);
        auto point = std::make_unique<btPoint2PointConstraint>(
            *jb.rb_a, *jb.rb_b, jb.rb_a->getCenterOfMassTransform().inverse() * pivot,
            jb.rb_b->getCenterOfMassTransform().inverse() * pivot);
        JointSettings s{PHYS_JOINT_POINT, def->collide_connected};
        return add_joint(w, jb, s, std::move(point), out);
    });
}

// ---- lifetime ------------------------------------------------------------------

phys_result phys_joint_destroy(phys_world* world, phys_joint_id joint) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        uint32_t slot = 0;
        CHECK(lookup(world, fn, "phys_joint_id", "joint", world->joints, joint, &slot));
        destroy_joint_slot(world, slot);
        return PHYS_OK;
    });
}

bool phys_joint_is_valid(const phys_world* world, phys_joint_id joint) {
    return world && id_is_live(world, world->joints, joint);
}

phys_result phys_joint_get_type(phys_world* world, phys_joint_id joint, phys_joint_type* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        JointSlot* j = nullptr;
        CHECK(get_joint(world, fn, joint, &j));
        *out = j->type;
        return PHYS_OK;
    });
}

// ---- motors and limits -------------------------------------------------------------

phys_result phys_joint_set_motor(phys_world* world, phys_joint_id joint, bool enabled,
                                 float target_velocity, float max_force) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_motor(world, fn, "target_velocity", target_velocity, "max_force", max_force));
        JointSlot* j = nullptr;
        CHECK(get_joint(world, fn, joint, &j));
        CHECK(need_type(world, fn, *j, true, true, "only hinge and slider joints have motors"));
        j->motor = enabled;
        j->motor_speed = target_velocity;
        j->max_motor = max_force;
        apply_motor(*j, world->last_dt > 0 ? world->last_dt : kFirstDt);
        update_holds(world, *j);
        wake(world, *j);
        return PHYS_OK;
    });
}

phys_result phys_joint_set_limits(phys_world* world, phys_joint_id joint, bool enabled,
                                  float lower, float upper) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        JointSlot* j = nullptr;
        CHECK(get_joint(world, fn, joint, &j));
        CHECK(need_type(world, fn, *j, true, true, "only hinge and slider joints have limits"));
        CHECK(check_limits(world, fn, j->type, "lower", lower, "upper", upper));
        j->limit = enabled;
        j->lower = lower;
        j->upper = upper;
        apply_limits(*j);
        wake(world, *j);
        return PHYS_OK;
    });
}

// ---- measures ------------------------------------------------------------------------

phys_result phys_joint_get_angle(phys_world* world, phys_joint_id joint, float* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        JointSlot* j = nullptr;
        CHECK(get_joint(world, fn, joint, &j));
        CHECK(need_type(world, fn, *j, true, false,
                        "only hinge joints have an angle (sliders: phys_joint_get_position)"));
        *out = static_cast<btHingeConstraint*>(j->constraint.get())->getHingeAngle();
        return PHYS_OK;
    });
}

phys_result phys_joint_get_position(phys_world* world, phys_joint_id joint, float* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        JointSlot* j = nullptr;
        CHECK(get_joint(world, fn, joint, &j));
        CHECK(need_type(world, fn, *j, false, true,
                        "only slider joints have a position (hinges: phys_joint_get_angle)"));
        const auto* s = static_cast<const btSliderConstraint*>(j->constraint.get());
        // From the current poses (Bullet's getLinearPos is from the start of the last step).
        const btTransform ta = s->getRigidBodyA().getCenterOfMassTransform() * s->getFrameOffsetA();
        const btTransform tb = s->getRigidBodyB().getCenterOfMassTransform() * s->getFrameOffsetB();
        *out = (ta.getOrigin() - tb.getOrigin()).dot(ta.getBasis().getColumn(0));
        return PHYS_OK;
    });
}

phys_result phys_joint_get_applied_impulse(phys_world* world, phys_joint_id joint,
                                           phys_vec3* out_impulse, phys_vec3* out_angular_impulse) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        JointSlot* j = nullptr;
        CHECK(get_joint(world, fn, joint, &j));
        // Bullet writes the feedback only for joints it solved: not while both bodies
        // sleep, when it still holds an older step's values.
        const bool a_awake = world->bodies[j->body_a].body->isActive();
        const bool b_awake = j->body_b != kWorldSlot &&
                             world->bodies[j->body_b].type == PHYS_BODY_DYNAMIC &&
                             world->bodies[j->body_b].body->isActive();
        const float dt = (a_awake || b_awake) ? world->last_dt : 0.0f;
        // Bullet's feedback is force = impulse / dt of the step; back to impulses.
        if (out_impulse) *out_impulse = from_bt(j->feedback->m_appliedForceBodyA * dt);
        if (out_angular_impulse) {
            *out_angular_impulse = from_bt(j->feedback->m_appliedTorqueBodyA * dt);
        }
        return PHYS_OK;
    });
}

} // extern "C"
