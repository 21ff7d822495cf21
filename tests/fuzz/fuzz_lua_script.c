// libFuzzer harness: hostile scene scripts through the Lua host (engine/script/script.h)
// with real worlds on a real GL context, a few frames each.
//
// One headless EGL context (llvmpipe here, KHR_debug and the strict GL mode on: a GL error
// or a synchronisation hazard aborts like a crash), one fluid world of 2048 particles, the
// scene graph, mesh store, input queue and camera are made once. Each input gets a fresh
// Bullet world and coupling, and a fresh script; the fluid world is reset after it.
//
// An input is either raw Lua text (first byte < RAW_MODE) or, else, decisions that a small
// grammar turns into a script: calls of every seiche.* function and of every handle method
// with junk arguments (wrong types, NaN, infinities, huge numbers, nil, nested and
// self-referencing tables, tables whose metatables error in __index, __len, __tostring,
// __eq or __call, functions, handles of the wrong kind), templates of good calls with one
// field spoiled, callbacks (functions, callable tables, values that cannot be called),
// coroutines that call the API and yield, pcall and xpcall loops, finalisers (__gc, refused
// by the sandbox) and __close, error objects whose __tostring errors, string patterns and
// string.rep, load of junk, deep recursion, metatables on _G, and now and then an endless
// loop (stopped by the script's time budget).
//
// The script runs as the runner runs it (engine/app/app.c): main chunk, the queued edits
// applied, on_start, then FRAMES frames of input callbacks, edits, a coupled step and
// on_step. The scene's fluid parameters and container go to the shared world (iterations
// and substeps capped at 4, so steps stay cheap); its capacity and domain do not.
// A script error or failed check is fine: it must come back as a status with a message.
// A crash, sanitizer report, leak, GL error, synchronisation hazard or an input running
// past libFuzzer's -timeout is a bug.
// FUZZ_LUA_VERBOSE=1 prints each script and how it ended (to replay an input by eye).
// Build and run: make fuzz (docs/testing.md).
#include "tests/fuzz/fuzz_gl.h"
#include "engine/gl/input.h"
#include "engine/render/camera.h"
#include "engine/render/mesh.h"
#include "engine/render/renderer.h"
#include "engine/render/scene.h"
#include "engine/script/script.h"
#include "fluid/bullet/coupling.h"
#include "fluid/bullet/phys.h"
#include "fluid/pbf.h"
#include "fluid/pbf_internal.h"
#include "tests/fuzz/fuzz_input.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define RAW_MODE 24       // first byte below this: the rest is the script's text
#define MAX_SCRIPT 65536  // bytes of generated script
#define MAX_STATEMENTS 40
#define MAX_DEPTH 3
#define HANDLES 8         // H[1..8], V[1..8] in the script
#define FRAMES 2
#define BUDGET_S 0.25     // the script's time budget per frame (and for the load)
#define CALL_LIMIT_S 5.25 // the longest one call into the host may take (sanitizers, llvmpipe, shared cores)

static eng_context *ctx;
static pbf_world *base;
static pbf_world_def base_def;
static eng_scene *scene;
static eng_mesh_store *meshes;
static eng_input *input;
static const char *const *functions; // seiche.NAME
static int function_count;
static const char *methods[160];     // NAME of "kind:NAME"
static int method_count;
static bool verbose;                 // FUZZ_LUA_VERBOSE=1: each script and how it ended, on stderr

static void quiet_log(void *user, int level, const char *message)
{
    (void)user;
    if (level < 0 || level > 3 || !message) abort();
}

static void quiet_phys_log(void *user, phys_log_level level, const char *message)
{
    (void)user;
    (void)level;
    (void)message;
}

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    verbose = getenv("FUZZ_LUA_VERBOSE") && getenv("FUZZ_LUA_VERBOSE")[0] == '1';
    if (!freopen("/dev/null", "w", stdout)) return 1; // the scripts' print()
    ctx = fuzz_gl_context("fuzz_lua_script");
    base = fuzz_gl_base_world("fuzz_lua_script", quiet_log, &base_def);
    eng_scene_def sd = eng_default_scene_def();
    scene = eng_scene_create(&sd);
    eng_mesh_store_def md = eng_default_mesh_store_def();
    meshes = eng_mesh_store_create(&md);
    input = eng_input_create(ctx);
    if (!scene || !meshes || !input) exit(1);
    functions = eng_script_function_names();
    while (functions[function_count]) function_count++;
    for (const char *const *n = eng_script_api_names(); *n; n++) {
        const char *colon = strchr(*n, ':');
        if (colon && method_count < (int)(sizeof methods / sizeof methods[0])) methods[method_count++] = colon + 1;
    }
    return 0;
}

