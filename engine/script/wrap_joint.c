// Binds seiche.joint (hinge, slider, fixed and point joints between two bodies, or a body and
// the world; fluid/bullet/phys.h "Joints") and the joint methods: what it measures (angle,
// position, force), its motor and limits, its bodies, removal.
//
// A joint names its bodies by their slots and generations: destroying either body releases
// the joint's handles (scr_release_joints_of; Bullet destroys the joint with the body), and a
// reset throws the whole script away, handles and all.
#include "engine/script/script_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

const char *const scr_joint_kind_name[5] = { "", "hinge", "slider", "fixed", "point" };

static const char *const JOINT_FIELDS[] = { "kind", "a", "b", "pivot", "anchor", "axis", "limits", "motor", "collide",
                                            NULL };

// The fields each kind takes besides kind, a, b and collide.
static const char *const KIND_FIELDS[5][5] = {
    { NULL },
    { "pivot", "axis", "limits", "motor", NULL },
    { "anchor", "axis", "limits", "motor", NULL },
    { NULL },
    { "pivot", NULL },
};

// The measure of a kind: its unit and range, and its motor's strength field.
static const char *unit_of(phys_joint_type t) { return t == PHYS_JOINT_HINGE ? "rad" : "m"; }
// (A float π: the range reads 3.141593 and math.pi passes.)
static double limit_of(phys_joint_type t) { return t == PHYS_JOINT_HINGE ? (double)(float)PI : MAX_COORD; }
static const char *strength_of(phys_joint_type t) { return t == PHYS_JOINT_HINGE ? "max_torque" : "max_force"; }

// The body handle at index idx (a field's value): a body that is not destroyed. Returns its
// slot; *gen its generation.
static uint32_t check_body_value(lua_State *L, int idx, const char *fn, const char *what, uint32_t *gen)
{
    eng_script *s = scr_get_script(L);
    handle *h = luaL_testudata(L, idx, scr_kind_meta[OBJ_BODY]);
    char got[64];
    if (!h) scr_raise(L, "%s: %s must be a body (got %s)", fn, what, scr_describe(L, idx, got, sizeof got));
    obj *o = scr_obj_at(s, h->slot, h->generation);
    if (!o || o->kind != OBJ_BODY) scr_raise(L, "%s: %s is a destroyed body", fn, what);
    *gen = h->generation;
    return h->slot;
}

// {lo, hi} of field 'limits' (or argument #2 of set_limits, at index t).
static void read_limits(lua_State *L, int t, const char *fn, const char *what, phys_joint_type type, float *lo,
                        float *hi)
{
    char got[64];
    const char *unit = unit_of(type);
    double range = limit_of(type);
    if (!lua_istable(L, t) || scr_len(L, t, fn, what) != 2)
        scr_raise(L, "%s: %s must be a table {lo, hi} of 2 numbers in [%.7g, %.7g] %s, lo <= hi (got %s)", fn, what, -range,
                  range, unit, lua_istable(L, t) ? "a table of another length" : scr_describe(L, t, got, sizeof got));
    double v[2];
    for (int k = 0; k < 2; k++) {
        char item[96];
        snprintf(item, sizeof item, "%s[%d]", what, k + 1);
        lua_geti(L, t, k + 1);
        v[k] = scr_check_number_at(L, -1, fn, item, -range, range, 0, unit);
        lua_pop(L, 1);
    }
    if (!(v[0] <= v[1])) scr_raise(L, "%s: %s must have lo <= hi (got {%g, %g})", fn, what, v[0], v[1]);
    *lo = (float)v[0];
    *hi = (float)v[1];
}

// {speed = .., max_torque = ..} (hinge) or {speed = .., max_force = ..} (slider) at index t.
static void read_motor(lua_State *L, int t, const char *fn, const char *what, phys_joint_type type, float *speed,
                       float *max)
{
    char got[64], sub[128];
    const char *strength = strength_of(type);
    if (!lua_istable(L, t))
        scr_raise(L, "%s: %s must be a table {speed = %s, %s = %s} (got %s)", fn, what,
                  type == PHYS_JOINT_HINGE ? "rad/s" : "m/s", strength, type == PHYS_JOINT_HINGE ? "N m" : "N",
                  scr_describe(L, t, got, sizeof got));
    snprintf(sub, sizeof sub, "%s: %s", fn, what);
    const char *const known[] = { "speed", strength, NULL };
    scr_check_fields(L, t, sub, known);
    *speed = (float)scr_req_number(L, t, sub, "speed", -MAX_SPEED, MAX_SPEED, 0, type == PHYS_JOINT_HINGE ? "rad/s" : "m/s");
    *max = (float)scr_req_number(L, t, sub, strength, 0, 1e9, 0, type == PHYS_JOINT_HINGE ? "N m" : "N");
}

