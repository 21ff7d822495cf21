// The script sandbox and its limits, without a GL context or a world: the bounded string
// and table functions behave as Lua 5.4's own (compared case by case with a plain Lua
// state); every known way to spend time inside one C call, or to catch the budget error,
// still ends at the budget, quickly; the frame's calls share one budget; require stays in
// the scene's folder; binary and odd script files are refused; callbacks are looked up
// raw and may be callable tables; --trusted gives the full libraries and still checks a
// handle's kind.
#include "tests/support.h"

#include <lauxlib.h>
#include <lualib.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "engine/script/script.h"

// ---- helpers -------------------------------------------------------------------------

static eng_script *new_script(double budget, bool trusted)
{
    eng_script_def d = eng_default_script_def();
    d.log.min_level = ENG_LOG_ERROR;
    d.budget_s = budget;
    d.trusted = trusted;
    eng_script *s = eng_script_create(&d);
    assert_non_null(s);
    return s;
}

// How long a case may run before the budget stops it: the hook fires between instructions,
// so one C call over 64 MiB finishes first. Under AddressSanitizer that call alone took
// 1.5-1.7 s (string.upper of 64 MiB, 2026-11-26), so the sanitizer build allows twice as long.
#ifdef SEICHE_SANITIZE
#define BUDGET_STOP_S 3.0
#else
#define BUDGET_STOP_S 1.5
#endif

// Runs `code` as the main chunk "case.lua" of a sandboxed script with a 0.2 s budget and
// expects it stopped by the budget within BUDGET_STOP_S.
static void expect_budget_stop(const char *code)
{
    eng_script *s = new_script(0.2, false);
    double t0 = support_seconds();
    eng_script_status st = eng_script_load_string(s, "case.lua", code);
    double secs = support_seconds() - t0;
    if (st != ENG_SCRIPT_ERROR || !strstr(eng_script_error(s), "ran longer than its budget of 0.2 s"))
        fail_msg("not stopped by the budget (status %d): %s\n  %s", (int)st, code, eng_script_error(s));
    if (strncmp(eng_script_error(s), "case.lua:", 9) != 0) fail_msg("no file:line first: %s", eng_script_error(s));
    if (secs > BUDGET_STOP_S) fail_msg("stopped after %.2f s (budget 0.2 s): %s", secs, code);
    eng_script_destroy(s);
}

static void expect_ok(eng_script *s, const char *code)
{
    if (eng_script_load_string(s, "case.lua", code) != ENG_SCRIPT_OK) fail_msg("%s\n  %s", code, eng_script_error(s));
}

static void expect_error(eng_script *s, const char *code, const char *want)
{
    if (eng_script_load_string(s, "case.lua", code) == ENG_SCRIPT_OK) fail_msg("accepted: %s", code);
    if (!strstr(eng_script_error(s), want)) fail_msg("%s\n  want: %s\n  got:  %s", code, want, eng_script_error(s));
}

// ---- the bounded library functions behave as Lua's ------------------------------------------

