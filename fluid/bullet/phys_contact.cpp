// phys_contact.cpp: contact reports of the C API (phys.h): the body pairs that pushed on each
// other in the last step, with their summed normal impulse, mean point and normal.
//
// Read from Bullet's persistent manifolds after the step. Each contact point holds the normal
// impulse the solver applied to it in that step (btManifoldPoint::getAppliedImpulse; it is
// also the warm start of the next step, so the wrapper only reads it). A pair can have more
// than one manifold (compound children): they are merged. Manifolds of sleeping bodies are not
// solved and keep an old step's impulses, so pairs with no awake dynamic body are skipped.
//
// Contact sums (phys_world_set_contact_sums): after every step the step's pairs are merged
// into a list sorted by body slots, which phys_world_take_contact_sums hands out and empties.

#include "phys_internal.hpp"

#include <algorithm>
#include <cmath>

using namespace phys_internal;

namespace {

struct PairSum {
    uint32_t a = 0, b = 0;  // body slots, a < b
    double impulse = 0;     // N·s
    btVector3 point{0, 0, 0};   // sum of impulse × point
    btVector3 normal{0, 0, 0};  // sum of impulse × normal (a towards b)
    float largest = -1;         // the point with the largest impulse: a fallback normal
    btVector3 largest_normal{0, 1, 0};
};

bool live_body(const phys_world* w, const btCollisionObject* o, uint32_t* slot) {
    const int i = o->getUserIndex();
    if (i < 0 || (size_t)i >= w->bodies.size() || !w->bodies[(size_t)i].alive) return false;
    *slot = (uint32_t)i;
    return true;
}

bool solved(const phys_world* w, uint32_t slot) {
    const BodySlot& b = w->bodies[slot];
    return b.type == PHYS_BODY_DYNAMIC && b.body->isActive();
}

// Every touching pair of the last step whose impulse is > 0, its manifolds merged, sorted
// by (a, b).
std::vector<PairSum> step_pairs(phys_world* w) {
    std::vector<PairSum> pairs;
    btDispatcher* dispatcher = w->dynamics->getDispatcher();
    const int manifolds = dispatcher->getNumManifolds();
    for (int m = 0; m < manifolds; ++m) {
        const btPersistentManifold* pm = dispatcher->getManifoldByIndexInternal(m);
        if (pm->getNumContacts() == 0) continue;
        uint32_t s0 = 0, s1 = 0;
        if (!live_body(w, pm->getBody0(), &s0) || !live_body(w, pm->getBody1(), &s1)) continue;
        if (s0 == s1 || (!solved(w, s0) && !solved(w, s1))) continue;
        // Bullet's normal is on body 1, pointing at body 0: the impulse on body 0 is
        // along it. From a towards b is then -normal when body 0 is a.
        const bool body0_is_a = s0 < s1;
        const btScalar sign = body0_is_a ? -1 : 1;
        PairSum p;
        p.a = body0_is_a ? s0 : s1;
        p.b = body0_is_a ? s1 : s0;
        for (int c = 0; c < pm->getNumContacts(); ++c) {
            const btManifoldPoint& cp = pm->getContactPoint(c);
            const btScalar j = cp.getAppliedImpulse();
            const btVector3 n = cp.m_normalWorldOnB * sign;
            if (j > p.largest) {
                p.largest = j;
                p.largest_normal = n;
            }
            if (!(j > 0)) continue;
            p.impulse += j;
            p.point += j * (cp.getPositionWorldOnA() + cp.getPositionWorldOnB()) * 0.5f;
            p.normal += j * n;
        }
        if (p.impulse > 0) pairs.push_back(p);
    }
    std::sort(pairs.begin(), pairs.end(), [](const PairSum& x, const PairSum& y) {
        return x.a != y.a ? x.a < y.a : x.b < y.b;
    });
    std::vector<PairSum> merged;
    for (size_t i = 0; i < pairs.size();) {
        // Merge the manifolds of one pair (adjacent after the sort).
        PairSum p = pairs[i];
        size_t k = i + 1;
        for (; k < pairs.size() && pairs[k].a == p.a && pairs[k].b == p.b; ++k) {
            p.impulse += pairs[k].impulse;
            p.point += pairs[k].point;
            p.normal += pairs[k].normal;
            if (pairs[k].largest > p.largest) {
                p.largest = pairs[k].largest;
                p.largest_normal = pairs[k].largest_normal;
            }
        }
        i = k;
        // The pair's unit normal (opposed normals of a thin body pinched from both sides
        // cancel: then the strongest point's), times its impulse: sums over steps weight
        // each step's normal by its impulse.
        const btVector3 n = p.normal.length2() > 1e-12f * (btScalar)(p.impulse * p.impulse)
                                ? p.normal.normalized()
                                : p.largest_normal.normalized();
        p.normal = n * (btScalar)p.impulse;
        merged.push_back(p);
    }
    return merged;
}

// Checks the arguments of a contact query; *count is 0 from here on.
phys_result check_contact_args(phys_world* w, const char* fn, float min_impulse,
                               const phys_contact* out, int max, int* count) {
    CHECK(check_ptr(w, fn, "count", count));
    *count = 0;
    if (!std::isfinite(min_impulse) || min_impulse < 0) {
        return fail(w, PHYS_ERR_INVALID_ARG, "%s: min_impulse must be finite and >= 0 N·s (got %g)",
                    fn, (double)min_impulse);
    }
    if (max < 0) return fail(w, PHYS_ERR_INVALID_ARG, "%s: max must be >= 0 (got %d)", fn, max);
    if (max > 0) CHECK(check_ptr(w, fn, "out (with max > 0)", out));
    return PHYS_OK;
}

phys_contact to_contact(const phys_world* w, uint32_t a, uint16_t gen_a, uint32_t b, uint16_t gen_b,
                        double impulse, const btVector3& point, const btVector3& normal) {
    phys_contact c;
    c.a = make_id<phys_body_id>(w, a, gen_a);
    c.b = make_id<phys_body_id>(w, b, gen_b);
    c.impulse = (float)impulse;
    c.point = from_bt(point / (btScalar)impulse);
    btVector3 n = normal;
    c.normal = from_bt(n.length2() > 0 ? n.normalized() : btVector3(0, 1, 0));
    return c;
}

} // namespace

