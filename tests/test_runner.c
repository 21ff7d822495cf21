// The runner's contract (docs/runner.md): exit statuses and one-line messages for good and
// bad command lines, and the files it writes. Each test runs build/bin/seiche as a child
// process (headless, a tiny scene) and reads its exit status, stdout and stderr. The test
// that emulates a machine without GL 4.3 needs Mesa, the video test ffmpeg on the PATH:
// without them they are skipped, saying why.
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tests/support.h"

#include <stb/stb_image.h>

typedef struct run_result {
    int status;      // exit status, or 128 + signal
    char out[8192];  // stdout
    char err[8192];  // stderr
} run_result;

static void slurp(const char *path, char *buf, size_t size)
{
    buf[0] = 0;
    FILE *f = fopen(path, "rb");
    if (!f) return;
    size_t n = fread(buf, 1, size - 1, f);
    buf[n] = 0;
    fclose(f);
}

// Runs the runner with argv (NULL-terminated, without the program) and the environment
// changed by `envs` (NULL, or NULL-terminated: "NAME=VALUE" sets, "-NAME" unsets); kills
// it after 120 s.
static void run_env(run_result *r, const char *const *envs, const char *const *args)
{
    char exe[1024], dir[1024];
    support_bin_path("seiche", exe, sizeof exe);
    support_source_dir(dir, sizeof dir);
    const char *out_path = "/tmp/seiche_test_runner.out", *err_path = "/tmp/seiche_test_runner.err";
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        if (chdir(dir) != 0) _exit(120);
        int o = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        int e = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(o, 1);
        dup2(e, 2);
        for (const char *const *e = envs; e && *e; e++) {
            const char *env = *e, *eq = strchr(env, '=');
            char name[128];
            if (env[0] == '-') {
                unsetenv(env + 1);
                continue;
            }
            snprintf(name, sizeof name, "%.*s", (int)(eq - env), env);
            setenv(name, eq + 1, 1);
        }
        const char *argv[32];
        int n = 0;
        argv[n++] = exe;
        for (const char *const *a = args; *a && n < 31; a++) argv[n++] = *a;
        argv[n] = NULL;
        alarm(120);
        execv(exe, (char *const *)argv);
        _exit(121);
    }
    int st = 0;
    waitpid(pid, &st, 0);
    r->status = WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
    slurp(out_path, r->out, sizeof r->out);
    slurp(err_path, r->err, sizeof r->err);
    if (getenv("SEICHE_TEST_VERBOSE")) print_message("exit %d\nstdout: %s\nstderr: %s\n", r->status, r->out, r->err);
}

// Runs the runner with argv and one extra "NAME=VALUE" in its environment (or NULL).
static void run(run_result *r, const char *env, const char *const *args)
{
    const char *envs[2] = { env, NULL };
    run_env(r, envs, args);
}

// How often `needle` occurs in `s`.
static int occurrences(const char *s, const char *needle)
{
    int n = 0;
    for (const char *p = s; (p = strstr(p, needle)) != NULL; p += strlen(needle)) n++;
    return n;
}

static int lines(const char *s)
{
    int n = 0;
    for (; *s; s++) n += *s == '\n';
    return n;
}

#define SCENE "tests/scripts/check_fails.lua"
#define GOOD "tests/fixtures/tiny_scene.lua"

static void good_run_exits_0_and_prints_a_summary(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "5", GOOD, NULL });
    assert_int_equal(r.status, 0);
    assert_non_null(strstr(r.out, "5 frames"));
    assert_non_null(strstr(r.out, "particles"));
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