// ---- the script text ----------------------------------------------------------------------

typedef struct gen {
    fuzz_input *in;
    char *text;
    size_t len;
    bool full;
} gen;

static void out(gen *g, const char *fmt, ...)
{
    if (g->full) return;
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(g->text + g->len, MAX_SCRIPT - g->len, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= MAX_SCRIPT - g->len) {
        g->full = true;
        g->text[g->len] = 0;
        return;
    }
    g->len += (size_t)n;
}

#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))
static uint8_t byte(gen *g) { return fuzz_u8(g->in); }
static const char *pick(gen *g, const char *const *list, int n) { return list[byte(g) % n]; }

static const char *const NUMBERS[] = {
    "0", "-0.0", "1", "-1", "0/0", "-(0/0)", "1/0", "-1/0", "1e308", "-1e308", "math.huge", "math.mininteger",
    "math.maxinteger", "2^53", "2^63", "-2^63", "2^31", "-2^31", "2^32", "1e-310", "5e-324", "0.5", "3", "0.05",
    "0.01", "100", "1e9", "1e30", "65536", "0x7fffffff", "0.1", "-0.5", "0.3", "1.5", "64", "1000", "1e5", "1e6",
    "3.5e38", "1e-45", "4", "2", "0.025", "0.1", "0.99", "1e-9", "math.pi", "-math.pi", "7 // 0.0", "2^1023 * 2",
};
static const char *const WORDS[] = {
    "box", "sphere", "capsule", "cylinder", "hull", "plane", "compound", "mesh", "static", "dynamic", "kinematic",
    "hinge", "slider", "fixed", "point", "surface", "spheres", "density", "speed", "orbit", "fly", "press",
    "release", "repeat", "left", "right", "space", "a", "f5", "r", "escape", "iterations", "substeps",
    "viscosity", "vorticity", "particle_radius", "kernel_radius", "rest_density", "relaxation", "surface_tension",
    "assets/boat.obj", "tests/fixtures/cup.obj", "tests/fixtures/open_box.obj", "tests/fixtures/tetrahedron.glb",
    "tests/fixtures/tetrahedron.gltf", "tests/fixtures/not_a_mesh.txt", "tests/fixtures/surface_spheres.png",
    "tests/fixtures", "tests/fixtures/", "tests/fixtures/tiny_scene", "tests//fixtures/./cube.obj",
    "../../../../etc/passwd", "/dev/zero", "/proc/self/mem", "", "\\0", "\\255\\254",
    "%", "%b()", "(.-)*", "%f[%w]", "[^", "%1", "level", "mean", "top", "x", "y", "z", "xyz", "nan", "inf",
    "raster", "compute",
};
static const char *const FIELDS[] = {
    "min", "max", "position", "velocity", "size", "radius", "height", "shape", "kind", "density", "mass",
    "rotation", "angular_velocity", "friction", "restitution", "points", "vertices", "indices", "parts",
    "direction", "speed", "rate", "enabled", "name", "fluid", "capacity", "container", "domain", "camera", "eye",
    "target", "fov", "mode", "look", "sky", "light", "water", "ground", "ground_height", "panel", "closed_top",
    "gravity", "a", "b", "pivot", "anchor", "axis", "limits", "motor", "collide", "color", "visible", "offset",
    "scale", "mesh", "fill", "spacing", "seed", "centre", "flat", "axle", "linear_factor", "angular_factor",
    "spray_speed", "density_range", "speed_max", "refraction", "reflection", "specular", "shininess", "two_way",
    "linear_damping", "angular_damping", "center",
    "normal", "clearance", "absorption", "scatter", "smoothing", "spray", "shadows", "view", "iterations",
    "substeps", "viscosity", "particle_radius", "kernel_radius", "fields", "period", "delay", "count", "max_force",
    "max_torque", "x", "y", "z", "w", "resolution", "level", "from", "to", "threshold", "splat",
};
static const char *const CALLBACKS[] = { "on_start", "on_step", "on_key", "on_mouse", "on_mouse_move", "on_scroll",
                                         "on_reload", "on_contact", "on_splash" };

static void value(gen *g, int depth);

