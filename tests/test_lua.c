// The Lua host without a GL context or a world: the documentation covers every function,
// method and callback the bindings register (and names nothing that is not); every bad
// argument is refused with a message naming the function, the field or argument, the
// value given and what is allowed, at the caller's file:line; handles go stale when
// their object is removed; the main chunk's edits are queued, not applied; syntax errors,
// missing files, endless loops and runaway memory end in a clear message.
#include "tests/support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include "engine/script/script.h"

// ---- helpers -------------------------------------------------------------------------

static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = malloc((size_t)n + 1);
    if (text && fread(text, 1, (size_t)n, f) != (size_t)n) {
        free(text);
        text = NULL;
    }
    if (text) text[n] = 0;
    fclose(f);
    return text;
}

// The names of the "### name..." headings of docs/lua-api.md: the heading's first word,
// up to a space, '(' or '{'. Written NUL-separated into `out`; returns the count.
static int doc_headings(char *out, size_t size, const char **names, int max)
{
    char path[1024];
    support_source_path("docs/lua-api.md", path, sizeof path);
    char *text = read_file(path);
    if (!text) fail_msg("cannot read %s", path);
    int n = 0;
    size_t used = 0;
    for (char *line = text; line && *line; line = strchr(line, '\n') ? strchr(line, '\n') + 1 : NULL) {
        if (strncmp(line, "### ", 4) != 0) continue;
        const char *p = line + 4;
        size_t len = strcspn(p, " ({\n");
        if (n >= max || used + len + 1 > size) fail_msg("too many headings");
        memcpy(out + used, p, len);
        out[used + len] = 0;
        names[n++] = out + used;
        used += len + 1;
    }
    free(text);
    return n;
}

static eng_script *script(void)
{
    eng_script_def d = eng_default_script_def();
    d.log.min_level = ENG_LOG_ERROR;
    eng_script *s = eng_script_create(&d);
    assert_non_null(s);
    return s;
}

// Runs `code` as a main chunk named "case.lua" and returns its status; the message is in
// eng_script_error.
static eng_script_status run_chunk(eng_script *s, const char *code)
{
    return eng_script_load_string(s, "case.lua", code);
}

static void expect_error(const char *code, const char *want)
{
    eng_script *s = script();
    eng_script_status st = run_chunk(s, code);
    if (st == ENG_SCRIPT_OK) fail_msg("accepted: %s\n  (expected an error containing: %s)", code, want);
    const char *err = eng_script_error(s);
    if (strncmp(err, "case.lua:", 9) != 0) fail_msg("no file:line in the message for %s:\n  %s", code, err);
    if (!strstr(err, want)) fail_msg("%s\n  want: %s\n  got:  %s", code, want, err);
    eng_script_destroy(s);
}

// ---- the documentation -------------------------------------------------------------

static void every_function_method_and_callback_is_documented(void **state)
{
    (void)state;
    static char buf[16384];
    const char *headings[256];
    int n = doc_headings(buf, sizeof buf, headings, 256);
    int missing = 0;
    for (const char *const *name = eng_script_api_names(); *name; name++) {
        bool found = false;
        for (int i = 0; i < n && !found; i++) found = strcmp(headings[i], *name) == 0;
        if (!found) {
            print_message("docs/lua-api.md has no heading \"### %s\"\n", *name);
            missing++;
        }
    }
    assert_int_equal(missing, 0);
}

static void documentation_names_nothing_the_bindings_lack(void **state)
{
    (void)state;
    static char buf[16384];
    const char *headings[256];
    int n = doc_headings(buf, sizeof buf, headings, 256);
    int stale = 0;
    for (int i = 0; i < n; i++) {
        bool found = false;
        for (const char *const *name = eng_script_api_names(); *name && !found; name++) found = strcmp(headings[i], *name) == 0;
        if (!found) {
            print_message("docs/lua-api.md documents \"%s\", which the bindings do not register\n", headings[i]);
            stale++;
        }
    }
    assert_int_equal(stale, 0);
}

static void seiche_table_holds_exactly_the_registered_functions(void **state)
{
    (void)state;
    char code[8192];
    int count = 0;
    size_t len = (size_t)snprintf(code, sizeof code, "local want = {");
    for (const char *const *f = eng_script_function_names(); *f; f++, count++)
        len += (size_t)snprintf(code + len, sizeof code - len, "%s = true, ", *f);
    snprintf(code + len, sizeof code - len,
             "}\nlocal n = 0\nfor k, v in pairs(seiche) do\n"
             "  if type(v) == 'function' then n = n + 1; seiche.check(want[k], 'unlisted function seiche.' .. k) end\n"
             "end\nseiche.check(n == %d, 'seiche has ' .. n .. ' functions')\n"
             "for k in pairs(want) do seiche.check(type(seiche[k]) == 'function', 'missing seiche.' .. k) end\n",
             count);
    eng_script *s = script();
    if (run_chunk(s, code) != ENG_SCRIPT_OK) fail_msg("%s", eng_script_error(s));
    eng_script_destroy(s);
}

// ---- argument checks -------------------------------------------------------------------

