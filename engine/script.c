// Lua host for scene scripts. See script.h and docs/lua-api.md.
#include "engine/script.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <lauxlib.h>
#include <lua.h>
#include <lualib.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct eng_script {
    lua_State *L;
    eng_logger log;
    double budget_s;
    double deadline;      // monotonic seconds; 0 when no callback runs
    const char *running;  // name of the running callback, for messages
    char path[512];
    char error[4096];
    bool check_failed;
    bool quit;
    bool scene_called;
    eng_scene_config config;
    eng_command *commands;
    int command_count, command_cap;
    eng_script_host host;
};

static const char *const REGISTRY_KEY = "seiche.script";

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

eng_scene_config eng_default_scene_config(void)
{
    eng_scene_config c;
    memset(&c, 0, sizeof c);
    snprintf(c.name, sizeof c.name, "scene");
    c.params = pbf_default_params();
    c.capacity = 65536;
    c.camera_eye[0] = 2.0f;
    c.camera_eye[1] = 1.5f;
    c.camera_eye[2] = 3.0f;
    c.camera_fov = 50.0f;
    return c;
}

static eng_script *get_script(lua_State *L)
{
    lua_getfield(L, LUA_REGISTRYINDEX, REGISTRY_KEY);
    eng_script *s = lua_touserdata(L, -1);
    lua_pop(L, 1);
    return s;
}

// Raises a Lua error with the caller's file:line, formatted by printf rules (luaL_error's
// own formatter knows no %g).
static int raise(lua_State *L, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
static int raise(lua_State *L, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    luaL_where(L, 1);
    lua_pushstring(L, msg);
    lua_concat(L, 2);
    return lua_error(L);
}

// ---- argument helpers: every message names the function, the field, the value given and
// what is allowed; luaL_error prefixes the script's file:line.

static const char *describe(lua_State *L, int idx, char *buf, size_t size)
{
    int t = lua_type(L, idx);
    if (t == LUA_TNUMBER) snprintf(buf, size, "%s", lua_tostring(L, idx));
    else if (t == LUA_TSTRING) snprintf(buf, size, "\"%s\"", lua_tostring(L, idx));
    else snprintf(buf, size, "%s", luaL_typename(L, idx));
    return buf;
}

// Reads t[field] as a finite number in [lo, hi]; `has` tells whether it was present.
static bool opt_number(lua_State *L, int t, const char *fn, const char *field, double lo, double hi,
                       double *out)
{
    lua_getfield(L, t, field);
    if (lua_isnil(L, -1)) {
        lua_pop(L, 1);
        return false;
    }
    char buf[64];
    if (!lua_isnumber(L, -1) || lua_type(L, -1) != LUA_TNUMBER)
        raise(L, "%s: field '%s' must be a number in [%g, %g] (got %s)", fn, field, lo, hi, describe(L, -1, buf, sizeof buf));
    double v = lua_tonumber(L, -1);
    if (!isfinite(v) || v < lo || v > hi)
        raise(L, "%s: field '%s' must be a finite number in [%g, %g] (got %s)", fn, field, lo, hi, describe(L, -1, buf, sizeof buf));
    lua_pop(L, 1);
    *out = v;
    return true;
}

static bool opt_vec3(lua_State *L, int t, const char *fn, const char *field, float out[3])
{
    lua_getfield(L, t, field);
    if (lua_isnil(L, -1)) {
        lua_pop(L, 1);
        return false;
    }
    char buf[64];
    if (!lua_istable(L, -1) || luaL_len(L, -1) != 3)
        raise(L, "%s: field '%s' must be a table of 3 numbers {x, y, z} (got %s)", fn, field, describe(L, -1, buf, sizeof buf));
    for (int k = 0; k < 3; k++) {
        lua_geti(L, -1, k + 1);
        if (lua_type(L, -1) != LUA_TNUMBER || !isfinite(lua_tonumber(L, -1)))
            raise(L, "%s: field '%s'[%d] must be a finite number (got %s)", fn, field, k + 1, describe(L, -1, buf, sizeof buf));
        out[k] = (float)lua_tonumber(L, -1);
        lua_pop(L, 1);
    }
    lua_pop(L, 1);
    return true;
}

static void req_vec3(lua_State *L, int t, const char *fn, const char *field, float out[3])
{
    if (!opt_vec3(L, t, fn, field, out)) raise(L, "%s: field '%s' is required: a table of 3 numbers {x, y, z} (got nil)", fn, field);
}

static bool opt_bool(lua_State *L, int t, const char *fn, const char *field, bool *out)
{
    lua_getfield(L, t, field);
    if (lua_isnil(L, -1)) {
        lua_pop(L, 1);
        return false;
    }
    char buf[64];
    if (!lua_isboolean(L, -1)) raise(L, "%s: field '%s' must be a boolean (got %s)", fn, field, describe(L, -1, buf, sizeof buf));
    *out = lua_toboolean(L, -1);
    lua_pop(L, 1);
    return true;
}

// Rejects keys of table t that are not in `known` (a misspelt field is an error, not a no-op).
static void check_fields(lua_State *L, int t, const char *fn, const char *const *known)
{
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
            char list[512] = "";
            size_t n = 0;
            for (const char *const *p = known; *p && n < sizeof list; p++)
                n += (size_t)snprintf(list + n, sizeof list - n, "%s%s", p == known ? "" : ", ", *p);
            char buf[64];
            raise(L, "%s: unknown field %s (known: %s)", fn, describe(L, -1, buf, sizeof buf), list);
        }
    }
}

