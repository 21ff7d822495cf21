// The core of the Lua host (script.h): the Lua state with its time budget and memory limit,
// protected calls with a traceback, loading the script, callbacks and timers, the API areas.
#include "engine/script/script_internal.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <assert.h>
#include <lualib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/// The most memory a script's Lua state may hold.
#define LUA_MEMORY_LIMIT ((size_t)512 << 20)

static const char *const REGISTRY_KEY = "seiche.script";

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

eng_look eng_default_look(void)
{
    eng_look k;
    memset(&k, 0, sizeof k);
    eng_renderer_def rd = eng_default_renderer_def();
    memcpy(k.sky, rd.sky_color, sizeof k.sky);
    k.light = rd.light;
    k.water = eng_default_particle_style();
    k.ground = true;
    k.ground_height = 0.0f;
    k.container = true;
    k.panel = true;
    return k;
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
    c.camera_mode = ENG_CAMERA_ORBIT;
    c.look = eng_default_look();
    return c;
}

// The script for the budget hook, which has no upvalues (bindings use scr_get_script).
static eng_script *registry_script(lua_State *L)
{
    lua_getfield(L, LUA_REGISTRYINDEX, REGISTRY_KEY);
    eng_script *s = lua_touserdata(L, -1);
    lua_pop(L, 1);
    return s;
}

// ---- registration ------------------------------------------------------------------------

void scr_api_functions(scr_api *api, const luaL_Reg *functions)
{
    assert(api->area_count < SCR_MAX_AREAS);
    api->functions[api->area_count++] = functions;
}

void scr_api_methods(scr_api *api, obj_kind kind, const luaL_Reg *methods)
{
    assert(!api->methods[kind]);
    api->methods[kind] = methods;
}

// Every API area, in the order its functions enter the seiche table: what a script gets, as
// Lua's linit.c lists its libraries. Each wrap_*.c names its functions and handle methods in
// one scr_open_*; script_internal.h has the map of the files.
static void open_api(scr_api *api)
{
    memset(api, 0, sizeof *api);
    scr_open_scene(api);
    scr_open_fluid(api);
    scr_open_emitter(api);
    scr_open_body(api);
    scr_open_interact(api);
    scr_open_query(api);
    for (int k = 0; k < OBJ_KIND_COUNT; k++) assert(api->methods[k]);
}

static const char *const CALLBACKS[] = { "on_start", "on_step", "on_key", "on_mouse", "on_mouse_move", "on_scroll",
                                         "on_reload", NULL };

const char *const *eng_script_function_names(void)
{
    static const char *names[128];
    scr_api api;
    open_api(&api);
    int n = 0;
    for (int i = 0; i < api.area_count; i++)
        for (const luaL_Reg *r = api.functions[i]; r->name; r++) {
            assert(n + 1 < (int)(sizeof names / sizeof names[0]));
            names[n++] = r->name;
        }
    names[n] = NULL;
    return names;
}

const char *const *eng_script_api_names(void)
{
    static char storage[4096];
    static const char *names[160];
    if (names[0]) return names;
    scr_api api;
    open_api(&api);
    size_t used = 0;
    int n = 0;
    for (int i = 0; i < api.area_count; i++)
        for (const luaL_Reg *r = api.functions[i]; r->name; r++) {
            names[n++] = storage + used;
            used += (size_t)snprintf(storage + used, sizeof storage - used, "seiche.%s", r->name) + 1;
        }
    for (int k = 0; k < OBJ_KIND_COUNT; k++)
        for (const luaL_Reg *r = api.methods[k]; r->name; r++) {
            names[n++] = storage + used;
            used += (size_t)snprintf(storage + used, sizeof storage - used, "%s:%s", scr_kind_name[k], r->name) + 1;
        }
    for (const char *const *c = CALLBACKS; *c; c++) names[n++] = *c;
    names[n] = NULL;
    return names;
}

static void register_api(eng_script *s)
{
    lua_State *L = s->L;
    scr_api api;
    open_api(&api);
    lua_newtable(L);
    for (int i = 0; i < api.area_count; i++) {
        lua_pushlightuserdata(L, s);
        luaL_setfuncs(L, api.functions[i], 1);
    }
    lua_pushstring(L, "0.1");
    lua_setfield(L, -2, "version");
    lua_setglobal(L, "seiche");
    for (int k = 0; k < OBJ_KIND_COUNT; k++) scr_new_handle_type(L, s, (obj_kind)k, api.methods[k]);
}

// ---- running Lua ---------------------------------------------------------------------

static void budget_hook(lua_State *L, lua_Debug *ar)
{
    (void)ar;
    eng_script *s = registry_script(L);
    if (s->deadline > 0.0 && now_s() > s->deadline)
        scr_raise(L, "%s ran longer than its budget of %g s (an endless loop?)", s->running ? s->running : "the script",
                  s->budget_s);
}

static void *limited_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    eng_script *s = ud;
    if (ptr == NULL) osize = 0;
    if (nsize == 0) {
        free(ptr);
        s->memory -= osize;
        return NULL;
    }
    if (nsize > osize && s->memory + (nsize - osize) > LUA_MEMORY_LIMIT) {
        s->out_of_memory = true;
        return NULL;
    }
    void *p = realloc(ptr, nsize);
    if (p) s->memory = s->memory - osize + nsize;
    return p;
}

