// Shared by the bindings: argument readers that name fn, field, value and rule, vector and
// quaternion helpers, the handles a script holds (slots with a generation) and their metamethods.
#include "engine/script/script_internal.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const scr_kind_name[OBJ_KIND_COUNT] = { "emitter", "sink", "body", "timer", "grab", "joint" };
const char *const scr_kind_meta[OBJ_KIND_COUNT] = { "seiche.emitter", "seiche.sink", "seiche.body", "seiche.timer",
                                                    "seiche.grab", "seiche.joint" };
const char *const scr_shape_name[SHAPE_COUNT] = { "box", "sphere", "capsule", "cylinder", "plane", "hull", "mesh",
                                                  "compound" };
const char *const scr_body_kind_name[3] = { "static", "kinematic", "dynamic" }; // = phys_body_type

// The script of a binding: an upvalue of every function (lmathlib style).
eng_script *scr_get_script(lua_State *L)
{
    eng_script *s = lua_touserdata(L, lua_upvalueindex(1));
    if (s->closing) luaL_error(L, "the scene is closing: a finaliser cannot use the seiche API or its handles");
    return s;
}

int scr_raise(lua_State *L, const char *fmt, ...)
{
    char msg[1536], where[600];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    lua_pushfstring(L, "%s%s", scr_where(L, where, sizeof where), msg);
    return lua_error(L);
}

// ---- arguments -----------------------------------------------------------------------
// Every message names the function, the field or argument, the value given and what is
// allowed: "seiche.emitter: field 'rate' must be a number in [0, 1e+06] particles/s (got -5)".

const char *scr_fmt_number(double v, char *buf, size_t size)
{
    if (isnan(v)) snprintf(buf, size, "nan");
    else if (isinf(v)) snprintf(buf, size, v > 0 ? "inf" : "-inf");
    else if (v == floor(v) && fabs(v) < 1e15) snprintf(buf, size, "%.0f", v);
    else if ((double)(float)v == v) snprintf(buf, size, "%.7g", v); // a float: its 7 digits
    else snprintf(buf, size, "%.14g", v);
    return buf;
}

// What the value at idx is, for "(got ...)": numbers and short strings as written, other
// types by name.
const char *scr_describe(lua_State *L, int idx, char *buf, size_t size)
{
    int t = lua_type(L, idx);
    if (t == LUA_TNUMBER) {
        if (lua_isinteger(L, idx)) snprintf(buf, size, "%lld", (long long)lua_tointeger(L, idx));
        else scr_fmt_number(lua_tonumber(L, idx), buf, size);
    } else if (t == LUA_TSTRING) {
        snprintf(buf, size, "\"%.40s%s\"", lua_tostring(L, idx), lua_rawlen(L, idx) > 40 ? "..." : "");
    } else if (t == LUA_TBOOLEAN) {
        snprintf(buf, size, "%s", lua_toboolean(L, idx) ? "true" : "false");
    } else if (t == LUA_TUSERDATA && luaL_getmetafield(L, idx, "__name") == LUA_TSTRING) {
        snprintf(buf, size, "%s", lua_tostring(L, -1));
        lua_pop(L, 1);
    } else {
        snprintf(buf, size, "%s", luaL_typename(L, idx));
    }
    return buf;
}

// "in [0, 100] m/s", "in (0, 1]", "a finite number" (unbounded).
static const char *range_text(double lo, double hi, int flags, const char *unit, char *buf, size_t size)
{
    char a[32], b[32];
    const char *kind = flags & WHOLE ? "a whole number" : "a number";
    if (lo <= -1e30 && hi >= 1e30) snprintf(buf, size, "a finite number%s%s%s", unit && *unit ? " (" : "", unit ? unit : "", unit && *unit ? ")" : "");
    else snprintf(buf, size, "%s in %c%s, %s%c%s%s", kind, flags & OPEN_LO ? '(' : '[', scr_fmt_number(lo, a, sizeof a),
                  scr_fmt_number(hi, b, sizeof b), flags & OPEN_HI ? ')' : ']', unit && *unit ? " " : "", unit ? unit : "");
    return buf;
}

static bool in_range(double v, double lo, double hi, int flags)
{
    if (!isfinite(v)) return false;
    if (flags & OPEN_LO ? !(v > lo) : !(v >= lo)) return false;
    if (flags & OPEN_HI ? !(v < hi) : !(v <= hi)) return false;
    if ((flags & WHOLE) && v != floor(v)) return false;
    return true;
}

