// phys.cpp: the C API of phys.h over Bullet (C++17). What the parts share (the world, its
// slots, id helpers, input checks, the exception guard) is in phys_internal.hpp.

#include "phys_internal.hpp"

#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <LinearMath/btConvexHullComputer.h>

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

const char* shape_name(phys_shape_type t) {
    switch (t) {
    case PHYS_SHAPE_PLANE: return "plane";
    case PHYS_SHAPE_BOX: return "box";
    case PHYS_SHAPE_SPHERE: return "sphere";
    case PHYS_SHAPE_CAPSULE: return "capsule";
    case PHYS_SHAPE_CYLINDER: return "cylinder";
    case PHYS_SHAPE_CONVEX_HULL: return "convex hull";
    case PHYS_SHAPE_TRIANGLE_MESH: return "triangle mesh";
    case PHYS_SHAPE_COMPOUND: return "compound";
    }
    return "unknown shape";
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

// ---- shapes -----------------------------------------------------------------

// Hull faces from btConvexHullComputer: outward unit normals, offsets and volume.
void hull_faces(const btConvexHullComputer& hull, std::vector<phys_hull_plane>* planes,
                double* volume) {
    btVector3 centre(0, 0, 0);
    for (int i = 0; i < hull.vertices.size(); ++i) centre += hull.vertices[i];
    if (hull.vertices.size() > 0) centre /= (btScalar)hull.vertices.size();

    planes->clear();
    double vol = 0;
    for (int f = 0; f < hull.faces.size(); ++f) {
        const btConvexHullComputer::Edge* first = &hull.edges[hull.faces[f]];
        const btConvexHullComputer::Edge* e = first;
        // Newell's method: the sum of cross products of consecutive corners is
        // twice the area-weighted normal of the (planar) face polygon.
        double nx = 0, ny = 0, nz = 0, px = 0, py = 0, pz = 0;
        int corners = 0;
        do {
            const btVector3& a = hull.vertices[e->getSourceVertex()];
            const btVector3& b = hull.vertices[e->getTargetVertex()];
            nx += (double)a.y() * b.z() - (double)a.z() * b.y();
            ny += (double)a.z() * b.x() - (double)a.x() * b.z();
            nz += (double)a.x() * b.y() - (double)a.y() * b.x();
            px += a.x();
            py += a.y();
            pz += a.z();
            ++corners;
            e = e->getNextEdgeOfFace();
        } while (e != first && corners <= hull.edges.size());
        const double len = std::sqrt(nx * nx + ny * ny + nz * nz);
        if (len <= 0 || corners < 3) continue;
        nx /= len;
        ny /= len;
        nz /= len;
        px /= corners;
        py /= corners;
        pz /= corners;
        double offset = nx * px + ny * py + nz * pz;
        // Orient outward: the hull centre must be on the inside.
        if (nx * centre.x() + ny * centre.y() + nz * centre.z() > offset) {
            nx = -nx;
            ny = -ny;
            nz = -nz;
            offset = -offset;
        }
        vol += offset * (0.5 * len) / 3.0;  // divergence theorem: V = Σ (n·p) A / 3
        planes->push_back(phys_hull_plane{phys_vec3{(float)nx, (float)ny, (float)nz}, (float)offset});
    }
    *volume = vol;
}

phys_result create_shape(phys_world* w, const char* fn, phys_shape_id* out,
                         phys_result (*build)(phys_world*, const char*, const void*, ShapeSlot*),
                         const void* input, const char* input_name) {
    CHECK(check_ptr(w, fn, input_name, input));
    CHECK(check_ptr(w, fn, "out", out));
    const uint32_t slot = reserve_slot(w->shapes, w->free_shapes);
    ShapeSlot& s = w->shapes[slot];
    s.clear();
    s.desc = phys_shape_desc{};
    const phys_result r = build(w, fn, input, &s);
    if (r != PHYS_OK) {
        s.clear();
        return r;
    }
    s.use_count = 0;
    s.alive = true;
    claim_slot(w->free_shapes, slot);
    s.desc.shape = make_id<phys_shape_id>(w, slot, s.generation);
    *out = s.desc.shape;
    return PHYS_OK;
}

phys_result build_plane(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
    const phys_plane& p = *static_cast<const phys_plane*>(in);
    CHECK(check_vec3(w, fn, "phys_plane.normal", p.normal));
    CHECK(check_finite(w, fn, "phys_plane.offset", p.offset));
    const btVector3 n = to_bt(p.normal);
    const float len = n.length();
    if (std::fabs(len - 1.0f) > kUnitTolerance) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: phys_plane.normal must have unit length within %g (got length %g)", fn,
                    (double)kUnitTolerance, (double)len);
    }
    const btVector3 unit = n / len;
    s->shape.reset(new btStaticPlaneShape(unit, p.offset));
    s->desc.type = PHYS_SHAPE_PLANE;
    s->desc.plane.normal = from_bt(unit);
    s->desc.plane.offset = p.offset;
    s->desc.margin = s->shape->getMargin();
    s->desc.volume = std::numeric_limits<float>::infinity();
    return PHYS_OK;
}