// Expressions, each evaluated as `return <expr>` under pcall in a plain Lua state and in the
// sandbox, their results (count, types, values, error messages) compared. (Not here: what
// stock Lua never finishes, such as string.rep('', 1e15): see the budget tests.)
static const char *const CASES[] = {
    "string.find('hello world', 'o w')",
    "string.find('hello world', 'o', 6)",
    "string.find('hello world', 'l+')",
    "string.find('hello', '')",
    "string.find('hello', '', 10)",
    "string.find('hello', '', 6)",
    "string.find('hello', '', -2)",
    "string.find('hello', 'l', -100)",
    "string.find('a.b', '.', 1, true)",
    "string.find('a.b', '%.')",
    "string.find('a+b', '+', 1, true)",
    "string.find('a+b', 'b', 1, true)",
    "string.find('aaab', 'aab', 1, true)",
    "string.find('a\\0b', '\\0')",
    "string.find('a\\0b', '%z')",
    "string.find('abc', '[a-')",
    "string.find('abc', '[]')",
    "string.find('abc]', '[]]')",
    "string.find('abc', '[^a]')",
    "string.find('a-b', '[a%-]+')",
    "string.find('b-z', '[a-c-]+')",
    "string.find('x^y', '^x')",
    "string.find('x^y', '%^y')",
    "string.find('abc', '^b')",
    "string.find('abc', 'c$')",
    "string.find('ab$c', 'b$c')",
    "string.find('THE (quick) fox', '%((%a+)%)')",
    "string.find('f(a(b)c)d', '%b()')",
    "string.find('f(a(b)c', '%b()')",
    "string.find('THE (quick) fox', '%f[%a]%a+')",
    "string.find('hello', '%f[%l]')",
    "string.find('hello', '()ll()')",
    "string.find('hello', '(h)(e)(l)')",
    "string.find('hello hello', '(l+)o %1')",
    "string.find('abcabc', '(a)(b)(c)%3')",
    "string.find('aaa', 'a-')",
    "string.find('aaa', 'a-$')",
    "string.find('aaab', 'a*b')",
    "string.find('aaab', 'a+b')",
    "string.find('b', 'a?b')",
    "string.find('ab', 'a?b')",
    "string.find('  x', '%s*()')",
    "string.find('x', '%')",
    "string.find('x', '(')",
    "string.find('x', '(()')",
    "string.find('x', '%1')",
    "string.find('x', '(x)%2')",
    "string.find('x', ')')",
    "string.find('x', 'x)')",
    "string.find('x', '%b')",
    "string.find('x', '%bx')",
    "string.find('x', '%f')",
    "string.find('x', '%fx')",
    "string.find('x', '[%')",
    "string.find()",
    "string.find('x', {})",
    "string.match('key = value', '(%w+)%s*=%s*(%w+)')",
    "string.match('2024-01-02', '(%d+)-(%d+)-(%d+)')",
    "string.match('hello', '.-(l+)(.*)')",
    "string.match('hello', '()')",
    "string.match('hello', 'x')",
    "string.match('[[x]]', '%[(%b[])%]')",
    "string.match(string.rep('a', 40), string.rep('(a)', 32))",
    "string.match(string.rep('a', 40), string.rep('(a)', 33))",
    "string.match(string.rep('a', 300), string.rep('a?', 300))",
    "string.match('abc', '((((((((((a))))))))))')",
    "string.match('0x1F', '^0[xX](%x+)$')",
    "string.match('UPPER lower', '%u+ %l+')",
    "string.match('a,b;c', '[%p]')",
    "string.match('\\t\\n x', '%c+')",
    "string.match('ab12', '%W*(%d+)')",
    "string.match('ab12 ', '%D+%S+%G')",
    "string.match('hello', '(h)(.)', 2)",
    "string.match('hello', 'l', -2)",
    "string.match('\\200\\201x', '[\\200-\\210]+')",
    "string.gsub('hello world', 'o', '0')",
    "string.gsub('hello world', 'o', '0', 1)",
    "string.gsub('hello world', '(o)', '[%1]')",
    "string.gsub('hello world', '%w+', '<%0>')",
    "string.gsub('hello', '', '-')",
    "string.gsub('abc', '.', {a = 1, b = true})",
    "string.gsub('abc', '.', {a = 'A'})",
    "string.gsub('abc', '(.)', function(c) if c == 'b' then return nil end return c:upper() end)",
    "string.gsub('abc', '.', function() return {} end)",
    "string.gsub('abc', '.', '%2')",
    "string.gsub('abc', '.', '%')",
    "string.gsub('abc', '.', '%x')",
    "string.gsub('abc', '.', '%%')",
    "string.gsub('abc', '()', '%1')",
    "string.gsub('abc', '^a', 'X')",
    "string.gsub('aaa', '^a', 'X')",
    "string.gsub('abc', 'b*', '-')",
    "string.gsub('hello world', '(%w+) (%w+)', '%2 %1')",
    "string.gsub('abc', 'x*', '-', 2)",
    "string.gsub('abc', '.', 5)",
    "string.gsub('abc', '.', true)",
    "string.gsub('abc', 'b', '', -1)",
    "string.gsub('', '', 'x')",
    "string.gsub('abc', 'z', 'y')",
    "string.gsub('a(b)c', '%b()', function(s) return #s end)",
    "string.rep('ab', 3)",
    "string.rep('ab', 3, ',')",
    "string.rep('ab', 0)",
    "string.rep('ab', -1)",
    "string.rep('', 5, ',')",
    "string.rep('x', 1, ',')",
    "string.rep()",
    "string.rep('x', 'y')",
    "string.rep('x', 2.5)",
    "(function() local t = {} for w in string.gmatch('one two  three', '%a+') do t[#t+1] = w end return table.concat(t, '|') end)()",
    "(function() local t = {} for k, v in string.gmatch('a=1, b=2', '(%w+)=(%w+)') do t[#t+1] = k .. v end return table.concat(t, '|') end)()",
    "(function() local t = {} for p in string.gmatch('abc', '()') do t[#t+1] = p end return table.concat(t, '|') end)()",
    "(function() local t = {} for w in string.gmatch('abc', '') do t[#t+1] = '[' .. w .. ']' end return table.concat(t) end)()",
    "(function() local t = {} for w in string.gmatch('^a^b', '^.') do t[#t+1] = w end return table.concat(t, '|') end)()",
    "(function() local t = {} for w in string.gmatch('abcdef', '..', 3) do t[#t+1] = w end return table.concat(t, '|') end)()",
    "(function() local t = {} for w in string.gmatch('abc', '.', 10) do t[#t+1] = w end return #t end)()",
    "(function() local t = {} for w in string.gmatch('abc', '.', -1) do t[#t+1] = w end return table.concat(t, '|') end)()",
    "(function() local t = {} for a, b in string.gmatch('abab', '(a)(b)') do t[#t+1] = a .. b end return table.concat(t, '|') end)()",
    "string.gmatch('x', '%')()",
    "('x'):rep(3)",
    "('hello'):find('l')",
    "('hello'):gsub('l', 'L')",
    "('hello'):match('(h)(e)')",
    "table.concat({1, 2, 3})",
    "table.concat({1, 2, 3}, ', ')",
    "table.concat({1, 2, 3}, ', ', 2)",
    "table.concat({1, 2, 3}, ', ', 2, 3)",
    "table.concat({1, 2, 3}, ', ', 3, 2)",
    "table.concat({}, 'x')",
    "table.concat({1, {}, 3})",
    "table.concat({1, 2}, ', ', 1, 3)",
    "table.concat({'a', 1.5, 2^63}, '')",
    "table.concat(setmetatable({}, {__index = function(_, i) return 'v' .. i end, __len = function() return 3 end}))",
    "table.concat(5)",
    "table.concat({}, {})",
    "(function() local t = {1, 2, 3} table.insert(t, 4) return table.concat(t, ',') end)()",
    "(function() local t = {1, 2, 3} table.insert(t, 1, 0) return table.concat(t, ',') end)()",
    "(function() local t = {1, 2, 3} table.insert(t, 4, 9) return table.concat(t, ',') end)()",
    "(function() local t = {1, 2, 3} table.insert(t, 5, 9) return table.concat(t, ',') end)()",
    "(function() local t = {1, 2, 3} table.insert(t, 0, 9) return table.concat(t, ',') end)()",
    "(function() local t = {1, 2, 3} table.insert(t, 1, 2, 3) end)()",
    "(function() local t = {1, 2, 3} table.insert(t) end)()",
    "table.insert(nil, 1)",
    "(function() local t = {1, 2, 3} local v = table.remove(t) return v, table.concat(t, ',') end)()",
    "(function() local t = {1, 2, 3} local v = table.remove(t, 1) return v, table.concat(t, ',') end)()",
    "(function() local t = {1, 2, 3} local v = table.remove(t, 4) return v, table.concat(t, ',') end)()",
    "(function() local t = {1, 2, 3} return table.remove(t, 5) end)()",
    "(function() local t = {} return table.remove(t), #t end)()",
    "(function() local t = {} return table.remove(t, 0), #t end)()",
    "(function() local t = {1, 2, 3, 4, 5} table.move(t, 1, 3, 2) return table.concat(t, ',') end)()",
    "(function() local t = {1, 2, 3, 4, 5} table.move(t, 2, 4, 1) return table.concat(t, ',') end)()",
    "(function() local a, b = {1, 2, 3}, {} table.move(a, 1, 3, 2, b) return rawlen(b), b[2], b[4] end)()",
    "(function() return table.move({1}, 1, 0, 1)[1] end)()",
    "table.move({}, -1, math.maxinteger, 1)",
    "table.move({}, 1, 2, math.maxinteger)",
    "table.move({}, 1, 'x', 1)",
    "table.move(1, 1, 2, 1)",
    "(function() local t = {5, 2, 8, 1, 9, 3} table.sort(t) return table.concat(t, ',') end)()",
    "(function() local t = {5, 2, 8, 1, 9, 3} table.sort(t, function(a, b) return a > b end) return table.concat(t, ',') end)()",
    "(function() local t = {'b', 'a', 'c'} table.sort(t) return table.concat(t, ',') end)()",
    "(function() local t = {1, 'a'} table.sort(t) end)()",
    "(function() local t = {3, 1, 2} table.sort(t, 5) end)()",
    "(function() local t = {} for i = 1, 200 do t[i] = (i * 7919) % 211 end table.sort(t) return table.concat(t, ',') end)()",
    "(function() local t = {} for i = 1, 100 do t[i] = i % 7 end table.sort(t, function(a, b) return a < b end) return table.concat(t, ',') end)()",
    "(function() local t = {} for i = 1, 50 do t[i] = i % 5 end table.sort(t, function() return true end) end)()",
    "table.sort(5)",
    "table.unpack({1, 2, 3})",
    "utf8.len('h\\xc3\\xa9llo')",
    "utf8.len('h\\xffllo')",
    "utf8.len('h\\xc3\\xa9llo', 3)",
    "utf8.len('h\\xc3\\xa9llo', -2)",
    "utf8.len('abc', 5)",
    "utf8.len('abc', 1, 5)",
    "utf8.len('abc', 0)",
    "utf8.len('\\xed\\xa0\\x80')",
    "utf8.len('\\xed\\xa0\\x80', 1, -1, true)",
    "utf8.len('\\xf4\\x90\\x80\\x80')",
    "utf8.len('\\xc0\\x80')",
    "utf8.offset('h\\xc3\\xa9llo', 3)",
    "utf8.offset('h\\xc3\\xa9llo', -1)",
    "utf8.offset('h\\xc3\\xa9llo', -5)",
    "utf8.offset('h\\xc3\\xa9llo', 0, 3)",
    "utf8.offset('h\\xc3\\xa9llo', 1, 3)",
    "utf8.offset('abc', 5)",
    "utf8.offset('abc', 1, 10)",
    "utf8.offset('abc', 0)",
    "(function() local t = {} for _, c in utf8.codes('h\\xc3\\xa9') do t[#t+1] = c end return table.concat(t, ',') end)()",
    "coroutine.wrap(function(a) local b = coroutine.yield(a + 1) return b * 2 end)(1)",
    "(function() local co = coroutine.wrap(function(a) local b = coroutine.yield(a + 1) return b * 2 end) co(1) return co(5) end)()",
    "(function() local co = coroutine.wrap(function() error('in co') end) return co() end)()",
    "(function() local co = coroutine.wrap(function() error({}) end) return co() end)()",
    "(function() local co = coroutine.wrap(function() end) co() return co() end)()",
    "coroutine.resume(coroutine.create(function(...) return select('#', ...), ... end), 1, nil, 3)",
    "coroutine.resume(coroutine.create(function() error('boom') end))",
    "(function() local co = coroutine.create(function() end) coroutine.resume(co) return coroutine.resume(co) end)()",
    "(function() local co co = coroutine.create(function() return coroutine.resume(co) end) return coroutine.resume(co) end)()",
    "coroutine.resume(42)",
    "coroutine.wrap(42)",
    "coroutine.resume(coroutine.running())",
    NULL,
};

