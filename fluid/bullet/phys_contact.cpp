// phys_contact.cpp: contact reports of the C API (phys.h): the body pairs that pushed on each
// other in the last step, with their summed normal impulse, mean point and normal.
//
// Read from Bullet's persistent manifolds after the step. Each contact point holds the normal
// impulse the solver applied to it in that step (btManifoldPoint::getAppliedImpulse; it is
// also the warm start of the next step, so the wrapper only reads it). A pair can have more
// than one manifold (compound children): they are merged. Manifolds of sleeping bodies are not
// solved and keep an old step's impulses, so pairs with no awake dynamic body are skipped.

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

} // namespace

extern "C" {

phys_result phys_world_get_contacts(phys_world* world, float min_impulse, phys_contact* out,
                                    int max, int* count) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        phys_world* w = world;
        CHECK(check_ptr(w, fn, "count", count));
        *count = 0;
        if (!std::isfinite(min_impulse) || min_impulse < 0) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: min_impulse must be finite and >= 0 N·s (got %g)", fn,
                        (double)min_impulse);
        }
        if (max < 0) {
            return fail(w, PHYS_ERR_INVALID_ARG, "%s: max must be >= 0 (got %d)", fn, max);
        }
        if (max > 0) CHECK(check_ptr(w, fn, "out (with max > 0)", out));

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
        int found = 0;
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
            if (!(p.impulse > (double)min_impulse)) continue;
            if (found < max) {
                phys_contact& c = out[found];
                c.a = make_id<phys_body_id>(w, p.a, w->bodies[p.a].generation);
                c.b = make_id<phys_body_id>(w, p.b, w->bodies[p.b].generation);
                c.impulse = (float)p.impulse;
                c.point = from_bt(p.point / (btScalar)p.impulse);
                btVector3 n = p.normal;
                // Opposed normals (a thin body pinched from both sides) cancel: use the
                // strongest point's.
                n = n.length2() > 1e-12f ? n.normalized() : p.largest_normal.normalized();
                c.normal = from_bt(n);
            }
            ++found;
        }
        *count = found;
        return PHYS_OK;
    });
}

} // extern "C"
