// What a script's Lua state holds besides the seiche table, as Lua's linit.c lists the
// libraries of lua.c: by default an allow-list (docs/lua-api.md, "What a script can and
// cannot do"); with --trusted every standard library.
//
// The sandbox: the base library without dofile and loadfile, with load (text only),
// setmetatable (no __gc: a finaliser runs where no time budget reaches it, with Lua's debug
// hooks off), xpcall (its handler runs once the stack has unwound, not at the error: a
// handler runs with hooks off when the error came from the budget hook) and require (Lua
// modules from the scene's own folder); string (no dump), table, math, utf8, coroutine;
// os.clock, os.time, os.date and os.difftime. In both modes string.find/match/gmatch/gsub/rep,
// utf8.len/offset and table.concat/insert/remove/move/sort are the bounded versions
// (script_strlib.c, script_tablib.c), and coroutine.resume/wrap keep the chain of running
// coroutines for the budget.
#define _XOPEN_SOURCE 700 // realpath
#include "engine/script/script_internal.h"

#include <limits.h>
#include <lualib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *const LOADED_KEY = "seiche.modules";

// ---- base library replacements -------------------------------------------------------------

static int sb_setmetatable(lua_State *L)
{
    int t = lua_type(L, 2);
    luaL_checktype(L, 1, LUA_TTABLE);
    luaL_argexpected(L, t == LUA_TNIL || t == LUA_TTABLE, 2, "nil or table");
    if (t == LUA_TTABLE) {
        lua_pushliteral(L, "__gc");
        bool gc = lua_rawget(L, 2) != LUA_TNIL;
        lua_pop(L, 1);
        if (gc)
            return luaL_error(L, "setmetatable: a metatable with __gc (a finaliser) is not allowed in a scene script: "
                              "finalisers run where the time budget cannot stop them (run with --trusted to allow it)");
    }
    if (luaL_getmetafield(L, 1, "__metatable") != LUA_TNIL) return luaL_error(L, "cannot change a protected metatable");
    lua_settop(L, 2);
    lua_setmetatable(L, 1);
    return 1;
}

// load(chunk [, chunkname [, mode [, env]]]): Lua's, always in text mode.
static const char *reader(lua_State *L, void *ud, size_t *size)
{
    (void)ud;
    luaL_checkstack(L, 2, "too many nested functions");
    lua_pushvalue(L, 1);
    lua_call(L, 0, 1);
    if (lua_isnil(L, -1)) {
        lua_pop(L, 1);
        *size = 0;
        return NULL;
    }
    if (!lua_isstring(L, -1)) luaL_error(L, "reader function must return a string");
    lua_replace(L, 5); // kept alive in a reserved slot while the parser reads it
    return lua_tolstring(L, 5, size);
}

// A string chunk, given to the parser 64 KiB at a time with the work counted (scr_tick), so that
// the budget reaches into the parse of a long source (72 MB took 4 s in one call).
typedef struct string_chunk {
    const char *text;
    size_t left;
    eng_script *script;
} string_chunk;

static const char *string_reader(lua_State *L, void *ud, size_t *size)
{
    string_chunk *c = ud;
    size_t n = c->left < ((size_t)64 << 10) ? c->left : ((size_t)64 << 10);
    if (n == 0) {
        *size = 0;
        return NULL;
    }
    scr_tick(L, c->script, n);
    const char *piece = c->text;
    c->text += n;
    c->left -= n;
    *size = n;
    return piece;
}

static int sb_load(lua_State *L)
{
    size_t l;
    const char *s = lua_tolstring(L, 1, &l);
    luaL_optstring(L, 3, "t"); // any mode is read as "t"
    int env = !lua_isnone(L, 4) ? 4 : 0;
    int status;
    if (s) {
        const char *name = luaL_optstring(L, 2, s);
        string_chunk chunk = { s, l, scr_state_script(L) };
        status = lua_load(L, string_reader, &chunk, name, "t");
    } else {
        const char *name = luaL_optstring(L, 2, "=(load)");
        luaL_checktype(L, 1, LUA_TFUNCTION);
        lua_settop(L, 5);
        status = lua_load(L, reader, NULL, name, "t");
    }
    if (status == LUA_OK) {
        if (env) {
            lua_pushvalue(L, env);
            if (!lua_setupvalue(L, -2, 1)) lua_pop(L, 1);
        }
        return 1;
    }
    const char *msg = lua_tostring(L, -1);
    if (msg && strstr(msg, "attempt to load a binary chunk"))
        lua_pushliteral(L, "load: binary (precompiled) chunks are not allowed in a scene script: give Lua source text");
    luaL_pushfail(L);
    lua_insert(L, -2);
    return 2;
}

