// Binds seiche.body (every shape, compounds included), seiche.bodies, the body methods
// (pose, velocities, forces, move_to, teleport, look, grab, destroy) and the grab methods.
#include "engine/script/script_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// ---- bodies ------------------------------------------------------------------------------

static const float PALETTE[6][3] = {
    { 0.86f, 0.42f, 0.18f }, { 0.90f, 0.76f, 0.26f }, { 0.36f, 0.66f, 0.32f },
    { 0.78f, 0.26f, 0.30f }, { 0.50f, 0.40f, 0.70f }, { 0.62f, 0.46f, 0.30f },
};

static double dims_volume(body_shape shape, const float *d)
{
    switch (shape) {
    case SHAPE_BOX: return 8.0 * d[0] * d[1] * d[2];
    case SHAPE_SPHERE: return 4.0 / 3.0 * PI * d[0] * d[0] * d[0];
    case SHAPE_CAPSULE: return PI * d[0] * d[0] * (2.0 * d[1] + 4.0 / 3.0 * d[0]);
    case SHAPE_CYLINDER: return PI * d[0] * d[0] * 2.0 * d[1];
    default: return 0.0;
    }
}

// Volume of a shape whose dimensions are known here (not hulls or meshes), m^3; a
// compound's is the sum of its parts'.
static double shape_volume(const body_rec *b)
{
    if (b->shape != SHAPE_COMPOUND) return dims_volume(b->shape, b->dims);
    double v = 0.0;
    for (uint32_t i = 0; i < b->part_count; i++) v += dims_volume(b->parts[i].shape, b->parts[i].dims);
    return v;
}

static const char *const BODY_FIELDS[] = { "shape", "size", "radius", "height", "normal", "offset", "points", "vertices",
                                           "indices", "kind", "density", "mass", "position", "rotation", "velocity",
                                           "angular_velocity", "friction", "restitution", "linear_damping",
                                           "angular_damping", "two_way", "measure_force", "colour", "color", "visible",
                                           "parts",
                                           "linear_factor", "angular_factor", "axle", "mesh", "scale", "centre",
                                           "hull_points", NULL };

// A hull is checked at the call, so that its error carries the call's line: measured as the
// world would build it (without a world, and without Bullet's margin-shrunk copy, so a big cloud
// costs a fraction of a second), and the fluid's hull collider takes at most PBF_MAX_HULL_PLANES
// faces (cpl_add_body would refuse it when applied).
static void check_hull(lua_State *L, const float *pts, uint32_t n)
{
    phys_convex_hull h = { (const phys_vec3 *)pts, n };
    phys_hull_info info;
    char msg[512], lua[512];
    if (phys_convex_hull_measure(&h, &info, msg, sizeof msg) != PHYS_OK)
        scr_raise(L, "seiche.body: field 'points': %s", scr_lua_wording(msg, lua, sizeof lua));
    if (info.plane_count > PBF_MAX_HULL_PLANES)
        scr_raise(L, "seiche.body: field 'points' makes a convex hull of %u faces; the fluid takes at most %d (give fewer "
                  "points, or points on fewer faces)", info.plane_count, PBF_MAX_HULL_PLANES);
}

// The fields each shape takes (besides the common ones).
static void check_shape_fields(lua_State *L, body_shape shape)
{
    static const char *const own[SHAPE_COUNT][4] = {
        { "size" }, { "radius" }, { "radius", "height" }, { "radius", "height" },
        { "normal", "offset" }, { "points" }, { "vertices", "indices" }, { "parts" },
    };
    static const char *const geometric[] = { "size", "radius", "height", "normal", "offset", "points", "vertices",
                                             "indices", "parts", NULL };
    for (const char *const *g = geometric; *g; g++) {
        bool mine = false;
        for (int k = 0; k < 4 && own[shape][k]; k++)
            if (strcmp(own[shape][k], *g) == 0) mine = true;
        if (mine) continue;
        lua_getfield(L, 1, *g);
        bool given = !lua_isnil(L, -1);
        lua_pop(L, 1);
        if (given) {
            char list[96] = "";
            size_t n = 0;
            for (int k = 0; k < 4 && own[shape][k]; k++)
                n += (size_t)snprintf(list + n, sizeof list - n, "%s'%s'", k ? ", " : "", own[shape][k]);
            scr_raise(L, "seiche.body: field '%s' does not apply to shape \"%s\" (it takes %s)", *g, scr_shape_name[shape], list);
        }
    }
}

// A body from a mesh file takes none of the shapes' fields, and hull_points only when dynamic.
static void check_file_fields(lua_State *L, int kind, bool has_hull_points)
{
    static const char *const geometric[] = { "size", "radius", "height", "normal", "offset", "points", "vertices",
                                             "indices", "parts", NULL };
    for (const char *const *g = geometric; *g; g++)
        if (scr_field_present(L, 1, *g))
            scr_raise(L, "seiche.body: field '%s' does not apply to a body from a mesh file (its shape is the mesh's)", *g);
    if (has_hull_points && kind >= 0 && kind != PHYS_BODY_DYNAMIC)
        scr_raise(L, "seiche.body: field 'hull_points' applies to dynamic bodies (a %s body from a mesh file is its "
                  "triangles)", scr_body_kind_name[kind]);
}