// `what` names the place: "field 'rate'" or "argument #2 'speed'".
double scr_check_number_at(lua_State *L, int idx, const char *fn, const char *what, double lo, double hi, int flags,
                           const char *unit)
{
    char got[64], rule[128];
    if (lua_type(L, idx) != LUA_TNUMBER || !in_range(lua_tonumber(L, idx), lo, hi, flags))
        scr_raise(L, "%s: %s must be %s (got %s)", fn, what, range_text(lo, hi, flags, unit, rule, sizeof rule),
                  scr_describe(L, idx, got, sizeof got));
    return lua_tonumber(L, idx);
}

bool scr_field_present(lua_State *L, int t, const char *field)
{
    lua_getfield(L, t, field);
    if (lua_isnil(L, -1)) {
        lua_pop(L, 1);
        return false;
    }
    return true; // value left on the stack
}

bool scr_opt_number(lua_State *L, int t, const char *fn, const char *field, double lo, double hi, int flags,
                    const char *unit, double *out)
{
    if (!scr_field_present(L, t, field)) return false;
    char what[96];
    snprintf(what, sizeof what, "field '%s'", field);
    *out = scr_check_number_at(L, -1, fn, what, lo, hi, flags, unit);
    lua_pop(L, 1);
    return true;
}

double scr_req_number(lua_State *L, int t, const char *fn, const char *field, double lo, double hi, int flags,
                      const char *unit)
{
    double v = 0.0;
    if (!scr_opt_number(L, t, fn, field, lo, hi, flags, unit, &v)) {
        char rule[128];
        scr_raise(L, "%s: field '%s' is required: %s (got nil)", fn, field, range_text(lo, hi, flags, unit, rule, sizeof rule));
    }
    return v;
}

// The number a message gives argument `idx` of `fn`: Lua's convention, as luaL_argerror
// follows it, counts a method's arguments without self ("body:grab": stack index 2 is #1).
int scr_arg_position(const char *fn, int idx)
{
    size_t name = strcspn(fn, " ");                          // "body:grab", not "seiche.scene: domain"
    const char *colon = memchr(fn, ':', name);
    return colon && colon + 1 < fn + name ? idx - 1 : idx;
}

double scr_arg_number(lua_State *L, int idx, const char *fn, const char *name, double lo, double hi, int flags,
                      const char *unit)
{
    char what[96];
    snprintf(what, sizeof what, "argument #%d '%s'", scr_arg_position(fn, idx), name);
    return scr_check_number_at(L, idx, fn, what, lo, hi, flags, unit);
}

lua_Integer scr_len(lua_State *L, int idx, const char *fn, const char *what)
{
    char got[64];
    lua_len(L, idx);
    int whole;
    lua_Integer n = lua_tointegerx(L, -1, &whole);
    if (!whole)
        scr_raise(L, "%s: %s: its length (from __len) must be a whole number (got %s)", fn, what,
                  scr_describe(L, -1, got, sizeof got));
    lua_pop(L, 1);
    return n;
}

// A vector of n numbers: {a, b, c} or {x = a, y = b, z = c} (w for the fourth).
void scr_check_vec_at(lua_State *L, int idx, const char *fn, const char *what, int n, double lo, double hi,
                      int flags, const char *unit, float *out)
{
    static const char *const names[4] = { "x", "y", "z", "w" };
    char got[64], rule[128];
    idx = lua_absindex(L, idx);
    const char *shape = n == 4 ? "{x, y, z, w}" : "{x, y, z}";
    if (!lua_istable(L, idx))
        scr_raise(L, "%s: %s must be a table of %d numbers %s%s%s (got %s)", fn, what, n, shape, unit && *unit ? " in " : "",
                  unit ? unit : "", scr_describe(L, idx, got, sizeof got));
    lua_geti(L, idx, 1);
    bool named = lua_isnil(L, -1);
    lua_pop(L, 1);
    lua_Integer len = named ? n : scr_len(L, idx, fn, what);
    if (len != n)
        scr_raise(L, "%s: %s must be a table of %d numbers %s (got a table of %lld)", fn, what, n, shape, (long long)len);
    for (int k = 0; k < n; k++) {
        if (named) lua_getfield(L, idx, names[k]);
        else lua_geti(L, idx, k + 1);
        if (lua_type(L, -1) != LUA_TNUMBER || !in_range(lua_tonumber(L, -1), lo, hi, flags))
            scr_raise(L, "%s: %s.%s must be %s (got %s)", fn, what, names[k], range_text(lo, hi, flags, unit, rule, sizeof rule),
                      scr_describe(L, -1, got, sizeof got));
        out[k] = (float)lua_tonumber(L, -1);
        lua_pop(L, 1);
    }
}