// Evaluates CASES; the text of every result, one line per case. Shared by both states.
static const char *const HARNESS =
    "local function show(v)\n"
    "  if type(v) == 'table' then return 'table' end\n"
    "  return type(v) .. ':' .. tostring(v)\n"
    "end\n"
    "local function ser(...)\n"
    "  local parts = {}\n"
    "  for i = 1, select('#', ...) do parts[#parts + 1] = show((select(i, ...))) end\n"
    "  return select('#', ...) .. ' [' .. table.concat(parts, ' | ') .. ']'\n"
    "end\n"
    "local out = {}\n"
    "for line in CASES:gmatch('[^\\n]+') do\n"
    "  local f = assert(load('return ' .. line, '=case'))\n"
    "  out[#out + 1] = line .. ' => ' .. ser(pcall(f))\n"
    "end\n"
    "OUT = table.concat(out, '\\n')\n";

// `text` as a Lua string literal.
static char *lua_literal(const char *text)
{
    size_t n = strlen(text);
    char *out = malloc(4 * n + 3), *p = out;
    *p++ = '"';
    for (const unsigned char *c = (const unsigned char *)text; *c; c++) {
        if (*c == '"' || *c == '\\') p += sprintf(p, "\\%c", *c);
        else if (*c == '\n') p += sprintf(p, "\\n");
        else if (*c < 32 || *c >= 127) p += sprintf(p, "\\%03u", *c);
        else *p++ = (char)*c;
    }
    *p++ = '"';
    *p = 0;
    return out;
}