// The geometry fields of a box, sphere, capsule or cylinder in table t: dims as body_rec.
static void read_dims(lua_State *L, int t, const char *fn, body_shape shape, float dims[4])
{
    switch (shape) {
    case SHAPE_BOX: {
        float size[3];
        if (!scr_opt_vec(L, t, fn, "size", 3, 0, 1000, OPEN_LO, "m", size))
            scr_raise(L, "%s: field 'size' is required for a box: edge lengths {x, y, z}, each in (0, 1000] m (got nil)", fn);
        for (int k = 0; k < 3; k++) dims[k] = 0.5f * size[k];
        break;
    }
    case SHAPE_SPHERE: dims[0] = (float)scr_req_number(L, t, fn, "radius", 0, 1000, OPEN_LO, "m"); break;
    case SHAPE_CAPSULE:
    case SHAPE_CYLINDER: {
        double r = scr_req_number(L, t, fn, "radius", 0, 1000, OPEN_LO, "m");
        double h = scr_req_number(L, t, fn, "height", 0, 2000, OPEN_LO, "m");
        if (shape == SHAPE_CAPSULE && !(h > 2.0 * r))
            scr_raise(L, "%s: field 'height' of a capsule is its total height and must exceed 2 radius = %g m (got %g)", fn,
                      2.0 * r, h);
        dims[0] = (float)r;
        dims[1] = shape == SHAPE_CAPSULE ? (float)(0.5 * h - r) : (float)(0.5 * h);
        break;
    }
    default: break;
    }
}

// Field 'parts' of a compound: 1 to MAX_BODY_PARTS tables {shape, size | radius, height,
// position, rotation}. Returns them in garbage-collected userdata (left on the stack).
static body_part *read_parts(lua_State *L, int t, const char *fn, uint32_t *count)
{
    if (!scr_field_present(L, t, "parts"))
        scr_raise(L, "%s: field 'parts' is required for a compound: a list of 1 to %d parts {shape = \"box\", size = "
                  "{x, y, z}, position = {x, y, z}, rotation = ...} (got nil)", fn, MAX_BODY_PARTS);
    int pt = lua_gettop(L);
    char got[64];
    if (!lua_istable(L, pt))
        scr_raise(L, "%s: field 'parts' must be a list of parts {shape, size | radius, height, position, rotation} (got %s)",
                  fn, scr_describe(L, pt, got, sizeof got));
    lua_Integer n = scr_len(L, pt, fn, "field 'parts'");
    if (n < 1 || n > MAX_BODY_PARTS)
        scr_raise(L, "%s: field 'parts' must hold 1 to %d parts (each part is one of the fluid's %d colliders; got %lld)", fn,
                  MAX_BODY_PARTS, MAX_BODY_PARTS, (long long)n);
    body_part *parts = lua_newuserdatauv(L, (size_t)n * sizeof *parts, 0);
    static const char *const known[] = { "shape", "size", "radius", "height", "position", "rotation", NULL };
    static const char *const part_shapes[] = { "box", "sphere", "capsule", "cylinder" };
    static const char *const own[4][2] = { { "size" }, { "radius" }, { "radius", "height" }, { "radius", "height" } };
    for (lua_Integer i = 1; i <= n; i++) {
        char sub[96];
        snprintf(sub, sizeof sub, "%s: field 'parts'[%lld]", fn, (long long)i);
        lua_geti(L, pt, i);
        int e = lua_gettop(L);
        if (!lua_istable(L, e))
            scr_raise(L, "%s must be a table {shape, size | radius, height, position, rotation} (got %s)", sub,
                      scr_describe(L, e, got, sizeof got));
        scr_check_fields(L, e, sub, known);
        int shape = scr_opt_enum(L, e, sub, "shape", part_shapes, 4);
        if (shape < 0)
            scr_raise(L, "%s: field 'shape' is required: one of \"box\", \"sphere\", \"capsule\", \"cylinder\" (got nil)",
                      sub);
        static const char *const geometric[] = { "size", "radius", "height" };
        for (int g = 0; g < 3; g++) {
            bool mine = false;
            for (int k = 0; k < 2 && own[shape][k]; k++)
                if (strcmp(own[shape][k], geometric[g]) == 0) mine = true;
            if (!mine && scr_field_present(L, e, geometric[g]))
                scr_raise(L, "%s: field '%s' does not apply to shape \"%s\"", sub, geometric[g], part_shapes[shape]);
        }
        body_part *bp = &parts[i - 1];
        memset(bp, 0, sizeof *bp);
        bp->shape = (body_shape)shape;
        read_dims(L, e, sub, bp->shape, bp->dims);
        scr_opt_position(L, e, sub, "position", bp->pos);
        bp->rot[3] = 1.0f;
        scr_opt_rotation(L, e, sub, "rotation", bp->rot);
        lua_pop(L, 1);
    }
    *count = (uint32_t)n;
    return parts;
}