phys_result build_box(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
    const phys_box& b = *static_cast<const phys_box*>(in);
    CHECK(check_positive(w, fn, "phys_box.half_extents.x", b.half_extents.x));
    CHECK(check_positive(w, fn, "phys_box.half_extents.y", b.half_extents.y));
    CHECK(check_positive(w, fn, "phys_box.half_extents.z", b.half_extents.z));
    const btVector3 he = to_bt(b.half_extents);
    auto box = std::make_unique<btBoxShape>(he);
    box->setMargin(std::min(w->margin, 0.1f * he[he.minAxis()]));  // keeps the outer extents
    s->desc.type = PHYS_SHAPE_BOX;
    s->desc.box = b;
    s->desc.margin = box->getMargin();
    s->desc.volume = 8.0f * b.half_extents.x * b.half_extents.y * b.half_extents.z;
    s->shape = std::move(box);
    return PHYS_OK;
}

phys_result build_sphere(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
    const phys_sphere& sp = *static_cast<const phys_sphere*>(in);
    CHECK(check_positive(w, fn, "phys_sphere.radius", sp.radius));
    s->shape.reset(new btSphereShape(sp.radius));
    s->desc.type = PHYS_SHAPE_SPHERE;
    s->desc.sphere = sp;
    s->desc.margin = 0;
    s->desc.volume = (float)(4.0 / 3.0 * kPi * sp.radius * sp.radius * sp.radius);
    return PHYS_OK;
}

phys_result build_capsule(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
    const phys_capsule& c = *static_cast<const phys_capsule*>(in);
    CHECK(check_positive(w, fn, "phys_capsule.radius", c.radius));
    CHECK(check_positive(w, fn, "phys_capsule.half_height", c.half_height));
    s->shape.reset(new btCapsuleShape(c.radius, 2.0f * c.half_height));
    s->desc.type = PHYS_SHAPE_CAPSULE;
    s->desc.capsule = c;
    s->desc.margin = 0;
    const double r = c.radius, h = c.half_height;
    s->desc.volume = (float)(kPi * r * r * 2.0 * h + 4.0 / 3.0 * kPi * r * r * r);
    return PHYS_OK;
}

phys_result build_cylinder(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
    const phys_cylinder& c = *static_cast<const phys_cylinder*>(in);
    CHECK(check_positive(w, fn, "phys_cylinder.radius", c.radius));
    CHECK(check_positive(w, fn, "phys_cylinder.half_height", c.half_height));
    auto cyl = std::make_unique<btCylinderShape>(btVector3(c.radius, c.half_height, c.radius));
    cyl->setMargin(std::min(w->margin, 0.1f * std::min(c.radius, c.half_height)));
    s->desc.type = PHYS_SHAPE_CYLINDER;
    s->desc.cylinder = c;
    s->desc.margin = cyl->getMargin();
    const double r = c.radius, h = c.half_height;
    s->desc.volume = (float)(kPi * r * r * 2.0 * h);
    s->shape = std::move(cyl);
    return PHYS_OK;
}