// A script that pauses headless (seiche.inject_key("space")) could never resume: the run
// once spun through its remaining --frames at once, ended at frame 3 and failed a later
// check as "never ran". The pause is ignored with one warning, and --frames counts steps.
static void headless_pause_is_ignored_with_one_warning_and_frames_count_steps(void **state)
{
    (void)state;
    const char *lua = "/tmp/seiche_test_runner_pause.lua";
    write_file(lua, "seiche.scene { name = 'pause', capacity = 10 }\n"
                    "local keys = 0\n"
                    "function on_key(k, action) if k == 'space' then keys = keys + 1 end end\n"
                    "function on_step()\n"
                    "  local f = seiche.frame()\n"
                    "  if f == 2 or f == 4 then seiche.inject_key('space') end\n"
                    "  if f == 8 then seiche.check(keys == 2, 'both presses reached on_key') end\n"
                    "end\n");
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "10", lua, NULL });
    assert_int_equal(r.status, 0);
    assert_non_null(strstr(r.out, "seiche: pause: 10 frames,"));
    assert_int_equal(occurrences(r.err, "warning: a pause (the space key, from seiche.inject_key) is ignored headless"),
                     1);
    // One frame is a frame, not "1 frames".
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "1", GOOD, NULL });
    assert_int_equal(r.status, 0);
    assert_non_null(strstr(r.out, "tiny: 1 frame,"));
}

// In a window --frames counts steps too: a paused frame does not count, so a paused window
// waits for the user instead of quitting behind their back. The script pauses at frame 2
// and resumes on the next frame (its on_key presses space again): 10 steps take 11 frames
// and the summary says 10 (counting frames drawn, it ended at 9).
static void window_frames_count_steps_not_paused_frames(void **state)
{
    (void)state;
    const char *d = getenv("DISPLAY");
    bool display = d && d[0];
    if (!display) support_skip_unless_on_path("xvfb-run");
    const char *lua = "/tmp/seiche_test_runner_window_pause.lua";
    write_file(lua, "seiche.scene { name = 'wpause', capacity = 10 }\n"
                    "local presses = 0\n"
                    "function on_key(k, action)\n"
                    "  if k == 'space' and action == 'press' then\n"
                    "    presses = presses + 1\n"
                    "    if presses == 1 then seiche.inject_key('space') end\n"
                    "  end\n"
                    "end\n"
                    "function on_step() if seiche.frame() == 2 then seiche.inject_key('space') end end\n");
    char exe[1024], cmd[4096];
    support_bin_path("seiche", exe, sizeof exe);
    const char *out = "/tmp/seiche_test_runner_window.out";
    snprintf(cmd, sizeof cmd, "%s'%s' --no-watch --no-ui --size 64x64 --frames 10 '%s' >%s 2>&1",
             display ? "" : "xvfb-run -a -s '-screen 0 640x480x24' ", exe, lua, out);
    int st = system(cmd);
    char text[8192];
    slurp(out, text, sizeof text);
    if (!WIFEXITED(st) || WEXITSTATUS(st) != 0) fail_msg("the window run failed (%d): %s", st, text);
    assert_non_null(strstr(text, "seiche: wpause: 10 frames,"));
    assert_null(strstr(text, "warning: a pause"));
}

static void unknown_option_is_a_usage_error(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headles", GOOD, NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "unknown option '--headles'"));
}

static void option_without_its_value_is_a_usage_error(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ GOOD, "--frames", NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "--frames needs a value"));
    // --junit and --tap too: given last they were once taken as "no report" (fuzz_cli).
    run(&r, NULL, (const char *const[]){ GOOD, "--tap", NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "--tap needs a value"));
    run(&r, NULL, (const char *const[]){ GOOD, "--junit", NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "--junit needs a value"));
}

static void negative_frames_are_refused(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "-1", GOOD, NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "--frames"));
    assert_non_null(strstr(r.err, "-1"));
}

static void bad_dt_is_refused(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--dt", "0", GOOD, NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "--dt"));
}

static void missing_script_is_named(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "no/such/scene.lua", NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "no/such/scene.lua"));
    assert_true(lines(r.err) <= 2);
}

static void no_script_is_a_usage_error(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "no script"));
}