static int l_body(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.body";
    scr_check_table_arg(L, 1, fn, "shape = \"box\", size = {x, y, z}, position = {x, y, z}, ...");
    scr_check_fields(L, 1, fn, BODY_FIELDS);
    // A mesh from a file: its convex hull for a dynamic body, its triangles for the others.
    scr_mesh_request mesh_file;
    bool from_file = scr_read_mesh_fields(L, s, 1, fn, true, &mesh_file);
    if (from_file && scr_field_present(L, 1, "shape"))
        scr_raise(L, "seiche.body: give 'shape' or 'mesh', not both (a body from a mesh file is its convex hull when "
                  "dynamic, its triangles when static or kinematic)");
    int kind = scr_opt_enum(L, 1, fn, "kind", scr_body_kind_name, 3);
    int shape = from_file ? (kind < 0 || kind == PHYS_BODY_DYNAMIC ? SHAPE_HULL : SHAPE_MESH)
                          : scr_opt_enum(L, 1, fn, "shape", scr_shape_name, SHAPE_COUNT);
    if (shape < 0)
        scr_raise(L, "seiche.body: field 'shape' is required: one of \"box\", \"sphere\", \"capsule\", \"cylinder\", "
                  "\"plane\", \"hull\", \"mesh\", \"compound\" (got nil); or mesh = \"file.obj\"");
    if (from_file) check_file_fields(L, kind, mesh_file.has_hull_points);
    else check_shape_fields(L, (body_shape)shape);
    if (kind < 0) kind = (shape == SHAPE_PLANE || shape == SHAPE_MESH) ? PHYS_BODY_STATIC : PHYS_BODY_DYNAMIC;
    if (kind == PHYS_BODY_DYNAMIC && (shape == SHAPE_PLANE || shape == SHAPE_MESH))
        scr_raise(L, "seiche.body: shape \"%s\" has no volume and must be kind \"static\" or \"kinematic\" (got kind \"dynamic\")",
                  scr_shape_name[shape]);

    body_rec b;
    memset(&b, 0, sizeof b);
    b.shape = (body_shape)shape;
    b.def = phys_default_body_def();
    b.def.type = (phys_body_type)kind;
    b.def.allow_sleep = false; // bodies in fluid must feel it (the coupling keeps them awake anyway)
    b.two_way = true;
    b.visible = true;

    // Common fields.
    double v;
    bool has_mass = scr_opt_number(L, 1, fn, "mass", PHYS_MIN_MASS, PHYS_MAX_MASS, 0, "kg", &v);
    if (has_mass) b.def.mass = (float)v;
    bool has_density = scr_opt_number(L, 1, fn, "density", 0, 1e6, OPEN_LO, "kg/m^3", &v);
    if (has_density) b.def.density = (float)v;
    if ((has_mass || has_density) && kind != PHYS_BODY_DYNAMIC)
        scr_raise(L, "seiche.body: fields 'mass' and 'density' apply to dynamic bodies only (this one is %s: its mass is "
                  "infinite)", scr_body_kind_name[kind]);
    if (has_mass && has_density) scr_raise(L, "seiche.body: give 'mass' or 'density', not both");
    float pos[3] = { 0, 0, 0 };
    scr_opt_position(L, 1, fn, "position", pos);
    b.def.position = scr_pv(pos);
    float q[4];
    if (scr_opt_rotation(L, 1, fn, "rotation", q)) b.def.orientation = scr_pq(q);
    float vel[3] = { 0, 0, 0 }, ang[3] = { 0, 0, 0 };
    bool has_v = scr_opt_vec(L, 1, fn, "velocity", 3, -MAX_SPEED, MAX_SPEED, 0, "m/s", vel);
    bool has_w = scr_opt_vec(L, 1, fn, "angular_velocity", 3, -MAX_SPEED, MAX_SPEED, 0, "rad/s", ang);
    if ((has_v || has_w) && kind == PHYS_BODY_STATIC)
        scr_raise(L, "seiche.body: a static body cannot move: fields 'velocity' and 'angular_velocity' need kind "
                  "\"kinematic\" or \"dynamic\"");
    b.def.linear_velocity = scr_pv(vel);
    b.def.angular_velocity = scr_pv(ang);
    if (scr_opt_number(L, 1, fn, "friction", 0, 100, 0, "", &v)) b.def.friction = (float)v;
    if (scr_opt_number(L, 1, fn, "restitution", 0, 1, 0, "", &v)) b.def.restitution = (float)v;
    if (scr_opt_number(L, 1, fn, "linear_damping", 0, 1, 0, "(fraction of velocity removed per second)", &v))
        b.def.linear_damping = (float)v;
    if (scr_opt_number(L, 1, fn, "angular_damping", 0, 1, 0, "(fraction of angular velocity removed per second)", &v))
        b.def.angular_damping = (float)v;
    scr_opt_bool(L, 1, fn, "two_way", &b.two_way);
    scr_opt_bool(L, 1, fn, "measure_force", &b.measure_force);
    // Motion factors: per world axis, [0, 1]; `axle` is the short form of a fixed axle.
    for (int k = 0; k < 3; k++) b.linear_factor[k] = b.angular_factor[k] = 1.0f;
    bool has_lf = scr_opt_vec(L, 1, fn, "linear_factor", 3, 0, 1, 0, "", b.linear_factor);
    bool has_af = scr_opt_vec(L, 1, fn, "angular_factor", 3, 0, 1, 0, "", b.angular_factor);
    static const char *const AXES[3] = { "x", "y", "z" };
    int axle = scr_opt_enum(L, 1, fn, "axle", AXES, 3);
    if (axle >= 0) {
        if (has_lf || has_af)
            scr_raise(L, "seiche.body: give 'axle' or 'linear_factor'/'angular_factor', not both (axle = \"%s\" means "
                      "linear_factor = {0, 0, 0} and angular_factor = 1 about %s only)", AXES[axle], AXES[axle]);
        for (int k = 0; k < 3; k++) {
            b.linear_factor[k] = 0.0f;
            b.angular_factor[k] = k == axle ? 1.0f : 0.0f;
        }
    }
    b.has_factors = has_lf || has_af || axle >= 0;
    if (b.has_factors && kind != PHYS_BODY_DYNAMIC)
        scr_raise(L, "seiche.body: fields 'axle', 'linear_factor' and 'angular_factor' apply to dynamic bodies only (this "
                  "one is %s)", scr_body_kind_name[kind]);
    const char *colour = scr_colour_field(L, 1, fn);
    bool has_color = colour && scr_opt_color(L, 1, fn, colour, b.color);
    scr_opt_bool(L, 1, fn, "visible", &b.visible);

    // The shape. Point lists stay in garbage-collected userdata until everything is checked.
    const float *pts = NULL;
    const uint32_t *idx = NULL;
    const body_part *parts = NULL;
    switch (from_file ? SHAPE_COUNT : b.shape) {
    case SHAPE_BOX:
    case SHAPE_SPHERE:
    case SHAPE_CAPSULE:
    case SHAPE_CYLINDER: read_dims(L, 1, fn, b.shape, b.dims); break;
    case SHAPE_COMPOUND: parts = read_parts(L, 1, fn, &b.part_count); b.parts = (body_part *)parts; break;
    case SHAPE_PLANE: {
        float n[3] = { 0, 1, 0 };
        scr_opt_vec(L, 1, fn, "normal", 3, -1e6, 1e6, 0, "", n);
        double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        if (!(len > 1e-9)) scr_raise(L, "seiche.body: field 'normal' must not be zero (got {0, 0, 0})");
        for (int k = 0; k < 3; k++) b.dims[k] = (float)(n[k] / len);
        double off = 0;
        scr_opt_number(L, 1, fn, "offset", -MAX_COORD, MAX_COORD, 0, "m", &off);
        b.dims[3] = (float)off;
        break;
    }
    case SHAPE_HULL:
    case SHAPE_MESH: {
        const char *field = b.shape == SHAPE_HULL ? "points" : "vertices";
        pts = scr_read_point_list(L, 1, fn, field, -MAX_COORD, MAX_COORD, "m", &b.point_count, b.shape == SHAPE_HULL ? 4 : 3,
                                  65536);
        if (b.shape == SHAPE_HULL) check_hull(L, pts, b.point_count);
        if (b.shape == SHAPE_MESH) {
            if (!scr_field_present(L, 1, "indices"))
                scr_raise(L, "seiche.body: field 'indices' is required for a mesh: vertex numbers (1-based), three per triangle");
            int it = lua_gettop(L);
            char got[64];
            if (!lua_istable(L, it))
                scr_raise(L, "seiche.body: field 'indices' must be a list of vertex numbers (got %s)", scr_describe(L, it, got, sizeof got));
            lua_Integer m = scr_len(L, it, "seiche.body", "field 'indices'");
            if (m < 3 || m % 3 != 0 || m > 3 * 262144)
                scr_raise(L, "seiche.body: field 'indices' must hold 3 to %d vertex numbers, a multiple of 3 (got %lld)",
                          3 * 262144, (long long)m);
            uint32_t *ix = lua_newuserdatauv(L, (size_t)m * sizeof *ix, 0);
            for (lua_Integer i = 1; i <= m; i++) {
                lua_geti(L, it, i);
                char what[64];
                snprintf(what, sizeof what, "field 'indices'[%lld]", (long long)i);
                ix[i - 1] = (uint32_t)scr_check_number_at(L, -1, fn, what, 1, b.point_count, WHOLE, "(a vertex number)") - 1;
                lua_pop(L, 1);
            }
            idx = ix;
            b.index_count = (uint32_t)m;
        }
        break;
    }
    default: break;
    }
    if (kind == PHYS_BODY_DYNAMIC && !has_mass && b.shape != SHAPE_HULL) {
        double m = shape_volume(&b) * b.def.density;
        if (!(m >= PHYS_MIN_MASS && m <= PHYS_MAX_MASS))
            scr_raise(L, "seiche.body: density %g kg/m^3 times volume %g m^3 gives mass %g kg, outside [%g, %g] kg "
                      "(Bullet lets heavier bodies fall through static ones, and keeps 1/mass in a float)",
                      (double)b.def.density, shape_volume(&b), m, (double)PHYS_MIN_MASS, (double)PHYS_MAX_MASS);
    }

    // The shape's data counts against the script's memory: refused before anything is made.
    size_t data_bytes = (parts ? (size_t)b.part_count * sizeof(body_part) : 0) +
                        (pts ? (size_t)b.point_count * 3 * sizeof(float) + (size_t)b.index_count * sizeof(uint32_t) : 0);
    scr_charge(L, s, fn, data_bytes);
    scr_uncharge(s, data_bytes);
    uint32_t slot = scr_obj_new(L, s, OBJ_BODY);
    obj *o = &s->objs[slot];
    if (!has_color) {
        if (kind == PHYS_BODY_DYNAMIC) memcpy(b.color, PALETTE[slot % 6], sizeof b.color);
        else b.color[0] = b.color[1] = b.color[2] = 0.55f;
    }
    command *c = scr_push_command(L, s, CMD_BODY_ADD, fn);
    c->slot = slot;
    c->gen = o->generation;
    if (from_file) { // read last: nothing after this may raise without freeing it
        char err[768];
        if (!scr_load_mesh(&mesh_file, &b.file, err, sizeof err)) {
            s->command_count--;
            scr_obj_release(s, slot);
            scr_check_now(L, s); // an importer the budget's end stopped: the budget is the reason
            scr_raise(L, "seiche.body: %s", err);
        }
        b.hull_points = mesh_file.hull_points;
        data_bytes = scr_mesh_bytes(b.file);
        if (data_bytes > scr_memory_room(s)) {
            scr_free_mesh(b.file);
            s->command_count--;
            scr_obj_release(s, slot);
            scr_charge(L, s, fn, data_bytes); // raises with the numbers
        }
    }
    b.parts = NULL;
    if (parts) b.parts = malloc((size_t)b.part_count * sizeof *b.parts);
    if (pts) {
        b.points = malloc((size_t)b.point_count * 3 * sizeof(float));
        b.indices = b.index_count ? malloc((size_t)b.index_count * sizeof(uint32_t)) : NULL;
    }
    if ((parts && !b.parts) || (pts && (!b.points || (b.index_count && !b.indices)))) {
        free(b.parts);
        free(b.points);
        free(b.indices);
        s->command_count--;
        scr_obj_release(s, slot);
        scr_raise(L, "seiche.body: out of memory");
    }
    s->c_memory += data_bytes; // given back by scr_body_free_data
    if (parts) memcpy(b.parts, parts, (size_t)b.part_count * sizeof *b.parts);
    if (pts) {
        memcpy(b.points, pts, (size_t)b.point_count * 3 * sizeof(float));
        if (b.index_count) memcpy(b.indices, idx, (size_t)b.index_count * sizeof(uint32_t));
    }
    o->u.body = b;
    scr_push_handle(L, s, slot);
    return 1;
}