// os.date(format [, time]): Lua's, with the format at most SB_DATE_FORMAT_MAX bytes: one call
// expands it in C, where no budget reaches (string.rep("%n", 8e7) took 6.6 s).
#define SB_DATE_FORMAT_MAX 1024

static int sb_os_date(lua_State *L)
{
    size_t n = 0;
    if (lua_type(L, 1) == LUA_TSTRING) lua_tolstring(L, 1, &n);
    if (n > SB_DATE_FORMAT_MAX)
        return luaL_error(L, "os.date: argument #1 'format' is %I bytes long; at most %d", (lua_Integer)n, SB_DATE_FORMAT_MAX);
    lua_pushvalue(L, lua_upvalueindex(1));
    lua_insert(L, 1);
    lua_call(L, lua_gettop(L) - 1, LUA_MULTRET);
    return lua_gettop(L);
}

// xpcall(f, handler, ...): the handler runs after the call has unwound.
static int finish_xpcall(lua_State *L, int status, lua_KContext extra)
{
    if (status != LUA_OK && status != LUA_YIELD) {
        lua_pushvalue(L, 2);
        lua_rotate(L, -2, 1);
        lua_pcall(L, 1, 1, 0); // a failing handler's error becomes the result
        lua_pushboolean(L, 0);
        lua_rotate(L, -2, 1);
        return 2;
    }
    return lua_gettop(L) - (int)extra;
}

static int sb_xpcall(lua_State *L)
{
    int n = lua_gettop(L);
    luaL_checktype(L, 2, LUA_TFUNCTION);
    lua_pushboolean(L, 1);
    lua_pushvalue(L, 1);
    lua_rotate(L, 3, 2);
    int status = lua_pcallk(L, n - 2, LUA_MULTRET, 0, 2, finish_xpcall);
    return finish_xpcall(L, status, 2);
}

// ---- coroutine.resume and wrap: Lua's, keeping the chain of running coroutines -------------
//
// The budget's hook is per coroutine; the allocator and a stop set it on the one that runs
// (script.c), which only these two functions know.

static int resume(lua_State *L, lua_State *co, int narg)
{
    eng_script *s = scr_state_script(L);
    if (!lua_checkstack(co, narg)) {
        lua_pushliteral(L, "too many arguments to resume");
        return -1;
    }
    lua_xmove(L, co, narg);
    int depth = s->thread_depth, nres;
    if (depth < SCR_MAX_THREADS) s->threads[depth] = co;
    s->thread_depth = depth + 1;
    int status = lua_resume(co, L, narg, &nres); // errors in co end here: no longjmp past the pop
    s->thread_depth = depth;
    if (status == LUA_OK || status == LUA_YIELD) {
        if (!lua_checkstack(L, nres + 1)) {
            lua_pop(co, nres);
            lua_pushliteral(L, "too many results to resume");
            return -1;
        }
        lua_xmove(co, L, nres);
        return nres;
    }
    lua_xmove(co, L, 1); // the error
    return -1;
}

static int co_resume(lua_State *L)
{
    lua_State *co = lua_tothread(L, 1);
    luaL_argexpected(L, co, 1, "thread");
    int r = resume(L, co, lua_gettop(L) - 1);
    if (r < 0) {
        lua_pushboolean(L, 0);
        lua_insert(L, -2);
        return 2;
    }
    lua_pushboolean(L, 1);
    lua_insert(L, -(r + 1));
    return r + 1;
}

