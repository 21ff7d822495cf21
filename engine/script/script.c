// The core of the Lua host (script.h): the Lua state with its time budget and memory limit,
// protected calls with a traceback, loading the script, callbacks, the API areas.
#include "engine/script/script_internal.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <assert.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <errno.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

/// Work units (scr_tick) between two looks at the clock.
#define TICK_QUANTUM ((size_t)1 << 16)
/// Bytes allocated between two looks at the clock: an instruction that makes a long string
/// (s:upper(), s .. t, string.format) is as slow as the string is long.
#define ALLOC_QUANTUM ((size_t)4 << 20)
/// Allocations may pass SCR_MEMORY_LIMIT by this much before the allocator refuses them: the
/// next budget check stops the script with its file:line instead (a refused allocation is a
/// Lua memory error, which names no line).
#define MEMORY_HEADROOM ((size_t)64 << 20)

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
    c.coupling = cpl_default_def();
    return c;
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
    scr_open_render(api);
    scr_open_query(api);
    scr_open_measure(api);
    scr_open_joint(api);
    scr_open_events(api);
    scr_open_mesh(api);
    scr_open_look(api);
    for (int k = 0; k < OBJ_KIND_COUNT; k++) assert(api->methods[k]);
}

static const char *const CALLBACKS[] = { "on_start", "on_step", "on_key", "on_mouse", "on_mouse_move", "on_scroll",
                                         "on_reload", "on_contact", "on_splash", NULL };

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
    lua_pushstring(L, pbf_version());
    lua_setfield(L, -2, "version");
    lua_setglobal(L, "seiche");
    for (int k = 0; k < OBJ_KIND_COUNT; k++) scr_new_handle_type(L, s, (obj_kind)k, api.methods[k]);
}

// ---- limits: the time budget and the memory limit ----------------------------------------
//
// How the limits hold (docs/lua-api.md, "What a script can and cannot do"):
//
// - The budget is a deadline on the monotonic clock, set when the host calls into the
//   script (run). The frame's calls share one budget: on_key, on_mouse, ..., on_step and
//   the timers of one frame (eng_script_deliver_input starts a frame); the main chunk,
//   on_start and on_reload share the load's.
// - A count hook (budget_hook) looks at the clock every 1000 VM instructions, more often
//   while the script holds much memory (one instruction may then touch all of it: comparing
//   long strings), at the next instruction after every 4 MiB allocated (making a long string
//   is one instruction too), and at every instruction once the script is stopped. The hook
//   is per coroutine: our coroutine.resume and wrap (script_sandbox.c) keep the chain of
//   running ones (s->threads), so the allocator and a stop reach the one that runs.
// - C code runs no instructions, so the library functions that can loop long in one call
//   (patterns, string.rep, table.concat/insert/remove/move/sort) are our own versions that
//   count their work with scr_tick; every 2^16 units it looks at the clock too.
// - Over the budget (or the memory limit, or after a failed seiche.check) scr_stop records
//   the message and raises it. pcall in the script catches that error, but the stop stays:
//   the hook now fires at every instruction, in every coroutine, and raises the same
//   message again, as does every scr_tick, so the next instruction after any catch raises
//   again, until the error leaves the host's lua_pcall. Lua runs an error's message handler
//   with hooks off when the error comes from a hook; xpcall's handler would escape that
//   way, so the sandbox's xpcall calls its handler after unwinding (script_sandbox.c).
// - Finalisers run with hooks off too (in any GC step and in lua_close): the sandbox's
//   setmetatable refuses __gc. Callback lookups are raw (no __index runs) and protected.

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static void budget_hook(lua_State *L, lua_Debug *ar);

double scr_budget_left(const eng_script *s)
{
    if (!(s->deadline > 0.0)) return 0.0;
    double left = s->deadline - now_s();
    return left > 0.0 ? left : 0.0;
}