static int l_bodies(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    lua_newtable(L);
    lua_Integer n = 0;
    for (uint32_t i = 0; i < s->obj_count; i++)
        if (s->objs[i].state != OBJ_FREE && s->objs[i].kind == OBJ_BODY) {
            scr_push_handle(L, s, i);
            lua_rawseti(L, -2, ++n);
        }
    return 1;
}

// The body's pose and velocities: from Bullet when it is in the world, else from its def.
void scr_body_state(eng_script *s, obj *o, float pos[3], float rot[4], float vel[3], float ang[3])
{
    body_rec *b = &o->u.body;
    phys_vec3 p = b->def.position, v = b->def.linear_velocity, w = b->def.angular_velocity;
    phys_quat q = b->def.orientation;
    if (o->state == OBJ_LIVE && s->host.phys) {
        phys_body_get_pose(s->host.phys, b->id, &p, &q);
        phys_body_get_linear_velocity(s->host.phys, b->id, &v);
        phys_body_get_angular_velocity(s->host.phys, b->id, &w);
    }
    if (pos) pos[0] = p.x, pos[1] = p.y, pos[2] = p.z;
    if (rot) rot[0] = q.x, rot[1] = q.y, rot[2] = q.z, rot[3] = q.w;
    if (vel) vel[0] = v.x, vel[1] = v.y, vel[2] = v.z;
    if (ang) ang[0] = w.x, ang[1] = w.y, ang[2] = w.z;
}