static void bounded_functions_behave_as_lua_does(void **state)
{
    (void)state;
    size_t len = 1;
    for (int i = 0; CASES[i]; i++) len += strlen(CASES[i]) + 1;
    char *joined = malloc(len), *end = joined;
    for (int i = 0; CASES[i]; i++) end += sprintf(end, "%s\n", CASES[i]);
    *end = 0;
    char *cases = lua_literal(joined);
    free(joined);
    size_t size = strlen(cases) + strlen(HARNESS) + 64;
    char *prelude = malloc(size);
    snprintf(prelude, size, "CASES = %s\n%s", cases, HARNESS);
    // Lua's own libraries.
    lua_State *L = luaL_newstate();
    luaL_openlibs(L);
    if (luaL_dostring(L, prelude) != LUA_OK) fail_msg("reference: %s", lua_tostring(L, -1));
    lua_getglobal(L, "OUT");
    char *expected = lua_literal(lua_tostring(L, -1));
    lua_close(L);
    // The sandbox: the same text, or the first line that differs.
    size = strlen(prelude) + strlen(expected) + 1024;
    char *code = malloc(size);
    snprintf(code, size,
             "%s\nlocal expected = %s\n"
             "if OUT ~= expected then\n"
             "  local a, b = {}, {}\n"
             "  for l in OUT:gmatch('[^\\n]+') do a[#a + 1] = l end\n"
             "  for l in expected:gmatch('[^\\n]+') do b[#b + 1] = l end\n"
             "  for i = 1, math.max(#a, #b) do\n"
             "    seiche.check(a[i] == b[i], '\\n  sandbox: ' .. tostring(a[i]) .. '\\n  Lua:     ' .. tostring(b[i]))\n"
             "  end\n"
             "end\n",
             prelude, expected);
    eng_script *s = new_script(5.0, false);
    if (eng_script_load_string(s, "case.lua", code) != ENG_SCRIPT_OK) fail_msg("%s", eng_script_error(s));
    eng_script_destroy(s);
    free(code);
    free(expected);
    free(prelude);
    free(cases);
}

