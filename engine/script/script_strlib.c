// The string functions whose cost a C call can hide from the time budget, written again with
// a work counter: string.find, match, gmatch and gsub (Lua 5.4 patterns: a pattern like
// string.rep("a*", 30) .. "b" backtracks for hours inside one call, where the count hook
// never fires), string.rep (string.rep("", 1e15) loops 1e15 times and allocates nothing),
// utf8.len and utf8.offset (a slow scan of a long string that allocates nothing: the
// allocator cannot see it either, script.c).
//
// The behaviour is Lua 5.4's own, message for message (tests/test_sandbox.c compares them
// with the standard library on a table of cases); the only addition is scr_tick, called for
// every few thousand steps of matching, which stops the call once the budget is spent.
#include "engine/script/script_internal.h"

#include <ctype.h>
#include <string.h>

#define ESC '%'
#define SPECIALS "^$*+?.([%-"
#define MAX_CAPTURES 32
#define MAX_MATCH_DEPTH 200
#define CAP_UNFINISHED (-1)
#define CAP_POSITION (-2)
/// Steps of matching between two looks at the budget.
#define WORK_QUANTUM 4096

typedef struct match_state {
    const char *src_init, *src_end, *p_end;
    lua_State *L;
    eng_script *s;
    size_t work;
    int depth;     // recursion left before "pattern too complex"
    int level;     // captures open or closed
    struct { const char *init; ptrdiff_t len; } capture[MAX_CAPTURES];
} match_state;

static void add_work(match_state *ms, size_t n)
{
    ms->work += n;
    if (ms->work >= WORK_QUANTUM) {
        scr_tick(ms->L, ms->s, ms->work);
        ms->work = 0;
    }
}

static const char *match(match_state *ms, const char *s, const char *p);

static int check_capture(match_state *ms, int l)
{
    l -= '1';
    if (l < 0 || l >= ms->level || ms->capture[l].len == CAP_UNFINISHED)
        return luaL_error(ms->L, "invalid capture index %%%d", l + 1);
    return l;
}

static int capture_to_close(match_state *ms)
{
    for (int level = ms->level - 1; level >= 0; level--)
        if (ms->capture[level].len == CAP_UNFINISHED) return level;
    return luaL_error(ms->L, "invalid pattern capture");
}

// The end of the single-character class at p ("x", "%a", "[...]").
static const char *class_end(match_state *ms, const char *p)
{
    switch (*p++) {
    case ESC:
        if (p == ms->p_end) luaL_error(ms->L, "malformed pattern (ends with '%%')");
        return p + 1;
    case '[':
        if (*p == '^') p++;
        do { // look for a ']'; the first character is always part of the set
            if (p == ms->p_end) luaL_error(ms->L, "malformed pattern (missing ']')");
            if (*(p++) == ESC && p < ms->p_end) p++; // skip escapes such as "%]"
        } while (*p != ']');
        return p + 1;
    default:
        return p;
    }
}

static int match_class(int c, int cl)
{
    int res;
    switch (tolower(cl)) {
    case 'a': res = isalpha(c); break;
    case 'c': res = iscntrl(c); break;
    case 'd': res = isdigit(c); break;
    case 'g': res = isgraph(c); break;
    case 'l': res = islower(c); break;
    case 'p': res = ispunct(c); break;
    case 's': res = isspace(c); break;
    case 'u': res = isupper(c); break;
    case 'w': res = isalnum(c); break;
    case 'x': res = isxdigit(c); break;
    case 'z': res = c == 0; break; // deprecated in 5.2, still in 5.4
    default: return cl == c;
    }
    if (isupper(cl)) res = !res;
    return res;
}

// c against the set [p .. ec] (p at '[', ec at the closing ']').
static int match_bracket_class(int c, const char *p, const char *ec)
{
    int sig = 1;
    if (*(p + 1) == '^') {
        sig = 0;
        p++;
    }
    while (++p < ec) {
        if (*p == ESC) {
            p++;
            if (match_class(c, (unsigned char)*p)) return sig;
        } else if (*(p + 1) == '-' && p + 2 < ec) {
            p += 2;
            if ((unsigned char)*(p - 2) <= c && c <= (unsigned char)*p) return sig;
        } else if ((unsigned char)*p == c) {
            return sig;
        }
    }
    return !sig;
}