bool scr_opt_vec(lua_State *L, int t, const char *fn, const char *field, int n, double lo, double hi, int flags,
                 const char *unit, float *out)
{
    if (!scr_field_present(L, t, field)) return false;
    char what[96];
    snprintf(what, sizeof what, "field '%s'", field);
    scr_check_vec_at(L, -1, fn, what, n, lo, hi, flags, unit, out);
    lua_pop(L, 1);
    return true;
}

bool scr_opt_position(lua_State *L, int t, const char *fn, const char *field, float out[3])
{
    return scr_opt_vec(L, t, fn, field, 3, -MAX_COORD, MAX_COORD, 0, "m", out);
}

void scr_req_position(lua_State *L, int t, const char *fn, const char *field, float out[3])
{
    if (!scr_opt_position(L, t, fn, field, out))
        scr_raise(L, "%s: field '%s' is required: a table of 3 numbers {x, y, z} in m (got nil)", fn, field);
}

void scr_arg_vec(lua_State *L, int idx, const char *fn, const char *name, double lo, double hi, const char *unit,
                 float out[3])
{
    char what[96];
    snprintf(what, sizeof what, "argument #%d '%s'", scr_arg_position(fn, idx), name);
    scr_check_vec_at(L, idx, fn, what, 3, lo, hi, 0, unit, out);
}

bool scr_opt_bool(lua_State *L, int t, const char *fn, const char *field, bool *out)
{
    if (!scr_field_present(L, t, field)) return false;
    char got[64];
    if (!lua_isboolean(L, -1)) scr_raise(L, "%s: field '%s' must be true or false (got %s)", fn, field, scr_describe(L, -1, got, sizeof got));
    *out = lua_toboolean(L, -1);
    lua_pop(L, 1);
    return true;
}

bool scr_opt_color(lua_State *L, int t, const char *fn, const char *field, float out[3])
{
    return scr_opt_vec(L, t, fn, field, 3, 0.0, 1.0, 0, "", out);
}

// Which spelling of a colour field table t gives: "colour", "color" (the same field), or NULL
// for neither; a table that gives both is refused.
const char *scr_colour_field(lua_State *L, int t, const char *fn)
{
    lua_getfield(L, t, "colour");
    bool british = !lua_isnil(L, -1);
    lua_getfield(L, t, "color");
    bool american = !lua_isnil(L, -1);
    lua_pop(L, 2);
    if (british && american)
        scr_raise(L, "%s: give 'colour' or 'color' (two spellings of one field), not both", fn);
    return british ? "colour" : american ? "color" : NULL;
}

// A water tint: {r, g, b} each in [0, 1] (*tinted = true) or false (no tint: the height
// colour). False when the field is absent (nothing changes).
bool scr_opt_tint(lua_State *L, int t, const char *fn, const char *field, bool *tinted, float rgb[3])
{
    if (!scr_field_present(L, t, field)) return false;
    char got[64];
    int type = lua_type(L, -1);
    if (type == LUA_TBOOLEAN && !lua_toboolean(L, -1)) {
        lua_pop(L, 1);
        *tinted = false;
        return true;
    }
    if (type != LUA_TTABLE)
        scr_raise(L, "%s: field '%s' must be a colour {r, g, b} with each in [0, 1], or false for none (got %s)", fn, field,
                  scr_describe(L, -1, got, sizeof got));
    lua_pop(L, 1);
    scr_opt_color(L, t, fn, field, rgb);
    *tinted = true;
    return true;
}

