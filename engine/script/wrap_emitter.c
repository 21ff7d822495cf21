// Binds seiche.emitter and seiche.sink and the methods of their handles (emitter:set, get,
// remove, ...; sink:get, remove, ...).
#include "engine/script/script_internal.h"

#include <math.h>
#include <string.h>

// ---- emitters ----------------------------------------------------------------------------

// Reads the emitter fields of table t over `d` and the tint (which hold the current values).
// Returns true when the table gave a rate.
static bool read_emitter(lua_State *L, eng_script *s, int t, const char *fn, pbf_emitter_def *d, bool full_rate,
                         bool *tinted, float tint[3])
{
    static const char *const known[] = { "position", "direction", "speed", "rate", "radius", "enabled", "colour", "color", NULL };
    scr_check_fields(L, t, fn, known);
    const char *colour = scr_colour_field(L, t, fn);
    if (colour) scr_opt_tint(L, t, fn, colour, tinted, tint);
    scr_opt_position(L, t, fn, "position", d->position);
    char msg[256];
    if (s->host.world && !scr_domain_check(s, d->position, "field 'position'", msg, sizeof msg))
        scr_raise(L, "%s: %s", fn, msg);
    float dir[3];
    if (scr_opt_vec(L, t, fn, "direction", 3, -1e6, 1e6, 0, "", dir)) {
        if (!(fabsf(dir[0]) + fabsf(dir[1]) + fabsf(dir[2]) > 0.0f))
            scr_raise(L, "%s: field 'direction' must not be zero (got {0, 0, 0})", fn);
        memcpy(d->direction, dir, sizeof dir);
    }
    double v;
    if (scr_opt_number(L, t, fn, "speed", 0, 100, OPEN_LO, "m/s", &v)) d->speed = (float)v;
    const pbf_params *p = scr_current_params(s);
    if (scr_opt_number(L, t, fn, "radius", p->particle_radius, 10, 0, "m (the particle radius at least)", &v))
        d->radius = (float)v;
    if (scr_field_present(L, t, "rate")) {
        char got[64];
        double max_rate = s->host.world ? pbf_emitter_max_rate(s->host.world, d->speed, d->radius) : 1e9;
        double r = lua_tonumber(L, -1);
        if (lua_type(L, -1) != LUA_TNUMBER || !(isfinite(r) && r >= 0.0 && r <= max_rate * 1.0001)) {
            if (s->host.world)
                scr_raise(L, "%s: field 'rate' must be a number in [0, %g] particles/s (got %s); %g is the most a nozzle of "
                          "radius %g m pours at speed %g m/s: raise speed or radius for more", fn, max_rate,
                          scr_describe(L, -1, got, sizeof got), max_rate, (double)d->radius, (double)d->speed);
            scr_raise(L, "%s: field 'rate' must be a number >= 0 particles/s, at most seiche.max_emitter_rate(speed, radius) "
                      "(got %s)", fn, scr_describe(L, -1, got, sizeof got));
        }
        d->rate = (float)r;
        lua_pop(L, 1);
        scr_opt_bool(L, t, fn, "enabled", &d->enabled);
        return true;
    } else if (!full_rate && s->host.world && d->rate > pbf_emitter_max_rate(s->host.world, d->speed, d->radius) * 1.0001) {
        double max_rate = pbf_emitter_max_rate(s->host.world, d->speed, d->radius);
        char got[32];
        scr_raise(L, "%s: the rate %s particles/s is more than a nozzle of radius %g m pours at speed %g m/s (at most %g); "
                  "raise speed or radius, or lower rate", fn, scr_fmt_number(d->rate, got, sizeof got), (double)d->radius,
                  (double)d->speed, max_rate);
    }
    scr_opt_bool(L, t, fn, "enabled", &d->enabled);
    return false;
}

// Queues `type` for emitter `slot` with its state as the object holds it now.
static void push_emitter_command(lua_State *L, eng_script *s, cmd_type type, const char *fn, uint32_t slot)
{
    command *c = scr_push_command(L, s, type, fn);
    const obj *o = &s->objs[slot];
    c->slot = slot;
    c->gen = o->generation;
    c->full_rate = o->u.emitter.full_rate;
    c->u.emitter = o->u.emitter.def;
    c->tinted = o->u.emitter.tinted;
    memcpy(c->tint, o->u.emitter.tint, sizeof c->tint);
}

static int l_emitter(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    scr_check_table_arg(L, 1, "seiche.emitter", "position, direction, speed, rate, radius, enabled, colour");
    pbf_emitter_def d = pbf_default_emitter_def();
    lua_getfield(L, 1, "position");
    bool has_pos = !lua_isnil(L, -1);
    lua_pop(L, 1);
    if (!has_pos) scr_raise(L, "seiche.emitter: field 'position' is required: a table of 3 numbers {x, y, z} in m (got nil)");
    bool tinted = false;
    float tint[3] = { 0, 0, 0 };
    bool full = !read_emitter(L, s, 1, "seiche.emitter", &d, true, &tinted, tint);
    uint32_t slot = scr_obj_new(L, s, OBJ_EMITTER);
    s->objs[slot].u.emitter.def = d;
    s->objs[slot].u.emitter.full_rate = full;
    s->objs[slot].u.emitter.tinted = tinted;
    memcpy(s->objs[slot].u.emitter.tint, tint, sizeof tint);
    push_emitter_command(L, s, CMD_EMITTER_ADD, "seiche.emitter", slot);
    scr_push_handle(L, s, slot);
    return 1;
}