// One message, naming the option and the path as given (once it was printed twice, the
// second time as "no-such-shaders/render/mesh.vert", without --shaders or the leading '/').
static void missing_shader_directory_is_one_message_naming_the_option_and_path(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "2", "--shaders", "/tmp/no-such-shaders", GOOD, NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "seiche: --shaders: cannot read the shader directory '/tmp/no-such-shaders': "
                                  "No such file or directory"));
    assert_int_equal(occurrences(r.err, "no-such-shaders"), 1);
    // From the environment, the message names the variable.
    run(&r, "SEICHE_SHADER_DIR=/tmp/no-such-shaders", (const char *const[]){ "--headless", "--frames", "2", GOOD, NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "SEICHE_SHADER_DIR: cannot read the shader directory '/tmp/no-such-shaders'"));
}

// A directory without the shaders: the renderer's error once (it was logged and printed),
// naming the option and the directory.
static void shader_missing_from_the_directory_is_one_message_naming_the_option(void **state)
{
    (void)state;
    const char *dir = "/tmp/seiche_test_runner_empty_shaders";
    mkdir(dir, 0755);
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "2", "--shaders", dir, GOOD, NULL });
    rmdir(dir);
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "seiche: --shaders '/tmp/seiche_test_runner_empty_shaders': "));
    assert_int_equal(occurrences(r.err, "cannot open shader file"), 1);
}

static void scalar_option_given_twice_is_refused_naming_it(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "3", "--frames", "5", GOOD, NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "--frames may be given once (got '3' and '5')"));
    run(&r, NULL, (const char *const[]){ "--headless", "--size", "160x120", "--render", "speed", "--size", "64x64", GOOD,
                                        NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "--size may be given once (got '160x120' and '64x64')"));
}

// strtol and strtod skip leading space and take '+' and hexadecimal: a number on the
// command line is digits as typed, nothing around them.
static void numbers_with_space_sign_or_hex_are_refused(void **state)
{
    (void)state;
    const char *cases[][3] = { { "--frames", " 5", "--frames must be a whole number in [0, 100000000] (got ' 5')" },
                               { "--frames", "5 ", "(got '5 ')" },
                               { "--frames", "+5", "(got '+5')" },
                               { "--dt", "\t0.01", "--dt must be a number of seconds" },
                               { "--dt", "0x1p-7", "(got '0x1p-7')" },
                               { "--budget", " 2", "--budget must be" },
                               { "--size", " 16x16", "--size must be WxH" },
                               { "--size", "16x 16", "--size must be WxH" },
                               { "--set", "fluid.iterations= 4", "value must be a finite number (got ' 4')" } };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        run_result r;
        run(&r, NULL, (const char *const[]){ "--headless", cases[i][0], cases[i][1], GOOD, NULL });
        if (r.status != 2 || !strstr(r.err, cases[i][2]))
            fail_msg("%s '%s': exit %d, stderr %s", cases[i][0], cases[i][1], r.status, r.err);
    }
}

// A value too small for a double is still a number (strtod rounds it to zero or a
// subnormal and reports ERANGE); one too large for it is not.
static void underflowing_number_is_taken_and_overflowing_refused(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "1", "--set", "gravity.y=-1e-400", GOOD, NULL });
    if (r.status != 0) fail_msg("gravity.y=-1e-400: exit %d, stderr %s", r.status, r.err);
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "1", "--set", "gravity.y=-1e400", GOOD, NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "--set gravity.y: value must be a finite number (got '-1e400')"));
}

static void unknown_set_key_lists_the_known_ones(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--set", "fluid.iteratoins=4", GOOD, NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "iteratoins"));
    assert_non_null(strstr(r.err, "iterations"));
    run(&r, NULL, (const char *const[]){ "--headless", "--set", "fluid.iterations=0", GOOD, NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "iterations must be in [1, 100] (got 0)"));
}

static void failed_check_exits_1_with_file_and_line(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "3", SCENE, NULL });
    assert_int_equal(r.status, 1);
    assert_non_null(strstr(r.err, "check_fails.lua:"));
    assert_non_null(strstr(r.err, "check failed"));
}

