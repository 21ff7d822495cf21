// The table functions whose loops a C call hides from the time budget, written again with a
// work counter: table.concat, insert, remove and move loop as often as a length or a range
// says (a __len of 1e15 or table.move(t, 1, 1e15, 1) is one call and never ends), and each
// element may go through a C metamethod that runs no Lua (__index = rawlen). table.sort
// keeps Lua's own algorithm but compares through a counting comparator.
//
// The behaviour is Lua 5.4's own, messages included; tests/test_sandbox.c compares them.
#include "engine/script/script_internal.h"

#include <limits.h>
#include <string.h>

enum { TAB_R = 1, TAB_W = 2, TAB_L = 4, TAB_RW = TAB_R | TAB_W };

static int has_field(lua_State *L, const char *key, int n)
{
    lua_pushstring(L, key);
    return lua_rawget(L, -n) != LUA_TNIL;
}

// Argument arg must be a table, or have the metamethods for what is done with it.
static void check_table(lua_State *L, int arg, int what)
{
    if (lua_type(L, arg) == LUA_TTABLE) return;
    int n = 1;
    if (lua_getmetatable(L, arg) && (!(what & TAB_R) || has_field(L, "__index", ++n)) &&
        (!(what & TAB_W) || has_field(L, "__newindex", ++n)) && (!(what & TAB_L) || has_field(L, "__len", ++n)))
        lua_pop(L, n);
    else
        luaL_checktype(L, arg, LUA_TTABLE); // raises the usual message
}

static lua_Integer checked_length(lua_State *L, int arg, int what)
{
    check_table(L, arg, what | TAB_L);
    return luaL_len(L, arg);
}

static int tab_insert(lua_State *L)
{
    eng_script *s = scr_state_script(L);
    lua_Integer e = checked_length(L, 1, TAB_RW);
    e = (lua_Integer)((lua_Unsigned)e + 1u); // the first empty slot
    lua_Integer pos;
    switch (lua_gettop(L)) {
    case 2:
        pos = e;
        break;
    case 3:
        pos = luaL_checkinteger(L, 2);
        luaL_argcheck(L, (lua_Unsigned)pos - 1u < (lua_Unsigned)e, 2, "position out of bounds");
        for (lua_Integer i = e; i > pos; i--) { // move up
            lua_geti(L, 1, i - 1);
            lua_seti(L, 1, i);
            scr_tick(L, s, 1);
        }
        break;
    default:
        return luaL_error(L, "wrong number of arguments to 'insert'");
    }
    lua_seti(L, 1, pos);
    return 0;
}

static int tab_remove(lua_State *L)
{
    eng_script *s = scr_state_script(L);
    lua_Integer size = checked_length(L, 1, TAB_RW);
    lua_Integer pos = luaL_optinteger(L, 2, size);
    if (pos != size) luaL_argcheck(L, (lua_Unsigned)pos - 1u <= (lua_Unsigned)size, 1, "position out of bounds"); // 1, as Lua 5.4.4
    lua_geti(L, 1, pos);
    for (; pos < size; pos++) {
        lua_geti(L, 1, pos + 1);
        lua_seti(L, 1, pos);
        scr_tick(L, s, 1);
    }
    lua_pushnil(L);
    lua_seti(L, 1, pos);
    return 1;
}

static int tab_move(lua_State *L)
{
    eng_script *s = scr_state_script(L);
    lua_Integer f = luaL_checkinteger(L, 2);
    lua_Integer e = luaL_checkinteger(L, 3);
    lua_Integer t = luaL_checkinteger(L, 4);
    int tt = !lua_isnoneornil(L, 5) ? 5 : 1;
    check_table(L, 1, TAB_R);
    check_table(L, tt, TAB_W);
    if (e >= f) {
        luaL_argcheck(L, f > 0 || e < LUA_MAXINTEGER + f, 3, "too many elements to move");
        lua_Integer n = e - f + 1;
        luaL_argcheck(L, t <= LUA_MAXINTEGER - n + 1, 4, "destination wrap around");
        if (t > e || t <= f || (tt != 1 && !lua_compare(L, 1, tt, LUA_OPEQ))) {
            for (lua_Integer i = 0; i < n; i++) {
                lua_geti(L, 1, f + i);
                lua_seti(L, tt, t + i);
                scr_tick(L, s, 1);
            }
        } else { // overlapping, moving up: from the end
            for (lua_Integer i = n - 1; i >= 0; i--) {
                lua_geti(L, 1, f + i);
                lua_seti(L, tt, t + i);
                scr_tick(L, s, 1);
            }
        }
    }
    lua_pushvalue(L, tt);
    return 1;
}