// VM instructions between two looks at the clock: the more memory, the longer one
// instruction can take.
static int hook_interval(const eng_script *s)
{
    size_t used = s->memory + s->c_memory;
    int n = used < ((size_t)8 << 20) ? 1000 : used < ((size_t)64 << 20) ? 100 : used < ((size_t)256 << 20) ? 10 : 1;
    // And at most one instruction per MiB of the longest live string (16 at 64 KiB): comparing
    // two 7.5 MB strings of NUL bytes took 50 ms, and at every 1000th instruction a loop of
    // comparisons ran 48 s past a 5 s budget.
    size_t longest = s->big_untracked ? ((size_t)1 << 20) : 0;
    for (int i = 0; i < s->big_string_count; i++)
        if (s->big_strings[i].size > longest) longest = s->big_strings[i].size;
    if (longest > 0) {
        size_t per = ((size_t)1 << 20) / longest;
        int cap = per < 1 ? 1 : (int)per;
        if (cap < n) n = cap;
    }
    return n;
}

static void check_soon(eng_script *s);

// Notes a string of SCR_BIG_STRING bytes or more as it is made, and forgets a block as it is freed.
static void note_big_string(eng_script *s, const void *at, size_t size)
{
    if (s->big_string_count < SCR_MAX_BIG_STRINGS) {
        s->big_strings[s->big_string_count].at = at;
        s->big_strings[s->big_string_count].size = size;
        s->big_string_count++;
    } else {
        s->big_untracked++;
    }
    check_soon(s); // the hook picks its new interval at the next instruction
}

static void forget_big_block(eng_script *s, const void *at)
{
    for (int i = 0; i < s->big_string_count; i++)
        if (s->big_strings[i].at == at) {
            s->big_strings[i] = s->big_strings[--s->big_string_count];
            return;
        }
    if (s->big_untracked > 0) s->big_untracked--; // one of those that did not fit (or not a string: harmless)
}

// The hook's events: the count, and from 64 MiB on every new line too, so that the line of a
// memory error Lua raises itself is known (budget_hook). Below 64 MiB one allocation would have
// to ask for most of the limit at once; the count hook's line stands in for it then.
static int hook_mask(const eng_script *s)
{
    return s->memory + s->c_memory < ((size_t)64 << 20) ? LUA_MASKCOUNT : LUA_MASKCOUNT | LUA_MASKLINE;
}

const char *scr_where(lua_State *L, char *buf, size_t size)
{
    lua_Debug ar;
    buf[0] = 0;
    for (int level = 0; lua_getstack(L, level, &ar); level++) {
        if (!lua_getinfo(L, "Sl", &ar) || ar.currentline <= 0) continue;
        snprintf(buf, size, "%s:%d: ", ar.short_src, ar.currentline);
        break;
    }
    return buf;
}

static int raise_stop(lua_State *L, eng_script *s)
{
    lua_sethook(L, budget_hook, LUA_MASKCOUNT, 1);
    lua_sethook(s->L, budget_hook, LUA_MASKCOUNT, 1);
    for (int i = 0; i < s->thread_depth && i < SCR_MAX_THREADS; i++) lua_sethook(s->threads[i], budget_hook, LUA_MASKCOUNT, 1);
    lua_pushstring(L, s->stop);
    return lua_error(L);
}

// The running coroutine (or the main thread) runs the hook at its next instruction.
static void check_soon(eng_script *s)
{
    int depth = s->thread_depth < SCR_MAX_THREADS ? s->thread_depth : SCR_MAX_THREADS;
    lua_sethook(depth > 0 ? s->threads[depth - 1] : s->L, budget_hook, LUA_MASKCOUNT, 1);
}

int scr_stop(lua_State *L, eng_script *s, scr_stop_kind kind, const char *fmt, ...)
{
    if (s->stop_kind == STOP_NONE) {
        char where[256], msg[700];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg, sizeof msg, fmt, ap);
        va_end(ap);
        if (*scr_where(L, where, sizeof where)) snprintf(s->stop, sizeof s->stop, "%s%s", where, msg);
        else snprintf(s->stop, sizeof s->stop, "%.300s: %s", s->path, msg);
        s->stop_kind = kind;
    }
    return raise_stop(L, s);
}