static void no_compute_context_exits_3(void **state)
{
    (void)state;
    support_skip_unless_mesa("emulating a GL 3.3 machine");
    run_result r;
    run(&r, "MESA_GL_VERSION_OVERRIDE=3.3", (const char *const[]){ "--headless", "--frames", "2", GOOD, NULL });
    if (r.status == 0) {
        print_message("SKIPPED: MESA_GL_VERSION_OVERRIDE=3.3 had no effect on this GL: %s", r.out);
        skip();
    }
    assert_int_equal(r.status, 3);
    assert_non_null(strstr(r.err, "4.3"));
}

// No display for a window is a machine without the GL context the run needs: status 3,
// as with no GL, with a message that says to use --headless (it was status 2, a usage
// error, which docs/runner.md keeps for bad command lines).
static void no_display_without_headless_exits_3_suggesting_headless(void **state)
{
    (void)state;
    run_result r;
    run_env(&r, (const char *const[]){ "-DISPLAY", "-WAYLAND_DISPLAY", NULL },
            (const char *const[]){ "--frames", "2", GOOD, NULL });
    assert_int_equal(r.status, 3);
    assert_non_null(strstr(r.err, "no display"));
    assert_non_null(strstr(r.err, "--headless"));
    assert_int_equal(lines(r.err), 1);
}

static void hash_is_printed_and_repeats(void **state)
{
    (void)state;
    run_result a, b;
    run(&a, NULL, (const char *const[]){ "--headless", "--frames", "8", "--hash", GOOD, NULL });
    run(&b, NULL, (const char *const[]){ "--headless", "--frames", "8", "--hash", GOOD, NULL });
    assert_int_equal(a.status, 0);
    const char *ha = strstr(a.out, "state hash: "), *hb = strstr(b.out, "state hash: ");
    assert_non_null(ha);
    assert_non_null(hb);
    assert_memory_equal(ha, hb, 12 + 16);
}

static void metrics_and_screenshot_are_written(void **state)
{
    (void)state;
    const char *csv = "/tmp/seiche_test_runner.csv", *png = "/tmp/seiche_test_runner.png";
    unlink(csv);
    unlink(png);
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "6", "--size", "160x120", "--metrics", csv,
                                        "--screenshot", png, GOOD, NULL });
    assert_int_equal(r.status, 0);
    char text[16384];
    slurp(csv, text, sizeof text);
    const char *need[] = { "frame", "time", "particles", "rho0", "rho_max", "rho_avg", "step_ms", "predict_ms",
                           "density_ms", "delta_ms", "metrics_ms", "overflow", "rho_err_avg" };
    for (size_t i = 0; i < sizeof need / sizeof need[0]; i++) assert_non_null(strstr(text, need[i]));
    assert_int_equal(lines(text), 1 + 6); // header and one row per frame
    unsigned char sig[8] = { 0 };
    FILE *f = fopen(png, "rb");
    assert_non_null(f);
    assert_int_equal(fread(sig, 1, 8, f), 8);
    fclose(f);
    assert_memory_equal(sig, "\x89PNG\r\n\x1a\n", 8);
}

// .jpg and .jpeg write a JPEG (once any name got a PNG); another extension is refused
// before the run, naming the option, the value and what is allowed, and nothing is written.
static void screenshot_format_follows_the_name_and_others_are_refused(void **state)
{
    (void)state;
    const char *jpg = "/tmp/seiche_test_runner.jpg", *bmp = "/tmp/seiche_test_runner.bmp";
    unlink(jpg);
    unlink(bmp);
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "2", "--size", "160x120", "--screenshot", jpg, GOOD,
                                        NULL });
    assert_int_equal(r.status, 0);
    unsigned char head[3] = { 0 };
    FILE *f = fopen(jpg, "rb");
    assert_non_null(f);
    assert_int_equal(fread(head, 1, 3, f), 3);
    fclose(f);
    assert_memory_equal(head, "\xff\xd8\xff", 3); // a JPEG's SOI marker
    int w = 0, h = 0, n = 0;
    unsigned char *img = stbi_load(jpg, &w, &h, &n, 3);
    assert_non_null(img);
    stbi_image_free(img);
    assert_int_equal(w, 160);
    assert_int_equal(h, 120);
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "2", "--screenshot", bmp, GOOD, NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "--screenshot must name a file ending in .png, .jpg or .jpeg "
                                  "(got '/tmp/seiche_test_runner.bmp')"));
    assert_int_not_equal(access(bmp, F_OK), 0);
}