// ---- seiche.* --------------------------------------------------------------------------

static void read_fluid(lua_State *L, int t, pbf_params *p)
{
    int n;
    const pbf_param_info *tab = pbf_param_table(&n);
    const char *known[32];
    for (int i = 0; i < n && i < 30; i++) known[i] = tab[i].name;
    known[n < 30 ? n : 30] = NULL;
    check_fields(L, t, "seiche.scene: fluid", known);
    for (int i = 0; i < n; i++) {
        double v;
        if (!opt_number(L, t, "seiche.scene: fluid", tab[i].name, -1e30, 1e30, &v)) continue;
        char err[512];
        if (pbf_params_set(p, tab[i].name, v, err, sizeof err) != PBF_OK) raise(L, "seiche.scene: fluid.%s: %s", tab[i].name, err);
    }
}

static int l_scene(lua_State *L)
{
    eng_script *s = get_script(L);
    luaL_checktype(L, 1, LUA_TTABLE);
    if (s->host.world) raise(L, "seiche.scene: the scene is described once, in the script's main chunk (not inside a callback)");
    static const char *const known[] = { "name", "preset", "fluid", "gravity", "capacity", "container", "domain", "camera", NULL };
    check_fields(L, 1, "seiche.scene", known);
    eng_scene_config *c = &s->config;
    lua_getfield(L, 1, "preset");
    if (!lua_isnil(L, -1)) {
        const char *preset = lua_tostring(L, -1);
        if (preset && strcmp(preset, "default") == 0) c->params = pbf_default_params();
        else if (preset && strcmp(preset, "seed") == 0) c->params = pbf_seed_params();
        else {
            char buf[64];
            raise(L, "seiche.scene: field 'preset' must be \"default\" or \"seed\" (got %s)", describe(L, -1, buf, sizeof buf));
        }
    }
    lua_pop(L, 1);
    lua_getfield(L, 1, "name");
    if (lua_type(L, -1) == LUA_TSTRING) snprintf(c->name, sizeof c->name, "%s", lua_tostring(L, -1));
    else if (!lua_isnil(L, -1)) raise(L, "seiche.scene: field 'name' must be a string");
    lua_pop(L, 1);
    lua_getfield(L, 1, "fluid");
    if (lua_istable(L, -1)) read_fluid(L, lua_gettop(L), &c->params);
    else if (!lua_isnil(L, -1)) raise(L, "seiche.scene: field 'fluid' must be a table of fluid parameters");
    lua_pop(L, 1);
    float g[3];
    if (opt_vec3(L, 1, "seiche.scene", "gravity", g)) {
        for (int k = 0; k < 3; k++)
            if (fabsf(g[k]) > 1000.0f) raise(L, "seiche.scene: field 'gravity'[%d] must be in [-1000, 1000] m/s^2 (got %g)", k + 1, (double)g[k]);
        memcpy(c->params.gravity, g, sizeof g);
    }
    double cap;
    if (opt_number(L, 1, "seiche.scene", "capacity", 1, 67108864, &cap)) {
        if (cap != floor(cap)) raise(L, "seiche.scene: field 'capacity' must be a whole number (got %g)", cap);
        c->capacity = (uint32_t)cap;
    }
    lua_getfield(L, 1, "container");
    if (lua_istable(L, -1)) {
        int t = lua_gettop(L);
        static const char *const ck[] = { "min", "max", "closed_top", NULL };
        check_fields(L, t, "seiche.scene: container", ck);
        req_vec3(L, t, "seiche.scene: container", "min", c->container_min);
        req_vec3(L, t, "seiche.scene: container", "max", c->container_max);
        for (int k = 0; k < 3; k++)
            if (!(c->container_max[k] > c->container_min[k]))
                raise(L, "seiche.scene: container.max[%d] must be greater than container.min[%d] (got min %g, max %g)",
                           k + 1, k + 1, (double)c->container_min[k], (double)c->container_max[k]);
        c->closed_top = false;
        opt_bool(L, t, "seiche.scene: container", "closed_top", &c->closed_top);
        c->has_container = true;
    } else if (!lua_isnil(L, -1)) {
        raise(L, "seiche.scene: field 'container' must be a table {min = {x,y,z}, max = {x,y,z}, closed_top = false}");
    }
    lua_pop(L, 1);
    lua_getfield(L, 1, "domain");
    if (lua_istable(L, -1)) {
        int t = lua_gettop(L);
        req_vec3(L, t, "seiche.scene: domain", "min", c->domain_min);
        req_vec3(L, t, "seiche.scene: domain", "max", c->domain_max);
        c->has_domain = true;
    } else if (!lua_isnil(L, -1)) {
        raise(L, "seiche.scene: field 'domain' must be a table {min = {x,y,z}, max = {x,y,z}}");
    }
    lua_pop(L, 1);
    lua_getfield(L, 1, "camera");
    if (lua_istable(L, -1)) {
        int t = lua_gettop(L);
        static const char *const ck[] = { "eye", "target", "fov", NULL };
        check_fields(L, t, "seiche.scene: camera", ck);
        opt_vec3(L, t, "seiche.scene: camera", "eye", c->camera_eye);
        opt_vec3(L, t, "seiche.scene: camera", "target", c->camera_target);
        double fov;
        if (opt_number(L, t, "seiche.scene: camera", "fov", 1, 170, &fov)) c->camera_fov = (float)fov;
    } else if (!lua_isnil(L, -1)) {
        raise(L, "seiche.scene: field 'camera' must be a table {eye = {x,y,z}, target = {x,y,z}, fov = degrees}");
    }
    lua_pop(L, 1);
    s->scene_called = true;
    return 0;
}