static int single_match(match_state *ms, const char *s, const char *p, const char *ep)
{
    if (s >= ms->src_end) return 0;
    int c = (unsigned char)*s;
    switch (*p) {
    case '.': return 1;
    case ESC: return match_class(c, (unsigned char)*(p + 1));
    case '[': return match_bracket_class(c, p, ep - 1);
    default: return (unsigned char)*p == c;
    }
}

static const char *match_balance(match_state *ms, const char *s, const char *p)
{
    if (p >= ms->p_end - 1) luaL_error(ms->L, "malformed pattern (missing arguments to '%%b')");
    if (*s != *p) return NULL;
    int b = *p, e = *(p + 1), depth = 1;
    const char *start = s;
    while (++s < ms->src_end) {
        if (*s == e) {
            if (--depth == 0) {
                add_work(ms, (size_t)(s - start));
                return s + 1;
            }
        } else if (*s == b) {
            depth++;
        }
    }
    add_work(ms, (size_t)(s - start));
    return NULL;
}

static const char *max_expand(match_state *ms, const char *s, const char *p, const char *ep)
{
    ptrdiff_t i = 0;
    while (single_match(ms, s + i, p, ep)) i++;
    add_work(ms, (size_t)i + 1);
    for (; i >= 0; i--) { // longest first, then shorter
        const char *res = match(ms, s + i, ep + 1);
        if (res) return res;
    }
    return NULL;
}

static const char *min_expand(match_state *ms, const char *s, const char *p, const char *ep)
{
    for (;;) {
        const char *res = match(ms, s, ep + 1);
        if (res) return res;
        if (!single_match(ms, s, p, ep)) return NULL;
        s++;
    }
}

static const char *start_capture(match_state *ms, const char *s, const char *p, int what)
{
    int level = ms->level;
    if (level >= MAX_CAPTURES) luaL_error(ms->L, "too many captures");
    ms->capture[level].init = s;
    ms->capture[level].len = what;
    ms->level = level + 1;
    const char *res = match(ms, s, p);
    if (!res) ms->level--;
    return res;
}

static const char *end_capture(match_state *ms, const char *s, const char *p)
{
    int l = capture_to_close(ms);
    ms->capture[l].len = s - ms->capture[l].init;
    const char *res = match(ms, s, p);
    if (!res) ms->capture[l].len = CAP_UNFINISHED;
    return res;
}

static const char *match_capture(match_state *ms, const char *s, int l)
{
    l = check_capture(ms, l);
    size_t len = (size_t)ms->capture[l].len;
    add_work(ms, len);
    if ((size_t)(ms->src_end - s) >= len && memcmp(ms->capture[l].init, s, len) == 0) return s + len;
    return NULL;
}

// The end of the match of pattern p at s, or NULL.
static const char *match(match_state *ms, const char *s, const char *p)
{
    if (ms->depth-- == 0) luaL_error(ms->L, "pattern too complex");
    while (p != ms->p_end) {
        add_work(ms, 1);
        switch (*p) {
        case '(':
            s = *(p + 1) == ')' ? start_capture(ms, s, p + 2, CAP_POSITION) : start_capture(ms, s, p + 1, CAP_UNFINISHED);
            goto done;
        case ')':
            s = end_capture(ms, s, p + 1);
            goto done;
        case '$':
            if (p + 1 != ms->p_end) goto single; // not at the end: an ordinary '$'
            s = s == ms->src_end ? s : NULL;
            goto done;
        case ESC:
            if (*(p + 1) == 'b') {
                s = match_balance(ms, s, p + 2);
                if (!s) goto done;
                p += 4;
                continue;
            }
            if (*(p + 1) == 'f') {
                p += 2;
                if (*p != '[') luaL_error(ms->L, "missing '[' after '%%f' in pattern");
                const char *ep = class_end(ms, p);
                int previous = s == ms->src_init ? '\0' : (unsigned char)*(s - 1);
                if (!match_bracket_class(previous, p, ep - 1) && match_bracket_class((unsigned char)*s, p, ep - 1)) {
                    p = ep;
                    continue;
                }
                s = NULL;
                goto done;
            }
            if (isdigit((unsigned char)*(p + 1))) {
                s = match_capture(ms, s, (unsigned char)*(p + 1));
                if (!s) goto done;
                p += 2;
                continue;
            }
            goto single;
        default:
        single: {
            const char *ep = class_end(ms, p);
            if (!single_match(ms, s, p, ep)) {
                if (*ep == '*' || *ep == '?' || *ep == '-') { // may match nothing
                    p = ep + 1;
                    continue;
                }
                s = NULL; // '+' or no suffix
                goto done;
            }
            switch (*ep) {
            case '?': {
                const char *res = match(ms, s + 1, ep + 1);
                if (res) {
                    s = res;
                    goto done;
                }
                p = ep + 1;
                continue;
            }
            case '+': s = max_expand(ms, s + 1, p, ep); goto done;
            case '*': s = max_expand(ms, s, p, ep); goto done;
            case '-': s = min_expand(ms, s, p, ep); goto done;
            default: s++; p = ep; continue;
            }
        }
        }
    }
done:
    ms->depth++;
    return s;
}