static void render_option_picks_the_water_look_and_names_the_modes(void **state)
{
    (void)state;
    const char *png[2] = { "/tmp/seiche_test_runner_surface.png", "/tmp/seiche_test_runner_density.png" };
    const char *mode[2] = { "surface", "density" };
    static char img[2][65536];
    for (int i = 0; i < 2; i++) {
        unlink(png[i]);
        run_result r;
        run(&r, NULL, (const char *const[]){ "--headless", "--frames", "3", "--size", "160x120", "--render", mode[i],
                                            "--screenshot", png[i], GOOD, NULL });
        assert_int_equal(r.status, 0);
        slurp(png[i], img[i], sizeof img[i]);
        assert_true(strlen(img[i]) > 4);
    }
    assert_true(memcmp(img[0], img[1], sizeof img[0]) != 0); // the two looks differ
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--render", "foam", GOOD, NULL });
    assert_int_equal(r.status, 2);
    assert_non_null(strstr(r.err, "--render must be one of surface|spheres|density|speed (got 'foam')"));
}

// The main chunk runs before the worlds exist, yet reads what the command line chose.
static void main_chunk_sees_dt_and_render_options(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "1", "--dt", "0.01", "--render", "speed",
                                        "tests/fixtures/main_chunk_sees_options.lua", NULL });
    assert_int_equal(r.status, 0);
    assert_non_null(strstr(r.out, "main chunk: dt 0.01, render speed"));
}

// --set is what the world is built with, and what the main chunk reads back.
static void main_chunk_sees_set_options(void **state)
{
    (void)state;
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "1", "--set", "fluid.viscosity=0.05",
                                        "--set", "fluid.particle_radius=0.01", "--set", "fluid.kernel_radius=0.04",
                                        "--set", "gravity.y=-3", "--set", "capacity=250",
                                        "--set", "coupling.force_latency=3", "--set", "coupling.force_smoothing=0.5",
                                        "tests/fixtures/main_chunk_sees_options.lua", NULL });
    assert_int_equal(r.status, 0);
    assert_non_null(strstr(r.out, "main chunk: viscosity 0.05, particle_radius 0.01, kernel_radius 0.04, gravity.y -3, "
                                  "capacity 250"));
    assert_non_null(strstr(r.out, "main chunk: vorticity 0.25, viscosity 0.05"));
    assert_non_null(strstr(r.out, "on_start: viscosity 0.05, particle_radius 0.01, gravity.y -3, capacity 250, "
                                  "vorticity 0.25"));
    assert_non_null(strstr(r.out, "main chunk: coupling latency 3, smoothing 0.5, impulse 2"));
    assert_non_null(strstr(r.out, "on_start: coupling latency 3, smoothing 0.5, impulse 2"));
}

// seiche.text shows in a headless screenshot: the script's red HUD text over a dark sky
// puts red pixels in the band it is drawn in, and none below it.
static void hud_text_is_in_a_headless_screenshot(void **state)
{
    (void)state;
    const char *png = "/tmp/seiche_test_runner_hud.png";
    unlink(png);
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "3", "--size", "320x200", "--screenshot", png,
                                        "tests/fixtures/hud_text.lua", NULL });
    assert_int_equal(r.status, 0);
    int w = 0, h = 0, n = 0;
    unsigned char *img = stbi_load(png, &w, &h, &n, 3);
    assert_non_null(img);
    assert_int_equal(w, 320);
    int in_band = 0, below = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const unsigned char *p = img + 3 * ((size_t)y * w + x);
            bool red = p[0] > 180 && p[1] < 60 && p[2] < 60;
            if (red && y >= 15 && y < 90) in_band++;
            else if (red) below++;
        }
    stbi_image_free(img);
    assert_true(in_band > 300); // "SCORE 42" at 64 px: the strokes fill about a tenth of the band
    assert_int_equal(below, 0);
}