static eng_command *push_command(lua_State *L, eng_script *s, eng_command_type type)
{
    if (s->command_count == s->command_cap) {
        int cap = s->command_cap ? 2 * s->command_cap : 16;
        eng_command *c = realloc(s->commands, (size_t)cap * sizeof *c);
        if (!c) raise(L, "out of memory");
        s->commands = c;
        s->command_cap = cap;
    }
    eng_command *c = &s->commands[s->command_count++];
    memset(c, 0, sizeof *c);
    c->type = type;
    luaL_where(L, 1);
    snprintf(c->where, sizeof c->where, "%s", lua_tostring(L, -1));
    lua_pop(L, 1);
    return c;
}

static int l_block(lua_State *L)
{
    eng_script *s = get_script(L);
    luaL_checktype(L, 1, LUA_TTABLE);
    static const char *const known[] = { "min", "max", "velocity", NULL };
    check_fields(L, 1, "seiche.block", known);
    pbf_block_def b = pbf_default_block_def();
    req_vec3(L, 1, "seiche.block", "min", b.min);
    req_vec3(L, 1, "seiche.block", "max", b.max);
    opt_vec3(L, 1, "seiche.block", "velocity", b.velocity);
    for (int k = 0; k < 3; k++)
        if (!(b.max[k] > b.min[k]))
            raise(L, "seiche.block: max[%d] must be greater than min[%d] (got min %g, max %g)", k + 1, k + 1,
                       (double)b.min[k], (double)b.max[k]);
    eng_command *c = push_command(L, s, ENG_CMD_BLOCK);
    c->block = b;
    return 0;
}

static int l_check(lua_State *L)
{
    eng_script *s = get_script(L);
    luaL_checkany(L, 1);
    if (lua_toboolean(L, 1)) return 0;
    const char *msg = luaL_optstring(L, 2, "(no message)");
    s->check_failed = true;
    luaL_where(L, 1);
    lua_pushfstring(L, "%scheck failed: %s", lua_tostring(L, -1), msg);
    return lua_error(L);
}

static int l_quit(lua_State *L)
{
    get_script(L)->quit = true;
    return 0;
}

static void set_num(lua_State *L, const char *k, double v)
{
    lua_pushnumber(L, v);
    lua_setfield(L, -2, k);
}