static void check_limits(lua_State *L, eng_script *s)
{
    if (s->stop_kind != STOP_NONE) raise_stop(L, s);
    if (s->deadline <= 0.0) return; // no host call runs (a finaliser in lua_close)
    s->allocated = 0;
    if (now_s() > s->deadline) {
        if (s->frame_used > 0.01 * s->budget_s)
            scr_stop(L, s, STOP_BUDGET, "%s ran past the frame's budget of %g s (the frame's callbacks and timers share "
                     "it; %.3g s went before this one; an endless loop?)", s->running, s->budget_s, s->frame_used);
        scr_stop(L, s, STOP_BUDGET, "%s ran longer than its budget of %g s (an endless loop?)", s->running, s->budget_s);
    }
    if (s->out_of_memory || s->memory + s->c_memory > SCR_MEMORY_LIMIT)
        scr_stop(L, s, STOP_MEMORY, "%s used more than the script's %d MiB of memory (Lua's objects and the edits, "
                 "handles and timers the engine keeps for it)", s->running, (int)(SCR_MEMORY_LIMIT >> 20));
}

static void budget_hook(lua_State *L, lua_Debug *ar)
{
    eng_script *s = scr_state_script(L);
    // Where the script is, for a memory error Lua raises itself: Lua runs no message handler
    // for those, and the stack is unwound when the host's pcall returns. The hook runs at
    // every instruction once the script holds 256 MiB (hook_interval), and at the instruction
    // after every 4 MiB allocated (limited_alloc), so near the limit this is the line that
    // asked for the memory.
    if (lua_getinfo(L, "Sl", ar) && ar->currentline > 0)
        snprintf(s->hook_where, sizeof s->hook_where, "%s:%d: ", ar->short_src, ar->currentline);
    if (ar->event == LUA_HOOKLINE) return; // a new line: noted; the count checks the limits
    check_limits(L, s);
    int want = hook_interval(s), mask = hook_mask(s);
    if (lua_gethookcount(L) != want || lua_gethookmask(L) != mask) lua_sethook(L, budget_hook, mask, want);
}

void scr_check_now(lua_State *L, eng_script *s) { scr_tick(L, s, TICK_QUANTUM); }

void scr_tick(lua_State *L, eng_script *s, size_t units)
{
    if (s->stop_kind != STOP_NONE) raise_stop(L, s);
    s->ticks += units;
    if (s->ticks < TICK_QUANTUM) return;
    s->ticks = 0;
    check_limits(L, s);
}

size_t scr_memory_room(const eng_script *s)
{
    size_t used = s->memory + s->c_memory;
    return used >= SCR_MEMORY_LIMIT ? 0 : SCR_MEMORY_LIMIT - used;
}

void scr_charge(lua_State *L, eng_script *s, const char *fn, size_t bytes)
{
    if (bytes > scr_memory_room(s))
        scr_raise(L, "%s: this would take the script past its memory limit of %d MiB (%.1f MiB held by Lua objects, "
                  "%.1f MiB by the engine for the script: queued edits, bodies' shapes, handles, timers; %.1f MiB more "
                  "asked for)", fn, (int)(SCR_MEMORY_LIMIT >> 20), (double)s->memory / 1048576.0,
                  (double)s->c_memory / 1048576.0, (double)bytes / 1048576.0);
    s->c_memory += bytes;
}

void scr_uncharge(eng_script *s, size_t bytes)
{
    assert(bytes <= s->c_memory);
    s->c_memory = bytes <= s->c_memory ? s->c_memory - bytes : 0; // never wraps round to "over the limit"
}

static void *limited_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    eng_script *s = ud;
    // A new object: osize is its type (Lua 5.4), and a string is made at its full size once.
    bool new_string = ptr == NULL && osize == LUA_TSTRING;
    if (ptr == NULL) osize = 0;
    if (nsize == 0) {
        if (osize >= SCR_BIG_STRING) forget_big_block(s, ptr);
        free(ptr);
        s->memory -= osize;
        return NULL;
    }
    if (nsize > osize && s->memory + s->c_memory + (nsize - osize) > SCR_MEMORY_LIMIT + MEMORY_HEADROOM) {
        s->out_of_memory = true;
        return NULL;
    }
    void *p = realloc(ptr, nsize);
    if (!p) return NULL;
    s->memory = s->memory - osize + nsize;
    if (new_string && nsize >= SCR_BIG_STRING) note_big_string(s, p, nsize);
    if (nsize > osize && s->deadline > 0.0 && (s->allocated += nsize - osize) >= ALLOC_QUANTUM) {
        s->allocated = 0;
        check_soon(s); // lua_sethook is safe here: Lua allows it even from a signal handler
    }
    return p;
}