static void record_writes_a_video(void **state)
{
    (void)state;
    support_skip_unless_on_path("ffmpeg");
    const char *mp4 = "/tmp/seiche_test_runner.mp4";
    unlink(mp4);
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "5", "--size", "160x120", "--record", mp4, GOOD, NULL });
    assert_int_equal(r.status, 0);
    unsigned char head[12] = { 0 };
    FILE *f = fopen(mp4, "rb");
    assert_non_null(f);
    assert_int_equal(fread(head, 1, sizeof head, f), sizeof head);
    fclose(f);
    assert_memory_equal(head + 4, "ftyp", 4); // an MP4 (ISO base media) file
}

// --dt 0.03 is 100/3 frames per second, not 33: ten frames last 0.3 s.
static void record_frame_rate_is_exactly_one_over_dt(void **state)
{
    (void)state;
    support_skip_unless_on_path("ffmpeg");
    support_skip_unless_on_path("ffprobe");
    const char *mp4 = "/tmp/seiche_test_runner_rate.mp4";
    unlink(mp4);
    run_result r;
    run(&r, NULL, (const char *const[]){ "--headless", "--frames", "10", "--dt", "0.03", "--size", "160x120", "--record",
                                        mp4, GOOD, NULL });
    assert_int_equal(r.status, 0);
    char cmd[512], out[256] = "";
    snprintf(cmd, sizeof cmd, "ffprobe -v error -select_streams v -show_entries stream=r_frame_rate,nb_frames "
                              "-show_entries format=duration -of csv=p=0 '%s'", mp4);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = 0;
    pclose(p);
    print_message("ffprobe: %s", out);
    assert_non_null(strstr(out, "100/3,10"));
    assert_non_null(strstr(out, "0.300000"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(good_run_exits_0_and_prints_a_summary),
        cmocka_unit_test(headless_pause_is_ignored_with_one_warning_and_frames_count_steps),
        cmocka_unit_test(window_frames_count_steps_not_paused_frames),
        cmocka_unit_test(unknown_option_is_a_usage_error),
        cmocka_unit_test(option_without_its_value_is_a_usage_error),
        cmocka_unit_test(negative_frames_are_refused),
        cmocka_unit_test(bad_dt_is_refused),
        cmocka_unit_test(missing_script_is_named),
        cmocka_unit_test(no_script_is_a_usage_error),
        cmocka_unit_test(missing_shader_directory_is_one_message_naming_the_option_and_path),
        cmocka_unit_test(shader_missing_from_the_directory_is_one_message_naming_the_option),
        cmocka_unit_test(scalar_option_given_twice_is_refused_naming_it),
        cmocka_unit_test(numbers_with_space_sign_or_hex_are_refused),
        cmocka_unit_test(underflowing_number_is_taken_and_overflowing_refused),
        cmocka_unit_test(unknown_set_key_lists_the_known_ones),
        cmocka_unit_test(failed_check_exits_1_with_file_and_line),
        cmocka_unit_test(no_compute_context_exits_3),
        cmocka_unit_test(no_display_without_headless_exits_3_suggesting_headless),
        cmocka_unit_test(hash_is_printed_and_repeats),
        cmocka_unit_test(metrics_and_screenshot_are_written),
        cmocka_unit_test(screenshot_format_follows_the_name_and_others_are_refused),
        cmocka_unit_test(render_option_picks_the_water_look_and_names_the_modes),
        cmocka_unit_test(main_chunk_sees_dt_and_render_options),
        cmocka_unit_test(main_chunk_sees_set_options),
        cmocka_unit_test(hud_text_is_in_a_headless_screenshot),
        cmocka_unit_test(record_writes_a_video),
        cmocka_unit_test(record_frame_rate_is_exactly_one_over_dt),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