// One of a list of names; returns its index or -1 when the field is absent.
int scr_opt_enum(lua_State *L, int t, const char *fn, const char *field, const char *const *names, int n)
{
    if (!scr_field_present(L, t, field)) return -1;
    if (lua_type(L, -1) == LUA_TSTRING)
        for (int i = 0; i < n; i++)
            if (strcmp(lua_tostring(L, -1), names[i]) == 0) {
                lua_pop(L, 1);
                return i;
            }
    char list[256] = "", got[64];
    size_t len = 0;
    for (int i = 0; i < n && len < sizeof list; i++)
        len += (size_t)snprintf(list + len, sizeof list - len, "%s\"%s\"", i ? ", " : "", names[i]);
    return scr_raise(L, "%s: field '%s' must be one of %s (got %s)", fn, field, list, scr_describe(L, -1, got, sizeof got));
}

void scr_check_table_arg(lua_State *L, int idx, const char *fn, const char *fields)
{
    char got[64];
    if (!lua_istable(L, idx))
        scr_raise(L, "%s: argument #%d must be a table {%s} (got %s)", fn, scr_arg_position(fn, idx), fields,
                  scr_describe(L, idx, got, sizeof got));
}

// A field that must hold a table: "fn: field 'name' must be a table {fields} (got ...)".
void scr_check_table_field(lua_State *L, int idx, const char *fn, const char *field, const char *fields)
{
    char got[64];
    if (!lua_istable(L, idx))
        scr_raise(L, "%s: field '%s' must be a table {%s} (got %s)", fn, field, fields, scr_describe(L, idx, got, sizeof got));
}

// Rejects keys of table t that are not in `known` (a misspelt field is an error, not a no-op).
void scr_check_fields(lua_State *L, int t, const char *fn, const char *const *known)
{
    t = lua_absindex(L, t);
    lua_pushnil(L);
    while (lua_next(L, t)) {
        lua_pop(L, 1);
        bool ok = false;
        if (lua_type(L, -1) == LUA_TSTRING) {
            const char *k = lua_tostring(L, -1);
            for (const char *const *p = known; *p; p++)
                if (strcmp(*p, k) == 0) ok = true;
        }
        if (!ok) {
            char list[640] = "";
            size_t n = 0;
            for (const char *const *p = known; *p && n < sizeof list; p++)
                n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", p == known ? "" : ", ", *p);
            char buf[64];
            scr_raise(L, "%s: unknown field %s (known: %s)", fn, scr_describe(L, -1, buf, sizeof buf), list);
        }
    }
}

// A rotation: a unit quaternion {x, y, z, w} (normalised when its length is within 1 %
// of 1) or {axis = {x, y, z}, angle = radians}.
bool scr_opt_rotation(lua_State *L, int t, const char *fn, const char *field, float q[4])
{
    if (!scr_field_present(L, t, field)) return false;
    int v = lua_gettop(L);
    char what[96], got[64];
    snprintf(what, sizeof what, "field '%s'", field);
    if (!lua_istable(L, v))
        scr_raise(L, "%s: %s must be a unit quaternion {x, y, z, w} or {axis = {x, y, z}, angle = radians} (got %s)", fn,
                  what, scr_describe(L, v, got, sizeof got));
    lua_getfield(L, v, "axis");
    bool axis_angle = !lua_isnil(L, -1);
    lua_pop(L, 1);
    if (axis_angle) {
        static const char *const known[] = { "axis", "angle", NULL };
        char sub[128];
        snprintf(sub, sizeof sub, "%s: field '%s'", fn, field);
        scr_check_fields(L, v, sub, known);
        float axis[3];
        scr_opt_vec(L, v, sub, "axis", 3, -1e6, 1e6, 0, "", axis);
        double angle = scr_req_number(L, v, sub, "angle", -1e6, 1e6, 0, "radians");
        double len = sqrt((double)axis[0] * axis[0] + (double)axis[1] * axis[1] + (double)axis[2] * axis[2]);
        if (!(len > 1e-9)) scr_raise(L, "%s: field '%s'.axis must not be zero (got {0, 0, 0})", fn, field);
        double sn = sin(angle / 2.0) / len;
        q[0] = (float)(axis[0] * sn);
        q[1] = (float)(axis[1] * sn);
        q[2] = (float)(axis[2] * sn);
        q[3] = (float)cos(angle / 2.0);
    } else {
        scr_check_vec_at(L, v, fn, what, 4, -2.0, 2.0, 0, "", q);
        double len = sqrt((double)q[0] * q[0] + (double)q[1] * q[1] + (double)q[2] * q[2] + (double)q[3] * q[3]);
        if (!(fabs(len - 1.0) <= 0.01))
            scr_raise(L, "%s: %s must be a unit quaternion {x, y, z, w} (length 1; got length %.6g); or use {axis = "
                      "{x, y, z}, angle = radians}", fn, what, len);
        for (int k = 0; k < 4; k++) q[k] = (float)(q[k] / len);
    }
    lua_pop(L, 1);
    return true;
}