static void add_field(lua_State *L, luaL_Buffer *b, lua_Integer i)
{
    lua_geti(L, 1, i);
    if (!lua_isstring(L, -1))
        luaL_error(L, "invalid value (%s) at index %I in table for 'concat'", luaL_typename(L, -1), i);
    luaL_addvalue(b);
}

static int tab_concat(lua_State *L)
{
    eng_script *s = scr_state_script(L);
    lua_Integer last = checked_length(L, 1, TAB_R);
    size_t lsep;
    const char *sep = luaL_optlstring(L, 2, "", &lsep);
    lua_Integer i = luaL_optinteger(L, 3, 1);
    last = luaL_optinteger(L, 4, last);
    size_t room = scr_memory_room(s);
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    for (; i <= last; i++) {
        add_field(L, &b, i);
        if (i < last) luaL_addlstring(&b, sep, lsep);
        if (luaL_bufflen(&b) > room)
            return luaL_error(L, "table.concat: the result would be larger than the %I bytes left of the script's %d "
                              "MiB of memory", (lua_Integer)room, (int)(SCR_MEMORY_LIMIT >> 20));
        scr_tick(L, s, 1);
        if (i == LUA_MAXINTEGER) break; // i + 1 would overflow
    }
    luaL_pushresult(&b);
    return 1;
}

// The comparator table.sort gets: the script's (upvalue 1) or '<', counted.
static int counted_less(lua_State *L)
{
    scr_tick(L, scr_state_script(L), 1);
    if (lua_isnil(L, lua_upvalueindex(1))) {
        lua_pushboolean(L, lua_compare(L, 1, 2, LUA_OPLT));
    } else {
        lua_pushvalue(L, lua_upvalueindex(1));
        lua_pushvalue(L, 1);
        lua_pushvalue(L, 2);
        lua_call(L, 2, 1);
        lua_pushboolean(L, lua_toboolean(L, -1));
    }
    return 1;
}

static int tab_sort(lua_State *L)
{
    lua_Integer n = checked_length(L, 1, TAB_RW);
    if (n <= 1) return 0;
    luaL_argcheck(L, n < INT_MAX, 1, "array too big");
    if (!lua_isnoneornil(L, 2)) luaL_checktype(L, 2, LUA_TFUNCTION);
    lua_settop(L, 2);
    lua_pushvalue(L, lua_upvalueindex(1)); // Lua's sort
    lua_pushvalue(L, 1);
    lua_pushvalue(L, 2);
    lua_pushcclosure(L, counted_less, 1);
    if (lua_pcall(L, 2, 0, 0) != LUA_OK) {
        // Lua's sort names the line of its caller, which is this function: name the script's.
        const char *msg = lua_tostring(L, -1);
        char where[256];
        if (msg && strcmp(msg, "invalid order function for sorting") == 0)
            lua_pushfstring(L, "%s%s", scr_where(L, where, sizeof where), msg);
        return lua_error(L);
    }
    return 0;
}

void scr_open_bounded_table(lua_State *L)
{
    static const luaL_Reg fns[] = { { "insert", tab_insert }, { "remove", tab_remove }, { "move", tab_move },
                                    { "concat", tab_concat }, { NULL, NULL } };
    lua_getglobal(L, "table");
    luaL_setfuncs(L, fns, 0);
    lua_getfield(L, -1, "sort");
    lua_pushcclosure(L, tab_sort, 1);
    lua_setfield(L, -2, "sort");
    lua_pop(L, 1);
}