phys_result build_hull(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
    const phys_convex_hull& h = *static_cast<const phys_convex_hull*>(in);
    CHECK(check_ptr(w, fn, "phys_convex_hull.points", h.points));
    if (h.point_count < 4 || h.point_count > kMaxHullPoints) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: phys_convex_hull.point_count must be in [4, %u] (got %u)", fn,
                    (unsigned)kMaxHullPoints, (unsigned)h.point_count);
    }
    char field[64];
    for (uint32_t i = 0; i < h.point_count; ++i) {
        std::snprintf(field, sizeof field, "phys_convex_hull.points[%u]", (unsigned)i);
        CHECK(check_vec3(w, fn, field, h.points[i]));
    }
    const int count = (int)h.point_count;
    const float* coords = &h.points[0].x;
    btConvexHullComputer exact;
    exact.compute(coords, (int)sizeof(phys_vec3), count, 0, 0);
    double volume = 0;
    hull_faces(exact, &s->planes, &volume);
    // Reject hulls without a volume (all points on a plane or a line). The
    // threshold is relative to the size of the point cloud.
    btVector3 lo = to_bt(h.points[0]), hi = lo;
    for (uint32_t i = 1; i < h.point_count; ++i) {
        lo.setMin(to_bt(h.points[i]));
        hi.setMax(to_bt(h.points[i]));
    }
    const double extent = (hi - lo).length();
    if (exact.faces.size() < 4 || !(volume > 1e-9 * extent * extent * extent)) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: phys_convex_hull.points must span a volume (the %u points lie on a plane "
                    "or a line; hull volume %g m^3)",
                    fn, (unsigned)h.point_count, volume);
    }
    s->points.resize((size_t)exact.vertices.size());
    for (int i = 0; i < exact.vertices.size(); ++i) s->points[(size_t)i] = from_bt(exact.vertices[i]);

    // Bullet adds its margin outside a hull; shrink the hull by the margin so
    // hull + margin has the faces the caller gave.
    std::unique_ptr<btConvexHullShape> shape;
    btConvexHullComputer shrunk;
    const btScalar shrink = w->margin > 0 ? shrunk.compute(coords, (int)sizeof(phys_vec3), count,
                                                           w->margin, 0.25f)
                                          : 0;
    if (shrink > 0 && shrunk.vertices.size() >= 4) {
        shape.reset(new btConvexHullShape(&shrunk.vertices[0].x(), shrunk.vertices.size(),
                                          sizeof(btVector3)));
        shape->setMargin(shrink);
    } else {
        shape.reset(new btConvexHullShape(&exact.vertices[0].x(), exact.vertices.size(),
                                          sizeof(btVector3)));
        shape->setMargin(0);
    }
    shape->recalcLocalAabb();
    s->desc.type = PHYS_SHAPE_CONVEX_HULL;
    s->desc.margin = shape->getMargin();
    s->desc.volume = (float)volume;
    s->desc.hull.points = s->points.data();
    s->desc.hull.point_count = (uint32_t)s->points.size();
    s->desc.hull.planes = s->planes.data();
    s->desc.hull.plane_count = (uint32_t)s->planes.size();
    s->shape = std::move(shape);
    return PHYS_OK;
}