// ---- captures ---------------------------------------------------------------------------

// Capture i (or the whole match s..e when there are none): its text in *cap and its length,
// or CAP_POSITION with the position pushed.
static ptrdiff_t get_capture(match_state *ms, int i, const char *s, const char *e, const char **cap)
{
    if (i >= ms->level) {
        if (i != 0) luaL_error(ms->L, "invalid capture index %%%d", i + 1);
        *cap = s;
        return e - s;
    }
    ptrdiff_t len = ms->capture[i].len;
    *cap = ms->capture[i].init;
    if (len == CAP_UNFINISHED) luaL_error(ms->L, "unfinished capture");
    else if (len == CAP_POSITION) lua_pushinteger(ms->L, (ms->capture[i].init - ms->src_init) + 1);
    return len;
}

static void push_capture(match_state *ms, int i, const char *s, const char *e)
{
    const char *cap;
    ptrdiff_t len = get_capture(ms, i, s, e, &cap);
    if (len != CAP_POSITION) lua_pushlstring(ms->L, cap, (size_t)len);
}

static int push_captures(match_state *ms, const char *s, const char *e)
{
    int n = ms->level == 0 && s ? 1 : ms->level;
    luaL_checkstack(ms->L, n, "too many captures");
    for (int i = 0; i < n; i++) push_capture(ms, i, s, e);
    return n;
}

static void prepare(match_state *ms, lua_State *L, const char *s, size_t ls, const char *p, size_t lp)
{
    ms->L = L;
    ms->s = scr_state_script(L);
    ms->work = 0;
    ms->depth = MAX_MATCH_DEPTH;
    ms->src_init = s;
    ms->src_end = s + ls;
    ms->p_end = p + lp;
}

static void restart(match_state *ms)
{
    ms->level = 0;
    ms->depth = MAX_MATCH_DEPTH;
}

// ---- find, match, gmatch, gsub ------------------------------------------------------------

// A position argument made absolute: 1-based, negatives count from the end, clamped at 1.
static size_t absolute_position(lua_Integer pos, size_t len)
{
    if (pos > 0) return (size_t)pos;
    if (pos == 0) return 1;
    if (pos < -(lua_Integer)len) return 1;
    return len + (size_t)pos + 1;
}

static int has_specials(const char *p, size_t l)
{
    size_t upto = 0;
    do {
        if (strpbrk(p + upto, SPECIALS)) return 1;
        upto += strlen(p + upto) + 1; // past an embedded zero
    } while (upto <= l);
    return 0;
}

// A plain search of p in s, counted as work.
static const char *find_plain(match_state *ms, const char *s, size_t ls, const char *p, size_t lp)
{
    if (lp == 0) return s;
    if (lp > ls) return NULL;
    const char *end = s + (ls - lp) + 1; // the last place p can start, plus one
    for (;;) {
        const char *at = memchr(s, *p, (size_t)(end - s));
        if (!at) {
            add_work(ms, (size_t)(end - s) / 16 + 1);
            return NULL;
        }
        add_work(ms, (size_t)(at - s) / 16 + lp);
        if (memcmp(at + 1, p + 1, lp - 1) == 0) return at;
        s = at + 1;
    }
}