// ---- the budget holds -----------------------------------------------------------------------

static void pcall_cannot_swallow_the_budget(void **state)
{
    (void)state;
    expect_budget_stop("while true do pcall(function() while true do end end) end");
    expect_budget_stop("while true do pcall(pcall, pcall, function() while true do end end) end");
    expect_budget_stop("while true do xpcall(function() while true do end end, function() while true do end end) end");
    expect_budget_stop("local co = coroutine.wrap(function() while true do pcall(function() while true do end end) end end)\n"
                       "while true do pcall(co) end");
    expect_budget_stop("local co = coroutine.create(function() while true do end end)\n"
                       "while true do coroutine.resume(co) end");
    expect_budget_stop("local function f() local x <close> = setmetatable({}, {__close = function() while true do end end})\n"
                       "while true do end end\nwhile true do pcall(f) end");
    expect_budget_stop("while true do pcall(load, function() while true do end end) end");
    expect_budget_stop("while true do pcall(string.gsub, ('x'):rep(100), '.', function() while true do end end) end");
    expect_budget_stop("local t = setmetatable({}, {__index = function() while true do end end})\n"
                       "while true do pcall(table.concat, t, '', 1, 5) end");
    expect_budget_stop("while true do pcall(error, {}) end");
}

static void c_library_calls_stop_at_the_budget(void **state)
{
    (void)state;
    // Patterns: backtracking in find, match, gmatch and gsub; a quadratic plain find.
    expect_budget_stop("string.find(string.rep('a', 40), string.rep('a*', 40) .. 'b')");
    expect_budget_stop("string.match(string.rep('a', 40), string.rep('a-', 40) .. 'b')");
    expect_budget_stop("for _ in string.gmatch(string.rep('a', 40), string.rep('a*', 40) .. 'b') do end");
    expect_budget_stop("string.gsub(string.rep('a', 40), string.rep('a*', 40) .. 'b', '')");
    expect_budget_stop("local s = string.rep('a', 4e6)\nwhile true do string.find(s, string.rep('a', 2e6) .. 'b', 1, true) end");
    // Loops as long as an argument says, through C metamethods that run no Lua.
    expect_budget_stop("table.move({}, 1, 1e15, 1)");
    expect_budget_stop("table.concat(setmetatable({}, {__index = rawlen}), '', 1, 1e15)");
    expect_budget_stop("table.insert(setmetatable({}, {__len = function() return 1e15 end, __index = rawlen, "
                       "__newindex = rawequal}), 1, 'x')");
    expect_budget_stop("table.remove(setmetatable({}, {__len = function() return 1e15 end, __index = rawlen, "
                       "__newindex = rawequal}), 1)");
    expect_budget_stop("table.sort(setmetatable({}, {__len = function() return 2^30 end, __index = rawlen, "
                       "__newindex = rawequal}), rawequal)");
    // One instruction over long strings, many times.
    expect_budget_stop("local a, b = string.rep('x', 1 << 26) .. 'a', string.rep('x', 1 << 26) .. 'b'\n"
                       "while true do local _ = a == b end");
    expect_budget_stop("local s = string.rep('x', 1 << 26)\nwhile true do local _ = s:upper() end");
    expect_budget_stop("local s = string.rep('\\xc3\\xa9', 1 << 22)\nwhile true do local _ = utf8.len(s) + utf8.offset(s, -1) end");
    // The same inside a coroutine that was made while the script was small.
    expect_budget_stop("coroutine.wrap(function() local s = string.rep('x', 1 << 26)\n"
                       "while true do local _ = s:upper() end end)()");
    // Mesh files, each read by a child process that the budget left bounds: once the budget
    // is spent, the next load stops the call instead of starting an importer with its own
    // 30 s (the hook looks at the clock every 1000 instructions: a hundred loads apart).
    // (From the fixtures' folder, where a script loaded from a string finds cup.obj.)
    char fixtures[1024], cwd[1024];
    support_source_path("tests/fixtures", fixtures, sizeof fixtures);
    assert_non_null(getcwd(cwd, sizeof cwd));
    assert_int_equal(chdir(fixtures), 0);
    expect_budget_stop("for i = 1, 1e4 do seiche.body{mesh = 'cup.obj', density = 300, scale = 0.5} end");
    assert_int_equal(chdir(cwd), 0);
    // And what stays quick: nothing to repeat.
    eng_script *s = new_script(0.2, false);
    expect_ok(s, "assert(string.rep('', 1e15) == '' and string.rep('', 1e15, '') == '')");
    eng_script_destroy(s);
}