void scr_read_box(lua_State *L, int t, const char *fn, float mn[3], float mx[3])
{
    scr_req_position(L, t, fn, "min", mn);
    scr_req_position(L, t, fn, "max", mx);
    static const char axis[] = "xyz";
    for (int k = 0; k < 3; k++)
        if (!(mx[k] > mn[k]))
            scr_raise(L, "%s: max.%c must be greater than min.%c (got min %g, max %g)", fn, axis[k], axis[k], (double)mn[k],
                      (double)mx[k]);
}

// A list of n points {{x, y, z}, ...}: pushes a userdata holding 3n floats (garbage
// collected, so nothing leaks when a later check raises) and returns its memory.
float *scr_read_point_list(lua_State *L, int t, const char *fn, const char *field, double lo, double hi,
                           const char *unit, uint32_t *n_out, uint32_t min_n, uint32_t max_n)
{
    char got[64];
    t = lua_absindex(L, t);
    if (!scr_field_present(L, t, field))
        scr_raise(L, "%s: field '%s' is required: a list of %u to %u points {{x, y, z}, ...}", fn, field, min_n, max_n);
    int v = lua_gettop(L);
    if (!lua_istable(L, v))
        scr_raise(L, "%s: field '%s' must be a list of points {{x, y, z}, ...} (got %s)", fn, field, scr_describe(L, v, got, sizeof got));
    char list[96];
    snprintf(list, sizeof list, "field '%s'", field);
    lua_Integer n = scr_len(L, v, fn, list);
    if (n < (lua_Integer)min_n || n > (lua_Integer)max_n)
        scr_raise(L, "%s: field '%s' must hold %u to %u points (got %lld)", fn, field, min_n, max_n, (long long)n);
    float *out = lua_newuserdatauv(L, (size_t)(n > 0 ? n : 1) * 3 * sizeof(float), 0);
    for (lua_Integer i = 1; i <= n; i++) {
        char what[96];
        snprintf(what, sizeof what, "field '%s'[%lld]", field, (long long)i);
        lua_geti(L, v, i);
        scr_check_vec_at(L, -1, fn, what, 3, lo, hi, 0, unit, out + 3 * (i - 1));
        lua_pop(L, 1);
    }
    lua_remove(L, v);
    *n_out = (uint32_t)n;
    return out;
}

// A message of the C API (pbf_, cpl_, phys_) in the script's words: a leading C function or
// struct name ("pbf_world_add_particles: ", "cpl_add_body: ") is dropped and a struct field
// ("pbf_params.iterations", "pbf_emitter_def.radius") becomes the Lua field ("field 'radius'").
const char *scr_lua_wording(const char *msg, char *out, size_t size)
{
    static const char *const prefixes[] = { "pbf_", "cpl_", "phys_" };
    size_t n = 0;
    const char *p = msg;
    for (int i = 0; i < 3; i++) { // a leading "name: "
        size_t len = strlen(prefixes[i]);
        if (strncmp(p, prefixes[i], len) != 0) continue;
        size_t id = strspn(p, "abcdefghijklmnopqrstuvwxyz_0123456789");
        if (p[id] == ':' && p[id + 1] == ' ') p += id + 2;
    }
    while (*p && n + 1 < size) {
        bool at_word = p == msg || !(p[-1] == '_' || (p[-1] >= 'a' && p[-1] <= 'z'));
        size_t id = at_word && (strncmp(p, "pbf_", 4) == 0 || strncmp(p, "cpl_", 4) == 0 || strncmp(p, "phys_", 5) == 0)
                        ? strspn(p, "abcdefghijklmnopqrstuvwxyz_0123456789")
                        : 0;
        size_t field = id && p[id] == '.' ? strspn(p + id + 1, "abcdefghijklmnopqrstuvwxyz_0123456789") : 0;
        if (field > 1) { // "pbf_block_def.velocity" -> "field 'velocity'" (one letter is an axis, not a field)
            n += (size_t)snprintf(out + n, size - n, "field '%.*s'", (int)field, p + id + 1);
            if (n >= size) n = size - 1;
            p += id + 1 + field;
            continue;
        }
        out[n++] = *p++;
    }
    out[n] = 0;
    return out;
}