static int find_aux(lua_State *L, int find)
{
    size_t ls, lp;
    const char *s = luaL_checklstring(L, 1, &ls);
    const char *p = luaL_checklstring(L, 2, &lp);
    size_t init = absolute_position(luaL_optinteger(L, 3, 1), ls) - 1;
    if (init > ls) {
        luaL_pushfail(L);
        return 1;
    }
    match_state ms;
    if (find && (lua_toboolean(L, 4) || !has_specials(p, lp))) {
        prepare(&ms, L, s, ls, p, lp);
        const char *at = find_plain(&ms, s + init, ls - init, p, lp);
        if (at) {
            lua_pushinteger(L, (at - s) + 1);
            lua_pushinteger(L, (at - s) + (lua_Integer)lp);
            return 2;
        }
    } else {
        const char *s1 = s + init;
        int anchor = *p == '^';
        if (anchor) {
            p++;
            lp--;
        }
        prepare(&ms, L, s, ls, p, lp);
        do {
            restart(&ms);
            const char *res = match(&ms, s1, p);
            if (res) {
                if (find) {
                    lua_pushinteger(L, (s1 - s) + 1);
                    lua_pushinteger(L, res - s);
                    return push_captures(&ms, NULL, 0) + 2;
                }
                return push_captures(&ms, s1, res);
            }
        } while (s1++ < ms.src_end && !anchor);
    }
    luaL_pushfail(L);
    return 1;
}

static int str_find(lua_State *L) { return find_aux(L, 1); }
static int str_match(lua_State *L) { return find_aux(L, 0); }

typedef struct gmatch_state {
    const char *src, *p, *lastmatch;
    match_state ms;
} gmatch_state;

static int gmatch_next(lua_State *L)
{
    gmatch_state *gm = lua_touserdata(L, lua_upvalueindex(3));
    gm->ms.L = L;
    for (const char *src = gm->src; src <= gm->ms.src_end; src++) {
        restart(&gm->ms);
        const char *e = match(&gm->ms, src, gm->p);
        if (e && e != gm->lastmatch) {
            gm->src = gm->lastmatch = e;
            return push_captures(&gm->ms, src, e);
        }
    }
    return 0;
}

static int str_gmatch(lua_State *L)
{
    size_t ls, lp;
    const char *s = luaL_checklstring(L, 1, &ls);
    const char *p = luaL_checklstring(L, 2, &lp);
    size_t init = absolute_position(luaL_optinteger(L, 3, 1), ls) - 1;
    lua_settop(L, 2); // the string and the pattern stay alive as upvalues
    gmatch_state *gm = lua_newuserdatauv(L, sizeof *gm, 0);
    if (init > ls) init = ls + 1; // start after the end: nothing to find
    prepare(&gm->ms, L, s, ls, p, lp);
    gm->src = s + init;
    gm->p = p;
    gm->lastmatch = NULL;
    lua_pushcclosure(L, gmatch_next, 3);
    return 1;
}

// The replacement string (argument 3) with %0..%9 and %% expanded.
static void add_string(match_state *ms, luaL_Buffer *b, const char *s, const char *e)
{
    size_t l;
    lua_State *L = ms->L;
    const char *news = lua_tolstring(L, 3, &l);
    const char *p;
    add_work(ms, l);
    while ((p = memchr(news, ESC, l)) != NULL) {
        luaL_addlstring(b, news, (size_t)(p - news));
        p++;
        if (*p == ESC) {
            luaL_addchar(b, *p);
        } else if (*p == '0') {
            luaL_addlstring(b, s, (size_t)(e - s));
        } else if (isdigit((unsigned char)*p)) {
            const char *cap;
            ptrdiff_t len = get_capture(ms, *p - '1', s, e, &cap);
            if (len == CAP_POSITION) luaL_addvalue(b);
            else luaL_addlstring(b, cap, (size_t)len);
        } else {
            luaL_error(L, "invalid use of '%c' in replacement string", ESC);
        }
        l -= (size_t)(p + 1 - news);
        news = p + 1;
    }
    luaL_addlstring(b, news, l);
}