phys_result build_mesh(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
    const phys_triangle_mesh& m = *static_cast<const phys_triangle_mesh*>(in);
    CHECK(check_ptr(w, fn, "phys_triangle_mesh.vertices", m.vertices));
    CHECK(check_ptr(w, fn, "phys_triangle_mesh.indices", m.indices));
    const uint32_t int_max = (uint32_t)std::numeric_limits<int32_t>::max();
    if (m.vertex_count < 3 || m.vertex_count > int_max) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: phys_triangle_mesh.vertex_count must be in [3, %u] (got %u)", fn,
                    (unsigned)int_max, (unsigned)m.vertex_count);
    }
    if (m.triangle_count < 1 || m.triangle_count > int_max / 3) {
        return fail(w, PHYS_ERR_INVALID_ARG,
                    "%s: phys_triangle_mesh.triangle_count must be in [1, %u] (got %u)", fn,
                    (unsigned)(int_max / 3), (unsigned)m.triangle_count);
    }
    char field[64];
    for (uint32_t i = 0; i < m.vertex_count; ++i) {
        std::snprintf(field, sizeof field, "phys_triangle_mesh.vertices[%u]", (unsigned)i);
        CHECK(check_vec3(w, fn, field, m.vertices[i]));
    }
    const size_t index_count = (size_t)m.triangle_count * 3;
    for (size_t i = 0; i < index_count; ++i) {
        if (m.indices[i] >= m.vertex_count) {
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_triangle_mesh.indices[%zu] must be < vertex_count %u (got %u)",
                        fn, i, (unsigned)m.vertex_count, (unsigned)m.indices[i]);
        }
    }
    s->points.assign(m.vertices, m.vertices + m.vertex_count);
    s->indices.assign(m.indices, m.indices + index_count);

    btIndexedMesh part;
    part.m_numTriangles = (int)m.triangle_count;
    part.m_triangleIndexBase = reinterpret_cast<const unsigned char*>(s->indices.data());
    part.m_triangleIndexStride = (int)(3 * sizeof(uint32_t));
    part.m_numVertices = (int)m.vertex_count;
    part.m_vertexBase = reinterpret_cast<const unsigned char*>(s->points.data());
    part.m_vertexStride = (int)sizeof(phys_vec3);
    part.m_vertexType = PHY_FLOAT;
    s->mesh.reset(new btTriangleIndexVertexArray());
    s->mesh->addIndexedMesh(part, PHY_INTEGER);
    s->shape.reset(new btBvhTriangleMeshShape(s->mesh.get(), true, true));
    s->desc.type = PHYS_SHAPE_TRIANGLE_MESH;
    s->desc.margin = s->shape->getMargin();
    s->desc.volume = 0;
    s->desc.mesh.vertices = s->points.data();
    s->desc.mesh.vertex_count = m.vertex_count;
    s->desc.mesh.indices = s->indices.data();
    s->desc.mesh.triangle_count = m.triangle_count;
    return PHYS_OK;
}