// A unit axis from field 'axis' (required).
static void read_axis(lua_State *L, const char *fn, phys_joint_type type, float axis[3])
{
    if (!scr_opt_vec(L, 1, fn, "axis", 3, -1e6, 1e6, 0, "", axis))
        scr_raise(L, "%s: field 'axis' is required for a %s: a direction {x, y, z}, not zero (got nil)", fn,
                  scr_joint_kind_name[type]);
    double len = sqrt((double)axis[0] * axis[0] + (double)axis[1] * axis[1] + (double)axis[2] * axis[2]);
    if (!(len > 1e-9)) scr_raise(L, "%s: field 'axis' must not be zero (got {0, 0, 0})", fn);
    for (int k = 0; k < 3; k++) axis[k] = (float)(axis[k] / len);
}

static int l_joint(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.joint";
    scr_check_table_arg(L, 1, fn, "kind = \"hinge\", a = body, b = body, pivot = {x, y, z}, axis = {x, y, z}, ...");
    scr_check_fields(L, 1, fn, JOINT_FIELDS);
    int kind = scr_opt_enum(L, 1, fn, "kind", scr_joint_kind_name + 1, 4);
    if (kind < 0)
        scr_raise(L, "%s: field 'kind' is required: one of \"hinge\", \"slider\", \"fixed\", \"point\" (got nil)", fn);
    joint_rec j;
    memset(&j, 0, sizeof j);
    j.type = (phys_joint_type)(kind + 1);
    // Fields of other kinds are errors, not silently ignored.
    static const char *const optional[] = { "pivot", "anchor", "axis", "limits", "motor", NULL };
    for (const char *const *f = optional; *f; f++) {
        bool mine = false;
        for (const char *const *k = KIND_FIELDS[j.type]; *k; k++) mine |= strcmp(*k, *f) == 0;
        if (mine || !scr_field_present(L, 1, *f)) continue;
        char list[96] = "";
        size_t n = 0;
        for (const char *const *k = KIND_FIELDS[j.type]; *k; k++)
            n += (size_t)snprintf(list + n, sizeof list - n, "%s'%s'", n ? ", " : "", *k);
        scr_raise(L, "%s: field '%s' does not apply to a %s joint (it takes %s%s)", fn, *f, scr_joint_kind_name[j.type],
                  n ? list : "no fields but ", n ? "" : "kind, a, b and collide");
    }
    // The bodies.
    if (!scr_field_present(L, 1, "a"))
        scr_raise(L, "%s: field 'a' is required: the dynamic body the joint holds (got nil)", fn);
    j.a_slot = check_body_value(L, -1, fn, "field 'a'", &j.a_gen);
    lua_pop(L, 1);
    j.b_slot = NO_SLOT;
    if (scr_field_present(L, 1, "b")) {
        j.b_slot = check_body_value(L, -1, fn, "field 'b'", &j.b_gen);
        lua_pop(L, 1);
        if (j.b_slot == j.a_slot) scr_raise(L, "%s: fields 'a' and 'b' are the same body: a joint ties two bodies (leave "
                                            "'b' out to tie 'a' to the world)", fn);
    }
    const body_rec *a = &s->objs[j.a_slot].u.body;
    if (a->def.type != PHYS_BODY_DYNAMIC)
        scr_raise(L, "%s: field 'a' must be a dynamic body (got a %s body): a joint moves body a; make the %s body 'b'",
                  fn, scr_body_kind_name[a->def.type], scr_body_kind_name[a->def.type]);
    scr_opt_bool(L, 1, fn, "collide", &j.collide);
    // Where and about what.
    if (j.type == PHYS_JOINT_HINGE || j.type == PHYS_JOINT_POINT) {
        if (!scr_opt_position(L, 1, fn, "pivot", j.pivot))
            scr_raise(L, "%s: field 'pivot' is required for a %s: the world point {x, y, z} m it turns about (got nil)",
                      fn, scr_joint_kind_name[j.type]);
    }
    if (j.type == PHYS_JOINT_SLIDER && !scr_opt_position(L, 1, fn, "anchor", j.pivot)) {
        obj *ao = scr_obj_at(s, j.a_slot, j.a_gen); // reading the fields may have run Lua (SCR_SELF_AGAIN)
        if (!ao) scr_raise(L, "%s: field 'a': the body was destroyed while the joint's fields were read", fn);
        scr_body_state(s, ao, j.pivot, NULL, NULL, NULL); // default: a's centre
    }
    if (j.type == PHYS_JOINT_HINGE || j.type == PHYS_JOINT_SLIDER) read_axis(L, fn, j.type, j.axis);
    if (scr_field_present(L, 1, "limits")) {
        read_limits(L, lua_gettop(L), fn, "field 'limits'", j.type, &j.lo, &j.hi);
        j.limit = true;
        lua_pop(L, 1);
    }
    if (scr_field_present(L, 1, "motor")) {
        read_motor(L, lua_gettop(L), fn, "field 'motor'", j.type, &j.speed, &j.max);
        j.motor = true;
        lua_pop(L, 1);
    }
    uint32_t slot = scr_obj_new(L, s, OBJ_JOINT);
    obj *o = &s->objs[slot];
    o->u.joint = j;
    command *c = scr_push_command(L, s, CMD_JOINT_ADD, fn);
    c->slot = slot;
    c->gen = o->generation;
    scr_push_handle(L, s, slot);
    return 1;
}