static void vec_value(gen *g, int depth)
{
    uint8_t how = byte(g);
    if (how < 160) out(g, "{%.3f, %.3f, %.3f}", byte(g) / 255.0, byte(g) / 255.0, byte(g) / 255.0);
    else if (how < 200) out(g, "{x = %.3f, y = %.3f, z = %.3f}", byte(g) / 255.0, byte(g) / 255.0, byte(g) / 255.0);
    else {
        out(g, "{");
        for (int i = 0, n = byte(g) % 5; i < n; i++) {
            value(g, depth + 1);
            out(g, ", ");
        }
        out(g, "}");
    }
}

static void string_value(gen *g)
{
    uint8_t how = byte(g);
    if (how < 170) {
        out(g, "\"%s\"", pick(g, WORDS, COUNT(WORDS)));
    } else if (how < 200) {
        out(g, "string.rep(\"%s\", %d)", pick(g, WORDS, COUNT(WORDS)), 1 << (byte(g) % 21));
    } else { // bytes, escaped
        out(g, "\"");
        for (int i = 0, n = byte(g) % 24; i < n; i++) out(g, "\\%d", byte(g));
        out(g, "\"");
    }
}

static void table_value(gen *g, int depth)
{
    uint8_t how = byte(g);
    out(g, "{");
    int n = byte(g) % 6;
    for (int i = 0; i < n; i++) {
        if (how & 1) out(g, "%s = ", pick(g, FIELDS, COUNT(FIELDS)));
        else if (how & 2) { // keys that are no field name (nil and NaN keys are errors of their own)
            if (byte(g) & 1) out(g, "[%d] = ", (int)(int8_t)byte(g));
            else out(g, "[\"%s\"] = ", pick(g, WORDS, COUNT(WORDS)));
        }
        value(g, depth + 1);
        out(g, ", ");
    }
    out(g, "}");
}

// A table whose metamethods misbehave.
static void hostile_table(gen *g, int depth)
{
    static const char *const metas[] = {
        "__index = function(t, k) error(\"__index \" .. tostring(k)) end",
        "__index = function(t, k) return t end",
        "__index = function(t, k) return 0/0 end",
        "__newindex = function() error(\"__newindex\") end",
        "__len = function() return 1e300 end",
        "__len = function() return -1 end",
        "__len = function() error(\"__len\") end",
        "__len = function() return math.maxinteger end",
        "__tostring = function() error(\"__tostring\") end",
        "__tostring = function() return {} end",
        "__name = 42",
        "__name = \"seiche.body\"",
        "__eq = function() error(\"__eq\") end",
        "__lt = function() error(\"__lt\") end",
        "__call = function(...) return ... end",
        "__call = function() error(\"__call\") end",
        "__pairs = function() error(\"__pairs\") end",
        "__metatable = \"locked\"",
        "__close = function() error(\"__close\") end",
        "__unm = function() coroutine.yield() end",
        "__concat = function() error(\"__concat\") end",
        // Re-entry: the API called while C code reads an argument.
        "__index = function(t, k) for i = 1, 3 do pcall(seiche.body, {shape = \"sphere\", radius = 0.03, "
        "position = {0.5, 0.5, 0.5}}) end return 0.5 end",
        "__index = function(t, k) for _, h in pairs(H) do pcall(function() h:destroy() end) pcall(function() "
        "h:remove() end) pcall(function() h:cancel() end) pcall(function() h:release() end) end collectgarbage() "
        "return 0.5 end",
        "__index = function(t, k) for i = 1, 8 do H[i] = nil end collectgarbage() return 0.25 end",
        "__len = function() pcall(seiche.block, {min = {0.1, 0.1, 0.1}, max = {0.2, 0.2, 0.2}}) return 3 end",
        "__index = function(t, k) coroutine.yield(k) end",
        "__index = function(t, k) seiche.quit() return 1 end",
    };
    out(g, "setmetatable(");
    if (byte(g) < 128) out(g, "{1, 2, 3}");
    else table_value(g, depth);
    out(g, ", {");
    for (int i = 0, n = 1 + byte(g) % 3; i < n; i++) out(g, "%s, ", pick(g, metas, COUNT(metas)));
    out(g, "})");
}