// Adds the replacement of the match s..e; false when the original text was kept.
static int add_value(match_state *ms, luaL_Buffer *b, const char *s, const char *e, int tr)
{
    lua_State *L = ms->L;
    if (tr == LUA_TFUNCTION) {
        lua_pushvalue(L, 3);
        int n = push_captures(ms, s, e);
        lua_call(L, n, 1);
    } else if (tr == LUA_TTABLE) {
        push_capture(ms, 0, s, e);
        lua_gettable(L, 3);
    } else {
        add_string(ms, b, s, e);
        return 1;
    }
    if (!lua_toboolean(L, -1)) { // nil or false: keep the original text
        lua_pop(L, 1);
        luaL_addlstring(b, s, (size_t)(e - s));
        return 0;
    }
    if (!lua_isstring(L, -1)) return luaL_error(L, "invalid replacement value (a %s)", luaL_typename(L, -1));
    luaL_addvalue(b);
    return 1;
}

static int str_gsub(lua_State *L)
{
    size_t srcl, lp;
    const char *src = luaL_checklstring(L, 1, &srcl);
    const char *p = luaL_checklstring(L, 2, &lp);
    const char *lastmatch = NULL;
    int tr = lua_type(L, 3);
    lua_Integer max_s = luaL_optinteger(L, 4, (lua_Integer)srcl + 1);
    int anchor = *p == '^';
    lua_Integer n = 0;
    int changed = 0;
    luaL_argexpected(L, tr == LUA_TNUMBER || tr == LUA_TSTRING || tr == LUA_TFUNCTION || tr == LUA_TTABLE, 3,
                     "string/function/table");
    luaL_Buffer b;
    luaL_buffinit(L, &b);
    if (anchor) {
        p++;
        lp--;
    }
    match_state ms;
    prepare(&ms, L, src, srcl, p, lp);
    while (n < max_s) {
        restart(&ms);
        const char *e = match(&ms, src, p);
        if (e && e != lastmatch) {
            n++;
            changed = add_value(&ms, &b, src, e, tr) | changed;
            src = lastmatch = e;
        } else if (src < ms.src_end) {
            luaL_addchar(&b, *src++);
        } else {
            break;
        }
        if (anchor) break;
    }
    if (!changed) {
        lua_pushvalue(L, 1);
    } else {
        luaL_addlstring(&b, src, (size_t)(ms.src_end - src));
        luaL_pushresult(&b);
    }
    lua_pushinteger(L, n);
    return 2;
}

// ---- rep ----------------------------------------------------------------------------------

static int str_rep(lua_State *L)
{
    eng_script *s = scr_state_script(L);
    size_t l, lsep;
    const char *str = luaL_checklstring(L, 1, &l);
    lua_Integer n = luaL_checkinteger(L, 2);
    const char *sep = luaL_optlstring(L, 3, "", &lsep);
    if (n <= 0 || l + lsep == 0) { // nothing to repeat: no loop of n empty copies
        lua_pushliteral(L, "");
        return 1;
    }
    size_t room = scr_memory_room(s);
    if (l + lsep < l || l + lsep > room / (size_t)n)
        return luaL_error(L, "string.rep: the result (%I copies of %I bytes) would be larger than the %I bytes left "
                          "of the script's %d MiB of memory", n, (lua_Integer)(l + lsep), (lua_Integer)room,
                          (int)(SCR_MEMORY_LIMIT >> 20));
    size_t total = (size_t)n * l + (size_t)(n - 1) * lsep;
    scr_tick(L, s, total / 16);
    luaL_Buffer b;
    char *p = luaL_buffinitsize(L, &b, total);
    while (n-- > 1) {
        memcpy(p, str, l);
        p += l;
        if (lsep > 0) {
            memcpy(p, sep, lsep);
            p += lsep;
        }
    }
    memcpy(p, str, l);
    luaL_pushresultsize(&b, total);
    return 1;
}

// ---- utf8.len and utf8.offset: a scan of the whole string that allocates nothing -------------

typedef unsigned int utfint;
#define MAX_UNICODE 0x10FFFFu
#define MAX_UTF 0x7FFFFFFFu
#define IS_CONT(p) ((*(p) & 0xC0) == 0x80)

static lua_Integer utf_position(lua_Integer pos, size_t len)
{
    if (pos >= 0) return pos;
    if (0u - (size_t)pos > len) return 0;
    return (lua_Integer)len + pos + 1;
}