// ---- protected calls ---------------------------------------------------------------------------

// True when the message's first line holds a "file:line:" (it may follow a chunk name with
// colons of its own: [string "a:b()"]:1:).
static bool has_position(const char *msg)
{
    for (const char *p = msg; *p && *p != '\n'; p++) {
        if (*p != ':' || p[1] < '0' || p[1] > '9') continue;
        const char *q = p + 1;
        while (*q >= '0' && *q <= '9') q++;
        if (*q == ':') return true;
    }
    return false;
}

// The message handler of every call into the script: the message with the file:line of the
// innermost Lua function when it has none (error objects that are not strings, errors of C
// functions called through pcall, "C stack overflow"), then a traceback.
static int message_handler(lua_State *L)
{
    const char *msg = lua_tostring(L, 1);
    if (!msg && luaL_callmeta(L, 1, "__tostring") && lua_type(L, -1) == LUA_TSTRING) msg = lua_tostring(L, -1);
    if (!msg) msg = lua_pushfstring(L, "(error object is a %s value, not a string)", luaL_typename(L, 1));
    char where[600];
    if (!has_position(msg) && *scr_where(L, where, sizeof where)) msg = lua_pushfstring(L, "%s%s", where, msg);
    luaL_traceback(L, L, msg, 1);
    return 1;
}

// Calls the function below its nargs arguments on the stack, protected, under what is left
// of the budget. On failure eng_script_error holds "file:line: message" and a traceback.
static eng_script_status run(eng_script *s, int nargs, const char *what)
{
    lua_State *L = s->L;
    int base = lua_gettop(L) - nargs;
    lua_pushcfunction(L, message_handler);
    lua_insert(L, base);
    s->running = what;
    double start = now_s(), left = s->budget_s - s->frame_used;
    s->deadline = start + (left > 0.0 ? left : 0.0);
    s->out_of_memory = false;
    s->ticks = 0;
    s->allocated = 0;
    s->thread_depth = 0;
    s->hook_where[0] = 0;
    int rc = lua_pcall(L, nargs, 0, base);
    s->thread_depth = 0;
    s->frame_used += now_s() - start;
    s->deadline = 0.0;
    const char *msg = rc != LUA_OK ? lua_tostring(L, -1) : NULL;
    eng_script_status st = rc == LUA_OK ? ENG_SCRIPT_OK : ENG_SCRIPT_ERROR;
    if (s->stop_kind != STOP_NONE) { // the error that left may be a later raise of the stop
        bool same = msg && strncmp(msg, s->stop, strlen(s->stop)) == 0;
        snprintf(s->error, sizeof s->error, "%s", same ? msg : s->stop);
        st = s->stop_kind == STOP_CHECK ? ENG_SCRIPT_CHECK_FAILED : ENG_SCRIPT_ERROR;
    } else if (rc == LUA_ERRMEM || (rc != LUA_OK && s->out_of_memory)) {
        // The line the budget hook saw last (every error's first line is file:line); only an
        // allocation before the call's first hook has none, and names the file.
        char where[340];
        if (s->hook_where[0]) snprintf(where, sizeof where, "%s", s->hook_where);
        else snprintf(where, sizeof where, "%.300s: ", s->path);
        snprintf(s->error, sizeof s->error, "%s%s used more than the script's %d MiB of memory (%s)", where, what,
                 (int)(SCR_MEMORY_LIMIT >> 20), msg ? msg : "not enough memory");
    } else if (rc != LUA_OK) {
        if (!msg) msg = "(no message)";
        if (has_position(msg)) snprintf(s->error, sizeof s->error, "%s", msg);
        else snprintf(s->error, sizeof s->error, "%s: %s%s", s->path, rc == LUA_ERRERR ? "error in the error handler: " : "", msg);
    }
    if (rc != LUA_OK) lua_pop(L, 1);
    lua_remove(L, base);
    s->running = NULL;
    s->stop_kind = STOP_NONE;
    s->stop[0] = 0;
    s->out_of_memory = false;
    lua_sethook(L, budget_hook, hook_mask(s), hook_interval(s));
    return st;
}

