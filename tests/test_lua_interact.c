// The Lua host's interaction bindings without a GL context or a world (as tests/test_lua.c):
// joints (seiche.joint and its methods) and the event thresholds refuse bad input naming the
// function, the field or argument, the value and what is allowed, at the caller's file:line;
// what a joint records before it is in the world; the thresholds' defaults.
#include "tests/support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "engine/script/script.h"

static eng_script *script(void)
{
    eng_script_def d = eng_default_script_def();
    d.log.min_level = ENG_LOG_ERROR;
    eng_script *s = eng_script_create(&d);
    assert_non_null(s);
    return s;
}

// `setup` (its lines end in '\n') then `code`; the error must be on the line of `code`.
static void expect_error_after(const char *setup, const char *code, const char *want)
{
    int line = 1;
    for (const char *p = setup; *p; p++) line += *p == '\n';
    char chunk[4096], where[32];
    snprintf(chunk, sizeof chunk, "%s%s", setup, code);
    snprintf(where, sizeof where, "case.lua:%d: ", line);
    eng_script *s = script();
    if (eng_script_load_string(s, "case.lua", chunk) == ENG_SCRIPT_OK)
        fail_msg("accepted: %s\n  (expected an error containing: %s)", code, want);
    const char *err = eng_script_error(s);
    if (strncmp(err, where, strlen(where)) != 0 || !strstr(err, want))
        fail_msg("%s\n  want: %s%s\n  got:  %s", code, where, want, err);
    eng_script_destroy(s);
}

static void expect_ok(const char *code)
{
    eng_script *s = script();
    if (eng_script_load_string(s, "case.lua", code) != ENG_SCRIPT_OK) fail_msg("%s", eng_script_error(s));
    eng_script_destroy(s);
}

// ---- joints -------------------------------------------------------------------------------

static const char *const BODIES =
    "local d = seiche.body{shape = 'box', size = {0.4, 0.02, 0.3}, position = {0.5, 0.5, 0.5}}\n"
    "local e = seiche.body{shape = 'sphere', radius = 0.1, position = {0.2, 0.5, 0.5}}\n"
    "local s = seiche.body{shape = 'box', kind = 'static', size = {1, 1, 1}}\n"
    "local gone = seiche.body{shape = 'sphere', radius = 0.1}; gone:destroy()\n";