phys_result build_compound(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
    const phys_compound& c = *static_cast<const phys_compound*>(in);
    CHECK(check_ptr(w, fn, "phys_compound.parts", c.parts));
    if (c.part_count < 1 || c.part_count > PHYS_MAX_COMPOUND_PARTS) {
        return fail(w, PHYS_ERR_INVALID_ARG, "%s: phys_compound.part_count must be in [1, %d] (got %u)",
                    fn, PHYS_MAX_COMPOUND_PARTS, (unsigned)c.part_count);
    }
    char where[160], field[96];
    std::vector<btTransform> poses(c.part_count);
    for (uint32_t i = 0; i < c.part_count; ++i) {
        const phys_compound_part& p = c.parts[i];
        std::snprintf(where, sizeof where, "%s: phys_compound.parts[%u]", fn, (unsigned)i);
        std::snprintf(field, sizeof field, "phys_compound.parts[%u].position", (unsigned)i);
        CHECK(check_vec3(w, fn, field, p.position));
        std::snprintf(field, sizeof field, "phys_compound.parts[%u].rotation", (unsigned)i);
        btQuaternion q;
        CHECK(check_quat(w, fn, field, p.rotation, &q));
        poses[i] = btTransform(q, to_bt(p.position));
        phys_result (*build)(phys_world*, const char*, const void*, ShapeSlot*) = nullptr;
        const void* geometry = nullptr;
        switch (p.type) {
        case PHYS_SHAPE_BOX: build = build_box; geometry = &p.box; break;
        case PHYS_SHAPE_SPHERE: build = build_sphere; geometry = &p.sphere; break;
        case PHYS_SHAPE_CAPSULE: build = build_capsule; geometry = &p.capsule; break;
        case PHYS_SHAPE_CYLINDER: build = build_cylinder; geometry = &p.cylinder; break;
        case PHYS_SHAPE_CONVEX_HULL: build = build_hull; geometry = &p.hull; break;
        default:
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_compound.parts[%u].type must be PHYS_SHAPE_BOX, PHYS_SHAPE_SPHERE, "
                        "PHYS_SHAPE_CAPSULE, PHYS_SHAPE_CYLINDER or PHYS_SHAPE_CONVEX_HULL (got %d%s%s)",
                        fn, (unsigned)i, (int)p.type, p.type >= PHYS_SHAPE_PLANE && p.type <= PHYS_SHAPE_COMPOUND ? ", " : "",
                        p.type >= PHYS_SHAPE_PLANE && p.type <= PHYS_SHAPE_COMPOUND ? shape_name(p.type) : "");
        }
        auto child = std::make_unique<ShapeSlot>();
        CHECK(build(w, where, geometry, child.get()));
        s->children.push_back(std::move(child));
    }
    // Children and their poses in the parts frame; masses per unit density.
    auto compound = std::make_unique<btCompoundShape>(true, (int)c.part_count);
    std::vector<btScalar> volumes(c.part_count);
    double total = 0;
    for (uint32_t i = 0; i < c.part_count; ++i) {
        compound->addChildShape(poses[i], s->children[i]->shape.get());
        volumes[i] = s->children[i]->desc.volume;
        total += volumes[i];
    }
    if (!(total > 0) || !std::isfinite(total)) {
        return fail(w, PHYS_ERR_INVALID_ARG, "%s: the parts' volumes sum to %g m^3; it must be > 0 and finite",
                    fn, total);
    }
    // Centre of mass and principal axes (parallel-axis sum of the children's
    // inertias, diagonalised); the moments come out for a total mass equal
    // to the total volume, i.e. per unit density.
    btTransform principal;
    btVector3 moments;
    compound->calculatePrincipalAxisTransform(volumes.data(), principal, moments);
    // Keep the parts' own axes when they already are principal (a symmetric wheel): an
    // axis-symmetric body has a free choice of axes, and the diagonalisation's is arbitrary.
    {
        btVector3 com(0, 0, 0);
        for (uint32_t i = 0; i < c.part_count; ++i) com += poses[i].getOrigin() * (volumes[i] / (btScalar)total);
        btMatrix3x3 tensor(0, 0, 0, 0, 0, 0, 0, 0, 0);
        for (uint32_t i = 0; i < c.part_count; ++i) {
            btVector3 diag;
            s->children[i]->shape->calculateLocalInertia(volumes[i], diag);
            const btMatrix3x3 r = poses[i].getBasis();
            btMatrix3x3 j = r.scaled(diag) * r.transpose();
            const btVector3 o = poses[i].getOrigin() - com;
            const btScalar o2 = o.length2();
            for (int a = 0; a < 3; ++a) {
                for (int b = 0; b < 3; ++b) j[a][b] += volumes[i] * ((a == b ? o2 : 0) - o[a] * o[b]);
            }
            tensor[0] += j[0];
            tensor[1] += j[1];
            tensor[2] += j[2];
        }
        const btScalar scale = btMax(tensor[0][0], btMax(tensor[1][1], tensor[2][2]));
        const btScalar off = btMax(btFabs(tensor[0][1]), btMax(btFabs(tensor[0][2]), btFabs(tensor[1][2])));
        if (off <= 1e-5f * scale) {
            principal = btTransform(btQuaternion::getIdentity(), com);
            moments = btVector3(tensor[0][0], tensor[1][1], tensor[2][2]);
        }
    }
    // Move the children into the principal frame: the shape origin becomes
    // the centre of mass.
    const btTransform to_principal = principal.inverse();
    for (uint32_t i = 0; i < c.part_count; ++i) {
        compound->updateChildTransform((int)i, to_principal * poses[i], false);
    }
    compound->recalculateLocalAabb();
    s->inertia_per_kg = moments / (btScalar)total;
    s->child_descs.resize(c.part_count);
    for (uint32_t i = 0; i < c.part_count; ++i) {
        const btTransform& t = compound->getChildTransform((int)i);
        phys_compound_child& d = s->child_descs[i];
        d.desc = s->children[i]->desc;
        d.position = from_bt(t.getOrigin());
        d.rotation = from_bt(t.getRotation());
    }
    s->desc.type = PHYS_SHAPE_COMPOUND;
    s->desc.margin = compound->getMargin();
    s->desc.volume = (float)total;
    s->desc.compound.children = s->child_descs.data();
    s->desc.compound.child_count = c.part_count;
    s->desc.compound.frame_origin = from_bt(principal.getOrigin());
    s->desc.compound.frame_rotation = from_bt(principal.getRotation());
    s->shape = std::move(compound);
    return PHYS_OK;
}

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