eng_script_def eng_default_script_def(void)
{
    eng_script_def d;
    memset(&d, 0, sizeof d);
    d.log = eng_default_logger();
    d.budget_s = 5.0;
    d.trusted = false;
    return d;
}

// Lua's warnings: the script's warn(...) and the state's own (an error in a trusted script's
// __gc finaliser, which Lua cannot raise). A message comes in pieces (tocont) and goes to
// the log as one warning; a single piece "@off" / "@on" turns them off and on, as in Lua's
// standalone interpreter, but they start on: a scene's warning is meant to be read.
static void script_warn(void *ud, const char *msg, int tocont)
{
    eng_script *s = ud;
    if (s->warning_len == 0 && !tocont && msg[0] == '@') {
        if (strcmp(msg, "@off") == 0) s->warnings_off = true;
        else if (strcmp(msg, "@on") == 0) s->warnings_off = false;
        return; // other controls are ignored, as Lua's own warn function does
    }
    size_t room = sizeof s->warning - 1 - s->warning_len;
    size_t n = strlen(msg);
    if (n > room) n = room;
    memcpy(s->warning + s->warning_len, msg, n);
    s->warning_len += n;
    s->warning[s->warning_len] = '\0';
    if (tocont) return;
    if (!s->warnings_off) eng_log(&s->log, ENG_LOG_WARN, "%s: %s", s->path[0] ? s->path : "script", s->warning);
    s->warning_len = 0;
}

// The libraries and the API, in a protected call (they allocate).
static int open_state(lua_State *L)
{
    eng_script *s = lua_touserdata(L, 1);
    scr_open_libraries(L, s->trusted);
    register_api(s);
    return 0;
}

eng_script *eng_script_create(const eng_script_def *def)
{
    if (!def || !(def->budget_s > 0.0 && def->budget_s <= 3600.0)) return NULL;
    eng_script *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->log = def->log;
    s->budget_s = def->budget_s;
    s->trusted = def->trusted;
    s->config = eng_default_scene_config();
    s->host.dt = 1.0 / 60.0;
    s->host.fluid_look = eng_default_fluid_look();
    s->contact_threshold = SCR_DEFAULT_CONTACT_THRESHOLD;
    s->splash_speed = SCR_DEFAULT_SPLASH_SPEED;
    s->L = lua_newstate(limited_alloc, s);
    if (!s->L) {
        free(s);
        return NULL;
    }
    *(eng_script **)lua_getextraspace(s->L) = s; // every coroutine copies it
    lua_setwarnf(s->L, script_warn, s);
    lua_pushcfunction(s->L, open_state);
    lua_pushlightuserdata(s->L, s);
    if (lua_pcall(s->L, 1, 0, 0) != LUA_OK) { // out of memory: no Lua state
        lua_close(s->L);
        free(s);
        return NULL;
    }
    lua_sethook(s->L, budget_hook, LUA_MASKCOUNT, hook_interval(s));
    return s;
}

void eng_script_destroy(eng_script *s)
{
    if (!s) return;
    // The Lua state first, while everything its handles name still exists: the finalisers of
    // a trusted script run in lua_close, and `closing` makes the API refuse them.
    s->closing = true;
    lua_close(s->L);
    s->L = NULL;
    for (uint32_t i = 0; i < s->obj_count; i++) {
        obj *o = &s->objs[i];
        if (o->state == OBJ_FREE || o->kind != OBJ_BODY) continue;
        if (s->host.scene && o->u.body.node.index1) eng_node_destroy(s->host.scene, o->u.body.node);
        if (s->host.meshes && o->u.body.mesh.index1) eng_mesh_destroy(s->host.meshes, o->u.body.mesh);
        scr_body_free_data(s, &o->u.body);
    }
    scr_clear_commands(s);
    free(s->commands);
    free(s->objs);
    free(s->timers);
    free(s->cache);
    free(s->texts);
    free(s->events);
    free(s->contacts);
    free(s->hits);
    free(s);
}