static void joint_input_is_checked_naming_the_field(void **state)
{
    (void)state;
    static const char *const cases[][2] = {
        { "seiche.joint()", "seiche.joint: argument #1 must be a table {kind = \"hinge\", a = body" },
        { "seiche.joint{}", "seiche.joint: field 'kind' is required: one of \"hinge\", \"slider\", \"fixed\", \"point\" (got nil)" },
        { "seiche.joint{kind = 'rope', a = d}", "seiche.joint: field 'kind' must be one of \"hinge\", \"slider\", \"fixed\", \"point\" (got \"rope\")" },
        { "seiche.joint{kind = 'fixed', a = d, strength = 1}", "seiche.joint: unknown field \"strength\" (known: kind, a, b, pivot, anchor, axis, limits, motor, collide)" },
        { "seiche.joint{kind = 'fixed'}", "seiche.joint: field 'a' is required: the dynamic body the joint holds (got nil)" },
        { "seiche.joint{kind = 'fixed', a = 5}", "seiche.joint: field 'a' must be a body (got 5)" },
        { "seiche.joint{kind = 'fixed', a = d, b = 'world'}", "seiche.joint: field 'b' must be a body (got \"world\")" },
        { "seiche.joint{kind = 'fixed', a = gone}", "seiche.joint: field 'a' is a destroyed body" },
        { "seiche.joint{kind = 'fixed', a = s, b = d}", "seiche.joint: field 'a' must be a dynamic body (got a static body): a joint moves body a; make the static body 'b'" },
        { "seiche.joint{kind = 'fixed', a = d, b = d}", "seiche.joint: fields 'a' and 'b' are the same body" },
        { "seiche.joint{kind = 'fixed', a = d, collide = 'yes'}", "seiche.joint: field 'collide' must be true or false (got \"yes\")" },
        { "seiche.joint{kind = 'fixed', a = d, pivot = {0, 0, 0}}", "seiche.joint: field 'pivot' does not apply to a fixed joint (it takes no fields but kind, a, b and collide)" },
        { "seiche.joint{kind = 'point', a = d, pivot = {0, 0, 0}, axis = {0, 0, 1}}", "seiche.joint: field 'axis' does not apply to a point joint (it takes 'pivot')" },
        { "seiche.joint{kind = 'slider', a = d, axis = {1, 0, 0}, pivot = {0, 0, 0}}", "seiche.joint: field 'pivot' does not apply to a slider joint (it takes 'anchor', 'axis', 'limits', 'motor')" },
        { "seiche.joint{kind = 'point', a = d}", "seiche.joint: field 'pivot' is required for a point: the world point {x, y, z} m it turns about (got nil)" },
        { "seiche.joint{kind = 'hinge', a = d, pivot = {0, 0/0, 0}, axis = {0, 0, 1}}", "seiche.joint: field 'pivot'.y must be a number in [-100000, 100000] m (got nan)" },
        { "seiche.joint{kind = 'hinge', a = d, pivot = {0, 0, 0}}", "seiche.joint: field 'axis' is required for a hinge: a direction {x, y, z}, not zero (got nil)" },
        { "seiche.joint{kind = 'slider', a = d, axis = {0, 0, 0}}", "seiche.joint: field 'axis' must not be zero (got {0, 0, 0})" },
        { "seiche.joint{kind = 'hinge', a = d, pivot = {0, 0, 0}, axis = {0, 0, 1}, limits = 1}", "seiche.joint: field 'limits' must be a table {lo, hi} of 2 numbers in [-3.141593, 3.141593] rad, lo <= hi (got 1)" },
        { "seiche.joint{kind = 'hinge', a = d, pivot = {0, 0, 0}, axis = {0, 0, 1}, limits = {0, 1, 2}}", "seiche.joint: field 'limits' must be a table {lo, hi} of 2 numbers in [-3.141593, 3.141593] rad, lo <= hi (got a table of another length)" },
        { "seiche.joint{kind = 'hinge', a = d, pivot = {0, 0, 0}, axis = {0, 0, 1}, limits = {0, 4}}", "seiche.joint: field 'limits'[2] must be a number in [-3.141593, 3.141593] rad (got 4)" },
        { "seiche.joint{kind = 'hinge', a = d, pivot = {0, 0, 0}, axis = {0, 0, 1}, limits = {1, -1}}", "seiche.joint: field 'limits' must have lo <= hi (got {1, -1})" },
        { "seiche.joint{kind = 'slider', a = d, axis = {1, 0, 0}, limits = {-1e6, 0}}", "seiche.joint: field 'limits'[1] must be a number in [-100000, 100000] m (got -1000000)" },
        { "seiche.joint{kind = 'hinge', a = d, pivot = {0, 0, 0}, axis = {0, 0, 1}, motor = 2}", "seiche.joint: field 'motor' must be a table {speed = rad/s, max_torque = N m} (got 2)" },
        { "seiche.joint{kind = 'hinge', a = d, pivot = {0, 0, 0}, axis = {0, 0, 1}, motor = {speed = 1, max_force = 2}}", "seiche.joint: field 'motor': unknown field \"max_force\" (known: speed, max_torque)" },
        { "seiche.joint{kind = 'hinge', a = d, pivot = {0, 0, 0}, axis = {0, 0, 1}, motor = {speed = 1}}", "seiche.joint: field 'motor': field 'max_torque' is required: a number in [0, 1000000000] N m (got nil)" },
        { "seiche.joint{kind = 'slider', a = d, axis = {1, 0, 0}, motor = {speed = 1, max_force = -2}}", "seiche.joint: field 'motor': field 'max_force' must be a number in [0, 1000000000] N (got -2)" },
        { "seiche.joint{kind = 'slider', a = d, axis = {1, 0, 0}, motor = {speed = 1/0, max_force = 2}}", "seiche.joint: field 'motor': field 'speed' must be a number in [-10000, 10000] m/s (got inf)" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) expect_error_after(BODIES, cases[i][0], cases[i][1]);
}

static void joint_methods_are_checked(void **state)
{
    (void)state;
    static const char *const setup =
        "local d = seiche.body{shape = 'box', size = {0.4, 0.02, 0.3}, position = {0.5, 0.5, 0.5}}\n"
        "local h = seiche.joint{kind = 'hinge', a = d, pivot = {0.3, 0.5, 0.5}, axis = {0, 0, 2}}\n"
        "local r = seiche.joint{kind = 'slider', a = d, axis = {1, 0, 0}}\n"
        "local f = seiche.joint{kind = 'fixed', a = d}\n";
    static const char *const cases[][2] = {
        { "h.angle()", "joint:angle: 'self' must be a joint (got no value); call methods with a colon: x:angle(...)" },
        { "h.angle(d)", "joint:angle: 'self' must be a joint (got seiche.body)" },
        { "r:angle()", "joint:angle: the joint is a slider: angle() measures hinges (position() measures sliders)" },
        { "h:position()", "joint:position: the joint is a hinge: position() measures sliders (angle() measures hinges)" },
        { "f:set_motor{speed = 1, max_torque = 1}", "joint:set_motor: the joint is a fixed: only hinges and sliders have a motor" },
        { "f:set_limits{0, 1}", "joint:set_limits: the joint is a fixed: only hinges and sliders have limits" },
        { "h:set_motor(true)", "joint:set_motor: argument #1 'motor' (or false) must be a table {speed = rad/s, max_torque = N m} (got true)" },
        { "r:set_motor{speed = 1, max_torque = 1}", "joint:set_motor: argument #1 'motor' (or false): unknown field \"max_torque\" (known: speed, max_force)" },
        { "h:set_limits{2, 1}", "joint:set_limits: argument #1 'limits' (or false) must have lo <= hi (got {2, 1})" },
        { "h:set_limits()", "joint:set_limits: argument #1 'limits' (or false) must be a table {lo, hi} of 2 numbers in [-3.141593, 3.141593] rad, lo <= hi (got no value)" },
        { "h.remove = 1", "seiche.joint: 'remove' is a method and cannot be assigned" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) expect_error_after(setup, cases[i][0], cases[i][1]);
}

// Before the world exists a joint keeps what it was given: get() shows it (the axis made a
// unit vector, the slider's anchor at its body), angle and position are 0, the handle reads
// "not yet in the world", and motor and limit changes show at once.
static void joint_records_what_it_was_given(void **state)
{
    (void)state;
    expect_ok("local function near(a, b) return math.abs(a - b) < 1e-6 end\n"
              "local d = seiche.body{shape = 'box', size = {0.4, 0.02, 0.3}, position = {0.5, 0.6, 0.7}}\n"
              "local h = seiche.joint{kind = 'hinge', a = d, pivot = {0.3, 0.5, 0.5}, axis = {0, 0, 2},\n"
              "                       limits = {-1, 0.5}, motor = {speed = 2, max_torque = 3}, collide = true}\n"
              "local g = h:get()\n"
              "seiche.check(g.kind == 'hinge' and g.collide == true and near(g.pivot.x, 0.3) and g.axis.z == 1, 'get')\n"
              "seiche.check(g.limits[1] == -1 and g.limits[2] == 0.5, 'limits')\n"
              "seiche.check(g.motor.speed == 2 and g.motor.max_torque == 3, 'motor')\n"
              "seiche.check(h:angle() == 0 and tostring(h):find('hinge, not yet in the world'), tostring(h))\n"
              "h:set_motor(false); h:set_limits(false)\n"
              "seiche.check(h:get().motor == nil and h:get().limits == nil, 'off')\n"
              "local r = seiche.joint{kind = 'slider', a = d, axis = {1, 0, 0}}\n"
              "seiche.check(near(r:get().anchor.y, 0.6) and r:position() == 0, 'anchor')\n"
              "r:set_limits{-0.2, 0.3}\n"
              "seiche.check(near(r:get().limits[2], 0.3), 'slider limits')\n"
              "local a, b = r:bodies(); seiche.check(a == d and b == nil, 'bodies')\n"
              "local f, t = r:force(); seiche.check(f.x == 0 and t.z == 0, 'no force before a step')\n");
}

// ---- events -------------------------------------------------------------------------------

static void event_thresholds_are_checked_and_kept(void **state)
{
    (void)state;
    expect_error_after("", "seiche.set_contact_threshold(-1)",
                       "seiche.set_contact_threshold: argument #1 'impulse' must be a number in [0, 1000000000] N s (got -1)");
    expect_error_after("", "seiche.set_contact_threshold()",
                       "seiche.set_contact_threshold: argument #1 'impulse' must be a number in [0, 1000000000] N s (got no value)");
    expect_error_after("", "seiche.set_splash_threshold(0/0)",
                       "seiche.set_splash_threshold: argument #1 'speed' must be a number in [0, 10000] m/s (got nan)");
    expect_ok("seiche.check(seiche.contact_threshold() == 0.2 and seiche.splash_threshold() == 0.5, 'defaults')\n"
              "seiche.set_contact_threshold(0); seiche.set_splash_threshold(2.5)\n"
              "seiche.check(seiche.contact_threshold() == 0 and seiche.splash_threshold() == 2.5, 'kept')\n");
}

// ---- grabs ---------------------------------------------------------------------------------

static void grab_release_takes_a_boolean(void **state)
{
    (void)state;
    expect_error_after("local g = seiche.body{shape = 'sphere', radius = 0.1}:grab({0, 0, 0})\n", "g:release('far')",
                       "grab:release: argument #1 'throw' must be true or false (got \"far\")");
    expect_ok("local g = seiche.body{shape = 'sphere', radius = 0.1}:grab({0, 0, 0})\n"
              "g:release(false)\nseiche.check(not g:is_valid(), 'released')\n");
}

// ---- meshes from files --------------------------------------------------------------------

// A scene folder in /tmp: scene.lua's folder holds assets/ (cube.obj, open_box.obj, a text
// file, a link to a mesh outside the folder); the mesh outside sits beside the folder.
static void make_scene_folder(char *dir, size_t size)
{
    snprintf(dir, size, "/tmp/seiche_test_meshes_%ld", (long)getpid());
    char cmd[8192], fixtures[1024];
    support_source_path("tests/fixtures", fixtures, sizeof fixtures);
    snprintf(cmd, sizeof cmd,
             "rm -rf '%s' '%s_outside.obj' && mkdir -p '%s/assets/sub' && cp '%s/cube.obj' '%s/open_box.obj' "
             "'%s/not_a_mesh.txt' '%s/assets/' && cp '%s/cube.obj' '%s_outside.obj' && "
             "ln -s '%s_outside.obj' '%s/assets/link.obj'",
             dir, dir, dir, fixtures, fixtures, fixtures, dir, fixtures, dir, dir, dir);
    if (system(cmd) != 0) fail_msg("could not make %s", dir);
}

static void remove_scene_folder(const char *dir)
{
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "rm -rf '%s' '%s_outside.obj'", dir, dir);
    if (system(cmd) != 0) fail_msg("could not remove %s", dir);
}

static eng_script_status run_in(const char *dir, bool trusted, const char *code, eng_script **out)
{
    eng_script_def d = eng_default_script_def();
    d.log.min_level = ENG_LOG_ERROR;
    d.trusted = trusted;
    *out = eng_script_create(&d);
    assert_non_null(*out);
    char name[1100];
    snprintf(name, sizeof name, "%s/scene.lua", dir);
    return eng_script_load_string(*out, name, code);
}

static void mesh_files_are_found_in_the_scene_folder_only(void **state)
{
    (void)state;
    char dir[256];
    make_scene_folder(dir, sizeof dir);
    static const char *const cases[][2] = {
        { "seiche.body{mesh = '../x_outside.obj'}", "seiche.body: field 'mesh': \"../x_outside.obj\" is a path through '..' (mesh files are found from the folder of the script that names them, in the scene's folder or below" },
        { "seiche.body{mesh = 'assets/sub/../cube.obj'}", "field 'mesh': \"assets/sub/../cube.obj\" is a path through '..'" },
        { "seiche.body{mesh = '/etc/passwd'}", "seiche.body: field 'mesh': \"/etc/passwd\" is an absolute path: a scene names its files relative to its own file" },
        { "seiche.body{mesh = 'assets/missing.obj'}", "seiche.body: field 'mesh': \"assets/missing.obj\" does not exist" },
        { "seiche.body{mesh = 'assets/link.obj'}", "seiche.body: field 'mesh': \"assets/link.obj\" lies outside the scene's folder (a link?)" },
        { "seiche.body{mesh = 'assets/sub'}", "seiche.body: field 'mesh': \"assets/sub\" is not a regular file" },
        { "seiche.body{mesh = ''}", "seiche.body: field 'mesh': \"\" is an empty path" },
        { "seiche.body{mesh = 5}", "seiche.body: field 'mesh' must be a file name, e.g. \"assets/boat.obj\" (got 5)" },
        { "seiche.body{mesh = 'assets/not_a_mesh.txt'}", "seiche.body: mesh file '" },
        { "seiche.body{mesh = 'assets/cube.obj', shape = 'box'}", "seiche.body: give 'shape' or 'mesh', not both" },
        { "seiche.body{mesh = 'assets/cube.obj', size = {1, 1, 1}}", "seiche.body: field 'size' does not apply to a body from a mesh file" },
        { "seiche.body{mesh = 'assets/cube.obj', kind = 'static', hull_points = 16}", "seiche.body: field 'hull_points' applies to dynamic bodies (a static body from a mesh file is its triangles)" },
        { "seiche.body{mesh = 'assets/cube.obj', hull_points = 200}", "seiche.body: field 'hull_points' must be a whole number in [8, 130] (points) (got 200)" },
        { "seiche.body{mesh = 'assets/cube.obj', scale = 0}", "seiche.body: field 'scale' must be a number in (0, 1000000] (metres per file unit) (got 0)" },
        { "seiche.body{mesh = 'assets/cube.obj', centre = 'middle'}", "seiche.body: field 'centre' must be one of \"origin\", \"bounds\", \"base\" (got \"middle\")" },
        { "seiche.body{shape = 'box', size = {1, 1, 1}, scale = 2}", "seiche.body: field 'scale' applies to meshes from files only (give mesh = \"file.obj\")" },
        { "seiche.fill{mesh = 'assets/missing.obj'}", "seiche.fill: field 'mesh': \"assets/missing.obj\" does not exist" },
        { "seiche.fill{}", "seiche.fill: field 'mesh' is required: the file of a closed mesh whose inside to fill" },
        { "seiche.fill{mesh = 'assets/open_box.obj'}", "seiche.fill: mesh 'assets/open_box.obj' has 4 open edges (edges of one triangle only: holes): it has no inside to fill" },
        { "seiche.fill{mesh = 'assets/cube.obj', clearance = -1}", "seiche.fill: field 'clearance' must be a number in [0, 1000] m (got -1)" },
        { "seiche.fill{mesh = 'assets/cube.obj', hull_points = 8}", "seiche.fill: unknown field \"hull_points\"" },
        { "seiche.fill{mesh = 'assets/cube.obj', colour = 1}", "seiche.fill: unknown field \"colour\"" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        eng_script *s;
        char where[1100];
        snprintf(where, sizeof where, "%s/scene.lua:1: ", dir);
        if (run_in(dir, false, cases[i][0], &s) == ENG_SCRIPT_OK) fail_msg("accepted: %s", cases[i][0]);
        const char *err = eng_script_error(s);
        if (strncmp(err, where, strlen(where)) != 0 || !strstr(err, cases[i][1]))
            fail_msg("%s\n  want: %s%s\n  got:  %s", cases[i][0], where, cases[i][1], err);
        eng_script_destroy(s);
    }
    // Found: queued, and the body's shape follows its kind.
    eng_script *s;
    if (run_in(dir, false,
               "local b = seiche.body{mesh = 'assets/cube.obj', scale = 0.5}\n"
               "local k = seiche.body{mesh = 'assets/cube.obj', kind = 'kinematic'}\n"
               "seiche.check(b:shape() == 'hull' and k:shape() == 'mesh', 'shapes')\n"
               "seiche.fill{mesh = 'assets/cube.obj', velocity = {0, -1, 0}}\n", &s) != ENG_SCRIPT_OK)
        fail_msg("%s", eng_script_error(s));
    assert_int_equal(eng_script_pending(s), 3);
    eng_script_destroy(s);
    // --trusted: any file, '..' and links included.
    if (run_in(dir, true, "seiche.body{mesh = 'assets/link.obj'}\nseiche.fill{mesh = '../' .. "
               "(debug.getinfo(1, 'S').source:match('([^/]*)/scene.lua$')) .. '_outside.obj'}\n", &s) != ENG_SCRIPT_OK)
        fail_msg("%s", eng_script_error(s));
    eng_script_destroy(s);
    remove_scene_folder(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(joint_input_is_checked_naming_the_field),
        cmocka_unit_test(joint_methods_are_checked),
        cmocka_unit_test(joint_records_what_it_was_given),
        cmocka_unit_test(event_thresholds_are_checked_and_kept),
        cmocka_unit_test(grab_release_takes_a_boolean),
        cmocka_unit_test(mesh_files_are_found_in_the_scene_folder_only),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