static void bad_arguments_name_function_argument_value_and_rule(void **state)
{
    (void)state;
    static const char *const cases[][2] = {
        { "seiche.block(42)", "seiche.block: argument #1 must be a table {min = {x, y, z}, max = {x, y, z}, velocity = {x, y, z}} (got 42)" },
        { "seiche.block{min = {0, 0, 0}, max = {0/0, 1, 1}}", "seiche.block: field 'max'.x must be a number in [-100000, 100000] m (got nan)" },
        { "seiche.block{min = {0, 0, 0}, max = {1, -math.huge, 1}}", "field 'max'.y must be a number in [-100000, 100000] m (got -inf)" },
        { "seiche.block{min = {0, 0, 0}, max = {x = 1, y = 1}}", "field 'max'.z must be a number in [-100000, 100000] m (got nil)" },
        { "seiche.block{min = {0, 0, 0}}", "seiche.block: field 'max' is required: a table of 3 numbers {x, y, z} in m (got nil)" },
        { "seiche.block{min = {0, 0, 0}, max = {1, 1, 1}, velocity = {1e9, 0, 0}}", "field 'velocity'.x must be a number in [-10000, 10000] m/s (got 1000000000)" },
        { "seiche.sphere{center = {0, 0, 0}, radius = 0}", "seiche.sphere: field 'radius' must be a number in (0, 1000] m (got 0)" },
        { "seiche.sphere{center = {0, 0, 0}, radius = '1'}", "seiche.sphere: field 'radius' must be a number in (0, 1000] m (got \"1\")" },
        { "seiche.particles{positions = {{0, 0}}}", "seiche.particles: field 'positions'[1] must be a table of 3 numbers {x, y, z} (got a table of 2)" },
        { "seiche.particles{positions = {{0, 0, 0}}, velocity = {0, 0, 0}, velocities = {{0, 0, 0}}}", "give either 'velocities' (one per point) or 'velocity' (one for all), not both" },
        { "seiche.emitter{position = {0, 0, 0}, speed = 0}", "seiche.emitter: field 'speed' must be a number in (0, 100] m/s (got 0)" },
        { "seiche.emitter{position = {0, 0, 0}, rate = -5}", "seiche.emitter: field 'rate' must be a number >= 0 particles/s, at most seiche.max_emitter_rate(speed, radius) (got -5)" },
        { "seiche.emitter{position = {0, 0, 0}, enabled = 1}", "seiche.emitter: field 'enabled' must be true or false (got 1)" },
        { "seiche.sink{min = {0, 0, 0}, max = {1, 1, 0}}", "seiche.sink: max.z must be greater than min.z (got min 0, max 0)" },
        { "seiche.body{}", "seiche.body: field 'shape' is required: one of \"box\", \"sphere\", \"capsule\", \"cylinder\", \"plane\", \"hull\", \"mesh\", \"compound\" (got nil)" },
        { "seiche.body{shape = 'compound'}", "seiche.body: field 'parts' is required for a compound: a list of 1 to 64 parts" },
        { "seiche.body{shape = 'compound', parts = {{shape = 'plane'}}}", "seiche.body: field 'parts'[1]: field 'shape' must be one of \"box\", \"sphere\", \"capsule\", \"cylinder\" (got \"plane\")" },
        { "seiche.body{shape = 'compound', parts = {{shape = 'box', size = {1, 1, 1}, radius = 1}}}", "seiche.body: field 'parts'[1]: field 'radius' does not apply to shape \"box\"" },
        { "seiche.body{shape = 'compound', parts = {{shape = 'box', size = {1, -1, 1}}}}", "seiche.body: field 'parts'[1]: field 'size'.y must be a number in (0, 1000] m (got -1)" },
        { "local p = {} for i = 1, 65 do p[i] = {shape = 'sphere', radius = 0.1} end seiche.body{shape = 'compound', parts = p}", "seiche.body: field 'parts' must hold 1 to 64 parts (each part is one of the fluid's 64 colliders; got 65)" },
        { "seiche.body{shape = 'box', size = {1, 1, 1}, linear_factor = {0, 2, 0}}", "seiche.body: field 'linear_factor'.y must be a number in [0, 1] (got 2)" },
        { "seiche.body{shape = 'box', size = {1, 1, 1}, axle = 'w'}", "seiche.body: field 'axle' must be one of \"x\", \"y\", \"z\" (got \"w\")" },
        { "seiche.body{shape = 'box', size = {1, 1, 1}, axle = 'z', angular_factor = {0, 0, 1}}", "seiche.body: give 'axle' or 'linear_factor'/'angular_factor', not both" },
        { "seiche.body{shape = 'box', kind = 'static', size = {1, 1, 1}, axle = 'z'}", "seiche.body: fields 'axle', 'linear_factor' and 'angular_factor' apply to dynamic bodies only (this one is static)" },
        { "seiche.body{shape = 'box', size = {1, 0, 1}}", "seiche.body: field 'size'.y must be a number in (0, 1000] m (got 0)" },
        { "seiche.body{shape = 'box', size = {1, 1, 1}, kind = 'floating'}", "seiche.body: field 'kind' must be one of \"static\", \"kinematic\", \"dynamic\" (got \"floating\")" },
        { "seiche.body{shape = 'box', size = {1, 1, 1}, mass = 1, density = 1}", "seiche.body: give 'mass' or 'density', not both" },
        { "seiche.body{shape = 'box', size = {1, 1, 1}, kind = 'static', velocity = {1, 0, 0}}", "a static body cannot move" },
        { "seiche.body{shape = 'mesh', kind = 'dynamic', vertices = {{0,0,0},{1,0,0},{0,1,0}}, indices = {1,2,3}}", "shape \"mesh\" has no volume and must be kind \"static\" or \"kinematic\"" },
        { "seiche.body{shape = 'sphere', radius = 1, rotation = {axis = {0, 0, 0}, angle = 1}}", "seiche.body: field 'rotation'.axis must not be zero" },
        { "seiche.body{shape = 'sphere', radius = 1, friction = -1}", "seiche.body: field 'friction' must be a number in [0, 100] (got -1)" },
        { "seiche.body{shape = 'sphere', radius = 100, density = 1e6}", "gives mass 4.18879e+12 kg, outside [1e-06, 1e+06] kg" },
        { "seiche.scene{capacity = 1.5}", "seiche.scene: field 'capacity' must be a whole number in [1, 67108864] particles (got 1.5)" },
        { "seiche.scene{capacity = 1e12}", "(got 1000000000000)" },
        { "seiche.scene{container = {min = {0, 0, 0}, max = {1, 1, 1}, lid = true}}", "seiche.scene: container: unknown field \"lid\" (known: min, max, closed_top)" },
        { "seiche.scene{fluid = {iterations = 0}}", "seiche.scene: fluid: field 'iterations' must be in [1, 100] (got 0)" },
        { "seiche.scene{fluid = {viscocity = 0.1}}", "seiche.scene: fluid: unknown field \"viscocity\"" },
        { "seiche.scene{gravity = {0, 0/0, 0}}", "seiche.scene: field 'gravity'.y must be a number in [-1000, 1000] m/s^2 (got nan)" },
        { "seiche.scene{camera = {eye = {1, 1, 1}, target = {1, 1, 1}}}", "seiche.scene: camera eye and target must differ" },
        { "seiche.scene{camera = {mode = 'free'}}", "seiche.scene: camera: field 'mode' must be one of \"orbit\", \"fly\" (got \"free\")" },
        { "seiche.scene{look = {water = {specular = 2}}}", "seiche.scene: look: water: field 'specular' must be a number in [0, 1] (got 2)" },
        { "seiche.scene{look = {light = {direction = {0, 0, 0}}}}", "field 'direction' must not be zero" },
        { "seiche.scene{camera = 5}", "seiche.scene: field 'camera' must be a table {eye, target, fov, mode} (got 5)" },
        { "seiche.set_look{water = 'blue'}", "seiche.set_look: field 'water' must be a table {low, mid, high, specular, shininess} (got \"blue\")" },
        { "seiche.scene{name = ''}", "seiche.scene: field 'name' must be a string of 1 to 63 characters (got \"\")" },
        { "seiche.scene{}; seiche.scene{}", "seiche.scene: called twice (the first call was at case.lua:1)" },
        { "seiche.scene{domain = {min = {0, 0, 0}, max = {1, 1, 1}}, container = {min = {0, 0, 0}, max = {2, 1, 1}}}", "the container's x range [0, 2] must lie inside the domain's [0, 1]" },
        { "seiche.after(1)", "seiche.after: argument #2 'callback' must be a function or a table with a __call metamethod (got no value)" },
        { "seiche.every(0/0, print)", "seiche.every: argument #1 'period' must be a number in (0, 1000000000] s (got nan)" },
        { "seiche.set_param('iterations', '3')", "seiche.set_param: argument #2 'value' (iterations) must be a whole number in [1, 100] (got \"3\")" },
        { "seiche.set_param(3, 3)", "seiche.set_param: argument #1 'name' must be a fluid parameter name (one of particle_radius, kernel_radius" },
        { "seiche.param('nope')", "seiche.param: argument #1 'name' must be a fluid parameter name" },
        { "seiche.set_gravity('down')", "seiche.set_gravity: argument #1 'gravity' must be a table of 3 numbers {x, y, z} in m/s^2 (got \"down\")" },
        { "seiche.set_camera{eye = {0, 0, 0}, target = {0, 0, 0}}", "seiche.set_camera: eye and target must differ" },
        { "seiche.set_look{ground = 'yes'}", "seiche.set_look: field 'ground' must be true or false (got \"yes\")" },
        { "seiche.key_down(65)", "seiche.key_down: argument #1 'key' must be a key name" },
        { "seiche.mouse_down(0)", "seiche.mouse_down: argument #1 'button' must be a whole number in [1, 8] (1 left, 2 right, 3 middle) (got 0)" },
        { "seiche.inject_mouse(1, 'repeat')", "seiche.inject_mouse: argument #2 'action' must be \"press\" or \"release\" (got \"repeat\")" },
        { "seiche.inject_motion(math.huge, 0)", "seiche.inject_motion: argument #1 'x' must be a number in [-1000000, 1000000] pixels (got inf)" },
        { "seiche.inject_scroll(0)", "seiche.inject_scroll: argument #2 'dy' must be a number in [-10000, 10000] steps (got no value)" },
        { "seiche.surface_height(0, 0, -1)", "seiche.surface_height: argument #3 'radius' must be a number in (0, 100] m (got -1)" },
        { "seiche.surface_height(0, 0)", "seiche.surface_height: the world is built after the script's main chunk; call this from a callback" },
        { "seiche.particles_in({0, 0, 0})", "seiche.particles_in: argument #2 'max' must be a table of 3 numbers {x, y, z} in m (got no value)" },
        { "seiche.ray_cast({0, 0, 0}, {1, 1, 1})", "seiche.ray_cast: the world is built after the script's main chunk" },
        { "seiche.max_emitter_rate(-1, 0.1)", "seiche.max_emitter_rate: argument #1 'speed' must be a number in (0, 100] m/s (got -1)" },
        { "seiche.screen_point({0, 0})", "seiche.screen_point: argument #1 'point' must be a table of 3 numbers {x, y, z} (got a table of 2)" },
        { "seiche.screen_ray(0, 0)", "seiche.screen_ray: there is no camera yet; call this from a callback" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) expect_error(cases[i][0], cases[i][1]);
}

static void method_arguments_are_checked_like_functions(void **state)
{
    (void)state;
    static const char *const setup =
        "local b = seiche.body{shape = 'box', size = {0.1, 0.1, 0.1}}\n"
        "local k = seiche.body{shape = 'box', kind = 'kinematic', size = {0.1, 0.1, 0.1}}\n"
        "local e = seiche.emitter{position = {0, 0, 0}}\n"
        "local t = seiche.after(1, print)\n";
    static const char *const cases[][2] = {
        { "b.position()", "body:position: 'self' must be a body (got no value); call methods with a colon: x:position(...)" },
        { "b.position(e)", "body:position: 'self' must be a body (got seiche.emitter)" },
        { "e.set(b, {})", "emitter:set: 'self' must be an emitter (got seiche.body)" },
        { "e:set{rate = -1}", "emitter:set: field 'rate' must be a number >= 0" },
        { "e:set{colour = 1}", "emitter:set: field 'colour' must be a colour {r, g, b} with each in [0, 1], or false for none (got 1)" },
        { "e:set{color = {1, 0, 0}, colour = {1, 0, 0}}", "emitter:set: give 'colour' or 'color' (two spellings of one field), not both" },
        { "e:set_enabled('on')", "emitter:set_enabled: argument #1 'on' must be true or false (got \"on\")" },
        { "b:apply_force({1, 2, 0/0})", "body:apply_force: argument #1 'force'.z must be a number in [-1000000000, 1000000000] N (got nan)" },
        { "b:apply_torque()", "body:apply_torque: argument #1 'torque' must be a table of 3 numbers {x, y, z} in N m (got no value)" },
        { "b:set_velocity({0, 0, math.huge})", "body:set_velocity: argument #1 'velocity'.z must be a number" },
        { "b:teleport({0, 0, 0}, {1, 1, 1, 1})", "body:teleport: argument #2: field 'rotation' must be a unit quaternion {x, y, z, w} (length 1; got length 2)" },
        { "b:move_to({0, 0, 0})", "body:move_to: the body is dynamic: move_to drives kinematic bodies" },
        { "k:apply_impulse({0, 1, 0})", "body:apply_impulse: the body is kinematic: forces and impulses move dynamic bodies only" },
        { "k:grab({0, 0, 0})", "body:grab: the body is kinematic: only dynamic bodies can be grabbed" },
        { "b:velocity_at('here')", "body:velocity_at: argument #1 'point' must be a table of 3 numbers {x, y, z} in m (got \"here\")" },
        { "b:set_visible(nil)", "body:set_visible: argument #1 'visible' must be true or false (got nil)" },
        { "b.apply_force = nil", "seiche.body: 'apply_force' is a method and cannot be assigned" },
        { "t.cancel(b)", "timer:cancel: 'self' must be a timer (got seiche.body)" },
        { "local g = b:grab({0, 0, 0}); g:move({0, 0/0, 0})", "grab:move: argument #1 'point'.y must be a number in [-100000, 100000] m (got nan)" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char code[1024];
        snprintf(code, sizeof code, "%s%s", setup, cases[i][0]);
        // The error is on line 5 (after the four setup lines).
        eng_script *s = script();
        if (run_chunk(s, code) == ENG_SCRIPT_OK) fail_msg("accepted: %s", cases[i][0]);
        const char *err = eng_script_error(s);
        if (strncmp(err, "case.lua:5: ", 12) != 0 || !strstr(err, cases[i][1]))
            fail_msg("%s\n  want: case.lua:5: ...%s\n  got:  %s", cases[i][0], cases[i][1], err);
        eng_script_destroy(s);
    }
}

// Every function and method, given junk (a function value) for every argument, either
// ignores arguments (functions that take none) or refuses with its own name: no crash,
// no anonymous "bad argument" from deep inside.
static void junk_arguments_never_crash_and_name_the_callee(void **state)
{
    (void)state;
    int refused = 0;
    for (const char *const *name = eng_script_api_names(); *name; name++) {
        if (strncmp(*name, "on_", 3) == 0) continue;
        char code[1024], callee[96];
        const char *colon = strchr(*name, ':');
        if (colon) {
            char kind[32];
            snprintf(kind, sizeof kind, "%.*s", (int)(colon - *name), *name);
            const char *make = strcmp(kind, "emitter") == 0 ? "seiche.emitter{position = {0, 0, 0}}"
                               : strcmp(kind, "sink") == 0  ? "seiche.sink{min = {0, 0, 0}, max = {1, 1, 1}}"
                               : strcmp(kind, "body") == 0  ? "seiche.body{shape = 'sphere', radius = 0.1}"
                               : strcmp(kind, "timer") == 0 ? "seiche.after(1, print)"
                               : strcmp(kind, "joint") == 0
                                   ? "seiche.joint{kind = 'hinge', a = seiche.body{shape = 'sphere', radius = 0.1}, "
                                     "pivot = {0, 0, 0}, axis = {0, 0, 1}}"
                                   : "seiche.body{shape = 'sphere', radius = 0.1}:grab({0, 0, 0})";
            snprintf(code, sizeof code, "local h = %s\nh:%s(print, print, print)", make, colon + 1);
            snprintf(callee, sizeof callee, "%s: ", *name);
        } else {
            snprintf(code, sizeof code, "\n%s(print, print, print, print)", *name);
            snprintf(callee, sizeof callee, "%s: ", *name);
        }
        eng_script *s = script();
        if (run_chunk(s, code) != ENG_SCRIPT_OK) {
            const char *err = eng_script_error(s);
            if (strncmp(err, "case.lua:2: ", 12) != 0 || !strstr(err, callee))
                fail_msg("%s with junk arguments:\n  want: case.lua:2: %s...\n  got:  %s", *name, callee, err);
            refused++;
        }
        eng_script_destroy(s);
    }
    // About half take arguments (the rest are queries like seiche.time() and ignore them).
    if (refused < 40) fail_msg("only %d of the functions and methods refused junk arguments", refused);
}

static void removed_handles_raise_attempt_to_use_a_destroyed_object(void **state)
{
    (void)state;
    static const char *const cases[][3] = {
        { "local h = seiche.body{shape = 'sphere', radius = 0.1}; h:destroy()", "h:position()", "body:position: attempt to use a destroyed body" },
        { "local h = seiche.body{shape = 'sphere', radius = 0.1}; h:destroy()", "h:destroy()", "body:destroy: attempt to use a destroyed body" },
        { "local h = seiche.emitter{position = {0, 0, 0}}; h:remove()", "h:set{rate = 1}", "emitter:set: attempt to use a destroyed emitter" },
        { "local h = seiche.sink{min = {0, 0, 0}, max = {1, 1, 1}}; h:remove()", "h:get()", "sink:get: attempt to use a destroyed sink" },
        { "local h = seiche.after(1, print); h:cancel()", "h:remaining()", "timer:remaining: attempt to use a destroyed timer" },
        { "local b = seiche.body{shape = 'sphere', radius = 0.1}; local h = b:grab({0, 0, 0}); b:destroy()", "h:move({0, 1, 0})", "grab:move: attempt to use a destroyed grab" },
        { "local b = seiche.body{shape = 'sphere', radius = 0.1}; local h = seiche.joint{kind = 'point', a = b, pivot = {0, 0, 0}}; b:destroy()", "h:force()", "joint:force: attempt to use a destroyed joint" },
        { "local h = seiche.joint{kind = 'point', a = seiche.body{shape = 'sphere', radius = 0.1}, pivot = {0, 0, 0}}; h:remove()", "h:get()", "joint:get: attempt to use a destroyed joint" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char code[1024];
        snprintf(code, sizeof code, "%s\nseiche.check(not h:is_valid(), 'still valid')\n%s", cases[i][0], cases[i][1]);
        eng_script *s = script();
        if (run_chunk(s, code) == ENG_SCRIPT_OK) fail_msg("accepted: %s", code);
        const char *err = eng_script_error(s);
        if (strncmp(err, "case.lua:3: ", 12) != 0 || !strstr(err, cases[i][2]))
            fail_msg("%s\n  want: case.lua:3: %s\n  got:  %s", code, cases[i][2], err);
        eng_script_destroy(s);
    }
}

// ---- the review of the Lua API: indices, integers, callables, spellings --------------------

// Runs `code` (a main chunk) and fails with its message unless it runs clean.
static void expect_ok(const char *code)
{
    eng_script *s = script();
    if (run_chunk(s, code) != ENG_SCRIPT_OK) fail_msg("%s\n  refused: %s", code, eng_script_error(s));
    eng_script_destroy(s);
}

// Runs `code` and wants an error at case.lua:LINE holding `want`.
static void expect_error_at(const char *code, int line, const char *want)
{
    eng_script *s = script();
    if (run_chunk(s, code) == ENG_SCRIPT_OK) fail_msg("accepted: %s", code);
    char where[32];
    snprintf(where, sizeof where, "case.lua:%d: ", line);
    const char *err = eng_script_error(s);
    if (strncmp(err, where, strlen(where)) != 0 || !strstr(err, want))
        fail_msg("%s\n  want: %s...%s\n  got:  %s", code, where, want, err);
    eng_script_destroy(s);
}

static void whole_numbers_come_back_as_integers(void **state)
{
    (void)state;
    expect_ok("local function int(v, what) seiche.check(math.type(v) == 'integer', what .. ' is ' .. tostring(v)) end\n"
              "local function float(v, what) seiche.check(math.type(v) == 'float', what .. ' is ' .. tostring(v)) end\n"
              "int(seiche.param('iterations'), 'param iterations')\n"
              "int(seiche.params().iterations, 'params().iterations')\n"
              "float(seiche.param('particle_radius'), 'param particle_radius')\n"
              "float(seiche.params().viscosity, 'params().viscosity')\n"
              "seiche.set_param('iterations', 3)\n"
              "seiche.check(seiche.param('iterations') == 3 and math.type(seiche.param('iterations')) == 'integer', 'set')\n"
              "local c = seiche.coupling()\n"
              "int(c.force_latency, 'coupling().force_latency')\n"
              "local st = seiche.stats()\n"
              "for _, k in ipairs{'particles', 'capacity', 'nan', 'outside', 'overflow', 'step', 'substeps'} do\n"
              "  int(st[k], 'stats().' .. k)\n"
              "end\n"
              "seiche.check(st.step == -1, 'step before the first is -1')\n"
              "float(st.rho0, 'stats().rho0')\n"
              "int(seiche.capacity(), 'capacity()')\n"
              "int(seiche.particle_count(), 'particle_count()')\n");
}

static void methods_count_their_arguments_without_self(void **state)
{
    (void)state;
    static const char *const setup = "local b = seiche.body{shape = 'box', size = {0.1, 0.1, 0.1}}\n"
                                     "local e = seiche.emitter{position = {0, 0, 0}}\n";
    static const char *const cases[][2] = {
        { "b:apply_force({1, 0})", "body:apply_force: argument #1 'force' must be a table of 3 numbers" },
        { "b:apply_impulse({0, 0, 1}, {0/0, 0, 0})", "body:apply_impulse: argument #2 'point'.x must be a number" },
        { "b:grab({0, 0, 0}, -1)", "body:grab: argument #2 'max_force' must be a number in (0, 1000000000] N (got -1)" },
        { "b:grab('here')", "body:grab: argument #1 'point' must be a table of 3 numbers" },
        { "b:teleport('there')", "body:teleport: argument #1 'position' must be a table of 3 numbers" },
        { "b:set_color({1, 1, 2})", "body:set_color: argument #1 'color'.z must be a number in [0, 1] (got 2)" },
        { "b:set_colour({1, 1, 2})", "body:set_colour: argument #1 'colour'.z must be a number in [0, 1] (got 2)" },
        { "e:set(5)", "emitter:set: argument #1 must be a table {position, direction" },
        { "b.position(5)", "body:position: 'self' must be a body (got 5); call methods with a colon" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char code[1024];
        snprintf(code, sizeof code, "%s%s", setup, cases[i][0]);
        expect_error_at(code, 3, cases[i][1]);
    }
    // seiche.render's density range counts from 1, as Lua does.
    expect_error_at("seiche.render{density_range = {1.0, 0.9}}", 1,
                    "seiche.render: field 'density_range'[2] must be greater than density_range[1] (got {1, 0.9})");
}

static void timers_take_callable_tables_like_callbacks(void **state)
{
    (void)state;
    expect_ok("local callable = setmetatable({}, {__call = function(self, t) end})\n"
              "local a = seiche.after(1, callable)\n"
              "local e = seiche.every(0.5, callable)\n"
              "seiche.check(a:is_valid() and e:is_valid(), 'timers made')\n");
    expect_error_at("seiche.every(1, {})", 1,
                    "seiche.every: argument #2 'callback' must be a function or a table with a __call metamethod (got table)");
    expect_error_at("seiche.after(1, 'later')", 1,
                    "seiche.after: argument #2 'callback' must be a function or a table with a __call metamethod (got \"later\")");
}

static void colour_fields_take_both_spellings(void **state)
{
    (void)state;
    expect_ok("local a = seiche.body{shape = 'sphere', radius = 0.1, color = {1, 0, 0}}\n"
              "local b = seiche.body{shape = 'sphere', radius = 0.1, colour = {0, 1, 0}}\n"
              "a:set_colour({0, 0, 1}); b:set_color({1, 1, 0})\n"
              "local e = seiche.emitter{position = {0, 0, 0}, color = {1, 0, 0}}\n"
              "e:set{colour = {0, 1, 0}}\n"
              "local g = e:get(); seiche.check(g.colour[2] == 1 and g.color[2] == 1, 'emitter:get gives both')\n"
              "e:set{color = false}\n"
              "seiche.colour{min = {0, 0, 0}, max = {1, 1, 1}, color = {1, 0, 0}}\n"
              "seiche.color{min = {0, 0, 0}, max = {1, 1, 1}, colour = false}\n"
              "seiche.set_look{light = {colour = {1, 1, 1}}}\n"
              "seiche.set_look{light = {color = {1, 0.5, 1}}}\n"
              "seiche.check(seiche.look().light.colour[2] == 0.5 and seiche.look().light.color[2] == 0.5, 'look')\n");
    static const char *const cases[][2] = {
        { "seiche.body{shape = 'sphere', radius = 0.1, color = {1, 0, 0}, colour = {1, 0, 0}}",
          "seiche.body: give 'colour' or 'color' (two spellings of one field), not both" },
        { "seiche.body{shape = 'sphere', radius = 0.1, colour = {1, 0, 2}}", "seiche.body: field 'colour'.z must be a number in [0, 1] (got 2)" },
        { "seiche.emitter{position = {0, 0, 0}, color = 1}", "seiche.emitter: field 'color' must be a colour {r, g, b} with each in [0, 1], or false for none (got 1)" },
        { "seiche.color{min = {0, 0, 0}, max = {1, 1, 1}}", "seiche.color: field 'colour' is required" },
        { "seiche.colour{min = {0, 0, 0}, max = {1, 1, 1}, color = false, colour = false}", "seiche.colour: give 'colour' or 'color'" },
        { "seiche.set_look{light = {color = {1, 1, 1}, colour = {1, 1, 1}}}", "seiche.set_look: light: give 'colour' or 'color'" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) expect_error_at(cases[i][0], 1, cases[i][1]);
}

static void particle_lists_are_counted_per_position(void **state)
{
    (void)state;
    expect_error_at("seiche.particles{positions = {{0.1, 0.1, 0.1}, {0.2, 0.1, 0.1}}, velocities = {}}", 1,
                    "seiche.particles: field 'velocities' must hold one velocity per position (2) (got 0)");
    expect_error_at("seiche.particles{positions = {{0.1, 0.1, 0.1}}, velocities = {{0, 0, 0}, {0, 0, 0}}}", 1,
                    "seiche.particles: field 'velocities' must hold one velocity per position (1) (got 2)");
    expect_error_at("seiche.particles{positions = {{0.1, 0.1, 0.1}}, velocities = {{0, 0/0, 0}}}", 1,
                    "seiche.particles: field 'velocities'[1].y must be a number");
}

// A hull the fluid cannot take (more than 256 faces) is refused at the call, with its line.
static void a_hull_of_too_many_faces_is_refused_at_the_call(void **state)
{
    (void)state;
    // 400 points spread over a sphere: their hull has hundreds of triangles.
    expect_error_at("local p = {}\n"
                    "for i = 0, 399 do\n"
                    "  local y = 1 - 2 * (i + 0.5) / 400; local r = math.sqrt(1 - y * y); local a = i * 2.399963\n"
                    "  p[#p + 1] = {r * math.cos(a), y, r * math.sin(a)}\n"
                    "end\n"
                    "seiche.body{shape = 'hull', points = p}\n", 6,
                    "seiche.body: field 'points' makes a convex hull of ");
    expect_error_at("seiche.body{shape = 'hull', points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}}", 1,
                    "seiche.body: field 'points': ");
    // A cube's 8 corners: 6 faces, taken.
    expect_ok("seiche.body{shape = 'hull', points = {{0,0,0},{1,0,0},{0,1,0},{1,1,0},{0,0,1},{1,0,1},{0,1,1},{1,1,1}}}");
}

// Lua raises a memory error itself (no message handler runs): the error still starts with the
// line that asked for the memory.
static void a_memory_error_lua_raises_has_a_line(void **state)
{
    (void)state;
    eng_script_def d = eng_default_script_def();
    d.log.min_level = ENG_LOG_ERROR;
    d.budget_s = 120.0;
    eng_script *s = eng_script_create(&d);
    assert_non_null(s);
    // 200 MiB, then one concatenation of 600 MiB: the allocator refuses it inside the VM.
    eng_script_status st = run_chunk(s, "local a = string.rep('x', 200 << 20)\n"
                                        "local b = 1\n"
                                        "local c = a .. a .. a\n");
    char err[600];
    snprintf(err, sizeof err, "%s", eng_script_error(s));
    eng_script_destroy(s);
    assert_int_equal(st, ENG_SCRIPT_ERROR);
    static const char want[] = "case.lua:3: the script's main chunk used more than the script's 512 MiB of memory";
    if (strncmp(err, want, sizeof want - 1) != 0)
        fail_msg("want case.lua:3: the script's main chunk used more than ...\n  got:  %s", err);
}

// ---- the scene description and the queue ------------------------------------------------

static void main_chunk_describes_the_scene_and_queues_its_edits(void **state)
{
    (void)state;
    eng_script *s = script();
    const char *code =
        "seiche.scene{name = 'tank', capacity = 1234, fluid = {iterations = 7}, gravity = {0, -3, 0},\n"
        "  container = {min = {0, 0, 0}, max = {1, 2, 3}, closed_top = true},\n"
        "  camera = {eye = {1, 2, 3}, target = {0, 1, 0}, fov = 40, mode = 'fly'},\n"
        "  look = {sky = {0, 0, 0}, ground = false, panel = false}}\n"
        "seiche.set_param('viscosity', 0.25)\n"
        "seiche.block{min = {0, 0, 0}, max = {0.5, 0.5, 0.5}}\n"
        "local e = seiche.emitter{position = {0.5, 1, 0.5}, rate = 10}\n"
        "local b = seiche.body{shape = 'box', size = {0.1, 0.2, 0.3}, position = {0.5, 1, 1}, density = 500}\n"
        "seiche.check(tostring(b) == 'body #2 (dynamic box, not yet in the world)', tostring(b))\n"
        "seiche.check(math.abs(b:mass() - 3) < 1e-6, 'mass of a queued body: ' .. b:mass())\n"
        "seiche.check(b:position().y == 1 and b:position()[3] == 1, 'position of a queued body')\n"
        "seiche.check(e:get().rate == 10 and e:get().speed == 1, 'emitter defaults')\n"
        "seiche.check(#seiche.bodies() == 1 and seiche.bodies()[1] == b, 'bodies() returns the same handle')\n"
        "seiche.check(seiche.particle_count() == 0 and seiche.capacity() == 1234, 'no world yet')\n"
        "seiche.check(seiche.param('iterations') == 7 and seiche.params().viscosity == 0.25, 'params')\n"
        "seiche.check(seiche.camera().mode == 'fly' and seiche.look().ground == false, 'camera and look')\n";
    if (run_chunk(s, code) != ENG_SCRIPT_OK) fail_msg("%s", eng_script_error(s));
    const eng_scene_config *c = eng_script_config(s);
    assert_string_equal(c->name, "tank");
    assert_int_equal(c->capacity, 1234);
    assert_int_equal(c->params.iterations, 7);
    assert_float_equal(c->params.viscosity, 0.25f, 1e-6);
    assert_float_equal(c->params.gravity[1], -3.0f, 1e-6);
    assert_true(c->has_container && c->closed_top);
    assert_float_equal(c->container_max[2], 3.0f, 1e-6);
    assert_float_equal(c->camera_fov, 40.0f, 1e-6);
    assert_int_equal(c->camera_mode, ENG_CAMERA_FLY);
    assert_false(c->look.ground);
    assert_false(c->look.panel);
    assert_string_equal(c->scene_where, "case.lua:1: ");
    assert_int_equal(eng_script_pending(s), 3); // block, emitter, body: waiting for a world
    assert_int_equal(eng_script_apply(s), ENG_SCRIPT_OK); // no world: nothing happens
    assert_int_equal(eng_script_pending(s), 3);
    eng_script_destroy(s);
}

static void parameter_panel_changes_are_checked(void **state)
{
    (void)state;
    eng_script *s = script();
    char err[512];
    assert_true(eng_script_set_param(s, "iterations", 5, err, sizeof err));
    assert_int_equal(eng_script_config(s)->params.iterations, 5);
    assert_false(eng_script_set_param(s, "iterations", 0, err, sizeof err));
    assert_non_null(strstr(err, "pbf_params.iterations must be in [1, 100] (got 0)"));
    assert_false(eng_script_set_param(s, "nope", 1, err, sizeof err));
    eng_script_destroy(s);
}

// ---- failures -------------------------------------------------------------------------------

static void missing_file_is_named(void **state)
{
    (void)state;
    eng_script *s = script();
    assert_int_equal(eng_script_load(s, "/nonexistent/scene.lua"), ENG_SCRIPT_ERROR);
    assert_string_equal(eng_script_error(s), "/nonexistent/scene.lua: cannot open the script file: No such file or directory");
    eng_script_destroy(s);
}

static void syntax_error_has_file_and_line(void **state)
{
    (void)state;
    eng_script *s = script();
    assert_int_equal(run_chunk(s, "seiche.scene{}\n\nlocal x = = 1\n"), ENG_SCRIPT_ERROR);
    assert_non_null(strstr(eng_script_error(s), "case.lua:3: unexpected symbol near '='"));
    eng_script_destroy(s);
}

static void runtime_error_has_a_traceback(void **state)
{
    (void)state;
    eng_script *s = script();
    assert_int_equal(run_chunk(s, "local function f(t) return t.x end\nf(nil)\n"), ENG_SCRIPT_ERROR);
    const char *err = eng_script_error(s);
    assert_non_null(strstr(err, "case.lua:1: attempt to index a nil value (local 't')"));
    assert_non_null(strstr(err, "stack traceback:"));
    assert_non_null(strstr(err, "case.lua:2: in main chunk"));
    eng_script_destroy(s);
}

static void failed_check_is_its_own_status(void **state)
{
    (void)state;
    eng_script *s = script();
    assert_int_equal(run_chunk(s, "\nseiche.check(1 == 2, 'one is not two')"), ENG_SCRIPT_CHECK_FAILED);
    assert_non_null(strstr(eng_script_error(s), "case.lua:2: check failed: one is not two"));
    eng_script_destroy(s);
}

static void endless_loop_is_stopped_by_the_budget(void **state)
{
    (void)state;
    eng_script_def d = eng_default_script_def();
    d.budget_s = 0.2;
    eng_script *s = eng_script_create(&d);
    double t0 = support_seconds();
    assert_int_equal(run_chunk(s, "while true do end"), ENG_SCRIPT_ERROR);
    double secs = support_seconds() - t0;
    assert_non_null(strstr(eng_script_error(s), "the script's main chunk ran longer than its budget of 0.2 s (an endless loop?)"));
    assert_true(secs < 2.0);
    eng_script_destroy(s);
    d.budget_s = 0.0;
    assert_null(eng_script_create(&d)); // no budget is not allowed
}

// Work one instruction or one library call does in C: comparing two long strings (strcoll once
// per NUL byte: 50 ms for 7.5 MB, so the hook, at every 1000th instruction, let a loop of them run
// 48 s past a 5 s budget), parsing a long source in load (72 MB: 4 s), and expanding a long date
// format (string.rep("%n", 8e7): 6.6 s). Each is stopped near its budget now, or refused.
static void long_string_work_is_stopped_by_the_budget(void **state)
{
    (void)state;
    static const char *const chunks[] = {
        "local a = string.rep('\\0', 7 * 1024 * 1024 + 512 * 1024)\nrepeat until a < a",
        "local src = string.rep('local x = 1\\n', 6000000)\nwhile true do load(src) end",
    };
    for (int i = 0; i < 2; i++) {
        eng_script_def d = eng_default_script_def();
        d.budget_s = 0.3;
        eng_script *s = eng_script_create(&d);
        double t0 = support_seconds();
        assert_int_equal(run_chunk(s, chunks[i]), ENG_SCRIPT_ERROR);
        double secs = support_seconds() - t0;
        assert_non_null(strstr(eng_script_error(s), "ran longer than its budget of 0.3 s"));
        assert_true(secs < 3.0);
        eng_script_destroy(s);
    }
    eng_script *s = script();
    assert_int_equal(run_chunk(s, "os.date(string.rep('%n', 512))"), ENG_SCRIPT_OK); // 1024 bytes
    assert_int_equal(run_chunk(s, "os.date(string.rep('%n', 80000000))"), ENG_SCRIPT_ERROR);
    assert_non_null(strstr(eng_script_error(s), "os.date: argument #1 'format' is 160000000 bytes long; at most 1024"));
    eng_script_destroy(s);
}

static void runaway_memory_is_stopped(void **state)
{
    (void)state;
    // A time budget far beyond what filling 512 MiB takes, so the memory limit is what stops
    // it even on a loaded machine under AddressSanitizer (where the default 5 s budget
    // sometimes ran out first).
    eng_script_def d = eng_default_script_def();
    d.log.min_level = ENG_LOG_ERROR;
    d.budget_s = 120.0;
    eng_script *s = eng_script_create(&d);
    assert_non_null(s);
    // 1 MiB strings until the 512 MiB limit.
    eng_script_status st = run_chunk(s, "local t = {}\nfor i = 1, 100000 do t[i] = string.rep('x', 1 << 20) .. i end");
    bool named = strstr(eng_script_error(s), "used more than the script's 512 MiB of memory") != NULL;
    if (!named) print_error("got: %s\n", eng_script_error(s));
    eng_script_destroy(s); // before the checks: a failed one must not leak the state
    assert_int_equal(st, ENG_SCRIPT_ERROR);
    assert_true(named);
}

static void key_names_round_trip(void **state)
{
    (void)state;
    int named = 0;
    for (int k = 0; k <= GLFW_KEY_LAST; k++) {
        const char *n = eng_key_name(k);
        if (!n) continue;
        named++;
        int back = eng_key_code(n);
        // Left and right shift/ctrl share a name; the name maps back to the left key.
        assert_string_equal(eng_key_name(back), n);
    }
    assert_true(named >= 26 + 10 + 12 + 11);
    assert_int_equal(eng_key_code("hyper"), -1);
    assert_int_equal(eng_key_code("space"), GLFW_KEY_SPACE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_function_method_and_callback_is_documented),
        cmocka_unit_test(documentation_names_nothing_the_bindings_lack),
        cmocka_unit_test(seiche_table_holds_exactly_the_registered_functions),
        cmocka_unit_test(bad_arguments_name_function_argument_value_and_rule),
        cmocka_unit_test(method_arguments_are_checked_like_functions),
        cmocka_unit_test(junk_arguments_never_crash_and_name_the_callee),
        cmocka_unit_test(removed_handles_raise_attempt_to_use_a_destroyed_object),
        cmocka_unit_test(whole_numbers_come_back_as_integers),
        cmocka_unit_test(methods_count_their_arguments_without_self),
        cmocka_unit_test(timers_take_callable_tables_like_callbacks),
        cmocka_unit_test(colour_fields_take_both_spellings),
        cmocka_unit_test(particle_lists_are_counted_per_position),
        cmocka_unit_test(a_hull_of_too_many_faces_is_refused_at_the_call),
        cmocka_unit_test(a_memory_error_lua_raises_has_a_line),
        cmocka_unit_test(main_chunk_describes_the_scene_and_queues_its_edits),
        cmocka_unit_test(parameter_panel_changes_are_checked),
        cmocka_unit_test(missing_file_is_named),
        cmocka_unit_test(syntax_error_has_file_and_line),
        cmocka_unit_test(runtime_error_has_a_traceback),
        cmocka_unit_test(failed_check_is_its_own_status),
        cmocka_unit_test(endless_loop_is_stopped_by_the_budget),
        cmocka_unit_test(long_string_work_is_stopped_by_the_budget),
        cmocka_unit_test(runaway_memory_is_stopped),
        cmocka_unit_test(key_names_round_trip),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