static eng_script_status load_chunk(eng_script *s, int rc)
{
    if (rc != LUA_OK) {
        const char *msg = lua_tostring(s->L, -1) ? lua_tostring(s->L, -1) : "(load error)";
        if (strstr(msg, "attempt to load a binary chunk"))
            snprintf(s->error, sizeof s->error, "%s:1: the script is a precompiled (binary) chunk: a scene script must "
                     "be Lua source text", s->path);
        else if (has_position(msg)) snprintf(s->error, sizeof s->error, "%s", msg);
        else snprintf(s->error, sizeof s->error, "%s: %s", s->path, msg);
        lua_pop(s->L, 1);
        return ENG_SCRIPT_ERROR;
    }
    s->in_main_chunk = true;
    eng_script_status st = run(s, 0, "the script's main chunk");
    s->in_main_chunk = false;
    return st;
}

eng_script_status eng_script_load(eng_script *s, const char *path)
{
    snprintf(s->path, sizeof s->path, "%s", path);
    struct stat st;
    const char *kind = NULL; // what the path names when that is not a regular file
    int why = 0;             // else the system's reason
    FILE *f = NULL;
    if (stat(path, &st) != 0) why = errno;
    else if (!S_ISREG(st.st_mode)) kind = S_ISDIR(st.st_mode) ? "a directory" : S_ISFIFO(st.st_mode) ? "a FIFO" : "a device or socket";
    else if (!(f = fopen(path, "rb"))) why = errno;
    if (!f) {
        if (kind) snprintf(s->error, sizeof s->error, "%s: cannot open the script file (not a regular file: %s)", path, kind);
        else snprintf(s->error, sizeof s->error, "%s: cannot open the script file: %s", path, strerror(why));
        return ENG_SCRIPT_ERROR;
    }
    fclose(f);
    if ((long long)st.st_size > SCR_MAX_SCRIPT_BYTES) {
        snprintf(s->error, sizeof s->error, "%s: the script is %lld bytes; a scene script may be at most %lld MiB", path,
                 (long long)st.st_size, SCR_MAX_SCRIPT_BYTES >> 20);
        return ENG_SCRIPT_ERROR;
    }
    return load_chunk(s, luaL_loadfilex(s->L, path, "t"));
}

eng_script_status eng_script_load_string(eng_script *s, const char *chunk_name, const char *code)
{
    snprintf(s->path, sizeof s->path, "%s", chunk_name);
    char name[520];
    snprintf(name, sizeof name, "@%s", chunk_name);
    return load_chunk(s, luaL_loadbufferx(s->L, code, strlen(code), name, "t"));
}

const char *eng_script_error(const eng_script *s) { return s->error; }
const char *eng_script_path(const eng_script *s) { return s->path; }
eng_scene_config *eng_script_config(eng_script *s) { return &s->config; }
void eng_script_set_host(eng_script *s, const eng_script_host *host)
{
    // A new Bullet world sums its contacts over each frame's substeps for on_contact.
    if (host->phys && host->phys != s->host.phys) phys_world_set_contact_sums(host->phys, true);
    s->host = *host;
}
int eng_script_check_sites(const eng_script *s, const eng_check_site **out)
{
    *out = s->checks;
    return s->check_count;
}

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
//
// Everything the host does in the Lua state happens inside run's protected call: the
// lookup (raw, so no __index of _G runs), the arguments (a string may not fit in memory)
// and the call.

// Arguments of callback_call: a number, an integer, a string.
#define NUM(v) { .type = 'n', .number = (v) }
#define INT(v) { .type = 'i', .number = (v) }
#define STR(v) { .type = 's', .string = (v) }

typedef struct callback_call {
    const char *name;       // the global's name
    int nargs;
    scr_arg args[SCR_MAX_CALLBACK_ARGS];
    bool want_result, result;
} callback_call;