static int co_wrapped(lua_State *L)
{
    lua_State *co = lua_tothread(L, lua_upvalueindex(1));
    int r = resume(L, co, lua_gettop(L));
    if (r < 0) {
        int status = lua_status(co);
        if (status != LUA_OK && status != LUA_YIELD) { // an error in the coroutine: close it
            lua_resetthread(co);
            lua_xmove(co, L, 1);
        }
        if (status != LUA_ERRMEM && lua_type(L, -1) == LUA_TSTRING) {
            luaL_where(L, 1);
            lua_insert(L, -2);
            lua_concat(L, 2);
        }
        return lua_error(L);
    }
    return r;
}

static int co_wrap(lua_State *L)
{
    luaL_checktype(L, 1, LUA_TFUNCTION);
    lua_State *co = lua_newthread(L);
    lua_pushvalue(L, 1);
    lua_xmove(L, co, 1);
    lua_pushcclosure(L, co_wrapped, 1);
    return 1;
}

// ---- require: Lua modules from the scene's folder -----------------------------------------------

// The folder of the script's file ("." for a bare name).
void scr_scene_root(const eng_script *s, char *out, size_t size)
{
    const char *slash = strrchr(s->path, '/');
    if (!slash) snprintf(out, size, ".");
    else if (slash == s->path) snprintf(out, size, "/");
    else snprintf(out, size, "%.*s", (int)(slash - s->path), s->path);
}