static int m_body_position(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:position", NULL);
    float p[3];
    scr_body_state(scr_get_script(L), o, p, NULL, NULL, NULL);
    scr_push_vec3(L, p[0], p[1], p[2]);
    return 1;
}

static int m_body_rotation(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:rotation", NULL);
    float q[4];
    scr_body_state(scr_get_script(L), o, NULL, q, NULL, NULL);
    scr_push_quat(L, q);
    return 1;
}

static int m_body_velocity(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:velocity", NULL);
    float v[3];
    scr_body_state(scr_get_script(L), o, NULL, NULL, v, NULL);
    scr_push_vec3(L, v[0], v[1], v[2]);
    return 1;
}

static int m_body_angular_velocity(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:angular_velocity", NULL);
    float w[3];
    scr_body_state(scr_get_script(L), o, NULL, NULL, NULL, w);
    scr_push_vec3(L, w[0], w[1], w[2]);
    return 1;
}

static int m_body_velocity_at(lua_State *L)
{
    scr_check_self(L, OBJ_BODY, "body:velocity_at", NULL);
    float pt[3], p[3], v[3], w[3];
    scr_arg_vec(L, 2, "body:velocity_at", "point", -MAX_COORD, MAX_COORD, "m", pt);
    obj *o = scr_check_self(L, OBJ_BODY, "body:velocity_at", NULL); // again: reading may have run Lua (SCR_SELF_AGAIN)
    scr_body_state(scr_get_script(L), o, p, NULL, v, w);
    float r[3] = { pt[0] - p[0], pt[1] - p[1], pt[2] - p[2] };
    scr_push_vec3(L, v[0] + w[1] * r[2] - w[2] * r[1], v[1] + w[2] * r[0] - w[0] * r[2], v[2] + w[0] * r[1] - w[1] * r[0]);
    return 1;
}

static int m_body_mass(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    obj *o = scr_check_self(L, OBJ_BODY, "body:mass", NULL);
    body_rec *b = &o->u.body;
    if (b->def.type != PHYS_BODY_DYNAMIC) {
        lua_pushnumber(L, HUGE_VAL);
        return 1;
    }
    if (o->state == OBJ_LIVE && s->host.phys) {
        phys_mass_data md;
        if (phys_body_get_mass_data(s->host.phys, b->id, &md) == PHYS_OK) {
            lua_pushnumber(L, md.mass);
            return 1;
        }
    }
    if (b->def.mass > 0) lua_pushnumber(L, b->def.mass);
    else if (b->shape != SHAPE_HULL) lua_pushnumber(L, shape_volume(b) * b->def.density);
    else scr_raise(L, "body:mass: the hull's mass is known once the body is in the world (after this callback)");
    return 1;
}

static int m_body_kind(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:kind", NULL);
    lua_pushstring(L, scr_body_kind_name[o->u.body.def.type]);
    return 1;
}

static int m_body_shape(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:shape", NULL);
    lua_pushstring(L, scr_shape_name[o->u.body.shape]);
    return 1;
}

// The water's force and torque on a body (latest measured step); raises for a body whose
// force is not measured.
static void body_fluid_stats(lua_State *L, const char *fn, cpl_body_stats *st)
{
    eng_script *s = scr_get_script(L);
    obj *o = scr_check_self(L, OBJ_BODY, fn, NULL);
    const body_rec *b = &o->u.body;
    phys_body_type t = b->def.type;
    if (!b->measure_force && (t == PHYS_BODY_STATIC || (t == PHYS_BODY_DYNAMIC && !b->two_way)))
        scr_raise(L, "%s: the body is %s and the water's force on it is not measured: create it with "
                  "measure_force = true", fn, t == PHYS_BODY_STATIC ? "static" : "one-way (two_way = false)");
    memset(st, 0, sizeof *st);
    if (o->state == OBJ_LIVE && s->host.coupling) cpl_body_get_stats(s->host.coupling, o->u.body.id, st);
}

static int m_body_fluid_force(lua_State *L)
{
    cpl_body_stats st;
    body_fluid_stats(L, "body:fluid_force", &st);
    scr_push_vec3(L, st.force[0], st.force[1], st.force[2]);
    scr_push_vec3(L, st.torque[0], st.torque[1], st.torque[2]);
    return 2;
}