// ---- small vector and quaternion helpers ------------------------------------------------

void scr_quat_mul(const float a[4], const float b[4], float out[4])
{
    float r[4] = {
        a[3] * b[0] + a[0] * b[3] + a[1] * b[2] - a[2] * b[1],
        a[3] * b[1] - a[0] * b[2] + a[1] * b[3] + a[2] * b[0],
        a[3] * b[2] + a[0] * b[1] - a[1] * b[0] + a[2] * b[3],
        a[3] * b[3] - a[0] * b[0] - a[1] * b[1] - a[2] * b[2],
    };
    memcpy(out, r, sizeof r);
}

void scr_quat_rotate(const float q[4], const float v[3], float out[3])
{
    // v' = v + 2 w (u x v) + 2 u x (u x v)
    float u[3] = { q[0], q[1], q[2] }, w = q[3];
    float t[3] = { 2 * (u[1] * v[2] - u[2] * v[1]), 2 * (u[2] * v[0] - u[0] * v[2]), 2 * (u[0] * v[1] - u[1] * v[0]) };
    float r[3] = { v[0] + w * t[0] + (u[1] * t[2] - u[2] * t[1]), v[1] + w * t[1] + (u[2] * t[0] - u[0] * t[2]),
                   v[2] + w * t[2] + (u[0] * t[1] - u[1] * t[0]) };
    memcpy(out, r, sizeof r);
}

// Pushes {x, y, z} as a table with both an array part and named fields.
void scr_push_vec3(lua_State *L, double x, double y, double z)
{
    lua_createtable(L, 3, 3);
    double v[3] = { x, y, z };
    static const char *const names[3] = { "x", "y", "z" };
    for (int k = 0; k < 3; k++) {
        lua_pushnumber(L, v[k]);
        lua_rawseti(L, -2, k + 1);
        lua_pushnumber(L, v[k]);
        lua_setfield(L, -2, names[k]);
    }
}

void scr_push_quat(lua_State *L, const float q[4])
{
    lua_createtable(L, 4, 4);
    static const char *const names[4] = { "x", "y", "z", "w" };
    for (int k = 0; k < 4; k++) {
        lua_pushnumber(L, q[k]);
        lua_rawseti(L, -2, k + 1);
        lua_pushnumber(L, q[k]);
        lua_setfield(L, -2, names[k]);
    }
}

void scr_set_num(lua_State *L, const char *k, double v)
{
    lua_pushnumber(L, v);
    lua_setfield(L, -2, k);
}

void scr_set_int(lua_State *L, const char *k, lua_Integer v)
{
    lua_pushinteger(L, v);
    lua_setfield(L, -2, k);
}

void scr_push_value(lua_State *L, double v, bool whole)
{
    if (whole && v == floor(v) && fabs(v) < 9.0e15) lua_pushinteger(L, (lua_Integer)v);
    else lua_pushnumber(L, v);
}

// ---- objects and handles --------------------------------------------------------------

obj *scr_obj_at(eng_script *s, uint32_t slot, uint32_t gen)
{
    if (slot >= s->obj_count) return NULL;
    obj *o = &s->objs[slot];
    return o->state != OBJ_FREE && o->generation == gen ? o : NULL;
}

uint32_t scr_obj_new(lua_State *L, eng_script *s, obj_kind kind)
{
    uint32_t slot = s->obj_count;
    for (uint32_t i = 0; i < s->obj_count; i++)
        if (s->objs[i].state == OBJ_FREE) {
            slot = i;
            break;
        }
    if (slot == s->obj_count) {
        if (s->obj_count == s->obj_cap) {
            uint32_t cap = s->obj_cap ? 2 * s->obj_cap : 32;
            if (cap > (1u << 20)) scr_raise(L, "seiche: more than %u live objects (emitters, sinks, bodies, timers)", 1u << 20);
            size_t more = (size_t)(cap - s->obj_cap) * sizeof(obj);
            scr_charge(L, s, "seiche: a new object", more);
            obj *o = realloc(s->objs, (size_t)cap * sizeof *o);
            if (!o) {
                scr_uncharge(s, more);
                scr_raise(L, "seiche: out of memory");
            }
            memset(o + s->obj_cap, 0, (size_t)(cap - s->obj_cap) * sizeof *o);
            s->objs = o;
            s->obj_cap = cap;
        }
        s->obj_count++;
    }
    obj *o = &s->objs[slot];
    uint32_t gen = o->generation + 1;
    memset(o, 0, sizeof *o);
    o->generation = gen;
    o->kind = kind;
    o->state = OBJ_PENDING;
    o->ref = LUA_NOREF;
    return slot;
}