static int traceback(lua_State *L)
{
    const char *msg = lua_tostring(L, 1);
    if (!msg) msg = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
    luaL_traceback(L, L, msg, 1);
    return 1;
}

// Calls the function below the nargs arguments on the stack with `nresults` results left
// on the stack on success.
static eng_script_status run(eng_script *s, int nargs, int nresults, const char *what)
{
    lua_State *L = s->L;
    int base = lua_gettop(L) - nargs;
    lua_pushcfunction(L, traceback);
    lua_insert(L, base);
    s->running = what;
    s->deadline = now_s() + s->budget_s;
    s->out_of_memory = false;
    int rc = lua_pcall(L, nargs, nresults, base);
    s->deadline = 0.0;
    s->running = NULL;
    lua_remove(L, base);
    if (rc == LUA_OK) return ENG_SCRIPT_OK;
    if (rc == LUA_ERRMEM || s->out_of_memory)
        snprintf(s->error, sizeof s->error, "%s: %s used more than the script's %zu MiB of memory (%s)", s->path, what,
                 LUA_MEMORY_LIMIT >> 20, lua_tostring(L, -1) ? lua_tostring(L, -1) : "not enough memory");
    else
        snprintf(s->error, sizeof s->error, "%s", lua_tostring(L, -1) ? lua_tostring(L, -1) : "(unknown error)");
    lua_pop(L, 1);
    return s->check_failed ? ENG_SCRIPT_CHECK_FAILED : ENG_SCRIPT_ERROR;
}

eng_script *eng_script_create(const eng_logger *log, double budget_s)
{
    if (!(budget_s > 0.0 && budget_s <= 3600.0)) return NULL;
    eng_script *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->log = log ? *log : eng_default_logger();
    s->budget_s = budget_s;
    s->config = eng_default_scene_config();
    s->host.dt = 1.0 / 60.0;
    s->L = lua_newstate(limited_alloc, s);
    if (!s->L) {
        free(s);
        return NULL;
    }
    luaL_openlibs(s->L);
    lua_pushlightuserdata(s->L, s);
    lua_setfield(s->L, LUA_REGISTRYINDEX, REGISTRY_KEY);
    register_api(s);
    lua_sethook(s->L, budget_hook, LUA_MASKCOUNT, 10000);
    return s;
}

void eng_script_destroy(eng_script *s)
{
    if (!s) return;
    for (uint32_t i = 0; i < s->obj_count; i++) {
        obj *o = &s->objs[i];
        if (o->state == OBJ_FREE || o->kind != OBJ_BODY) continue;
        if (s->host.scene && o->u.body.node.index1) eng_node_destroy(s->host.scene, o->u.body.node);
        if (s->host.meshes && o->u.body.mesh.index1) eng_mesh_destroy(s->host.meshes, o->u.body.mesh);
        scr_body_free_data(&o->u.body);
    }
    scr_clear_commands(s);
    lua_close(s->L);
    free(s->commands);
    free(s->objs);
    free(s->cache);
    free(s->events);
    free(s);
}

static eng_script_status load_chunk(eng_script *s, int rc)
{
    if (rc != LUA_OK) {
        snprintf(s->error, sizeof s->error, "%s", lua_tostring(s->L, -1) ? lua_tostring(s->L, -1) : "(load error)");
        lua_pop(s->L, 1);
        return ENG_SCRIPT_ERROR;
    }
    s->in_main_chunk = true;
    eng_script_status st = run(s, 0, 0, "the script's main chunk");
    s->in_main_chunk = false;
    return st;
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
    return load_chunk(s, luaL_loadfile(s->L, path));
}

eng_script_status eng_script_load_string(eng_script *s, const char *chunk_name, const char *code)
{
    snprintf(s->path, sizeof s->path, "%s", chunk_name);
    char name[520];
    snprintf(name, sizeof name, "@%s", chunk_name);
    return load_chunk(s, luaL_loadbuffer(s->L, code, strlen(code), name));
}

const char *eng_script_error(const eng_script *s) { return s->error; }
const char *eng_script_path(const eng_script *s) { return s->path; }
eng_scene_config *eng_script_config(eng_script *s) { return &s->config; }
void eng_script_set_host(eng_script *s, const eng_script_host *host) { s->host = *host; }
bool eng_script_quit_requested(const eng_script *s) { return s->quit; }
int eng_script_pending(const eng_script *s) { return s->command_count; }

bool eng_script_set_param(eng_script *s, const char *name, double value, char *err, size_t err_size)
{
    pbf_params p = *scr_current_params(s);
    if (pbf_params_set(&p, name, value, err, err_size) != PBF_OK) return false;
    if (s->host.world) {
        if (pbf_world_set_params(s->host.world, &p) != PBF_OK) {
            snprintf(err, err_size, "%s", pbf_world_last_error(s->host.world));
            return false;
        }
        if (s->have_pending_params) s->pending_params = p;
    } else {
        s->config.params = p;
    }
    return true;
}