static int m_body_fluid_torque(lua_State *L)
{
    cpl_body_stats st;
    body_fluid_stats(L, "body:fluid_torque", &st);
    scr_push_vec3(L, st.torque[0], st.torque[1], st.torque[2]);
    return 1;
}

// The velocity of the water pushing the body (the pushes' weighted mean) and the sum of the
// pushes' magnitudes (N), of the same measured step as body:fluid_force.
static int m_body_fluid_velocity(lua_State *L)
{
    cpl_body_stats st;
    body_fluid_stats(L, "body:fluid_velocity", &st);
    scr_push_vec3(L, st.fluid_velocity[0], st.fluid_velocity[1], st.fluid_velocity[2]);
    lua_pushnumber(L, st.fluid_push);
    return 2;
}

// A queued edit of a body that must be dynamic (forces) or may not be static (velocities).
static command *body_edit(lua_State *L, const char *fn, cmd_type type, bool dynamic_only)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_BODY, fn, &slot);
    phys_body_type t = o->u.body.def.type;
    if (dynamic_only && t != PHYS_BODY_DYNAMIC)
        scr_raise(L, "%s: the body is %s: forces and impulses move dynamic bodies only (use move_to or set_velocity on a "
                  "kinematic body)", fn, scr_body_kind_name[t]);
    if (t == PHYS_BODY_STATIC)
        scr_raise(L, "%s: the body is static: it never moves (make it kind = \"kinematic\" to move it by script)", fn);
    command *c = scr_push_command(L, s, type, fn);
    c->slot = slot;
    c->gen = o->generation;
    return c;
}

static int vector_edit(lua_State *L, const char *fn, cmd_type type, const char *name, const char *unit, bool dynamic_only,
                       bool point_allowed)
{
    float v[3], p[3] = { 0, 0, 0 };
    // Check the arguments before the handle's kind so that messages name the argument.
    scr_check_self(L, OBJ_BODY, fn, NULL);
    scr_arg_vec(L, 2, fn, name, -1e9, 1e9, unit, v);
    bool at_point = point_allowed && !lua_isnoneornil(L, 3);
    if (at_point) scr_arg_vec(L, 3, fn, "point", -MAX_COORD, MAX_COORD, "m", p);
    command *c = body_edit(L, fn, type, dynamic_only);
    memcpy(c->u.vec.v, v, sizeof v);
    memcpy(c->u.vec.p, p, sizeof p);
    c->u.vec.at_point = at_point;
    return 0;
}

// Forces act over the next step: held on the body through each of its Bullet steps (the coupling
// steps Bullet once per fluid substep), so a steady push is steady within the frame too.
static int m_body_apply_force(lua_State *L)
{
    return vector_edit(L, "body:apply_force", CMD_BODY_FORCE, "force", "N", true, true);
}

static int m_body_apply_torque(lua_State *L)
{
    return vector_edit(L, "body:apply_torque", CMD_BODY_TORQUE, "torque", "N m", true, false);
}

static int m_body_apply_impulse(lua_State *L)
{
    return vector_edit(L, "body:apply_impulse", CMD_BODY_IMPULSE, "impulse", "N s", true, true);
}

static int m_body_apply_angular_impulse(lua_State *L)
{
    return vector_edit(L, "body:apply_angular_impulse", CMD_BODY_ANGULAR_IMPULSE, "impulse", "N m s", true, false);
}

static int m_body_set_velocity(lua_State *L)
{
    return vector_edit(L, "body:set_velocity", CMD_BODY_VELOCITY, "velocity", "m/s", false, false);
}

static int m_body_set_angular_velocity(lua_State *L)
{
    return vector_edit(L, "body:set_angular_velocity", CMD_BODY_ANGULAR_VELOCITY, "velocity", "rad/s", false, false);
}

// pose(position [, rotation]) arguments of move_to and teleport; returns the body, looked up
// again after the arguments were read (SCR_SELF_AGAIN).
static obj *read_pose_args(lua_State *L, const char *fn, float pos[3], float rot[4])
{
    scr_check_self(L, OBJ_BODY, fn, NULL);
    scr_arg_vec(L, 2, fn, "position", -MAX_COORD, MAX_COORD, "m", pos);
    if (lua_isnoneornil(L, 3)) {
        obj *o = scr_check_self(L, OBJ_BODY, fn, NULL);
        scr_body_state(scr_get_script(L), o, NULL, rot, NULL, NULL);
        return o;
    }
    // scr_opt_rotation reads a field: wrap the argument in a table.
    lua_createtable(L, 0, 1);
    lua_pushvalue(L, 3);
    lua_setfield(L, -2, "rotation");
    char sub[64];
    snprintf(sub, sizeof sub, "%s: argument #2", fn);
    scr_opt_rotation(L, lua_gettop(L), sub, "rotation", rot);
    lua_pop(L, 1);
    return scr_check_self(L, OBJ_BODY, fn, NULL);
}

static int m_body_move_to(lua_State *L)
{
    const char *fn = "body:move_to";
    float pos[3], rot[4];
    obj *o = read_pose_args(L, fn, pos, rot);
    if (o->u.body.def.type != PHYS_BODY_KINEMATIC)
        scr_raise(L, "%s: the body is %s: move_to drives kinematic bodies (use teleport, set_velocity or forces)", fn,
                  scr_body_kind_name[o->u.body.def.type]);
    command *c = body_edit(L, fn, CMD_BODY_MOVE_TO, false);
    memcpy(c->u.pose.pos, pos, sizeof pos);
    memcpy(c->u.pose.rot, rot, sizeof rot);
    return 0;
}