static void value(gen *g, int depth)
{
    uint8_t how = byte(g);
    if (depth >= MAX_DEPTH) how %= 100; // leaves only
    if (how < 8) out(g, "nil");
    else if (how < 14) out(g, how & 1 ? "true" : "false");
    else if (how < 50) out(g, "%s", pick(g, NUMBERS, COUNT(NUMBERS)));
    else if (how < 60) {
        double d = fuzz_double(g->in);
        if (d != d) out(g, "(0/0)");
        else if (d > 1.7976931348623157e308) out(g, "(1/0)");
        else if (d < -1.7976931348623157e308) out(g, "(-1/0)");
        else out(g, "%.17g", d);
    } else if (how < 80) string_value(g);
    else if (how < 90) out(g, "H[%d]", 1 + byte(g) % HANDLES);
    else if (how < 95) out(g, "V[%d]", 1 + byte(g) % HANDLES);
    else if (how < 100) out(g, "seiche.%s", functions[byte(g) % function_count]);
    else if (how < 140) vec_value(g, depth);
    else if (how < 175) table_value(g, depth);
    else if (how < 195) hostile_table(g, depth);
    else if (how < 205) out(g, "function(...) return ... end");
    else if (how < 212) out(g, "function() error(\"from a callback argument\") end");
    else if (how < 218) out(g, "coroutine.create(function() end)");
    else if (how < 222) out(g, "seiche");
    else if (how < 226) out(g, "_G");
    else if (how < 230) out(g, "R"); // a table that holds itself
    else {
        out(g, "(function() local t = {} for i = 1, %d do t = {t} end return t end)()", 1 << (byte(g) % 12));
    }
}

// 0 to 4 arguments; each after ", " when `after_comma` (following a function), else
// separated by commas (a call's own list).
static void args(gen *g, int depth, bool after_comma)
{
    for (int i = 0, n = byte(g) % 5; i < n; i++) {
        if (i || after_comma) out(g, ", ");
        value(g, depth);
    }
}

// A good call with, now and then, one field spoiled.
static void template_call(gen *g)
{
    static const char *const templates[][8] = {
        { "block", "min = {0.1, 0.1, 0.1}", "max = {0.3, 0.3, 0.3}", "velocity = {0, 0, 0}", NULL },
        { "body", "shape = \"box\"", "size = {0.1, 0.1, 0.1}", "position = {0.5, 0.5, 0.5}", "density = 500", NULL },
        { "body", "shape = \"sphere\"", "radius = 0.05", "position = {0.4, 0.3, 0.5}", "kind = \"dynamic\"", NULL },
        { "body", "shape = \"hull\"", "points = {{0,0,0},{0.1,0,0},{0,0.1,0},{0,0,0.1}}", "position = {0.5, 0.6, 0.5}", NULL },
        { "body", "shape = \"capsule\"", "radius = 0.03", "height = 0.1", "kind = \"kinematic\"", NULL },
        { "emitter", "position = {0.5, 0.8, 0.5}", "direction = {0, -1, 0}", "speed = 1", "radius = 0.05", "rate = 100", NULL },
        { "sink", "min = {0, 0, 0}", "max = {0.2, 0.2, 0.2}", NULL },
        { "scene", "fluid = {iterations = 2, substeps = 1}", "capacity = 2048", "container = {min = {0, 0, 0}, max = {1, 1, 1}}",
          "camera = {eye = {0.5, 1, 2}, target = {0.5, 0.2, 0.5}, fov = 50}", NULL },
        { "set_camera", "eye = {0.5, 1, 2}", "target = {0.5, 0.2, 0.5}", NULL },
        { "render", "mode = \"spheres\"", "smoothing = 4", NULL },
        { "set_look", "sky = {0.1, 0.2, 0.3}", "ground = true", NULL },
        { "particle_data", "fields = {\"position\", \"velocity\"}", NULL },
        { "body", "mesh = \"tests/fixtures/cup.obj\"", "density = 300", "position = {0.5, 0.5, 0.5}", "scale = 0.5", NULL },
        { "body", "mesh = \"tests/fixtures/open_box.obj\"", "kind = \"static\"", "position = {0.5, 0.1, 0.5}", NULL },
        { "fill", "mesh = \"tests/fixtures/tetrahedron.glb\"", "scale = 0.2", "position = {0.5, 0.5, 0.5}", NULL },
        { "joint", "kind = \"hinge\"", "a = H[1]", "pivot = {0.5, 0.5, 0.5}", "axis = {0, 0, 1}", NULL },
        { "fill", "mesh = \"tests/fixtures/cup.obj\"", "scale = 0.3", "position = {0.5, 0.4, 0.5}", "clearance = 0.01", NULL },
        { "particle_data", "fields = {\"position\", \"density\"}", "min = {0, 0, 0}", "max = {1, 1, 1}", "flat = true", NULL },
    };
    const char *const *t = templates[byte(g) % COUNT(templates)];
    int spoil = byte(g) % 6; // 0: none
    out(g, "H[%d] = select(2, pcall(seiche.%s, {", 1 + byte(g) % HANDLES, t[0]);
    for (int i = 1; i < 8 && t[i]; i++) {
        if (i == spoil) {
            char field[64];
            snprintf(field, sizeof field, "%.*s", (int)strcspn(t[i], " ="), t[i]);
            out(g, "%s = ", field);
            value(g, 1);
            out(g, ", ");
        } else {
            out(g, "%s, ", t[i]);
        }
    }
    if (byte(g) < 40) {
        out(g, "%s = ", pick(g, FIELDS, COUNT(FIELDS)));
        value(g, 1);
    }
    out(g, "}))\n");
}