static void memory_limit_is_named_with_its_line(void **state)
{
    (void)state;
    eng_script *s = new_script(5.0, false);
    expect_error(s, "local s = string.rep('x', 1 << 20)\nlocal r = string.rep(s, 1 << 20)",
                 "case.lua:2: string.rep: the result (1048576 copies of 1048576 bytes) would be larger than");
    expect_error(s, "local t, s = {}, string.rep('x', 1 << 20)\nfor i = 1, 1e6 do t[i] = s .. i end",
                 "case.lua:2: the script's main chunk used more than the script's 512 MiB of memory");
    eng_script_destroy(s);
}

// The calls of one frame share the budget; a new frame (eng_script_deliver_input) starts
// a fresh one.
static void callbacks_of_a_frame_share_one_budget(void **state)
{
    (void)state;
    eng_script *s = new_script(0.3, false);
    expect_ok(s, "local function busy(t) local t0 = os.clock() while os.clock() - t0 < t do end end\n"
                 "function on_key() busy(0.2) end\nfunction on_step() busy(0.2) end");
    eng_script_deliver_input(s);
    assert_int_equal(eng_script_on_key(s, "a", "press", 0.0, 0.0), ENG_SCRIPT_OK);
    assert_int_equal(eng_script_on_step(s, 1.0 / 60, 1.0 / 60), ENG_SCRIPT_ERROR);
    assert_non_null(strstr(eng_script_error(s), "on_step ran past the frame's budget of 0.3 s"));
    eng_script_deliver_input(s);
    assert_int_equal(eng_script_on_step(s, 1.0 / 60, 2.0 / 60), ENG_SCRIPT_OK);
    eng_script_destroy(s);
}

// ---- callbacks ------------------------------------------------------------------------------

static void callbacks_are_looked_up_raw_and_may_be_callable_tables(void **state)
{
    (void)state;
    eng_script *s = new_script(0.2, false);
    expect_ok(s, "keys = 0\n"
                 "on_key = setmetatable({}, {__call = function(self, k, a) keys = keys + 1 end})\n"
                 "function on_step() assert(keys == 1, 'on_key ran once') end\n"
                 "setmetatable(_G, {__index = function(_, k) if k ~= 'keys' then while true do end end end})");
    eng_script_deliver_input(s);
    assert_int_equal(eng_script_on_mouse_move(s, 1, 2, 3, 4), ENG_SCRIPT_OK); // no on_mouse_move: __index never runs
    assert_int_equal(eng_script_on_key(s, "a", "press", 0.0, 0.0), ENG_SCRIPT_OK);
    if (eng_script_on_step(s, 1.0 / 60, 1.0 / 60) != ENG_SCRIPT_OK) fail_msg("%s", eng_script_error(s));
    eng_script_destroy(s);

    s = new_script(0.2, false);
    expect_ok(s, "on_scroll = 'not a function'");
    assert_int_equal(eng_script_on_scroll(s, 0, 1), ENG_SCRIPT_ERROR);
    assert_non_null(strstr(eng_script_error(s), "case.lua: on_scroll must be a function or a table with a __call metamethod"));
    eng_script_destroy(s);
}