static int m_body_teleport(lua_State *L)
{
    const char *fn = "body:teleport";
    float pos[3], rot[4];
    read_pose_args(L, fn, pos, rot);
    command *c = body_edit(L, fn, CMD_BODY_TELEPORT, false);
    obj *o = scr_check_self(L, OBJ_BODY, fn, NULL);
    memcpy(c->u.pose.pos, pos, sizeof pos);
    memcpy(c->u.pose.rot, rot, sizeof rot);
    if (o->state == OBJ_PENDING) { // not in the world yet: change its def instead
        o->u.body.def.position = scr_pv(pos);
        o->u.body.def.orientation = scr_pq(rot);
    }
    return 0;
}

// body:set_colour and body:set_color: one method, two spellings (as the field).
static int set_colour(lua_State *L, const char *fn, const char *what)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    scr_check_self(L, OBJ_BODY, fn, &slot);
    float c3[3];
    scr_check_vec_at(L, 2, fn, what, 3, 0.0, 1.0, 0, "", c3);
    obj *o = scr_check_self(L, OBJ_BODY, fn, &slot); // SCR_SELF_AGAIN
    memcpy(o->u.body.color, c3, sizeof c3);
    command *c = scr_push_command(L, s, CMD_BODY_LOOK, fn);
    c->slot = slot;
    c->gen = o->generation;
    return 0;
}

static int m_body_set_color(lua_State *L) { return set_colour(L, "body:set_color", "argument #1 'color'"); }
static int m_body_set_colour(lua_State *L) { return set_colour(L, "body:set_colour", "argument #1 'colour'"); }

static int m_body_set_visible(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_BODY, "body:set_visible", &slot);
    char got[64];
    if (!lua_isboolean(L, 2))
        scr_raise(L, "body:set_visible: argument #1 'visible' must be true or false (got %s)", scr_describe(L, 2, got, sizeof got));
    o->u.body.visible = lua_toboolean(L, 2);
    command *c = scr_push_command(L, s, CMD_BODY_LOOK, "body:set_visible");
    c->slot = slot;
    c->gen = o->generation;
    return 0;
}

// Releases the grabs that hold body `slot` (Bullet destroys their constraints with it; its
// joints go the same way, scr_release_joints_of).
static void release_grabs_of(eng_script *s, uint32_t slot, uint32_t gen)
{
    for (uint32_t i = 0; i < s->obj_count; i++) {
        obj *g = &s->objs[i];
        if (g->state != OBJ_FREE && g->kind == OBJ_GRAB && g->u.grab.body == slot && g->u.grab.body_gen == gen)
            scr_obj_release(s, i);
    }
}

static int m_body_destroy(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_BODY, "body:destroy", &slot);
    if (o->state == OBJ_LIVE) {
        command *c = scr_push_command(L, s, CMD_BODY_REMOVE, "body:destroy");
        c->u.body.id = o->u.body.id;
        c->u.body.shape = o->u.body.shape_id;
        c->u.body.node = o->u.body.node;
        c->u.body.mesh = o->u.body.mesh;
    }
    release_grabs_of(s, slot, o->generation);
    scr_release_joints_of(s, slot, o->generation);
    scr_obj_release(s, slot);
    return 0;
}

/// The window of pivot motion a release takes its throw from, s.
#define THROW_WINDOW 0.1
/// The fastest throw, m/s (a flick of the mouse far from the camera moves the pivot faster).
#define MAX_THROW_SPEED 20.0

// Notes the pivot's position at the current simulated time (a later move in the same frame
// replaces it).
static void record_pivot(eng_script *s, obj *g, const float p[3])
{
    uint32_t n = g->u.grab.path_count;
    double t = s->host.time;
    double *last = n ? g->u.grab.path[(n - 1) % GRAB_PATH] : NULL;
    double *e = last && last[0] == t ? last : g->u.grab.path[n++ % GRAB_PATH];
    e[0] = t, e[1] = p[0], e[2] = p[1], e[3] = p[2];
    g->u.grab.path_count = n;
}

// The pivot's velocity over the last THROW_WINDOW s, m/s (at most MAX_THROW_SPEED); false when
// fewer than two frames of it are known (grabbed and released in the same frame).
static bool throw_velocity(const eng_script *s, const obj *g, float out[3])
{
    uint32_t n = g->u.grab.path_count, kept = n < GRAB_PATH ? n : GRAB_PATH;
    const double(*path)[4] = g->u.grab.path;
    double dt = s->host.dt, now = s->host.time;
    int frames = (int)floor(THROW_WINDOW / dt + 0.5);
    if (frames < 1) frames = 1;
    double t[64], x[64][3];
    int m = 0;
    for (int j = frames; j >= 0 && m < 64; j--) {
        double tj = now - j * dt;
        // Where the moves left the pivot at tj: the latest one at or before it (none: not held yet).
        const double *at = NULL;
        for (uint32_t k = n - kept; k < n; k++) {
            const double *e = path[k % GRAB_PATH];
            if (e[0] <= tj + 1e-9 * (1.0 + fabs(tj))) at = e;
        }
        if (!at) continue;
        t[m] = tj;
        for (int a = 0; a < 3; a++) x[m][a] = at[a + 1];
        m++;
    }
    if (m < 2) return false;
    double tm = 0, xm[3] = { 0, 0, 0 };
    for (int i = 0; i < m; i++) {
        tm += t[i] / m;
        for (int a = 0; a < 3; a++) xm[a] += x[i][a] / m;
    }
    double stt = 0, stx[3] = { 0, 0, 0 };
    for (int i = 0; i < m; i++) {
        stt += (t[i] - tm) * (t[i] - tm);
        for (int a = 0; a < 3; a++) stx[a] += (t[i] - tm) * (x[i][a] - xm[a]);
    }
    double v[3], speed = 0;
    for (int a = 0; a < 3; a++) {
        v[a] = stx[a] / stt;
        speed += v[a] * v[a];
    }
    speed = sqrt(speed);
    double k = speed > MAX_THROW_SPEED ? MAX_THROW_SPEED / speed : 1.0;
    for (int a = 0; a < 3; a++) out[a] = (float)(v[a] * k);
    return true;
}