static void statements(gen *g, int depth, int max);

static void block(gen *g, int depth)
{
    statements(g, depth + 1, 1 + byte(g) % 4);
}

static void statement(gen *g, int depth)
{
    if (depth == 0 && byte(g) < 96) { // protected, so that an error does not end the main chunk
        out(g, "pcall(function()\n");
        statement(g, 1);
        out(g, "end)\n");
        return;
    }
    uint8_t how = byte(g);
    int h = 1 + byte(g) % HANDLES;
    if (depth >= MAX_DEPTH && how >= 150) how %= 150;
    if (how < 40) {
        out(g, "pcall(seiche.%s", functions[byte(g) % function_count]);
        args(g, 0, true);
        out(g, ")\n");
    } else if (how < 70) {
        out(g, "H[%d] = select(2, pcall(seiche.%s", h, functions[byte(g) % function_count]);
        args(g, 0, true);
        out(g, "))\n");
    } else if (how < 95) {
        template_call(g);
    } else if (how < 125) {
        const char *m = method_count ? methods[byte(g) % method_count] : "get";
        out(g, "pcall(function() return H[%d]%s%s(", h, byte(g) < 230 ? ":" : ".", m);
        args(g, 0, false);
        out(g, ") end)\n");
    } else if (how < 130) { // a direct call: an error ends the script
        out(g, "seiche.%s(", functions[byte(g) % function_count]);
        args(g, 1, false);
        out(g, ")\n");
    } else if (how < 140) {
        out(g, "V[%d] = ", h);
        value(g, 0);
        out(g, "\n");
    } else if (how < 150) {
        out(g, "seiche.check(");
        value(g, 1);
        out(g, ", ");
        value(g, 1);
        out(g, ")\n");
    } else if (how < 175) { // a callback
        const char *name = pick(g, CALLBACKS, COUNT(CALLBACKS));
        uint8_t kind = byte(g);
        if (kind < 200) {
            out(g, "function %s(...)\n", name);
            block(g, depth);
            out(g, "end\n");
        } else if (kind < 230) {
            out(g, "%s = setmetatable({}, {__call = function(self, ...)\n", name);
            block(g, depth);
            out(g, "end})\n");
        } else {
            out(g, "%s = ", name);
            value(g, 1);
            out(g, "\n");
        }
    } else if (how < 185) { // a timer
        out(g, "H[%d] = select(2, pcall(seiche.%s, ", h, byte(g) & 1 ? "every" : "after");
        value(g, 1);
        out(g, ", function(...)\n");
        block(g, depth);
        out(g, "end))\n");
    } else if (how < 195) { // a coroutine that calls the API and yields
        out(g, "V[%d] = coroutine.wrap(function(...)\n", h);
        block(g, depth);
        out(g, "coroutine.yield(");
        value(g, 1);
        out(g, ")\n");
        block(g, depth);
        out(g, "end)\npcall(V[%d]) pcall(V[%d]) pcall(V[%d])\n", h, h, h);
    } else if (how < 203) { // loops of protected calls
        out(g, "for i = 1, %d do pcall(seiche.%s", 1 << (byte(g) % 11), functions[byte(g) % function_count]);
        args(g, 1, true);
        out(g, ") end\n");
    } else if (how < 208) {
        out(g, "xpcall(function()\n");
        block(g, depth);
        out(g, "end, function(m)\n");
        block(g, depth);
        out(g, "return m end)\n");
    } else if (how < 213) {
        out(g, "do local c <close> = setmetatable({}, {__close = function()\n");
        block(g, depth);
        out(g, "end}) end\n");
    } else if (how < 218) { // string functions with fuzzed patterns
        static const char *const fns[] = { "find", "match", "gsub", "rep", "format", "byte", "char", "sub", "gmatch" };
        out(g, "pcall(string.%s", pick(g, fns, COUNT(fns)));
        args(g, 1, true);
        out(g, ")\n");
    } else if (how < 222) {
        static const char *const gc[] = { "collect", "step", "incremental", "generational", "count", "stop", "restart" };
        out(g, "collectgarbage(\"%s\")\n", pick(g, gc, COUNT(gc)));
    } else if (how < 226) {
        out(g, "pcall(setmetatable, {}, {__gc = function() seiche.quit() end})\n");
    } else if (how < 230) {
        out(g, "pcall(load, ");
        string_value(g);
        out(g, ")\n");
    } else if (how < 233) {
        out(g, "do local function r(n) return r(n + 1) + 1 end pcall(r, 1) end\n");
    } else if (how < 236) {
        out(g, "setmetatable(_G, {__index = function(t, k) error(\"no global \" .. tostring(k)) end, "
               "__newindex = function(t, k, v) rawset(t, k, v) end})\n");
    } else if (how < 239) { // an error object that resists being printed
        out(g, "error(");
        if (byte(g) & 1) hostile_table(g, 1);
        else value(g, 1);
        out(g, ")\n");
    } else if (how < 242) {
        out(g, "H[%d] = nil collectgarbage()\n", h);
    } else if (how < 245) {
        out(g, "pcall(rawset, seiche, \"%s\", ", functions[byte(g) % function_count]);
        value(g, 1);
        out(g, ")\n");
    } else if (how < 247) {
        out(g, "while true do end\n");
    } else if (how < 250) {
        out(g, "seiche.quit()\n");
    } else {
        out(g, "for i = 1, %d do V[%d] = {V[%d], i} end\n", 1 << (byte(g) % 16), h, h);
    }
}