size_t scr_body_data_bytes(const body_rec *b)
{
    return (size_t)b->point_count * 3 * sizeof(float) + (size_t)b->index_count * sizeof(uint32_t) +
           (size_t)b->part_count * sizeof(body_part) + scr_mesh_bytes(b->file);
}

void scr_body_free_data(eng_script *s, body_rec *b)
{
    if (b->points || b->indices || b->parts || b->file) scr_uncharge(s, scr_body_data_bytes(b));
    free(b->points);
    free(b->indices);
    free(b->parts);
    if (b->file) scr_free_mesh(b->file);
    b->points = NULL;
    b->indices = NULL;
    b->parts = NULL;
    b->file = NULL;
}

// Frees the slot: every handle to it becomes stale ("attempt to use a destroyed ...").
void scr_obj_release(eng_script *s, uint32_t slot)
{
    obj *o = &s->objs[slot];
    if (o->ref != LUA_NOREF) luaL_unref(s->L, LUA_REGISTRYINDEX, o->ref);
    if (o->kind == OBJ_TIMER && o->u.timer.fn != LUA_NOREF) luaL_unref(s->L, LUA_REGISTRYINDEX, o->u.timer.fn);
    if (o->kind == OBJ_BODY) scr_body_free_data(s, &o->u.body);
    uint32_t gen = o->generation;
    memset(o, 0, sizeof *o);
    o->generation = gen;
    o->state = OBJ_FREE;
    o->ref = LUA_NOREF;
}

// Pushes the (one) userdata of an object, making it on first use.
void scr_push_handle(lua_State *L, eng_script *s, uint32_t slot)
{
    obj *o = &s->objs[slot];
    if (o->ref != LUA_NOREF) {
        lua_rawgeti(L, LUA_REGISTRYINDEX, o->ref);
        return;
    }
    handle *h = lua_newuserdatauv(L, sizeof *h, 1);
    h->slot = slot;
    h->generation = o->generation;
    lua_newtable(L);
    lua_setiuservalue(L, -2, 1);
    luaL_setmetatable(L, scr_kind_meta[o->kind]);
    lua_pushvalue(L, -1);
    o->ref = luaL_ref(L, LUA_REGISTRYINDEX);
}

// The object behind argument 1 of a method `fn` ("body:position"): a live handle of the
// right kind, or an error that says what went wrong.
obj *scr_check_self(lua_State *L, obj_kind kind, const char *fn, uint32_t *slot_out)
{
    eng_script *s = scr_get_script(L);
    handle *h = luaL_testudata(L, 1, scr_kind_meta[kind]);
    if (!h) {
        char got[64];
        scr_raise(L, "%s: 'self' must be %s %s (got %s); call methods with a colon: x:%s(...)", fn,
                  kind == OBJ_EMITTER ? "an" : "a", scr_kind_name[kind], scr_describe(L, 1, got, sizeof got), strchr(fn, ':') + 1);
    }
    obj *o = scr_obj_at(s, h->slot, h->generation);
    if (!o || o->kind != kind) scr_raise(L, "%s: attempt to use a destroyed %s", fn, scr_kind_name[kind]);
    if (slot_out) *slot_out = h->slot;
    return o;
}

// x:is_valid() for every handle type: false once removed or destroyed.
int scr_is_valid(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    bool ok = false;
    for (int k = 0; k < OBJ_KIND_COUNT && !ok; k++) {
        handle *h = luaL_testudata(L, 1, scr_kind_meta[k]);
        obj *o = h ? scr_obj_at(s, h->slot, h->generation) : NULL;
        ok = o && o->kind == (obj_kind)k;
    }
    lua_pushboolean(L, ok);
    return 1;
}

// ---- handle metamethods -------------------------------------------------------------------