// ---- applying -------------------------------------------------------------------------------

static phys_body_id live_body_id(eng_script *s, uint32_t slot, uint32_t gen, bool *ok)
{
    obj *o = scr_obj_at(s, slot, gen);
    *ok = o && o->kind == OBJ_BODY && o->state == OBJ_LIVE;
    return *ok ? o->u.body.id : (phys_body_id){ 0, 0, 0 };
}

static eng_script_status add_joint(eng_script *s, const command *c, obj *o)
{
    phys_world *w = s->host.phys;
    joint_rec *j = &o->u.joint;
    bool ok_a, ok_b = true;
    phys_body_id a = live_body_id(s, j->a_slot, j->a_gen, &ok_a), b = { 0, 0, 0 };
    if (j->b_slot != NO_SLOT) b = live_body_id(s, j->b_slot, j->b_gen, &ok_b);
    if (!ok_a || !ok_b) return ENG_SCRIPT_OK; // a body was refused or destroyed first: the joint is gone with it
    phys_result r = PHYS_OK;
    switch (j->type) {
    case PHYS_JOINT_HINGE: {
        phys_hinge_joint_def d = phys_default_hinge_joint_def();
        d.body_a = a, d.body_b = b, d.pivot = scr_pv(j->pivot), d.axis = scr_pv(j->axis);
        d.enable_limit = j->limit, d.lower_angle = j->lo, d.upper_angle = j->hi;
        d.enable_motor = j->motor, d.motor_speed = j->speed, d.max_motor_torque = j->max;
        d.collide_connected = j->collide;
        r = phys_joint_create_hinge(w, &d, &j->id);
        break;
    }
    case PHYS_JOINT_SLIDER: {
        phys_slider_joint_def d = phys_default_slider_joint_def();
        d.body_a = a, d.body_b = b, d.anchor = scr_pv(j->pivot), d.axis = scr_pv(j->axis);
        d.enable_limit = j->limit, d.lower_translation = j->lo, d.upper_translation = j->hi;
        d.enable_motor = j->motor, d.motor_speed = j->speed, d.max_motor_force = j->max;
        d.collide_connected = j->collide;
        r = phys_joint_create_slider(w, &d, &j->id);
        break;
    }
    case PHYS_JOINT_FIXED: {
        phys_fixed_joint_def d = phys_default_fixed_joint_def();
        d.body_a = a, d.body_b = b, d.collide_connected = j->collide;
        r = phys_joint_create_fixed(w, &d, &j->id);
        break;
    }
    case PHYS_JOINT_POINT: {
        phys_point_joint_def d = phys_default_point_joint_def();
        d.body_a = a, d.body_b = b, d.pivot = scr_pv(j->pivot), d.collide_connected = j->collide;
        r = phys_joint_create_point(w, &d, &j->id);
        break;
    }
    }
    if (r != PHYS_OK) return scr_refuse(s, c, "%s", phys_world_last_error(w));
    o->state = OBJ_LIVE;
    return ENG_SCRIPT_OK;
}