static void statements(gen *g, int depth, int max)
{
    for (int i = 0; i < max && g->in->size > 0 && !g->full; i++) statement(g, depth);
}

static void generate(gen *g)
{
    out(g, "local H, V, R = {}, {}, {}\nR.self = R R[1] = R\n");
    if (byte(g) < 128) // a scene most of the time, so edits get to the world
        out(g, "seiche.scene{fluid = {iterations = 2, substeps = 1}, container = {min = {0, 0, 0}, max = {1, 1, 1}}}\n");
    statements(g, 0, 1 + byte(g) % MAX_STATEMENTS);
}

// ---- running it -----------------------------------------------------------------------

typedef struct run {
    eng_script *script;
    phys_world *phys;
    cpl_coupling *coupling;
    eng_node_id root;
    eng_camera camera;
    pbf_step_stats stats;
    bool have_stats;
    uint64_t frame;
    double time;
    double since; // monotonic s when the call being checked began
} run;

static void host(run *r, bool worlds)
{
    eng_script_host h;
    memset(&h, 0, sizeof h);
    if (worlds) {
        h.world = base;
        h.phys = r->phys;
        h.coupling = r->coupling;
        h.scene = scene;
        h.root = r->root;
        h.meshes = meshes;
        h.input = input;
        h.camera = &r->camera;
        h.stats = r->have_stats ? &r->stats : NULL;
    }
    h.view_width = h.view_height = 64;
    h.frame = r->frame;
    h.time = r->time;
    h.dt = 1.0 / 60.0;
    h.renderer = eng_context_renderer(ctx);
    h.fluid_look = eng_default_fluid_look();
    h.headless = true;
    eng_script_set_host(r->script, &h);
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void mark(run *r) { r->since = now_s(); }
#define STEP(r, call, what) (mark(r), ok((r), (call), (what)))

// false when the script stopped (an error, a failed check, quit); a status must come with
// a message. A call (since mark) that ran CALL_LIMIT_S is a hang: the budget did not stop it.
static bool ok(run *r, eng_script_status st, const char *what)
{
    double took = now_s() - r->since;
    if (took > CALL_LIMIT_S) {
        fprintf(stderr, "fuzz_lua_script: %s ran %.2f s: past the script's budget of %.2f s and a slack of %.1f s\n",
                what, took, BUDGET_S, CALL_LIMIT_S - BUDGET_S);
        abort();
    }
    if (st == ENG_SCRIPT_OK) return !eng_script_quit_requested(r->script);
    if (st != ENG_SCRIPT_CHECK_FAILED && st != ENG_SCRIPT_ERROR) {
        fprintf(stderr, "fuzz_lua_script: %s returned %d, not an eng_script_status\n", what, (int)st);
        abort();
    }
    const char *e = eng_script_error(r->script);
    if (verbose) fprintf(stderr, "fuzz_lua_script: %s: status %d: %s\n", what, (int)st, e ? e : "(null)");
    if (!e || !e[0]) {
        fprintf(stderr, "fuzz_lua_script: %s failed (%d) without a message\n", what, (int)st);
        abort();
    }
    // Every message starts with the file:line it was raised at (docs/runner.md): this
    // script's, or that of a chunk it loaded.
    if (strncmp(e, "fuzz.lua:", 9) != 0 && strncmp(e, "[string \"", 9) != 0) {
        fprintf(stderr, "fuzz_lua_script: %s failed (%d) with a message that has no file:line first: %s\n", what,
                (int)st, e);
        abort();
    }
    return false;
}

// The scene's settings that the shared world can take.
static void take_scene(run *r)
{
    eng_scene_config *c = eng_script_config(r->script);
    pbf_params p = c->params;
    if (p.iterations > 4) p.iterations = 4;
    if (p.substeps > 4) p.substeps = 4;
    (void)pbf_world_set_params(base, &p); // a refusal keeps the old ones
    if (c->has_container) (void)pbf_world_set_container(base, c->container_min, c->container_max, c->closed_top);
    // What the world uses, for the script's checks (as the app does): without it every emitter
    // and block was refused at a domain of [0, 0].
    memcpy(c->domain_min, base_def.domain_min, sizeof c->domain_min);
    memcpy(c->domain_max, base_def.domain_max, sizeof c->domain_max);
    const pbf_params *now = pbf_world_params(base);
    phys_world_set_gravity(r->phys, (phys_vec3){ now->gravity[0], now->gravity[1], now->gravity[2] });
    eng_camera_look_at(&r->camera, c->camera_eye, c->camera_target);
}

// The frame's input as the app hands it out (engine/app/app.c, handle_input).
static bool deliver(run *r)
{
    eng_event e;
    int count = eng_input_queued(input);
    while (count-- > 0 && eng_input_next_event(input, &e)) {
        const char *action = e.action == ENG_PRESS ? "press" : e.action == ENG_RELEASE ? "release" : "repeat";
        eng_script_status st = ENG_SCRIPT_OK;
        bool consumed = false;
        mark(r);
        switch (e.type) {
        case ENG_EVENT_KEY: {
            const char *name = eng_key_name(e.key);
            if (name) st = eng_script_on_key(r->script, name, action, e.x, e.y);
            break;
        }
        case ENG_EVENT_MOUSE_BUTTON: st = eng_script_on_mouse(r->script, e.button + 1, action, e.x, e.y, &consumed); break;
        case ENG_EVENT_MOTION: st = eng_script_on_mouse_move(r->script, e.x, e.y, e.dx, e.dy); break;
        case ENG_EVENT_SCROLL: st = eng_script_on_scroll(r->script, e.dx, e.dy); break;
        }
        if (!ok(r, st, "an input callback")) return false;
    }
    return true;
}

static void frames(run *r, fuzz_input *in)
{
    if (!STEP(r, eng_script_apply(r->script), "eng_script_apply (main chunk)")) return;
    if (!STEP(r, eng_script_on_start(r->script), "eng_script_on_start")) return;
    if (!STEP(r, eng_script_apply(r->script), "eng_script_apply (on_start)")) return;
    const double dt = 1.0 / 60.0;
    for (int f = 0; f < FRAMES; f++) {
        eng_input_begin_frame(input);
        eng_script_deliver_input(r->script);
        if (!deliver(r)) return;
        // The callbacks once each, with arguments from the input.
        uint8_t b = fuzz_u8(in);
        bool consumed;
        if (!STEP(r, eng_script_on_key(r->script, eng_key_name(32 + b % 64) ? eng_key_name(32 + b % 64) : "a",
                                     b & 1 ? "press" : "release", fuzz_double(in), 3.0), "eng_script_on_key") ||
            !STEP(r, eng_script_on_mouse(r->script, 1 + b % 3, "press", fuzz_double(in), 5.0, &consumed), "eng_script_on_mouse") ||
            !STEP(r, eng_script_on_mouse_move(r->script, 1.0, 2.0, fuzz_double(in), 0.5), "eng_script_on_mouse_move") ||
            !STEP(r, eng_script_on_scroll(r->script, 0.0, fuzz_double(in)), "eng_script_on_scroll"))
            return;
        host(r, true);
        if (!STEP(r, eng_script_apply(r->script), "eng_script_apply")) return;
        if (cpl_step(r->coupling, (float)dt) != CPL_OK) {
            if (!cpl_last_error(r->coupling)[0]) abort();
            return; // the runner exits 2 with the message
        }
        eng_script_step_taken(r->script);
        r->frame++;
        r->time = (double)r->frame * dt;
        pbf_step_stats st[4];
        int n = pbf_world_poll_stats(base, st, 4, false);
        if (n > 0) {
            r->stats = st[n - 1];
            r->have_stats = true;
        }
        host(r, true);
        if (!STEP(r, eng_script_on_step(r->script, dt, r->time), "eng_script_on_step")) return;
        eng_script_sync_nodes(r->script); // as before drawing
        // A slider of the parameter panel, as the app applies it.
        uint8_t p = fuzz_u8(in);
        if (p < 64) {
            int count = 0;
            const pbf_param_info *t = pbf_param_table(&count);
            char err[512];
            err[0] = 0;
            const char *name = p < 60 && count > 0 ? t[p % count].name : p == 60 ? "" : "no_such_parameter";
            if (!eng_script_set_param(r->script, name, fuzz_double(in), err, sizeof err) && !err[0]) {
                fprintf(stderr, "fuzz_lua_script: eng_script_set_param refused '%s' without a message\n", name);
                abort();
            }
        }
    }
    // The check sites the reports list: each with a file, a line and counts that add up.
    const eng_check_site *sites = NULL;
    int n = eng_script_check_sites(r->script, &sites);
    if (n < 0 || n > ENG_SCRIPT_MAX_CHECK_SITES || (n > 0 && !sites)) abort();
    for (int i = 0; i < n; i++)
        if (!memchr(sites[i].source, 0, sizeof sites[i].source) || !memchr(sites[i].message, 0, sizeof sites[i].message) ||
            sites[i].passed + sites[i].failed == 0) {
            fprintf(stderr, "fuzz_lua_script: check site %d is malformed\n", i);
            abort();
        }
    if (fuzz_u8(in) < 32) (void)STEP(r, eng_script_on_reload(r->script), "eng_script_on_reload");
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size == 0) return 0;
    fuzz_input in = { data, size };
    char *text = malloc(MAX_SCRIPT + 1);
    if (!text) return 0;
    if (data[0] < RAW_MODE) {
        size_t n = size - 1 < MAX_SCRIPT ? size - 1 : MAX_SCRIPT;
        memcpy(text, data + 1, n);
        text[n] = 0;
        in.size = 0;
    } else {
        fuzz_u8(&in);
        gen g = { &in, text, 0, false };
        text[0] = 0;
        generate(&g);
    }
    if (verbose) fprintf(stderr, "fuzz_lua_script: the script:\n%s\n-- end of the script\n", text);
    // Input left from the last run, if any, goes.
    eng_input_begin_frame(input);
    for (eng_event e; eng_input_next_event(input, &e);) {}

    run r;
    memset(&r, 0, sizeof r);
    eng_camera_def cd = eng_default_camera_def();
    char err[512];
    if (!eng_camera_init(&r.camera, &cd, err, sizeof err)) abort();
    phys_world_def pd = phys_default_world_def();
    pd.log = quiet_phys_log;
    if (phys_world_create(&pd, &r.phys) != PHYS_OK) abort();
    cpl_def cpd = cpl_default_def();
    cpd.phys = r.phys;
    cpd.fluid = base;
    r.coupling = cpl_create(&cpd, err, sizeof err);
    if (!r.coupling) abort();
    eng_node_def nd = eng_default_node_def();
    r.root = eng_node_create(scene, &nd);

    eng_script_def sd = eng_default_script_def();
    sd.log.min_level = (eng_log_level)(ENG_LOG_ERROR + 1); // quiet: messages come back through eng_script_error
    sd.budget_s = BUDGET_S;
    r.script = eng_script_create(&sd);
    if (!r.script) abort();
    host(&r, false); // what the main chunk may read before the worlds exist
    if (STEP(&r, eng_script_load_string(r.script, "fuzz.lua", text), "eng_script_load_string")) {
        take_scene(&r);
        host(&r, true);
        frames(&r, &in);
    }
    if (verbose) fprintf(stderr, "fuzz_lua_script: %d frames run\n", (int)r.frame);
    eng_script_destroy(r.script);
    if (eng_node_is_valid(scene, r.root)) eng_node_destroy(scene, r.root);
    cpl_destroy(r.coupling);
    phys_world_destroy(r.phys);
    fuzz_gl_reset_base(base, &base_def.params);
    free(text);
    return 0;
}