static bool valid_module_name(const char *name)
{
    if (!*name || *name == '.') return false;
    for (const char *p = name; *p; p++) {
        bool ok = (*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') || *p == '_' ||
                  (*p == '.' && p[1] && p[1] != '.');
        if (!ok) return false;
    }
    return true;
}

// path is a regular file whose real path lies inside the folder's real path.
static const char *check_module_file(const char *path, const char *folder_real, char *real, size_t real_size)
{
    struct stat st;
    if (stat(path, &st) != 0) return "missing";
    if (!S_ISREG(st.st_mode)) return "not a regular file";
    if (st.st_size > SCR_MAX_SCRIPT_BYTES) return "larger than 64 MiB";
    char buf[PATH_MAX];
    if (!realpath(path, buf)) return "unreadable";
    size_t n = strlen(folder_real);
    bool inside = strncmp(buf, folder_real, n) == 0 && (buf[n] == '/' || (n == 1 && folder_real[0] == '/'));
    if (!inside) return "outside the scene's folder (a link?)";
    snprintf(real, real_size, "%s", buf);
    return NULL;
}

static int sb_require(lua_State *L)
{
    eng_script *s = scr_state_script(L);
    const char *name = luaL_checkstring(L, 1);
    lua_settop(L, 1);
    lua_getfield(L, LUA_REGISTRYINDEX, LOADED_KEY);
    if (lua_getfield(L, 2, name) != LUA_TNIL) {
        if (lua_type(L, -1) == LUA_TLIGHTUSERDATA)
            return luaL_error(L, "require: module '%s' requires itself while it loads (a loop)", name);
        return 1;
    }
    lua_pop(L, 1);
    if (!valid_module_name(name))
        return luaL_error(L, "require: bad module name '%s': names are letters, digits and _ joined by dots, as in "
                          "require 'lib.waves' for lib/waves.lua in the scene's folder (no paths, no '..')", name);
    char folder[512], folder_real[PATH_MAX], rel[512], path[2][1100], real[PATH_MAX];
    scr_scene_root(s, folder, sizeof folder);
    if (!realpath(folder, folder_real)) return luaL_error(L, "require: cannot read the scene's folder '%s'", folder);
    snprintf(rel, sizeof rel, "%s", name);
    for (char *p = rel; *p; p++)
        if (*p == '.') *p = '/';
    const char *prefix = strcmp(folder, ".") == 0 ? "" : folder;
    const char *sep = *prefix && strcmp(prefix, "/") != 0 ? "/" : "";
    snprintf(path[0], sizeof path[0], "%s%s%s.lua", prefix, sep, rel);
    snprintf(path[1], sizeof path[1], "%s%s%s/init.lua", prefix, sep, rel);
    const char *why[2];
    int found = -1;
    for (int i = 0; i < 2 && found < 0; i++) {
        why[i] = check_module_file(path[i], folder_real, real, sizeof real);
        if (!why[i]) found = i;
    }
    if (found < 0)
        return luaL_error(L, "require: module '%s' not found: '%s' (%s), '%s' (%s); a scene requires Lua modules from its "
                          "own folder '%s' and below", name, path[0], why[0], path[1], why[1], folder);
    if (luaL_loadfilex(L, path[found], "t") != LUA_OK) return lua_error(L);
    lua_pushlightuserdata(L, s); // "loading": a module that requires itself is a loop
    lua_setfield(L, 2, name);
    lua_pushstring(L, name);
    lua_pushstring(L, path[found]);
    if (lua_pcall(L, 2, 1, 0) != LUA_OK) { // forget the failed module, then pass its error on
        lua_pushnil(L);
        lua_setfield(L, 2, name);
        return lua_error(L);
    }
    if (lua_isnil(L, -1)) {
        lua_pop(L, 1);
        lua_pushboolean(L, 1);
    }
    lua_pushvalue(L, -1);
    lua_setfield(L, 2, name);
    lua_pushstring(L, path[found]);
    return 2;
}

// ---- files a scene names (meshes) ---------------------------------------------------------------

// The folder of the file whose code is running (the innermost Lua function loaded from a
// file), or the scene's folder when none is.
static void calling_folder(lua_State *L, const eng_script *s, char *out, size_t size)
{
    lua_Debug ar;
    for (int level = 0; lua_getstack(L, level, &ar); level++) {
        if (!lua_getinfo(L, "S", &ar) || ar.source[0] != '@') continue;
        const char *file = ar.source + 1, *slash = strrchr(file, '/');
        if (!slash) snprintf(out, size, ".");
        else if (slash == file) snprintf(out, size, "/");
        else snprintf(out, size, "%.*s", (int)(slash - file), file);
        return;
    }
    scr_scene_root(s, out, size);
}

const char *scr_scene_file(lua_State *L, const eng_script *s, const char *rel, char *out, size_t size)
{
    if (!*rel) return "an empty path";
    if (strlen(rel) > 500) return "a path longer than 500 characters";
    if (!s->trusted) {
        if (rel[0] == '/') return "an absolute path: a scene names its files relative to its own file";
        for (const char *p = rel; *p; p = strchr(p, '/') ? strchr(p, '/') + 1 : p + strlen(p))
            if (p[0] == '.' && p[1] == '.' && (p[2] == '/' || p[2] == 0)) return "a path through '..'";
    }
    char folder[600], path[1200];
    calling_folder(L, s, folder, sizeof folder);
    if (rel[0] == '/') snprintf(path, sizeof path, "%s", rel);
    else snprintf(path, sizeof path, "%s/%s", folder, rel);
    if (s->trusted) {
        struct stat st;
        if (stat(path, &st) != 0) return "missing";
        if (!S_ISREG(st.st_mode)) return "not a regular file";
        snprintf(out, size, "%s", path);
        return NULL;
    }
    char scene[512], scene_real[PATH_MAX], real[PATH_MAX];
    scr_scene_root(s, scene, sizeof scene);
    if (!realpath(scene, scene_real)) return "in a scene whose folder cannot be read";
    const char *why = check_module_file(path, scene_real, real, sizeof real);
    if (why) return why;
    snprintf(out, size, "%s", path);
    return NULL;
}

// ---- what the sandbox leaves out ------------------------------------------------------------
//
// A left-out name is not nil but says why: io, package and debug are tables whose every
// field raises, dofile, loadfile and string.dump functions that raise, and the os table
// raises for the fields it lacks (os.execute, os.getenv, os.exit, ...).

static int refuse_name(lua_State *L, const char *name)
{
    return luaL_error(L, "%s is not available in a scene script: scripts run in a sandbox (docs/lua-api.md, \"What a "
                      "script can and cannot do\"); the runner's --trusted gives a script you trust every library", name);
}

static int refused_function(lua_State *L) { return refuse_name(L, lua_tostring(L, lua_upvalueindex(1))); }

// __index and __newindex of a left-out library: (t, key) names "lib.key".
static int refused_field(lua_State *L)
{
    const char *lib = lua_tostring(L, lua_upvalueindex(1));
    if (lua_type(L, 2) == LUA_TSTRING) lua_pushfstring(L, "%s.%s", lib, lua_tostring(L, 2));
    else lua_pushfstring(L, "%s[%s]", lib, luaL_typename(L, 2));
    return refuse_name(L, lua_tostring(L, -1));
}

// Sets the table on top's metatable to one that refuses every missing field of `lib`.
static void refuse_missing_fields(lua_State *L, const char *lib)
{
    lua_createtable(L, 0, 3);
    lua_pushstring(L, lib);
    lua_pushcclosure(L, refused_field, 1);
    lua_setfield(L, -2, "__index");
    lua_pushstring(L, lib);
    lua_pushcclosure(L, refused_field, 1);
    lua_setfield(L, -2, "__newindex");
    lua_pushboolean(L, 0);
    lua_setfield(L, -2, "__metatable");
    lua_setmetatable(L, -2);
}

static void refuse_function(lua_State *L, int table, const char *field, const char *name)
{
    table = lua_absindex(L, table);
    lua_pushstring(L, name);
    lua_pushcclosure(L, refused_function, 1);
    lua_setfield(L, table, field);
}

// ---- opening the libraries ------------------------------------------------------------------

static void open_sandbox(lua_State *L)
{
    static const struct { const char *name; lua_CFunction open; } libs[] = {
        { LUA_GNAME, luaopen_base }, { LUA_COLIBNAME, luaopen_coroutine }, { LUA_TABLIBNAME, luaopen_table },
        { LUA_STRLIBNAME, luaopen_string }, { LUA_MATHLIBNAME, luaopen_math }, { LUA_UTF8LIBNAME, luaopen_utf8 },
    };
    for (size_t i = 0; i < sizeof libs / sizeof libs[0]; i++) {
        luaL_requiref(L, libs[i].name, libs[i].open, 1);
        lua_pop(L, 1);
    }
    // os: the clock and dates only (no execute, exit, getenv, remove, rename, tmpname, setlocale).
    luaL_requiref(L, LUA_OSLIBNAME, luaopen_os, 0);
    lua_createtable(L, 0, 4);
    static const char *const os_kept[] = { "clock", "time", "date", "difftime" };
    for (size_t i = 0; i < sizeof os_kept / sizeof os_kept[0]; i++) {
        lua_getfield(L, -2, os_kept[i]);
        lua_setfield(L, -2, os_kept[i]);
    }
    lua_getfield(L, -1, "date"); // os.date with its format's length bounded
    lua_pushcclosure(L, sb_os_date, 1);
    lua_setfield(L, -2, "date");
    refuse_missing_fields(L, "os");
    lua_setglobal(L, LUA_OSLIBNAME);
    lua_pop(L, 1);
    static const char *const left_out[] = { LUA_IOLIBNAME, LUA_LOADLIBNAME, LUA_DBLIBNAME };
    for (size_t i = 0; i < sizeof left_out / sizeof left_out[0]; i++) {
        lua_newtable(L);
        refuse_missing_fields(L, left_out[i]);
        lua_setglobal(L, left_out[i]);
    }
    static const luaL_Reg base[] = { { "load", sb_load }, { "setmetatable", sb_setmetatable }, { "xpcall", sb_xpcall },
                                     { "require", sb_require }, { NULL, NULL } };
    lua_pushglobaltable(L);
    luaL_setfuncs(L, base, 0);
    refuse_function(L, -1, "dofile", "dofile");
    refuse_function(L, -1, "loadfile", "loadfile");
    lua_pop(L, 1);
    lua_getglobal(L, LUA_STRLIBNAME);
    refuse_function(L, -1, "dump", "string.dump");
    lua_pop(L, 1);
    lua_newtable(L);
    lua_setfield(L, LUA_REGISTRYINDEX, LOADED_KEY);
}

void scr_open_libraries(lua_State *L, bool trusted)
{
    if (trusted) luaL_openlibs(L);
    else open_sandbox(L);
    scr_open_bounded_string(L);
    scr_open_bounded_table(L);
    static const luaL_Reg co[] = { { "resume", co_resume }, { "wrap", co_wrap }, { NULL, NULL } };
    lua_getglobal(L, LUA_COLIBNAME);
    luaL_setfuncs(L, co, 0);
    lua_pop(L, 1);
}