static int l_stats(lua_State *L)
{
    eng_script *s = get_script(L);
    const pbf_step_stats *st = s->host.stats;
    lua_createtable(L, 0, 10);
    set_num(L, "particles", s->host.world ? pbf_world_particle_count(s->host.world) : 0);
    set_num(L, "rho0", s->config.params.rest_density);
    set_num(L, "rho_avg", st ? st->density_avg : 0.0);
    set_num(L, "rho_max", st ? st->density_max : 0.0);
    set_num(L, "nan", st ? st->nan_count : 0);
    set_num(L, "outside", st ? st->outside_count : 0);
    set_num(L, "overflow", st ? st->overflow_count : 0);
    set_num(L, "step_ms", st ? st->step_ms : 0.0);
    set_num(L, "step", st ? (double)st->step : -1.0);
    set_num(L, "time", st ? st->time : 0.0);
    return 1;
}

static int l_time(lua_State *L)
{
    lua_pushnumber(L, get_script(L)->host.time);
    return 1;
}

static int l_frame(lua_State *L)
{
    lua_pushinteger(L, (lua_Integer)get_script(L)->host.frame);
    return 1;
}

static int l_renderer(lua_State *L)
{
    const char *r = get_script(L)->host.renderer;
    lua_pushstring(L, r ? r : "");
    return 1;
}

static int l_headless(lua_State *L)
{
    lua_pushboolean(L, get_script(L)->host.headless);
    return 1;
}

static int l_particle_count(lua_State *L)
{
    eng_script *s = get_script(L);
    lua_pushinteger(L, s->host.world ? (lua_Integer)pbf_world_particle_count(s->host.world) : 0);
    return 1;
}

static int l_param(lua_State *L)
{
    eng_script *s = get_script(L);
    const char *name = luaL_checkstring(L, 1);
    const pbf_param_info *info = pbf_param_find(name);
    if (!info) luaL_argerror(L, 1, lua_pushfstring(L, "unknown fluid parameter '%s'", name));
    const pbf_params *p = s->host.world ? pbf_world_params(s->host.world) : &s->config.params;
    lua_pushnumber(L, pbf_params_get(p, info));
    return 1;
}

static const luaL_Reg seiche_functions[] = {
    { "scene", l_scene },       { "block", l_block },       { "check", l_check },
    { "quit", l_quit },         { "stats", l_stats },       { "time", l_time },
    { "frame", l_frame },       { "renderer", l_renderer }, { "headless", l_headless },
    { "particle_count", l_particle_count }, { "param", l_param },
    { NULL, NULL },
};

const char *const *eng_script_function_names(void)
{
    static const char *names[sizeof seiche_functions / sizeof seiche_functions[0]];
    for (size_t i = 0; i < sizeof seiche_functions / sizeof seiche_functions[0]; i++) names[i] = seiche_functions[i].name;
    return names;
}

// ---- running Lua ---------------------------------------------------------------------

static void budget_hook(lua_State *L, lua_Debug *ar)
{
    (void)ar;
    eng_script *s = get_script(L);
    if (s->deadline > 0.0 && now_s() > s->deadline)
        raise(L, "%s ran longer than its budget of %g s (an endless loop?)", s->running ? s->running : "the script",
                   s->budget_s);
}

static int traceback(lua_State *L)
{
    const char *msg = lua_tostring(L, 1);
    if (!msg) msg = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
    luaL_traceback(L, L, msg, 1);
    return 1;
}

static eng_script_status run(eng_script *s, int nargs, const char *what)
{
    lua_State *L = s->L;
    int base = lua_gettop(L) - nargs;
    lua_pushcfunction(L, traceback);
    lua_insert(L, base);
    s->running = what;
    s->deadline = now_s() + s->budget_s;
    int rc = lua_pcall(L, nargs, 0, base);
    s->deadline = 0.0;
    s->running = NULL;
    lua_remove(L, base);
    if (rc == LUA_OK) return ENG_SCRIPT_OK;
    snprintf(s->error, sizeof s->error, "%s", lua_tostring(L, -1) ? lua_tostring(L, -1) : "(unknown error)");
    lua_pop(L, 1);
    return s->check_failed ? ENG_SCRIPT_CHECK_FAILED : ENG_SCRIPT_ERROR;
}

eng_script *eng_script_create(const eng_logger *log, double budget_s)
{
    eng_script *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->log = log ? *log : eng_default_logger();
    s->budget_s = budget_s;
    s->config = eng_default_scene_config();
    s->L = luaL_newstate();
    if (!s->L) {
        free(s);
        return NULL;
    }
    luaL_openlibs(s->L);
    lua_pushlightuserdata(s->L, s);
    lua_setfield(s->L, LUA_REGISTRYINDEX, REGISTRY_KEY);
    luaL_newlib(s->L, seiche_functions);
    lua_setglobal(s->L, "seiche");
    lua_sethook(s->L, budget_hook, LUA_MASKCOUNT, 10000);
    return s;
}