static int m_tostring(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    for (int k = 0; k < OBJ_KIND_COUNT; k++) {
        handle *h = luaL_testudata(L, 1, scr_kind_meta[k]);
        if (!h) continue;
        obj *o = scr_obj_at(s, h->slot, h->generation);
        if (o && o->kind != (obj_kind)k) o = NULL;
        if (!o) lua_pushfstring(L, "%s #%d (destroyed)", scr_kind_name[k], (int)h->slot + 1);
        else if (k == OBJ_BODY)
            lua_pushfstring(L, "body #%d (%s %s%s)", (int)h->slot + 1, scr_body_kind_name[o->u.body.def.type],
                            scr_shape_name[o->u.body.shape], o->state == OBJ_PENDING ? ", not yet in the world" : "");
        else if (k == OBJ_JOINT)
            lua_pushfstring(L, "joint #%d (%s%s)", (int)h->slot + 1, scr_joint_kind_name[o->u.joint.type],
                            o->state == OBJ_PENDING ? ", not yet in the world" : "");
        else lua_pushfstring(L, "%s #%d%s", scr_kind_name[k], (int)h->slot + 1, o->state == OBJ_PENDING ? " (not yet in the world)" : "");
        return 1;
    }
    return luaL_tolstring(L, 1, NULL) != NULL;
}

// h.key: a method, else the handle's own field (scripts may keep data on handles).
static int m_index(lua_State *L)
{
    lua_getmetatable(L, 1);
    lua_getfield(L, -1, "methods");
    lua_pushvalue(L, 2);
    lua_rawget(L, -2);
    if (!lua_isnil(L, -1)) return 1;
    lua_getiuservalue(L, 1, 1);
    lua_pushvalue(L, 2);
    lua_rawget(L, -2);
    return 1;
}

static int m_newindex(lua_State *L)
{
    lua_getmetatable(L, 1);
    lua_getfield(L, -1, "methods");
    lua_pushvalue(L, 2);
    lua_rawget(L, -2);
    if (!lua_isnil(L, -1)) {
        lua_getfield(L, -3, "__name");
        return scr_raise(L, "%s: '%s' is a method and cannot be assigned", lua_tostring(L, -1),
                         lua_type(L, 2) == LUA_TSTRING ? lua_tostring(L, 2) : "?");
    }
    lua_getiuservalue(L, 1, 1);
    lua_pushvalue(L, 2);
    lua_pushvalue(L, 3);
    lua_rawset(L, -3);
    return 0;
}

// The metatable of a handle kind: its methods (in a table of their own, each with the script
// as upvalue) and the metamethods every handle shares.
void scr_new_handle_type(lua_State *L, eng_script *s, obj_kind kind, const luaL_Reg *methods)
{
    luaL_newmetatable(L, scr_kind_meta[kind]);
    lua_newtable(L);
    lua_pushlightuserdata(L, s);
    luaL_setfuncs(L, methods, 1);
    lua_setfield(L, -2, "methods");
    static const luaL_Reg meta[] = { { "__index", m_index }, { "__newindex", m_newindex },
                                     { "__tostring", m_tostring }, { NULL, NULL } };
    lua_pushlightuserdata(L, s);
    luaL_setfuncs(L, meta, 1);
    lua_pushboolean(L, false);
    lua_setfield(L, -2, "__metatable"); // getmetatable(h) returns false: the methods are not for editing
    lua_pop(L, 1);
}

// ---- state the bindings share ------------------------------------------------------------

// The fluid parameters as they will be once the queued changes are applied.
const pbf_params *scr_current_params(eng_script *s)
{
    if (s->have_pending_params) return &s->pending_params;
    if (s->host.world) return pbf_world_params(s->host.world);
    return &scr_config_view(s)->params;
}

// The scene description as the world will be built from it: the config with the host's
// overrides (--set) applied, or the config itself.
const eng_scene_config *scr_config_view(eng_script *s)
{
    if (!s->host.apply_overrides) return &s->config;
    s->config_view = s->config;
    return s->host.apply_overrides(s->host.overrides_user, &s->config_view) ? &s->config_view : &s->config;
}

void scr_require_world(lua_State *L, eng_script *s, const char *fn)
{
    if (!s->host.world)
        scr_raise(L, "%s: the world is built after the script's main chunk; call this from a callback (on_start, "
                  "on_step, ...)", fn);
}

uint32_t scr_capacity_of(eng_script *s)
{
    return s->host.world ? pbf_world_capacity(s->host.world) : scr_config_view(s)->capacity;
}