namespace phys_internal {

void sum_step_contacts(phys_world* w) {
    if (!w->sum_contacts) return;
    const std::vector<PairSum> step = step_pairs(w);
    std::vector<ContactSum>& sums = w->contact_sums;
    std::vector<ContactSum> out;
    out.reserve(sums.size() + step.size());
    size_t i = 0, k = 0;
    // Both lists are sorted by (a, b): merge them.
    while (i < sums.size() || k < step.size()) {
        const bool take_sum = k == step.size() ||
                              (i < sums.size() && (sums[i].a != step[k].a ? sums[i].a < step[k].a
                                                                          : sums[i].b <= step[k].b));
        if (take_sum && (k == step.size() || sums[i].a != step[k].a || sums[i].b != step[k].b)) {
            out.push_back(sums[i++]);
            continue;
        }
        ContactSum c;
        if (take_sum) c = sums[i++]; // the same pair in both: add the step to it
        const PairSum& p = step[k++];
        c.a = p.a;
        c.b = p.b;
        c.gen_a = w->bodies[p.a].generation;
        c.gen_b = w->bodies[p.b].generation;
        c.impulse += p.impulse;
        c.point += p.point;
        c.normal += p.normal;
        out.push_back(c);
    }
    sums.swap(out);
}

} // namespace phys_internal

extern "C" {

phys_result phys_world_get_contacts(phys_world* world, float min_impulse, phys_contact* out,
                                    int max, int* count) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        CHECK(check_contact_args(w, fn, min_impulse, out, max, count));
        int found = 0;
        for (const PairSum& p : step_pairs(w)) {
            if (!(p.impulse > (double)min_impulse)) continue;
            if (found < max) {
                out[found] = to_contact(w, p.a, w->bodies[p.a].generation, p.b,
                                        w->bodies[p.b].generation, p.impulse, p.point, p.normal);
            }
            ++found;
        }
        *count = found;
        return PHYS_OK;
    });
}

phys_result phys_world_set_contact_sums(phys_world* world, bool enabled) {
    return guarded(world, __func__, [&](const char*) -> phys_result {
        world->sum_contacts = enabled;
        world->contact_sums.clear();
        return PHYS_OK;
    });
}

phys_result phys_world_take_contact_sums(phys_world* world, float min_impulse, phys_contact* out,
                                         int max, int* count) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        CHECK(check_contact_args(w, fn, min_impulse, out, max, count));
        if (!w->sum_contacts) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: contact sums are off: turn them on with "
                        "phys_world_set_contact_sums(world, true) before the steps to sum",
                        fn);
        }
        int found = 0;
        for (const ContactSum& c : w->contact_sums) {
            if (!(c.impulse > (double)min_impulse)) continue;
            if (found < max) out[found] = to_contact(w, c.a, c.gen_a, c.b, c.gen_b, c.impulse, c.point, c.normal);
            ++found;
        }
        w->contact_sums.clear();
        *count = found;
        return PHYS_OK;
    });
}

} // extern "C"