// ---- callbacks --------------------------------------------------------------------------

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
    return run(s, 0, 0, "on_start");
}

// Fires the timers due at `time`, earliest first (a repeating timer as often as it is
// due, so a period shorter than the frame step still fires the right number of times).
static eng_script_status fire_timers(eng_script *s, double time)
{
    for (int fired = 0; fired < 100000; fired++) {
        uint32_t best = UINT32_MAX;
        for (uint32_t i = 0; i < s->obj_count; i++) {
            obj *o = &s->objs[i];
            if (o->state != OBJ_LIVE || o->kind != OBJ_TIMER || o->u.timer.due > time + 1e-9) continue;
            if (best == UINT32_MAX || o->u.timer.due < s->objs[best].u.timer.due) best = i;
        }
        if (best == UINT32_MAX) return ENG_SCRIPT_OK;
        obj *o = &s->objs[best];
        lua_rawgeti(s->L, LUA_REGISTRYINDEX, o->u.timer.fn);
        lua_pushnumber(s->L, time);
        if (o->u.timer.period > 0) o->u.timer.due += o->u.timer.period;
        else scr_obj_release(s, best); // one-shot: done before it runs (it may make new timers)
        eng_script_status st = run(s, 1, 0, "a timer callback");
        if (st != ENG_SCRIPT_OK) return st;
    }
    return ENG_SCRIPT_OK;
}

eng_script_status eng_script_on_step(eng_script *s, double dt, double time)
{
    if (!s->capacity_warned && s->host.world && pbf_world_particle_count(s->host.world) >= pbf_world_capacity(s->host.world)) {
        for (uint32_t i = 0; i < s->obj_count; i++)
            if (s->objs[i].state == OBJ_LIVE && s->objs[i].kind == OBJ_EMITTER && s->objs[i].u.emitter.def.enabled) {
                eng_log(&s->log, ENG_LOG_WARN, "%s: the fluid is at its capacity of %u particles: emitters pour nothing "
                        "until sinks make room (raise seiche.scene{capacity = ...})", s->path,
                        pbf_world_capacity(s->host.world));
                s->capacity_warned = true;
                break;
            }
    }
    eng_script_status st = ENG_SCRIPT_OK;
    if (get_callback(s, "on_step")) {
        lua_pushnumber(s->L, dt);
        lua_pushnumber(s->L, time);
        st = run(s, 2, 0, "on_step");
    }
    if (st == ENG_SCRIPT_OK) st = fire_timers(s, time);
    return st;
}

eng_script_status eng_script_on_key(eng_script *s, const char *key, const char *action)
{
    if (!get_callback(s, "on_key")) return ENG_SCRIPT_OK;
    lua_pushstring(s->L, key);
    lua_pushstring(s->L, action);
    return run(s, 2, 0, "on_key");
}

eng_script_status eng_script_on_mouse(eng_script *s, int button, const char *action, double x, double y, bool *consumed)
{
    if (consumed) *consumed = false;
    if (!get_callback(s, "on_mouse")) return ENG_SCRIPT_OK;
    lua_pushinteger(s->L, button);
    lua_pushstring(s->L, action);
    lua_pushnumber(s->L, x);
    lua_pushnumber(s->L, y);
    eng_script_status st = run(s, 4, 1, "on_mouse");
    if (st == ENG_SCRIPT_OK) {
        if (consumed) *consumed = lua_toboolean(s->L, -1);
        lua_pop(s->L, 1);
    }
    return st;
}

eng_script_status eng_script_on_mouse_move(eng_script *s, double x, double y, double dx, double dy)
{
    if (!get_callback(s, "on_mouse_move")) return ENG_SCRIPT_OK;
    lua_pushnumber(s->L, x);
    lua_pushnumber(s->L, y);
    lua_pushnumber(s->L, dx);
    lua_pushnumber(s->L, dy);
    return run(s, 4, 0, "on_mouse_move");
}

eng_script_status eng_script_on_scroll(eng_script *s, double dx, double dy)
{
    if (!get_callback(s, "on_scroll")) return ENG_SCRIPT_OK;
    lua_pushnumber(s->L, dx);
    lua_pushnumber(s->L, dy);
    return run(s, 2, 0, "on_scroll");
}

eng_script_status eng_script_on_reload(eng_script *s)
{
    if (!get_callback(s, "on_reload")) return ENG_SCRIPT_OK;
    return run(s, 0, 0, "on_reload");
}

// ---- key names ------------------------------------------------------------------------------

const char *eng_key_name(int key)
{
    static const char *const letters[26] = { "a", "b", "c", "d", "e", "f", "g", "h", "i", "j", "k", "l", "m",
                                             "n", "o", "p", "q", "r", "s", "t", "u", "v", "w", "x", "y", "z" };
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) return letters[key - GLFW_KEY_A];
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

int eng_key_code(const char *name)
{
    if (!name) return -1;
    for (int k = 0; k <= GLFW_KEY_LAST; k++) {
        const char *n = eng_key_name(k);
        if (n && strcmp(n, name) == 0) return k;
    }
    return -1;
}