// ---- files and require ------------------------------------------------------------------------

static void write_file(const char *dir, const char *name, const char *text, size_t len)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1, len, f), len);
    fclose(f);
}

static void require_stays_in_the_scene_folder(void **state)
{
    (void)state;
    struct { char path[256]; } t = { "/tmp/seiche_sandbox_XXXXXX" };
    assert_non_null(mkdtemp(t.path));
    char sub[300], outside[300], scene[400];
    snprintf(sub, sizeof sub, "%s/scene", t.path);
    assert_int_equal(mkdir(sub, 0700), 0);
    snprintf(outside, sizeof outside, "%s/secret.lua", t.path);
    write_file(t.path, "secret.lua", "return 'secret'", 15);
    char link[600];
    snprintf(link, sizeof link, "%s/escape.lua", sub);
    assert_int_equal(symlink(outside, link), 0);
    char lib[600];
    snprintf(lib, sizeof lib, "%s/lib", sub);
    assert_int_equal(mkdir(lib, 0700), 0);
    write_file(lib, "init.lua", "return {name = 'lib'}", 21);
    write_file(lib, "loop.lua", "return require('lib.loop')", 26);
    write_file(lib, "broken.lua", "error('broken module')", 22);
    static const char main_lua[] =
        "assert(require('lib').name == 'lib', 'init.lua')\n"
        "local ok, e = pcall(require, 'escape')\n"
        "assert(not ok and e:find('outside the scene', 1, true), e)\n"
        "ok, e = pcall(require, 'lib.loop')\n"
        "assert(not ok and e:find('requires itself', 1, true), e)\n"
        "ok, e = pcall(require, 'lib.broken')\n"
        "assert(not ok and e:find('broken module', 1, true), e)\n"
        "ok, e = pcall(require, 'lib.broken')\n"
        "assert(not ok and e:find('broken module', 1, true), 'a failed module is tried again: ' .. e)\n"
        "for _, bad in ipairs {'../secret', '.secret', 'lib..init', 'lib/init', 'lib.', ''} do\n"
        "  ok, e = pcall(require, bad)\n"
        "  assert(not ok and e:find('bad module name', 1, true), bad .. ': ' .. tostring(e))\n"
        "end\n";
    write_file(sub, "main.lua", main_lua, sizeof main_lua - 1);
    snprintf(scene, sizeof scene, "%s/main.lua", sub);
    eng_script *s = new_script(1.0, false);
    if (eng_script_load(s, scene) != ENG_SCRIPT_OK) fail_msg("%s", eng_script_error(s));
    eng_script_destroy(s);
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", t.path);
    assert_int_equal(system(cmd), 0);
}

static void binary_and_odd_script_files_are_refused(void **state)
{
    (void)state;
    char dir[] = "/tmp/seiche_sandbox_XXXXXX";
    assert_non_null(mkdtemp(dir));
    // A precompiled chunk, corrupt: refused before Lua reads it as bytecode.
    static const char bytecode[] = "\x1bLua\x54\x00\x19\x93\r\n\x1a\n\x04\x08\x08garbage";
    write_file(dir, "binary.lua", bytecode, sizeof bytecode - 1);
    char path[600];
    snprintf(path, sizeof path, "%s/binary.lua", dir);
    eng_script *s = new_script(1.0, false);
    assert_int_equal(eng_script_load(s, path), ENG_SCRIPT_ERROR);
    char want[700];
    snprintf(want, sizeof want, "%s:1: the script is a precompiled (binary) chunk", path);
    if (!strstr(eng_script_error(s), want)) fail_msg("%s", eng_script_error(s));
    eng_script_destroy(s);
    // A FIFO would block the open for ever; a directory is no script.
    snprintf(path, sizeof path, "%s/fifo.lua", dir);
    assert_int_equal(mkfifo(path, 0600), 0);
    s = new_script(1.0, false);
    assert_int_equal(eng_script_load(s, path), ENG_SCRIPT_ERROR);
    assert_non_null(strstr(eng_script_error(s), "cannot open the script file (not a regular file: a FIFO)"));
    assert_int_equal(eng_script_load(s, dir), ENG_SCRIPT_ERROR);
    assert_non_null(strstr(eng_script_error(s), "cannot open the script file (not a regular file: a directory)"));
    // A link to itself: the system's reason.
    snprintf(path, sizeof path, "%s/loop.lua", dir);
    assert_int_equal(symlink("loop.lua", path), 0);
    assert_int_equal(eng_script_load(s, path), ENG_SCRIPT_ERROR);
    assert_non_null(strstr(eng_script_error(s), "cannot open the script file: Too many levels of symbolic links"));
    eng_script_destroy(s);
    // Over 64 MiB (sparse): refused by its size.
    snprintf(path, sizeof path, "%s/huge.lua", dir);
    FILE *f = fopen(path, "wb");
    assert_non_null(f);
    assert_int_equal(ftruncate(fileno(f), (off_t)65 << 20), 0);
    fclose(f);
    s = new_script(1.0, false);
    assert_int_equal(eng_script_load(s, path), ENG_SCRIPT_ERROR);
    assert_non_null(strstr(eng_script_error(s), "a scene script may be at most 64 MiB"));
    eng_script_destroy(s);
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    assert_int_equal(system(cmd), 0);
}

