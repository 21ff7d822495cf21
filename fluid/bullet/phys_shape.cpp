// phys_shape.cpp: shapes of the C API (phys.h): plane, box, sphere, capsule, cylinder, convex
// hull, triangle mesh and compound, with their volumes, margins and a compound's mass properties.

#include "phys_internal.hpp"

#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

using namespace phys_internal;

namespace phys_internal {

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

} // namespace phys_internal

// Hull faces from btConvexHullComputer: outward unit normals, offsets and volume.
static void hull_faces(const btConvexHullComputer& hull, std::vector<phys_hull_plane>* planes,
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

static phys_result create_shape(phys_world* w, const char* fn, phys_shape_id* out,
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

static phys_result build_plane(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
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

static phys_result build_box(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
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

static phys_result build_sphere(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
    const phys_sphere& sp = *static_cast<const phys_sphere*>(in);
    CHECK(check_positive(w, fn, "phys_sphere.radius", sp.radius));
    s->shape.reset(new btSphereShape(sp.radius));
    s->desc.type = PHYS_SHAPE_SPHERE;
    s->desc.sphere = sp;
    s->desc.margin = 0;
    s->desc.volume = (float)(4.0 / 3.0 * kPi * sp.radius * sp.radius * sp.radius);
    return PHYS_OK;
}

static phys_result build_capsule(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
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

static phys_result build_cylinder(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
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

// The checks of a hull's points and its exact hull (no margin), shared by the world's shapes and
// phys_convex_hull_measure. Messages go to `msg`; the caller records them.
struct ExactHull {
    btConvexHullComputer hull;
    std::vector<phys_hull_plane> planes;
    double volume = 0;
};

static phys_result exact_hull(const char* fn, const phys_convex_hull& h, ExactHull* out, char* msg,
                              size_t size) {
    if (!h.points) {
        std::snprintf(msg, size, "%s: phys_convex_hull.points must not be NULL", fn);
        return PHYS_ERR_INVALID_ARG;
    }
    if (h.point_count < 4 || h.point_count > kMaxHullPoints) {
        std::snprintf(msg, size, "%s: phys_convex_hull.point_count must be in [4, %u] (got %u)", fn,
                      (unsigned)kMaxHullPoints, (unsigned)h.point_count);
        return PHYS_ERR_INVALID_ARG;
    }
    static const char* const axis[3] = {"x", "y", "z"};
    for (uint32_t i = 0; i < h.point_count; ++i) {
        const float c[3] = {h.points[i].x, h.points[i].y, h.points[i].z};
        for (int k = 0; k < 3; ++k) {
            if (!std::isfinite(c[k])) {
                std::snprintf(msg, size, "%s: phys_convex_hull.points[%u].%s must be finite (got %g)", fn,
                              (unsigned)i, axis[k], (double)c[k]);
                return PHYS_ERR_INVALID_ARG;
            }
        }
    }
    out->hull.compute(&h.points[0].x, (int)sizeof(phys_vec3), (int)h.point_count, 0, 0);
    hull_faces(out->hull, &out->planes, &out->volume);
    // Reject hulls without a volume (all points on a plane or a line). The
    // threshold is relative to the size of the point cloud.
    btVector3 lo = to_bt(h.points[0]), hi = lo;
    for (uint32_t i = 1; i < h.point_count; ++i) {
        lo.setMin(to_bt(h.points[i]));
        hi.setMax(to_bt(h.points[i]));
    }
    const double extent = (hi - lo).length();
    if (out->hull.faces.size() < 4 || !(out->volume > 1e-9 * extent * extent * extent)) {
        std::snprintf(msg, size,
                      "%s: phys_convex_hull.points must span a volume (the %u points lie on a plane "
                      "or a line; hull volume %g m^3)",
                      fn, (unsigned)h.point_count, out->volume);
        return PHYS_ERR_INVALID_ARG;
    }
    return PHYS_OK;
}

static phys_result build_hull(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
    const phys_convex_hull& h = *static_cast<const phys_convex_hull*>(in);
    ExactHull exact;
    char msg[sizeof w->last_error];
    const phys_result r = exact_hull(fn, h, &exact, msg, sizeof msg);
    if (r != PHYS_OK) return fail(w, r, "%s", msg);
    s->planes = std::move(exact.planes);
    const btAlignedObjectArray<btVector3>& corners = exact.hull.vertices;
    s->points.resize((size_t)corners.size());
    for (int i = 0; i < corners.size(); ++i) s->points[(size_t)i] = from_bt(corners[i]);

    // Bullet adds its margin outside a hull; shrink the hull by the margin so
    // hull + margin has the faces the caller gave. The shrunk hull is computed from the exact
    // hull's corners, not every point given: the same hull, without the points inside it.
    std::unique_ptr<btConvexHullShape> shape;
    btConvexHullComputer shrunk;
    const btScalar shrink = w->margin > 0 ? shrunk.compute(&corners[0].x(), (int)sizeof(btVector3),
                                                           corners.size(), w->margin, 0.25f)
                                          : 0;
    if (shrink > 0 && shrunk.vertices.size() >= 4) {
        shape.reset(new btConvexHullShape(&shrunk.vertices[0].x(), shrunk.vertices.size(),
                                          sizeof(btVector3)));
        shape->setMargin(shrink);
    } else {
        shape.reset(new btConvexHullShape(&corners[0].x(), corners.size(), sizeof(btVector3)));
        shape->setMargin(0);
    }
    shape->recalcLocalAabb();
    s->desc.type = PHYS_SHAPE_CONVEX_HULL;
    s->desc.margin = shape->getMargin();
    s->desc.volume = (float)exact.volume;
    s->desc.hull.points = s->points.data();
    s->desc.hull.point_count = (uint32_t)s->points.size();
    s->desc.hull.planes = s->planes.data();
    s->desc.hull.plane_count = (uint32_t)s->planes.size();
    s->shape = std::move(shape);
    return PHYS_OK;
}

static phys_result build_mesh(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
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

static phys_result build_compound(phys_world* w, const char* fn, const void* in, ShapeSlot* s) {
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
        int part_type; // read as an int: the C caller may store any (see phys_body_create)
        std::memcpy(&part_type, &p.type, sizeof part_type);
        switch (part_type) {
        case PHYS_SHAPE_BOX: build = build_box; geometry = &p.box; break;
        case PHYS_SHAPE_SPHERE: build = build_sphere; geometry = &p.sphere; break;
        case PHYS_SHAPE_CAPSULE: build = build_capsule; geometry = &p.capsule; break;
        case PHYS_SHAPE_CYLINDER: build = build_cylinder; geometry = &p.cylinder; break;
        case PHYS_SHAPE_CONVEX_HULL: build = build_hull; geometry = &p.hull; break;
        default:
            return fail(w, PHYS_ERR_INVALID_ARG,
                        "%s: phys_compound.parts[%u].type must be PHYS_SHAPE_BOX, PHYS_SHAPE_SPHERE, "
                        "PHYS_SHAPE_CAPSULE, PHYS_SHAPE_CYLINDER or PHYS_SHAPE_CONVEX_HULL (got %d%s%s)",
                        fn, (unsigned)i, part_type, part_type >= PHYS_SHAPE_PLANE && part_type <= PHYS_SHAPE_COMPOUND ? ", " : "",
                        part_type >= PHYS_SHAPE_PLANE && part_type <= PHYS_SHAPE_COMPOUND
                            ? shape_name((phys_shape_type)part_type) : "");
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

extern "C" {

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

phys_result phys_convex_hull_measure(const phys_convex_hull* hull, phys_hull_info* out, char* message,
                                     size_t message_size) {
    static const char fn[] = "phys_convex_hull_measure";
    char scratch[512];
    char* msg = message && message_size > 0 ? message : scratch;
    const size_t size = message && message_size > 0 ? message_size : sizeof scratch;
    if (!hull || !out) {
        std::snprintf(msg, size, "%s: %s must not be NULL", fn, hull ? "out" : "hull");
        return PHYS_ERR_INVALID_ARG;
    }
    try {
        ExactHull exact;
        const phys_result r = exact_hull(fn, *hull, &exact, msg, size);
        if (r != PHYS_OK) return r;
        out->vertex_count = (uint32_t)exact.hull.vertices.size();
        out->plane_count = (uint32_t)exact.planes.size();
        out->volume = (float)exact.volume;
        if (message && message_size > 0) message[0] = 0;
        return PHYS_OK;
    } catch (const std::bad_alloc&) {
        std::snprintf(msg, size, "%s: out of memory", fn);
        return PHYS_ERR_OUT_OF_MEMORY;
    } catch (...) {
        std::snprintf(msg, size, "%s: internal error", fn);
        return PHYS_ERR_INTERNAL;
    }
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

} // extern "C"