static int m_body_grab(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "body:grab";
    uint32_t slot;
    scr_check_self(L, OBJ_BODY, fn, &slot);
    float p[3];
    scr_arg_vec(L, 2, fn, "point", -MAX_COORD, MAX_COORD, "m", p);
    double max_force = 0;
    if (!lua_isnoneornil(L, 3)) max_force = scr_arg_number(L, 3, fn, "max_force", 0, 1e9, OPEN_LO, "N");
    obj *o = scr_check_self(L, OBJ_BODY, fn, &slot); // SCR_SELF_AGAIN
    if (o->u.body.def.type != PHYS_BODY_DYNAMIC)
        scr_raise(L, "%s: the body is %s: only dynamic bodies can be grabbed", fn, scr_body_kind_name[o->u.body.def.type]);
    uint32_t body_gen = o->generation;
    uint32_t g = scr_obj_new(L, s, OBJ_GRAB);
    obj *go = &s->objs[g];
    go->u.grab.body = slot;
    go->u.grab.body_gen = body_gen;
    memcpy(go->u.grab.pivot, p, sizeof p);
    go->u.grab.max_force = (float)max_force;
    record_pivot(s, go, p);
    command *c = scr_push_command(L, s, CMD_GRAB_ADD, fn);
    c->slot = g;
    c->gen = go->generation;
    scr_push_handle(L, s, g);
    return 1;
}

// ---- grabs ------------------------------------------------------------------------------
//
// Throwing: a grab remembers where its pivot was moved and when (simulated time), and its
// release gives the body the pivot's velocity over the last THROW_WINDOW seconds: the slope of
// a least-squares line through the pivot's positions at the frames in that window (where it
// was at each, as the moves left it; a pointer held still counts as a still pivot).

static int m_grab_move(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    scr_check_self(L, OBJ_GRAB, "grab:move", &slot);
    float p[3];
    scr_arg_vec(L, 2, "grab:move", "point", -MAX_COORD, MAX_COORD, "m", p);
    obj *o = scr_check_self(L, OBJ_GRAB, "grab:move", &slot); // SCR_SELF_AGAIN
    memcpy(o->u.grab.pivot, p, sizeof p);
    record_pivot(s, o, p);
    command *c = scr_push_command(L, s, CMD_GRAB_MOVE, "grab:move");
    c->slot = slot;
    c->gen = o->generation;
    memcpy(c->u.vec.v, p, sizeof p);
    return 0;
}

static int m_grab_release(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_GRAB, "grab:release", &slot);
    bool thrown = true;
    char got[64];
    if (!lua_isnoneornil(L, 2) && !lua_isboolean(L, 2))
        scr_raise(L, "grab:release: argument #1 'throw' must be true or false (got %s)", scr_describe(L, 2, got, sizeof got));
    if (lua_isboolean(L, 2)) thrown = lua_toboolean(L, 2);
    if (o->state == OBJ_LIVE) {
        command *c = scr_push_command(L, s, CMD_GRAB_REMOVE, "grab:release");
        c->u.release.id = o->u.grab.id;
        c->u.release.body = o->u.grab.body;
        c->u.release.body_gen = o->u.grab.body_gen;
        c->u.release.thrown = thrown && throw_velocity(s, o, c->u.release.velocity);
    }
    scr_obj_release(s, slot);
    return 0;
}

static int m_grab_body(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    obj *o = scr_check_self(L, OBJ_GRAB, "grab:body", NULL);
    scr_push_handle(L, s, o->u.grab.body);
    return 1;
}

static int m_grab_pivot(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_GRAB, "grab:pivot", NULL);
    scr_push_vec3(L, o->u.grab.pivot[0], o->u.grab.pivot[1], o->u.grab.pivot[2]);
    return 1;
}

static const luaL_Reg functions[] = {
    { "body", l_body }, { "bodies", l_bodies }, { NULL, NULL },
};

static const luaL_Reg body_methods[] = {
    { "position", m_body_position }, { "rotation", m_body_rotation }, { "velocity", m_body_velocity },
    { "angular_velocity", m_body_angular_velocity }, { "velocity_at", m_body_velocity_at }, { "mass", m_body_mass },
    { "kind", m_body_kind }, { "shape", m_body_shape }, { "fluid_force", m_body_fluid_force },
    { "fluid_torque", m_body_fluid_torque }, { "fluid_velocity", m_body_fluid_velocity },
    { "apply_force", m_body_apply_force }, { "apply_torque", m_body_apply_torque },
    { "apply_impulse", m_body_apply_impulse }, { "apply_angular_impulse", m_body_apply_angular_impulse },
    { "set_velocity", m_body_set_velocity }, { "set_angular_velocity", m_body_set_angular_velocity },
    { "move_to", m_body_move_to }, { "teleport", m_body_teleport }, { "set_color", m_body_set_color },
    { "set_colour", m_body_set_colour }, { "set_visible", m_body_set_visible }, { "grab", m_body_grab }, { "destroy", m_body_destroy },
    { "is_valid", scr_is_valid }, { NULL, NULL },
};

static const luaL_Reg grab_methods[] = {
    { "move", m_grab_move }, { "release", m_grab_release }, { "body", m_grab_body }, { "pivot", m_grab_pivot },
    { "is_valid", scr_is_valid }, { NULL, NULL },
};

void scr_open_body(scr_api *api)
{
    scr_api_functions(api, functions);
    scr_api_methods(api, OBJ_BODY, body_methods);
    scr_api_methods(api, OBJ_GRAB, grab_methods);
}