static int call_callback(lua_State *L)
{
    callback_call *c = lua_touserdata(L, 1);
    lua_pushglobaltable(L);
    lua_pushstring(L, c->name);
    if (lua_rawget(L, -2) == LUA_TNIL) return 0; // not defined
    if (lua_type(L, -1) != LUA_TFUNCTION) {
        if (luaL_getmetafield(L, -1, "__call") == LUA_TNIL)
            return luaL_error(L, "%s must be a function or a table with a __call metamethod (got a %s value): the "
                              "runner calls the global %s", c->name, luaL_typename(L, -1), c->name);
        lua_pop(L, 1);
    }
    for (int i = 0; i < c->nargs; i++) {
        const scr_arg *a = &c->args[i];
        if (a->type == 's') lua_pushstring(L, a->string);
        else if (a->type == 'i') lua_pushinteger(L, (lua_Integer)a->number);
        else if (a->type == 'v') scr_push_vec3(L, a->vec[0], a->vec[1], a->vec[2]);
        else if (a->type == 'h' && a->slot != NO_SLOT) scr_push_handle(L, scr_state_script(L), a->slot);
        else if (a->type == 'h') lua_pushnil(L);
        else lua_pushnumber(L, a->number);
    }
    lua_call(L, c->nargs, c->want_result ? 1 : 0);
    if (c->want_result) c->result = lua_toboolean(L, -1);
    return 0;
}

static eng_script_status callback(eng_script *s, callback_call *c)
{
    if (strcmp(c->name, "on_start") != 0 && strcmp(c->name, "on_reload") != 0) s->loaded = true; // the load is over
    lua_pushcfunction(s->L, call_callback);
    lua_pushlightuserdata(s->L, c);
    return run(s, 1, c->name);
}

eng_script_status scr_callback(eng_script *s, const char *name, int nargs, const scr_arg *args)
{
    callback_call c = { .name = name, .nargs = nargs };
    assert(nargs <= SCR_MAX_CALLBACK_ARGS);
    memcpy(c.args, args, (size_t)nargs * sizeof *args);
    return callback(s, &c);
}

typedef struct timer_call {
    int fn;                 // registry reference to the timer's function
    double time;
} timer_call;

static int call_timer(lua_State *L)
{
    timer_call *c = lua_touserdata(L, 1);
    lua_rawgeti(L, LUA_REGISTRYINDEX, c->fn);
    lua_pushnumber(L, c->time);
    lua_call(L, 1, 0);
    return 0;
}

static eng_script_status run_timer(eng_script *s, int fn, double time)
{
    timer_call c = { fn, time };
    lua_pushcfunction(s->L, call_timer);
    lua_pushlightuserdata(s->L, &c);
    return run(s, 1, "a timer callback");
}

eng_script_status eng_script_on_start(eng_script *s)
{
    callback_call c = { .name = "on_start" };
    return callback(s, &c);
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
    eng_script_status st = scr_fire_events(s);
    if (st != ENG_SCRIPT_OK) return st;
    callback_call c = { .name = "on_step", .nargs = 2, .args = { NUM(dt), NUM(time) } };
    st = callback(s, &c);
    if (st == ENG_SCRIPT_OK) st = scr_fire_timers(s, time, run_timer);
    return st;
}

eng_script_status eng_script_on_key(eng_script *s, const char *key, const char *action, double x, double y)
{
    callback_call c = { .name = "on_key", .nargs = 4,
                        .args = { STR(key), STR(action), NUM(x), NUM(y) } };
    return callback(s, &c);
}

eng_script_status eng_script_on_mouse(eng_script *s, int button, const char *action, double x, double y, bool *consumed)
{
    callback_call c = { .name = "on_mouse", .nargs = 4, .want_result = true,
                        .args = { INT(button), STR(action), NUM(x), NUM(y) } };
    eng_script_status st = callback(s, &c);
    if (consumed) *consumed = st == ENG_SCRIPT_OK && c.result;
    return st;
}

eng_script_status eng_script_on_mouse_move(eng_script *s, double x, double y, double dx, double dy)
{
    callback_call c = { .name = "on_mouse_move", .nargs = 4,
                        .args = { NUM(x), NUM(y), NUM(dx), NUM(dy) } };
    return callback(s, &c);
}

eng_script_status eng_script_on_scroll(eng_script *s, double dx, double dy)
{
    callback_call c = { .name = "on_scroll", .nargs = 2, .args = { NUM(dx), NUM(dy) } };
    return callback(s, &c);
}

eng_script_status eng_script_on_reload(eng_script *s)
{
    callback_call c = { .name = "on_reload" };
    return callback(s, &c);
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