// The character at s: its end, or NULL when it is no valid UTF-8 (strict: no surrogates, at
// most U+10FFFF).
static const char *utf_decode(const char *s, int strict)
{
    static const utfint limits[] = { ~(utfint)0, 0x80, 0x800, 0x10000u, 0x200000u, 0x4000000u };
    unsigned int c = (unsigned char)s[0];
    utfint res = 0;
    if (c < 0x80) {
        res = c;
    } else {
        int count = 0;
        for (; c & 0x40; c <<= 1) {
            unsigned int cc = (unsigned char)s[++count];
            if ((cc & 0xC0) != 0x80) return NULL;
            res = (res << 6) | (cc & 0x3F);
        }
        res |= (utfint)(c & 0x7F) << (count * 5);
        if (count > 5 || res > MAX_UTF || res < limits[count]) return NULL;
        s += count;
    }
    if (strict && (res > MAX_UNICODE || (0xD800u <= res && res <= 0xDFFFu))) return NULL;
    return s + 1;
}

static int utf_len(lua_State *L)
{
    eng_script *sc = scr_state_script(L);
    lua_Integer n = 0;
    size_t len;
    const char *s = luaL_checklstring(L, 1, &len);
    lua_Integer posi = utf_position(luaL_optinteger(L, 2, 1), len);
    lua_Integer posj = utf_position(luaL_optinteger(L, 3, -1), len);
    int lax = lua_toboolean(L, 4);
    luaL_argcheck(L, 1 <= posi && --posi <= (lua_Integer)len, 2, "initial position out of bounds");
    luaL_argcheck(L, --posj < (lua_Integer)len, 3, "final position out of bounds");
    while (posi <= posj) {
        const char *s1 = utf_decode(s + posi, !lax);
        if (!s1) {
            luaL_pushfail(L);
            lua_pushinteger(L, posi + 1);
            return 2;
        }
        posi = s1 - s;
        if ((++n & 4095) == 0) scr_tick(L, sc, 256);
    }
    lua_pushinteger(L, n);
    return 1;
}

static int utf_offset(lua_State *L)
{
    eng_script *sc = scr_state_script(L);
    size_t len;
    const char *s = luaL_checklstring(L, 1, &len);
    lua_Integer n = luaL_checkinteger(L, 2);
    lua_Integer posi = n >= 0 ? 1 : (lua_Integer)len + 1;
    posi = utf_position(luaL_optinteger(L, 3, posi), len);
    luaL_argcheck(L, 1 <= posi && --posi <= (lua_Integer)len, 3, "position out of bounds");
    lua_Integer steps = 0;
    if (n == 0) {
        while (posi > 0 && IS_CONT(s + posi)) {
            posi--;
            if ((++steps & 4095) == 0) scr_tick(L, sc, 256);
        }
    } else {
        if (IS_CONT(s + posi)) return luaL_error(L, "initial position is a continuation byte");
        if (n < 0) {
            while (n < 0 && posi > 0) {
                do {
                    posi--;
                    if ((++steps & 4095) == 0) scr_tick(L, sc, 256);
                } while (posi > 0 && IS_CONT(s + posi));
                n++;
            }
        } else {
            n--;
            while (n > 0 && posi < (lua_Integer)len) {
                do {
                    posi++;
                    if ((++steps & 4095) == 0) scr_tick(L, sc, 256);
                } while (IS_CONT(s + posi)); // cannot pass the final '\0'
                n--;
            }
        }
    }
    if (n == 0) lua_pushinteger(L, posi + 1);
    else luaL_pushfail(L);
    return 1;
}

void scr_open_bounded_string(lua_State *L)
{
    static const luaL_Reg fns[] = { { "find", str_find }, { "match", str_match }, { "gmatch", str_gmatch },
                                    { "gsub", str_gsub }, { "rep", str_rep }, { NULL, NULL } };
    lua_getglobal(L, "string");
    luaL_setfuncs(L, fns, 0);
    lua_pop(L, 1);
    static const luaL_Reg utf[] = { { "len", utf_len }, { "offset", utf_offset }, { NULL, NULL } };
    lua_getglobal(L, "utf8");
    luaL_setfuncs(L, utf, 0);
    lua_pop(L, 1);
}