static int m_emitter_set(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_EMITTER, "emitter:set", &slot);
    scr_check_table_arg(L, 2, "emitter:set", "position, direction, speed, rate, radius, enabled, colour");
    pbf_emitter_def d = o->u.emitter.def;
    bool tinted = o->u.emitter.tinted;
    float tint[3];
    memcpy(tint, o->u.emitter.tint, sizeof tint);
    bool full_rate = o->u.emitter.full_rate;
    if (read_emitter(L, s, 2, "emitter:set", &d, full_rate, &tinted, tint)) full_rate = false;
    o = scr_check_self(L, OBJ_EMITTER, "emitter:set", &slot); // SCR_SELF_AGAIN
    o->u.emitter.full_rate = full_rate;
    o->u.emitter.def = d;
    o->u.emitter.tinted = tinted;
    memcpy(o->u.emitter.tint, tint, sizeof tint);
    push_emitter_command(L, s, CMD_EMITTER_SET, "emitter:set", slot);
    return 0;
}

static int m_emitter_set_enabled(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_EMITTER, "emitter:set_enabled", &slot);
    char got[64];
    if (!lua_isboolean(L, 2))
        scr_raise(L, "emitter:set_enabled: argument #1 'on' must be true or false (got %s)", scr_describe(L, 2, got, sizeof got));
    o->u.emitter.def.enabled = lua_toboolean(L, 2);
    push_emitter_command(L, s, CMD_EMITTER_SET, "emitter:set_enabled", slot);
    return 0;
}

static int m_emitter_get(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_EMITTER, "emitter:get", NULL);
    const pbf_emitter_def *d = &o->u.emitter.def;
    lua_createtable(L, 0, 6);
    scr_push_vec3(L, d->position[0], d->position[1], d->position[2]);
    lua_setfield(L, -2, "position");
    scr_push_vec3(L, d->direction[0], d->direction[1], d->direction[2]);
    lua_setfield(L, -2, "direction");
    scr_set_num(L, "speed", d->speed);
    eng_script *s = scr_get_script(L);
    if (!o->u.emitter.full_rate) scr_set_num(L, "rate", d->rate);
    else if (s->host.world) scr_set_num(L, "rate", pbf_emitter_max_rate(s->host.world, d->speed, d->radius));
    // else: the most the nozzle can pour, known once the world exists: rate is nil
    scr_set_num(L, "radius", d->radius);
    lua_pushboolean(L, d->enabled);
    lua_setfield(L, -2, "enabled");
    if (o->u.emitter.tinted) scr_push_vec3(L, o->u.emitter.tint[0], o->u.emitter.tint[1], o->u.emitter.tint[2]);
    else lua_pushboolean(L, false);
    lua_pushvalue(L, -1);
    lua_setfield(L, -3, "colour");
    lua_setfield(L, -2, "color"); // both spellings, as the fields take them
    return 1;
}

static int m_emitter_remove(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_EMITTER, "emitter:remove", &slot);
    if (o->state == OBJ_LIVE) {
        command *c = scr_push_command(L, s, CMD_EMITTER_REMOVE, "emitter:remove");
        c->u.emitter_id = o->u.emitter.id;
    }
    scr_obj_release(s, slot);
    return 0;
}

// ---- sinks ----------------------------------------------------------------------------

static int l_sink(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    scr_check_table_arg(L, 1, "seiche.sink", "min = {x, y, z}, max = {x, y, z}");
    static const char *const known[] = { "min", "max", NULL };
    scr_check_fields(L, 1, "seiche.sink", known);
    float mn[3], mx[3];
    scr_read_box(L, 1, "seiche.sink", mn, mx);
    uint32_t slot = scr_obj_new(L, s, OBJ_SINK);
    memcpy(s->objs[slot].u.sink.min, mn, sizeof mn);
    memcpy(s->objs[slot].u.sink.max, mx, sizeof mx);
    command *c = scr_push_command(L, s, CMD_SINK_ADD, "seiche.sink");
    c->slot = slot;
    c->gen = s->objs[slot].generation;
    scr_push_handle(L, s, slot);
    return 1;
}

static int m_sink_get(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_SINK, "sink:get", NULL);
    lua_createtable(L, 0, 2);
    scr_push_vec3(L, o->u.sink.min[0], o->u.sink.min[1], o->u.sink.min[2]);
    lua_setfield(L, -2, "min");
    scr_push_vec3(L, o->u.sink.max[0], o->u.sink.max[1], o->u.sink.max[2]);
    lua_setfield(L, -2, "max");
    return 1;
}

static int m_sink_remove(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_SINK, "sink:remove", &slot);
    if (o->state == OBJ_LIVE) {
        command *c = scr_push_command(L, s, CMD_SINK_REMOVE, "sink:remove");
        c->u.sink_id = o->u.sink.id;
    }
    scr_obj_release(s, slot);
    return 0;
}

static const luaL_Reg functions[] = {
    { "emitter", l_emitter }, { "sink", l_sink }, { NULL, NULL },
};

static const luaL_Reg emitter_methods[] = {
    { "set", m_emitter_set }, { "set_enabled", m_emitter_set_enabled }, { "get", m_emitter_get },
    { "remove", m_emitter_remove }, { "is_valid", scr_is_valid }, { NULL, NULL },
};

static const luaL_Reg sink_methods[] = {
    { "get", m_sink_get }, { "remove", m_sink_remove }, { "is_valid", scr_is_valid }, { NULL, NULL },
};

void scr_open_emitter(scr_api *api)
{
    scr_api_functions(api, functions);
    scr_api_methods(api, OBJ_EMITTER, emitter_methods);
    scr_api_methods(api, OBJ_SINK, sink_methods);
}