eng_script_status scr_apply_joint(eng_script *s, const command *c)
{
    phys_world *w = s->host.phys;
    if (c->type == CMD_JOINT_ADD) {
        obj *o = scr_obj_at(s, c->slot, c->gen);
        return o ? add_joint(s, c, o) : ENG_SCRIPT_OK;
    }
    // A joint made in the same frame got its id when its CMD_JOINT_ADD was applied.
    obj *o = scr_obj_at(s, c->slot, c->gen);
    phys_joint_id id = o && o->kind == OBJ_JOINT && o->state == OBJ_LIVE ? o->u.joint.id : c->u.joint.id;
    if (!phys_joint_is_valid(w, id)) return ENG_SCRIPT_OK; // gone with a body, or never made
    phys_result r = PHYS_OK;
    if (c->type == CMD_JOINT_MOTOR) r = phys_joint_set_motor(w, id, c->u.joint.on, c->u.joint.a, c->u.joint.b);
    else if (c->type == CMD_JOINT_LIMITS) r = phys_joint_set_limits(w, id, c->u.joint.on, c->u.joint.a, c->u.joint.b);
    else r = phys_joint_destroy(w, id);
    return r == PHYS_OK ? ENG_SCRIPT_OK : scr_refuse(s, c, "%s", phys_world_last_error(w));
}

void scr_release_joints_of(eng_script *s, uint32_t slot, uint32_t gen)
{
    for (uint32_t i = 0; i < s->obj_count; i++) {
        obj *o = &s->objs[i];
        if (o->state == OBJ_FREE || o->kind != OBJ_JOINT) continue;
        const joint_rec *j = &o->u.joint;
        if ((j->a_slot == slot && j->a_gen == gen) || (j->b_slot == slot && j->b_gen == gen)) scr_obj_release(s, i);
    }
}

// ---- methods --------------------------------------------------------------------------------

// A queued change of a live or pending joint (a pending one's id is looked up when applied).
static command *joint_edit(lua_State *L, eng_script *s, obj *o, uint32_t slot, cmd_type type, const char *fn)
{
    command *c = scr_push_command(L, s, type, fn);
    c->slot = slot;
    c->gen = o->generation;
    c->u.joint.id = o->u.joint.id;
    return c;
}

static int m_joint_angle(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    obj *o = scr_check_self(L, OBJ_JOINT, "joint:angle", NULL);
    if (o->u.joint.type != PHYS_JOINT_HINGE)
        scr_raise(L, "joint:angle: the joint is a %s: angle() measures hinges (position() measures sliders)",
                  scr_joint_kind_name[o->u.joint.type]);
    float a = 0.0f;
    if (o->state == OBJ_LIVE && s->host.phys) phys_joint_get_angle(s->host.phys, o->u.joint.id, &a);
    lua_pushnumber(L, a);
    return 1;
}

static int m_joint_position(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    obj *o = scr_check_self(L, OBJ_JOINT, "joint:position", NULL);
    if (o->u.joint.type != PHYS_JOINT_SLIDER)
        scr_raise(L, "joint:position: the joint is a %s: position() measures sliders (angle() measures hinges)",
                  scr_joint_kind_name[o->u.joint.type]);
    float p = 0.0f;
    if (o->state == OBJ_LIVE && s->host.phys) phys_joint_get_position(s->host.phys, o->u.joint.id, &p);
    lua_pushnumber(L, p);
    return 1;
}

// What the joint did to body a during the last Bullet step, as a force and a torque.
static int m_joint_force(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    obj *o = scr_check_self(L, OBJ_JOINT, "joint:force", NULL);
    phys_vec3 j = { 0, 0, 0 }, t = { 0, 0, 0 };
    if (o->state == OBJ_LIVE && s->host.phys && s->host.world &&
        phys_joint_get_applied_impulse(s->host.phys, o->u.joint.id, &j, &t) == PHYS_OK) {
        double h = s->host.dt / pbf_world_params(s->host.world)->substeps; // one Bullet step
        j = (phys_vec3){ (float)(j.x / h), (float)(j.y / h), (float)(j.z / h) };
        t = (phys_vec3){ (float)(t.x / h), (float)(t.y / h), (float)(t.z / h) };
    }
    scr_push_vec3(L, j.x, j.y, j.z);
    scr_push_vec3(L, t.x, t.y, t.z);
    return 2;
}

// set_motor{speed, max_torque | max_force} or set_motor(false).
static int m_joint_set_motor(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "joint:set_motor";
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_JOINT, fn, &slot);
    joint_rec *j = &o->u.joint;
    if (j->type != PHYS_JOINT_HINGE && j->type != PHYS_JOINT_SLIDER)
        scr_raise(L, "%s: the joint is a %s: only hinges and sliders have a motor", fn, scr_joint_kind_name[j->type]);
    bool on = !(lua_isboolean(L, 2) && !lua_toboolean(L, 2));
    float speed = j->speed, max = j->max;
    if (on) read_motor(L, 2, fn, "argument #1 'motor' (or false)", j->type, &speed, &max);
    o = scr_check_self(L, OBJ_JOINT, fn, &slot); // SCR_SELF_AGAIN
    j = &o->u.joint;
    j->motor = on;
    j->speed = speed;
    j->max = max;
    command *c = joint_edit(L, s, o, slot, CMD_JOINT_MOTOR, fn);
    c->u.joint.on = j->motor;
    c->u.joint.a = j->speed;
    c->u.joint.b = j->max;
    return 0;
}