// ---- shapes ------------------------------------------------------------------

phys_result phys_shape_create_plane(phys_world* world, const phys_plane* plane, phys_shape_id* out) {
    return guarded(world, __func__, [&](const char* fn) {
        return create_shape(world, fn, out, build_plane, plane, "plane");
    });
}

phys_result phys_shape_create_box(phys_world* world, const phys_box* box, phys_shape_id* out) {
    return guarded(world, __func__, [&](const char* fn) {
        return create_shape(world, fn, out, build_box, box, "box");
    });
}

phys_result phys_shape_create_sphere(phys_world* world, const phys_sphere* sphere, phys_shape_id* out) {
    return guarded(world, __func__, [&](const char* fn) {
        return create_shape(world, fn, out, build_sphere, sphere, "sphere");
    });
}

phys_result phys_shape_create_capsule(phys_world* world, const phys_capsule* capsule, phys_shape_id* out) {
    return guarded(world, __func__, [&](const char* fn) {
        return create_shape(world, fn, out, build_capsule, capsule, "capsule");
    });
}

phys_result phys_shape_create_cylinder(phys_world* world, const phys_cylinder* cylinder, phys_shape_id* out) {
    return guarded(world, __func__, [&](const char* fn) {
        return create_shape(world, fn, out, build_cylinder, cylinder,
                            "cylinder");
    });
}

phys_result phys_shape_create_convex_hull(phys_world* world, const phys_convex_hull* hull,
                                          phys_shape_id* out) {
    return guarded(world, __func__, [&](const char* fn) {
        return create_shape(world, fn, out, build_hull, hull, "hull");
    });
}

phys_result phys_shape_create_triangle_mesh(phys_world* world, const phys_triangle_mesh* mesh,
                                            phys_shape_id* out) {
    return guarded(world, __func__, [&](const char* fn) {
        return create_shape(world, fn, out, build_mesh, mesh, "mesh");
    });
}

phys_result phys_shape_create_compound(phys_world* world, const phys_compound* compound,
                                       phys_shape_id* out) {
    return guarded(world, __func__, [&](const char* fn) {
        return create_shape(world, fn, out, build_compound, compound, "compound");
    });
}

phys_result phys_shape_destroy(phys_world* world, phys_shape_id shape) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        uint32_t slot = 0;
        CHECK(lookup(world, fn, "phys_shape_id", "shape", world->shapes, shape, &slot));
        ShapeSlot& s = world->shapes[slot];
        if (s.use_count > 0) {
            return fail(world, PHYS_ERR_INVALID_ARG,
                        "%s: the %s is used by %u bodies; destroy them first", fn,
                        shape_name(s.desc.type), (unsigned)s.use_count);
        }
        s.clear();
        s.points.shrink_to_fit();
        s.planes.shrink_to_fit();
        s.indices.shrink_to_fit();
        s.desc = phys_shape_desc{};
        s.alive = false;
        s.generation = next_generation(s.generation);
        world->free_shapes.push_back(slot);
        return PHYS_OK;
    });
}

bool phys_shape_is_valid(const phys_world* world, phys_shape_id shape) {
    return world && id_is_live(world, world->shapes, shape);
}

phys_result phys_shape_get_desc(phys_world* world, phys_shape_id shape, phys_shape_desc* out) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out", out));
        uint32_t slot = 0;
        CHECK(lookup(world, fn, "phys_shape_id", "shape", world->shapes, shape, &slot));
        *out = world->shapes[slot].desc;
        return PHYS_OK;
    });
}

phys_result phys_shape_get_volume(phys_world* world, phys_shape_id shape, float* out_volume) {
    return guarded(world, __func__, [&](const char* fn) -> phys_result {
        CHECK(check_ptr(world, fn, "out_volume", out_volume));
        uint32_t slot = 0;
        CHECK(lookup(world, fn, "phys_shape_id", "shape", world->shapes, shape, &slot));
        *out_volume = world->shapes[slot].desc.volume;
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