// ---- --trusted ----------------------------------------------------------------------------------

static void trusted_scripts_get_every_library_and_handles_keep_their_kind(void **state)
{
    (void)state;
    eng_script *s = new_script(1.0, true);
    expect_ok(s, "assert(io.open and os.getenv and package.loadlib and debug.getinfo and dofile and loadfile)\n"
                 "assert(string.find('abc', 'b') == 2, 'the bounded string functions are there too')\n"
                 "setmetatable({}, {__gc = function() end})\n"
                 "local e = seiche.emitter{position = {0, 0, 0}}\n"
                 "local b = seiche.body{shape = 'box', size = {0.1, 0.1, 0.1}}\n"
                 "debug.setmetatable(b, debug.getmetatable(e))\n"
                 "local ok, err = pcall(e.set_enabled, b, false)\n"
                 "assert(not ok and err:find('attempt to use a destroyed emitter', 1, true), err)\n");
    eng_script_destroy(s);
    // The same script in the sandbox: no debug library.
    s = new_script(1.0, false);
    expect_error(s, "local e = debug.getmetatable", "case.lua:1: debug.getmetatable is not available in a scene script");
    eng_script_destroy(s);
}

// warn() and the state's own warnings reach the log as whole messages: pieces joined,
// "@off" / "@on" obeyed, and an error in a trusted script's finaliser (which Lua turns
// into a warning) is not lost.
typedef struct warn_log {
    char text[2048];
    int count;
} warn_log;

static void keep_warning(void *user, eng_log_level level, const char *message)
{
    warn_log *w = user;
    if (level != ENG_LOG_WARN) return;
    w->count++;
    size_t n = strlen(w->text);
    snprintf(w->text + n, sizeof w->text - n, "%s\n", message);
}

static void warnings_reach_the_log(void **state)
{
    (void)state;
    warn_log w = { { 0 }, 0 };
    eng_script_def d = eng_default_script_def();
    d.log.fn = keep_warning;
    d.log.user = &w;
    d.trusted = true;
    eng_script *s = eng_script_create(&d);
    assert_non_null(s);
    expect_ok(s, "warn('water ', 'is ', 'wet')\n"
                 "warn('@off') warn('not shown') warn('@on')\n"
                 "setmetatable({}, { __gc = function() error('finaliser failed') end })\n"
                 "collectgarbage() collectgarbage()\n");
    if (w.count != 2 || !strstr(w.text, "case.lua: water is wet\n") || strstr(w.text, "not shown") ||
        !strstr(w.text, "__gc") || !strstr(w.text, "finaliser failed"))
        fail_msg("%d warnings:\n%s", w.count, w.text);
    eng_script_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bounded_functions_behave_as_lua_does),
        cmocka_unit_test(pcall_cannot_swallow_the_budget),
        cmocka_unit_test(c_library_calls_stop_at_the_budget),
        cmocka_unit_test(memory_limit_is_named_with_its_line),
        cmocka_unit_test(callbacks_of_a_frame_share_one_budget),
        cmocka_unit_test(callbacks_are_looked_up_raw_and_may_be_callable_tables),
        cmocka_unit_test(require_stays_in_the_scene_folder),
        cmocka_unit_test(binary_and_odd_script_files_are_refused),
        cmocka_unit_test(trusted_scripts_get_every_library_and_handles_keep_their_kind),
        cmocka_unit_test(warnings_reach_the_log),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