void eng_script_destroy(eng_script *s)
{
    if (!s) return;
    lua_close(s->L);
    free(s->commands);
    free(s);
}

eng_script_status eng_script_load(eng_script *s, const char *path)
{
    snprintf(s->path, sizeof s->path, "%s", path);
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(s->error, sizeof s->error, "%s: cannot open the script file", path);
        return ENG_SCRIPT_ERROR;
    }
    fclose(f);
    if (luaL_loadfile(s->L, path) != LUA_OK) {
        snprintf(s->error, sizeof s->error, "%s", lua_tostring(s->L, -1));
        lua_pop(s->L, 1);
        return ENG_SCRIPT_ERROR;
    }
    return run(s, 0, "the script's main chunk");
}

const char *eng_script_error(const eng_script *s) { return s->error; }
const char *eng_script_path(const eng_script *s) { return s->path; }
eng_scene_config *eng_script_config(eng_script *s) { return &s->config; }
void eng_script_set_host(eng_script *s, const eng_script_host *host) { s->host = *host; }
bool eng_script_quit_requested(const eng_script *s) { return s->quit; }

int eng_script_commands(eng_script *s, const eng_command **out)
{
    *out = s->commands;
    return s->command_count;
}

void eng_script_clear_commands(eng_script *s) { s->command_count = 0; }

static bool get_callback(eng_script *s, const char *name)
{
    lua_getglobal(s->L, name);
    if (lua_isfunction(s->L, -1)) return true;
    lua_pop(s->L, 1);
    return false;
}

eng_script_status eng_script_on_start(eng_script *s)
{
    if (!get_callback(s, "on_start")) return ENG_SCRIPT_OK;
    return run(s, 0, "on_start");
}

eng_script_status eng_script_on_step(eng_script *s, double dt, double time)
{
    if (!get_callback(s, "on_step")) return ENG_SCRIPT_OK;
    lua_pushnumber(s->L, dt);
    lua_pushnumber(s->L, time);
    return run(s, 2, "on_step");
}

eng_script_status eng_script_on_key(eng_script *s, const char *key, const char *action)
{
    if (!get_callback(s, "on_key")) return ENG_SCRIPT_OK;
    lua_pushstring(s->L, key);
    lua_pushstring(s->L, action);
    return run(s, 2, "on_key");
}

eng_script_status eng_script_on_mouse(eng_script *s, int button, const char *action, double x, double y)
{
    if (!get_callback(s, "on_mouse")) return ENG_SCRIPT_OK;
    lua_pushinteger(s->L, button);
    lua_pushstring(s->L, action);
    lua_pushnumber(s->L, x);
    lua_pushnumber(s->L, y);
    return run(s, 4, "on_mouse");
}

eng_script_status eng_script_on_reload(eng_script *s)
{
    if (!get_callback(s, "on_reload")) return ENG_SCRIPT_OK;
    return run(s, 0, "on_reload");
}

const char *eng_key_name(int key)
{
    static char letter[2][2];
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) {
        int slot = key & 1;
        letter[slot][0] = (char)('a' + (key - GLFW_KEY_A));
        letter[slot][1] = 0;
        return letter[slot];
    }
    static const char *const digits[] = { "0", "1", "2", "3", "4", "5", "6", "7", "8", "9" };
    if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) return digits[key - GLFW_KEY_0];
    static const char *const fkeys[] = { "f1", "f2", "f3", "f4", "f5", "f6", "f7", "f8", "f9", "f10", "f11", "f12" };
    if (key >= GLFW_KEY_F1 && key <= GLFW_KEY_F12) return fkeys[key - GLFW_KEY_F1];
    switch (key) {
    case GLFW_KEY_SPACE: return "space";
    case GLFW_KEY_ENTER: return "enter";
    case GLFW_KEY_ESCAPE: return "escape";
    case GLFW_KEY_TAB: return "tab";
    case GLFW_KEY_BACKSPACE: return "backspace";
    case GLFW_KEY_LEFT: return "left";
    case GLFW_KEY_RIGHT: return "right";
    case GLFW_KEY_UP: return "up";
    case GLFW_KEY_DOWN: return "down";
    case GLFW_KEY_LEFT_SHIFT: case GLFW_KEY_RIGHT_SHIFT: return "shift";
    case GLFW_KEY_LEFT_CONTROL: case GLFW_KEY_RIGHT_CONTROL: return "ctrl";
    default: return NULL;
    }
}