// set_limits{lo, hi} or set_limits(false).
static int m_joint_set_limits(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "joint:set_limits";
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_JOINT, fn, &slot);
    joint_rec *j = &o->u.joint;
    if (j->type != PHYS_JOINT_HINGE && j->type != PHYS_JOINT_SLIDER)
        scr_raise(L, "%s: the joint is a %s: only hinges and sliders have limits", fn, scr_joint_kind_name[j->type]);
    bool on = !(lua_isboolean(L, 2) && !lua_toboolean(L, 2));
    float lo = j->lo, hi = j->hi;
    if (on) read_limits(L, 2, fn, "argument #1 'limits' (or false)", j->type, &lo, &hi);
    o = scr_check_self(L, OBJ_JOINT, fn, &slot); // SCR_SELF_AGAIN
    j = &o->u.joint;
    j->limit = on;
    j->lo = lo;
    j->hi = hi;
    command *c = joint_edit(L, s, o, slot, CMD_JOINT_LIMITS, fn);
    c->u.joint.on = j->limit;
    c->u.joint.a = j->lo;
    c->u.joint.b = j->hi;
    return 0;
}

static int m_joint_remove(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_JOINT, "joint:remove", &slot);
    if (o->state == OBJ_LIVE) joint_edit(L, s, o, slot, CMD_JOINT_REMOVE, "joint:remove");
    scr_obj_release(s, slot);
    return 0;
}

static int m_joint_bodies(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    obj *o = scr_check_self(L, OBJ_JOINT, "joint:bodies", NULL);
    uint32_t a = o->u.joint.a_slot, b = o->u.joint.b_slot;
    scr_push_handle(L, s, a);
    if (b == NO_SLOT) lua_pushnil(L);
    else scr_push_handle(L, s, b);
    return 2;
}

static int m_joint_get(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_JOINT, "joint:get", NULL);
    const joint_rec *j = &o->u.joint;
    lua_createtable(L, 0, 8);
    lua_pushstring(L, scr_joint_kind_name[j->type]);
    lua_setfield(L, -2, "kind");
    lua_pushboolean(L, j->collide);
    lua_setfield(L, -2, "collide");
    if (j->type == PHYS_JOINT_HINGE || j->type == PHYS_JOINT_POINT || j->type == PHYS_JOINT_SLIDER) {
        scr_push_vec3(L, j->pivot[0], j->pivot[1], j->pivot[2]);
        lua_setfield(L, -2, j->type == PHYS_JOINT_SLIDER ? "anchor" : "pivot");
    }
    if (j->type != PHYS_JOINT_HINGE && j->type != PHYS_JOINT_SLIDER) return 1;
    scr_push_vec3(L, j->axis[0], j->axis[1], j->axis[2]);
    lua_setfield(L, -2, "axis");
    if (j->limit) {
        lua_createtable(L, 2, 0);
        lua_pushnumber(L, j->lo);
        lua_rawseti(L, -2, 1);
        lua_pushnumber(L, j->hi);
        lua_rawseti(L, -2, 2);
        lua_setfield(L, -2, "limits");
    }
    if (j->motor) {
        lua_createtable(L, 0, 2);
        scr_set_num(L, "speed", j->speed);
        scr_set_num(L, strength_of(j->type), j->max);
        lua_setfield(L, -2, "motor");
    }
    return 1;
}

static const luaL_Reg functions[] = { { "joint", l_joint }, { NULL, NULL } };

static const luaL_Reg joint_methods[] = {
    { "angle", m_joint_angle }, { "position", m_joint_position }, { "force", m_joint_force },
    { "set_motor", m_joint_set_motor }, { "set_limits", m_joint_set_limits }, { "bodies", m_joint_bodies },
    { "get", m_joint_get }, { "remove", m_joint_remove }, { "is_valid", scr_is_valid }, { NULL, NULL },
};

void scr_open_joint(scr_api *api)
{
    scr_api_functions(api, functions);
    scr_api_methods(api, OBJ_JOINT, joint_methods);
}
