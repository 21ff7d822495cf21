// The runner against hostile and careless command lines (docs/runner.md): no shell between
// it and ffmpeg, outputs that fail are reported with the right status, an output never
// overwrites the script, a script of the suite or another output, numbers are range-checked,
// reports fail the scripts that fail, names with control characters stay on their lines;
// and the scene
// writer's traps: a consistent particle / kernel radius pair is accepted in any order.
#include "tests/support.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define TMP "/tmp/seiche-runner-io"

static char exe[1100], scene[1100];

static int setup(void **state)
{
    (void)state;
    support_bin_path("seiche", exe, sizeof exe);
    support_source_path("tests/fixtures/tiny_scene.lua", scene, sizeof scene);
    return system("rm -rf " TMP " && mkdir -p " TMP) == 0 ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    return system("rm -rf " TMP) == 0 ? 0 : -1;
}

// Runs the runner with `args` (already quoted for sh) from TMP, with `env` (sh's
// "NAME=VALUE ..." or "") in front; stderr into `err`.
static int run_env(const char *env, const char *args, char *err, size_t err_size)
{
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "cd " TMP " && %s '%s' --headless --quiet %s 2>" TMP "/stderr.txt >" TMP "/stdout.txt",
             env, exe, args);
    int st = system(cmd);
    err[0] = 0;
    FILE *f = fopen(TMP "/stderr.txt", "r");
    if (f) {
        size_t n = fread(err, 1, err_size - 1, f);
        err[n] = 0;
        fclose(f);
    }
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

static int run(const char *args, char *err, size_t err_size) { return run_env("", args, err, err_size); }

static void record_path_reaches_no_shell(void **state)
{
    (void)state;
    char args[2048], err[4096];
    unlink(TMP "/pwned");
    snprintf(args, sizeof args, "--frames 2 --record \"x.mp4'; touch " TMP "/pwned; echo '\" '%s'", scene);
    run(args, err, sizeof err);
    assert_int_not_equal(access(TMP "/pwned", F_OK), 0);
    snprintf(args, sizeof args, "--frames 2 --record '$(touch " TMP "/pwned).mp4' '%s'", scene);
    run(args, err, sizeof err);
    assert_int_not_equal(access(TMP "/pwned", F_OK), 0);
}

static void unwritable_outputs_exit_2_naming_the_flag(void **state)
{
    (void)state;
    char args[2048], err[4096];
    snprintf(args, sizeof args, "--frames 2 --record /nonexistent/x.mp4 '%s'", scene);
    assert_int_equal(run(args, err, sizeof err), 2);
    assert_non_null(strstr(err, "--record: cannot write '/nonexistent/x.mp4'"));
    snprintf(args, sizeof args, "--frames 2 --metrics /dev/full '%s'", scene);
    assert_int_equal(run(args, err, sizeof err), 2);
    assert_non_null(strstr(err, "--metrics: writing '/dev/full' failed"));
}

static bool file_has(const char *path, const char *needle)
{
    char buf[16384] = "";
    FILE *f = fopen(path, "r");
    if (!f) return false;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = 0;
    fclose(f);
    return strstr(buf, needle) != NULL;
}

static int occurrences(const char *s, const char *needle)
{
    int n = 0;
    for (const char *p = s; (p = strstr(p, needle)) != NULL; p += strlen(needle)) n++;
    return n;
}

// A failed screenshot is one message (it was logged and printed: two lines).
static void unwritable_screenshot_is_one_message(void **state)
{
    (void)state;
    char args[2048], err[4096];
    assert_int_equal(system("ln -sf /dev/full " TMP "/full.png"), 0);
    snprintf(args, sizeof args, "--frames 2 --size 64x64 --screenshot full.png '%s'", scene);
    assert_int_equal(run(args, err, sizeof err), 2);
    assert_non_null(strstr(err, "seiche: --screenshot: cannot write screenshot 'full.png': No space left on device"));
    assert_int_equal(occurrences(err, "full.png"), 1);
}

// A screenshot cut short (here by a file-size limit of 4 KiB, whose signal the shell ignores
// so the write fails with EFBIG) is not left behind as a broken image.
static void a_screenshot_cut_short_leaves_no_file(void **state)
{
    (void)state;
    char args[2048], err[4096];
    unlink(TMP "/cut.png");
    snprintf(args, sizeof args, "--frames 2 --size 256x256 --screenshot cut.png '%s'", scene);
    assert_int_equal(run_env("trap '' XFSZ; ulimit -f 8;", args, err, sizeof err), 2);
    assert_non_null(strstr(err, "--screenshot: cannot write screenshot 'cut.png': File too large (the incomplete file was removed)"));
    assert_int_not_equal(access(TMP "/cut.png", F_OK), 0);
    // Without the limit the same image is written whole.
    assert_int_equal(run(args, err, sizeof err), 0);
    assert_int_equal(access(TMP "/cut.png", F_OK), 0);
}

// A fake ffmpeg in TMP/NAME/ffmpeg running the shell text `body` (its last argument is
// file:PATH, the output).
static void fake_ffmpeg(const char *name, const char *body)
{
    char path[256];
    snprintf(path, sizeof path, TMP "/%s", name);
    mkdir(path, 0755);
    snprintf(path, sizeof path, TMP "/%s/ffmpeg", name);
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fprintf(f, "#!/bin/sh\nfor a; do out=${a#file:}; done\n%s\n", body);
    fclose(f);
    chmod(path, 0755);
}

// Once the size and the name were ffmpeg's to refuse, after the run had started, leaving
// a 0-byte file: now the command line is refused, nothing created, no ffmpeg needed.
static void record_refuses_odd_sizes_and_unknown_formats_before_the_run(void **state)
{
    (void)state;
    char args[2048], err[4096];
    fake_ffmpeg("never", "touch " TMP "/ffmpeg-ran; exit 1");
    snprintf(args, sizeof args, "--frames 2 --size 161x121 --record odd.mp4 '%s'", scene);
    assert_int_equal(run_env("PATH=" TMP "/never:$PATH", args, err, sizeof err), 2);
    assert_non_null(strstr(err, "--record needs an even width and height for the video encoder (got --size 161x121)"));
    assert_int_not_equal(access(TMP "/odd.mp4", F_OK), 0);
    snprintf(args, sizeof args, "--frames 2 --record vid '%s'", scene);
    assert_int_equal(run_env("PATH=" TMP "/never:$PATH", args, err, sizeof err), 2);
    assert_non_null(strstr(err, "--record must name a file ending in .mp4, .mkv, .mov, .webm or .avi"));
    assert_non_null(strstr(err, "(got 'vid')"));
    assert_int_not_equal(access(TMP "/vid", F_OK), 0);
    snprintf(args, sizeof args, "--frames 2 --record clip.gif '%s'", scene);
    assert_int_equal(run_env("PATH=" TMP "/never:$PATH", args, err, sizeof err), 2);
    assert_int_not_equal(access(TMP "/ffmpeg-ran", F_OK), 0);
}

// ffmpeg failing mid-run leaves no file pretending to be a video, and the message says
// so: whether it stopped reading (the frame write fails) or read everything and failed.
static void record_failure_removes_the_incomplete_file(void **state)
{
    (void)state;
    char args[2048], err[4096];
    fake_ffmpeg("quits", "printf partial >\"$out\"; echo 'fake ffmpeg: gave up' >&2; exit 1");
    fake_ffmpeg("fails", "cat >\"$out\"; exit 1");
    snprintf(args, sizeof args, "--frames 4 --size 160x120 --record a.mp4 '%s'", scene);
    assert_int_equal(run_env("PATH=" TMP "/quits:$PATH", args, err, sizeof err), 2);
    assert_non_null(strstr(err, "--record: ffmpeg stopped taking frames"));
    assert_non_null(strstr(err, "'a.mp4' (ffmpeg: exit status 1); removed the incomplete file"));
    assert_int_not_equal(access(TMP "/a.mp4", F_OK), 0);
    snprintf(args, sizeof args, "--frames 4 --size 160x120 --record b.mkv '%s'", scene);
    assert_int_equal(run_env("PATH=" TMP "/fails:$PATH", args, err, sizeof err), 2);
    assert_non_null(strstr(err, "--record: ffmpeg failed writing 'b.mkv' (ffmpeg: exit status 1); removed the incomplete"));
    assert_int_not_equal(access(TMP "/b.mkv", F_OK), 0);
    // A file that was there and that ffmpeg never touched stays.
    fake_ffmpeg("refuses", "exit 1");
    assert_int_equal(system("printf old >" TMP "/c.mp4 && touch -d 2020-01-01 " TMP "/c.mp4"), 0);
    snprintf(args, sizeof args, "--frames 4 --size 160x120 --record c.mp4 '%s'", scene);
    assert_int_equal(run_env("PATH=" TMP "/refuses:$PATH", args, err, sizeof err), 2);
    assert_non_null(strstr(err, "the file that was there is left as it was"));
    struct stat st;
    assert_int_equal(stat(TMP "/c.mp4", &st), 0);
    assert_int_equal(st.st_size, 3);
}

// ffmpeg gets 1/dt as an exact fraction (it was rounded: --dt 0.03 gave 33 fps).
static void record_gives_ffmpeg_the_exact_frame_rate(void **state)
{
    (void)state;
    char args[2048], err[4096];
    fake_ffmpeg("args", "echo \"$@\" >" TMP "/ffmpeg-args.txt; cat >\"$out\"");
    const char *dt[][2] = { { "0.03", "-r 100/3 " }, { "0.016", "-r 125/2 " }, { "0.00001", "-r 100000/1 " },
                            { "0.75", "-r 4/3 " } };
    for (size_t i = 0; i < sizeof dt / sizeof dt[0]; i++) {
        snprintf(args, sizeof args, "--frames 2 --size 64x64 --dt %s --record r.mp4 '%s'", dt[i][0], scene);
        assert_int_equal(run_env("PATH=" TMP "/args:$PATH", args, err, sizeof err), 0);
        assert_true(file_has(TMP "/ffmpeg-args.txt", dt[i][1]));
    }
    snprintf(args, sizeof args, "--frames 2 --size 64x64 --record r.mp4 '%s'", scene); // 1/60 s
    assert_int_equal(run_env("PATH=" TMP "/args:$PATH", args, err, sizeof err), 0);
    assert_true(file_has(TMP "/ffmpeg-args.txt", "-r 60/1 "));
}

// `--` ends the options, as in POSIX tools: the next argument is the script, even one
// whose name starts with '-'; without it such a name is an unknown option.
static void double_dash_ends_the_options(void **state)
{
    (void)state;
    char copy[1400], err[4096];
    snprintf(copy, sizeof copy, "cp '%s' " TMP "/-scene.lua", scene);
    assert_int_equal(system(copy), 0);
    assert_int_equal(run("--frames 1 -- -scene.lua", err, sizeof err), 0);
    assert_int_equal(run("--frames 1 -scene.lua", err, sizeof err), 2);
    assert_non_null(strstr(err, "unknown option '-scene.lua'"));
    assert_int_equal(run("--frames 1 --", err, sizeof err), 2);
    assert_non_null(strstr(err, "'--' must be followed by the script"));
    assert_int_equal(run("--frames 1 -- -scene.lua --quiet", err, sizeof err), 2);
    assert_non_null(strstr(err, "only one script may be given (got '-scene.lua' and '--quiet')"));
}

// More --set than the runner holds: the message says how many were given.
static void too_many_sets_say_how_many(void **state)
{
    (void)state;
    char args[4096], err[4096];
    size_t n = 0;
    for (int i = 0; i < 70; i++) n += (size_t)snprintf(args + n, sizeof args - n, "--set gravity.y=-9 ");
    snprintf(args + n, sizeof args - n, "'%s'", scene);
    assert_int_equal(run(args, err, sizeof err), 2);
    assert_non_null(strstr(err, "at most 64 --set options may be given (got 70)"));
}

static void output_over_the_script_or_another_output_is_refused(void **state)
{
    (void)state;
    char err[4096];
    char copy[1400];
    snprintf(copy, sizeof copy, "cp '%s' " TMP "/scene.lua", scene);
    assert_int_equal(system(copy), 0);
    assert_int_equal(run("--frames 2 --metrics scene.lua scene.lua", err, sizeof err), 2);
    assert_non_null(strstr(err, "--metrics would overwrite the script"));
    struct stat st;
    assert_int_equal(stat(TMP "/scene.lua", &st), 0);
    assert_true(st.st_size > 100); // untouched
    assert_int_equal(run("--frames 2 --metrics out.png --screenshot out.png scene.lua", err, sizeof err), 2);
    assert_non_null(strstr(err, "--screenshot would overwrite --metrics"));
}

static void numbers_out_of_range_name_the_flag_and_value(void **state)
{
    (void)state;
    char args[2048], err[4096];
    snprintf(args, sizeof args, "--size 4294967312x16 '%s'", scene);
    assert_int_equal(run(args, err, sizeof err), 2);
    assert_non_null(strstr(err, "--size must be WxH"));
    assert_non_null(strstr(err, "4294967312x16"));
    snprintf(args, sizeof args, "--dt 1e-300 '%s'", scene);
    assert_int_equal(run(args, err, sizeof err), 2);
    assert_non_null(strstr(err, "--dt must be"));
    assert_non_null(strstr(err, "1e-300"));
}

static void radius_pair_is_accepted_in_either_order_and_the_kernel_follows(void **state)
{
    (void)state;
    char args[2048], err[4096];
    // A script that prints the kernel radius it got.
    FILE *f = fopen(TMP "/radius.lua", "w");
    assert_non_null(f);
    fprintf(f, "seiche.scene { name = 'r', capacity = 200000, container = { min = {0,0,0}, max = {0.4,0.4,0.4} } }\n"
               "seiche.block { min = {0,0,0}, max = {0.1,0.1,0.1} }\n"
               "function on_step() if seiche.frame() == 1 then print(string.format('kernel %%.4f', "
               "seiche.param('kernel_radius'))) end end\n");
    fclose(f);
    // The defaults are r 0.0125, h 0.05: a pair far from both, in both orders.
    assert_int_equal(run("--frames 1 --set fluid.particle_radius=0.004 --set fluid.kernel_radius=0.016 radius.lua", err,
                         sizeof err), 0);
    assert_int_equal(run("--frames 1 --set fluid.kernel_radius=0.016 --set fluid.particle_radius=0.004 radius.lua", err,
                         sizeof err), 0);
    // The radius alone: the kernel follows (4 r).
    assert_int_equal(run("--frames 1 --set fluid.particle_radius=0.004 radius.lua", err, sizeof err), 0);
    char out[256] = "";
    f = fopen(TMP "/stdout.txt", "r");
    assert_non_null(f);
    size_t n = fread(out, 1, sizeof out - 1, f);
    out[n] = 0;
    fclose(f);
    assert_non_null(strstr(out, "kernel 0.0160"));
    // An inconsistent pair names the field and value that break it.
    snprintf(args, sizeof args, "--frames 1 --set fluid.particle_radius=0.004 --set fluid.kernel_radius=0.5 radius.lua");
    assert_int_equal(run(args, err, sizeof err), 2);
    assert_non_null(strstr(err, "kernel_radius"));
    assert_non_null(strstr(err, "0.5"));
}


static void directory_runs_as_one_suite_with_junit_and_tap_and_late_checks_fail(void **state)
{
    (void)state;
    char err[4096];
    assert_int_equal(system("mkdir -p " TMP "/suite"), 0);
    FILE *f = fopen(TMP "/suite/a_passes.lua", "w");
    assert_non_null(f);
    fprintf(f, "seiche.scene { capacity = 10 }\nfunction on_step() if seiche.frame() == 2 then "
               "seiche.check(1 + 1 == 2, 'sums') end end\n");
    fclose(f);
    f = fopen(TMP "/suite/b_late.lua", "w");
    assert_non_null(f);
    fprintf(f, "seiche.scene { capacity = 10 }\nfunction on_step()\n  if seiche.frame() == 500 then\n"
               "    seiche.check(true, 'after the last frame')\n  end\nend\n");
    fclose(f);
    assert_int_equal(run("--frames 5 --junit out.xml --tap out.tap suite", err, sizeof err), 1);
    assert_non_null(strstr(err, "b_late.lua:4: seiche.check never ran"));
    assert_true(file_has(TMP "/stdout.txt", "1 passed, 1 failed"));
    assert_true(file_has(TMP "/out.xml", "<testsuites name=\"seiche\" tests=\"4\" failures=\"2\""));
    assert_true(file_has(TMP "/out.xml", "a_passes.lua:2: seiche.check (1 passed, 0 failed)"));
    assert_true(file_has(TMP "/out.xml", "never ran"));
    assert_true(file_has(TMP "/out.tap", "1..4"));
    assert_true(file_has(TMP "/out.tap", "not ok 3 - suite/b_late.lua:4: seiche.check never ran"));
    // One script alone with the same late check: status 1 too, not a silent pass.
    assert_int_equal(run("--frames 5 suite/b_late.lua", err, sizeof err), 1);
    // A report file may not overwrite the script.
    assert_int_equal(run("--frames 5 --junit suite/a_passes.lua suite/a_passes.lua", err, sizeof err), 2);
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static void slurp(const char *path, char *buf, size_t size)
{
    buf[0] = 0;
    FILE *f = fopen(path, "r");
    if (!f) return;
    size_t n = fread(buf, 1, size - 1, f);
    buf[n] = 0;
    fclose(f);
}

// A directory suite: one passing script, one whose solver diverges, one with a failing check.
static void write_mixed_suite(void)
{
    assert_int_equal(system("rm -rf " TMP "/mixed && mkdir -p " TMP "/mixed"), 0);
    write_file(TMP "/mixed/a_ok.lua", "seiche.scene { capacity = 10 }\n"
                                      "function on_step() if seiche.frame() == 1 then print('a speaks') end end\n");
    // One substep of 1/60 s at 2.5 mm: rho_max passes 3 rho0 within a few steps
    // (tests/scripts/diverged_solver_exits_4.lua).
    write_file(TMP "/mixed/b_diverges.lua",
               "seiche.scene { fluid = { particle_radius = 0.0025, substeps = 1, cfl = 0 }, capacity = 20000,\n"
               "  container = { min = { 0, 0, 0 }, max = { 0.3, 0.3, 0.3 } } }\n"
               "seiche.block { min = { 0, 0, 0 }, max = { 0.1, 0.15, 0.1 } }\n");
    write_file(TMP "/mixed/c_fails.lua", "seiche.scene { capacity = 10 }\n"
                                         "function on_step() if seiche.frame() == 1 then seiche.check(false, 'broken') end end\n");
}

// Piped into one log, a suite's lines come out in the order they were written: stdout was
// block-buffered when piped, so every "ok" / "FAILED" line came after all the messages on
// stderr. And the runner's own messages name the script they belong to.
static void directory_suite_log_is_in_order_and_names_the_script(void **state)
{
    (void)state;
    write_mixed_suite();
    char cmd[4096], log[16384];
    snprintf(cmd, sizeof cmd, "cd " TMP " && '%s' --headless --frames 30 mixed 2>&1 | cat >" TMP "/log.txt", exe);
    assert_int_equal(system(cmd), 0);
    slurp(TMP "/log.txt", log, sizeof log);
    const char *order[] = {
        "a speaks\n",
        "ok      mixed/a_ok.lua (exit 0)\n",
        "seiche: mixed/b_diverges.lua: the solver diverged at step ",
        "FAILED  mixed/b_diverges.lua (exit 4)\n",
        "mixed/c_fails.lua:2: check failed: broken\n",
        "FAILED  mixed/c_fails.lua (exit 1)\n",
        "1 passed, 2 failed\n",
    };
    const char *at = log;
    for (size_t i = 0; i < sizeof order / sizeof order[0]; i++) {
        const char *next = strstr(at, order[i]);
        if (!next) fail_msg("'%s' is missing, or out of order, in the log:\n%s", order[i], log);
        at = next + strlen(order[i]);
    }
}

// The reports give the message that ended a run once, without the program's "seiche: "
// (it read "the solver diverged: seiche: the solver diverged at ..."), and count one frame
// as "1 frame".
static void reports_give_the_message_once_and_count_frames_in_words(void **state)
{
    (void)state;
    char err[4096], xml[16384], tap[16384];
    write_mixed_suite();
    write_file(TMP "/mixed/d_one_frame.lua", "seiche.scene { capacity = 10 }\n"
                                             "function on_step() if seiche.frame() == 1 then seiche.quit() end end\n");
    assert_int_equal(run("--frames 30 --junit mixed.xml --tap mixed.tap mixed", err, sizeof err), 4);
    slurp(TMP "/mixed.xml", xml, sizeof xml);
    slurp(TMP "/mixed.tap", tap, sizeof tap);
    assert_non_null(strstr(tap, "  message: 'the solver diverged at step "));
    assert_null(strstr(tap, "seiche: the solver diverged"));
    assert_null(strstr(xml, "seiche: the solver diverged"));
    assert_int_equal(occurrences(xml, "the solver diverged"), 1);
    assert_int_equal(occurrences(xml, "check failed: broken"), 1);
    assert_non_null(strstr(xml, "name=\"run (1 frame, 0.017 s simulated)\""));
    assert_null(strstr(xml, "1 frames"));
}

// A script that fails while loading is a failed run in the reports, as in the exit status:
// the reports said "ok (exit 0)" for a main chunk's error, a syntax error, a binary chunk,
// a failed seiche.check in the main chunk (which had no test case of its own either), a
// directory and a dangling link, because the report's status was set only after the frame
// loop.
static void reports_fail_scripts_that_do_not_load(void **state)
{
    (void)state;
    char err[8192], xml[16384], tap[16384], out[4096];
    write_file(TMP "/rt.lua", "seiche.scene { capacity = 10 }\nerror('boom')\n");
    assert_int_equal(run("--frames 3 --tap rt.tap --junit rt.xml rt.lua", err, sizeof err), 2);
    slurp(TMP "/rt.tap", tap, sizeof tap);
    assert_non_null(strstr(tap, "1..1\nnot ok 1 - rt.lua: run (exit 2, usage or script error)\n"));
    assert_non_null(strstr(tap, "  message: 'rt.lua:2: boom'"));
    slurp(TMP "/rt.xml", xml, sizeof xml);
    assert_non_null(strstr(xml, "<testsuites name=\"seiche\" tests=\"1\" failures=\"1\""));
    assert_non_null(strstr(xml, "<failure type=\"exit 2\" message=\"rt.lua:2: boom\"/>"));

    assert_int_equal(system("rm -rf " TMP "/loads && mkdir -p " TMP "/loads/d_dir.lua"), 0);
    write_file(TMP "/loads/a_ok.lua", "seiche.scene { capacity = 10 }\n");
    write_file(TMP "/loads/b_syntax.lua", "seiche.scene { capacity = \n");
    write_file(TMP "/loads/c_check.lua", "seiche.scene { capacity = 10 }\nseiche.check(false, 'at load')\n"
                                         "function on_step() seiche.check(true, 'later') end\n");
    write_file(TMP "/loads/f_binary.lua", "\033Lua\x54\x00");
    assert_int_equal(symlink("nowhere", TMP "/loads/e_dangling.lua"), 0);
    assert_int_equal(run("--frames 3 --tap loads.tap --junit loads.xml loads", err, sizeof err), 2);
    slurp(TMP "/stdout.txt", out, sizeof out);
    assert_non_null(strstr(out, "1 passed, 5 failed\n"));
    slurp(TMP "/loads.tap", tap, sizeof tap);
    // Cases: a_ok's run; b_syntax's; c_check's two checks (one failed at load, one never ran)
    // and its run; d_dir's, e_dangling's and f_binary's runs.
    assert_non_null(strstr(tap, "1..8\n"));
    assert_int_equal(occurrences(tap, "not ok "), 7);
    assert_non_null(strstr(tap, "ok 1 - loads/a_ok.lua: run (exit 0, ok)\n"));
    assert_non_null(strstr(tap, "not ok 2 - loads/b_syntax.lua: run (exit 2, "));
    assert_non_null(strstr(tap, "not ok 3 - loads/c_check.lua:2: seiche.check (0 passed, 1 failed)\n"));
    assert_non_null(strstr(tap, "not ok 4 - loads/c_check.lua:3: seiche.check never ran"));
    assert_non_null(strstr(tap, "not ok 5 - loads/c_check.lua: run (exit 1, a check failed)\n"));
    assert_non_null(strstr(tap, "not ok 6 - loads/d_dir.lua: run (exit 2, "));
    assert_non_null(strstr(tap, "not ok 7 - loads/e_dangling.lua: run (exit 2, "));
    assert_non_null(strstr(tap, "message: 'loads/e_dangling.lua: cannot open the script file (a symbolic link"));
    assert_non_null(strstr(tap, "not ok 8 - loads/f_binary.lua: run (exit 2, "));
    slurp(TMP "/loads.xml", xml, sizeof xml);
    assert_non_null(strstr(xml, "<testsuites name=\"seiche\" tests=\"8\" failures=\"7\""));
    assert_non_null(strstr(xml, "message=\"loads/c_check.lua:2: check failed: at load"));
}

// A suite's directory given with a trailing slash names its scripts DIR/x.lua (it printed
// DIR//x.lua), and a dangling link in it says why it cannot be opened (it said only that it
// could not).
static void suite_names_read_plainly_and_a_dangling_link_says_why(void **state)
{
    (void)state;
    char err[4096], out[4096];
    assert_int_equal(system("rm -rf " TMP "/plain && mkdir -p " TMP "/plain"), 0);
    write_file(TMP "/plain/a_ok.lua", "seiche.scene { capacity = 10 }\n");
    assert_int_equal(symlink("nowhere", TMP "/plain/b_dangling.lua"), 0);
    assert_int_equal(run("--frames 1 plain//", err, sizeof err), 2);
    assert_non_null(strstr(err, "plain/b_dangling.lua: cannot open the script file (a symbolic link to 'nowhere'): "
                                "No such file or directory"));
    slurp(TMP "/stdout.txt", out, sizeof out);
    assert_non_null(strstr(out, "ok      plain/a_ok.lua (exit 0)\n"));
    assert_non_null(strstr(out, "FAILED  plain/b_dangling.lua (exit 2)\n"));
    assert_null(strstr(out, "//"));
    assert_null(strstr(err, "//"));
}

// A report of a directory suite may not overwrite one of its scripts: "--tap suite2/b.lua
// suite2/" ran the suite and replaced b.lua with TAP text. Refused before anything runs.
static void a_report_never_overwrites_a_script_of_the_suite(void **state)
{
    (void)state;
    char err[4096], out[4096], text[256];
    assert_int_equal(system("rm -rf " TMP "/own && mkdir -p " TMP "/own"), 0);
    write_file(TMP "/own/a.lua", "seiche.scene { capacity = 10 }\nprint('a ran')\n");
    write_file(TMP "/own/b.lua", "seiche.scene { capacity = 10 }\n");
    assert_int_equal(run("--frames 1 --tap own/b.lua own/", err, sizeof err), 2);
    assert_non_null(strstr(err, "--tap would overwrite a script of the suite ('own/b.lua')"));
    slurp(TMP "/stdout.txt", out, sizeof out);
    assert_string_equal(out, ""); // nothing ran
    slurp(TMP "/own/b.lua", text, sizeof text);
    assert_string_equal(text, "seiche.scene { capacity = 10 }\n");
    // Another spelling of the same file, and a link to it.
    assert_int_equal(run("--frames 1 --junit ./own/../own/a.lua own", err, sizeof err), 2);
    assert_non_null(strstr(err, "--junit would overwrite a script of the suite ('own/a.lua')"));
    assert_int_equal(symlink("own/a.lua", TMP "/a_link.xml"), 0);
    assert_int_equal(run("--frames 1 --junit a_link.xml own", err, sizeof err), 2);
    slurp(TMP "/own/a.lua", text, sizeof text);
    assert_string_equal(text, "seiche.scene { capacity = 10 }\nprint('a ran')\n");
    // A report beside the suite is fine.
    assert_int_equal(run("--frames 1 --junit own.xml --tap own.tap own", err, sizeof err), 0);
}

// Control characters in a script's name are escaped where the runner writes the name: the
// console line, TAP (where a newline split the line, and a '#' made a directive of the
// rest) and JUnit's names.
static void control_characters_in_script_names_are_escaped(void **state)
{
    (void)state;
    char err[4096], out[4096], tap[4096], xml[8192];
    assert_int_equal(system("rm -rf " TMP "/ctl && mkdir -p " TMP "/ctl"), 0);
    write_file(TMP "/ctl/a\nline\x01.lua", "seiche.scene { capacity = 10 }\n");
    write_file(TMP "/ctl/b # TODO.lua", "seiche.scene { capacity = 10 }\nerror('boom')\n");
    write_file(TMP "/ctl/c\\nx.lua", "seiche.scene { capacity = 10 }\n"); // a backslash and an 'n', no newline
    assert_int_equal(run("--frames 1 --tap ctl.tap --junit ctl.xml ctl", err, sizeof err), 2);
    slurp(TMP "/stdout.txt", out, sizeof out);
    assert_non_null(strstr(out, "ok      ctl/a\\nline\\x01.lua (exit 0)\n"));
    slurp(TMP "/ctl.tap", tap, sizeof tap);
    assert_non_null(strstr(tap, "\nok 1 - ctl/a\\nline\\x01.lua: run (exit 0, ok)\n"));
    assert_non_null(strstr(tap, "\nnot ok 2 - ctl/b \\# TODO.lua: run (exit 2, usage or script error)\n"));
    assert_null(strstr(tap, "\x01"));
    assert_non_null(strstr(tap, "\nok 3 - ctl/c\\\\nx.lua: run (exit 0, ok)\n"));
    slurp(TMP "/ctl.xml", xml, sizeof xml);
    assert_non_null(strstr(xml, "<testsuite name=\"ctl/a\\nline\\x01.lua\""));
    assert_non_null(strstr(xml, "classname=\"ctl/a\\nline\\x01.lua\""));
    assert_null(strstr(xml, "a\nline"));
    assert_non_null(strstr(xml, "<testsuite name=\"ctl/c\\\\nx.lua\""));
    // The runner's own messages about a path escape it too: one line, not two.
    assert_int_equal(run("--frames 1 'no\nsuch.lua'", err, sizeof err), 2);
    if (!strstr(err, "seiche: cannot open script 'no\\nsuch.lua': No such file or directory\n(try 'seiche --help')\n"))
        fail_msg("stderr: %s", err);
}

// Each script of a suite runs in its own process: one that ends it (a crash, a kill, an
// os.exit of a --trusted script) fails with status 6 and a message that says how, the
// scripts after it still run, and the reports are written. In one process the first kill
// ended the suite with no report, and os.exit(0) ended it with status 0.
static void a_script_that_ends_its_process_fails_alone(void **state)
{
    (void)state;
    char err[4096], out[4096], tap[4096], xml[8192];
    assert_int_equal(system("rm -rf " TMP "/die && mkdir -p " TMP "/die"), 0);
    write_file(TMP "/die/a.lua", "seiche.scene { capacity = 10 }\nseiche.check(true, 'a ran')\n");
    write_file(TMP "/die/b.lua", "seiche.scene { capacity = 10 }\nos.exit(0)\n");
    write_file(TMP "/die/c.lua", "seiche.scene { capacity = 10 }\n"
                                 "function on_start() os.execute('kill -KILL ' .. io.open('/proc/self/stat'):read('n')) end\n");
    write_file(TMP "/die/d.lua", "seiche.scene { capacity = 10 }\nseiche.check(true, 'd ran')\n");
    assert_int_equal(run("--trusted --frames 2 --tap die.tap --junit die.xml die", err, sizeof err), 6);
    slurp(TMP "/stdout.txt", out, sizeof out);
    if (!strstr(out, "ok      die/a.lua (exit 0)\n") || !strstr(out, "FAILED  die/b.lua (exit 6)\n") ||
        !strstr(out, "FAILED  die/c.lua (exit 6)\n") || !strstr(out, "ok      die/d.lua (exit 0)\n") ||
        !strstr(out, "2 passed, 2 failed\n"))
        fail_msg("stdout:\n%s\nstderr:\n%s", out, err);
    assert_non_null(strstr(err, "seiche: die/b.lua: the run's process exited with status 0 before the run ended"));
    assert_non_null(strstr(err, "seiche: die/c.lua: the run's process was ended by signal 9 (Killed)"));
    slurp(TMP "/die.tap", tap, sizeof tap);
    assert_non_null(strstr(tap, "\nnot ok 4 - die/c.lua: run (exit 6, the run's process ended before the run)\n"));
    assert_non_null(strstr(tap, "\nok 6 - die/d.lua: run (exit 0, ok)\n"));
    slurp(TMP "/die.xml", xml, sizeof xml);
    assert_non_null(strstr(xml, "message=\"the run&apos;s process was ended by signal 9 (Killed)\""));
}

// A CI job's timeout (SIGTERM to the runner) during a suite: the run in progress is ended
// and recorded, the suite stops there, the reports are written, and the runner ends by the
// signal. Before each run had its own process, the reports were never written.
static void a_stopped_suite_still_writes_its_reports(void **state)
{
    (void)state;
    char err[4096], out[4096], tap[4096], xml[8192];
    assert_int_equal(system("rm -rf " TMP "/stop && mkdir -p " TMP "/stop"), 0);
    write_file(TMP "/stop/a.lua", "seiche.scene { capacity = 10 }\nfunction on_step() seiche.quit() end\n");
    // b runs its 10^8 frames; it says when it is under way (a file), and the runner is sent
    // SIGTERM then (at most 30 s on).
    write_file(TMP "/stop/b.lua", "seiche.scene { capacity = 10 }\n"
                                  "function on_step() if not told then io.open('ready', 'w'):close() told = true end end\n");
    write_file(TMP "/stop/c.lua", "seiche.scene { capacity = 10 }\n");
    unlink(TMP "/stop.tap");
    unlink(TMP "/stop.xml");
    unlink(TMP "/ready");
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "cd " TMP " && { '%s' --headless --quiet --trusted --frames 100000000 --tap stop.tap "
             "--junit stop.xml stop 2>stderr.txt >stdout.txt & p=$!; n=0; while [ ! -e ready ] && [ $n -lt 300 ]; "
             "do sleep 0.1; n=$((n+1)); done; kill -TERM $p; wait $p; }", exe);
    int st = system(cmd);
    assert_true(WIFEXITED(st));
    assert_int_equal(WEXITSTATUS(st), 128 + SIGTERM); // the runner ended by SIGTERM
    slurp(TMP "/stderr.txt", err, sizeof err);
    slurp(TMP "/stdout.txt", out, sizeof out);
    if (!strstr(out, "ok      stop/a.lua (exit 0)\n") || !strstr(out, "FAILED  stop/b.lua (exit 6)\n") ||
        strstr(out, "stop/c.lua") ||
        !strstr(out, "1 passed, 1 failed, 1 not run: the runner was stopped by signal 15 (Terminated)\n"))
        fail_msg("stdout:\n%s\nstderr:\n%s", out, err);
    slurp(TMP "/stop.tap", tap, sizeof tap);
    assert_non_null(strstr(tap, "1..2\n"));
    assert_non_null(strstr(tap, "\nnot ok 2 - stop/b.lua: run (exit 6, the run's process ended before the run)\n"));
    assert_non_null(strstr(tap, "message: 'the run''s process was ended by signal 15 (Terminated)'"));
    slurp(TMP "/stop.xml", xml, sizeof xml);
    assert_non_null(strstr(xml, "<testsuite name=\"stop/b.lua\""));
    assert_null(strstr(xml, "stop/c.lua"));
}

// A --set key given twice is refused naming it, as an option given twice is: the last one
// silently won.
static void set_key_given_twice_is_refused_naming_it(void **state)
{
    (void)state;
    char args[2048], err[4096];
    snprintf(args, sizeof args, "--frames 1 --set capacity=10 --set gravity.y=-9 --set capacity=20 '%s'", scene);
    assert_int_equal(run(args, err, sizeof err), 2);
    assert_non_null(strstr(err, "--set capacity may be given once (got 'capacity=10' and 'capacity=20')"));
    snprintf(args, sizeof args, "--frames 1 --set gravity.x=1 --set gravity.y=-9 --set capacity=2000 '%s'", scene);
    assert_int_equal(run(args, err, sizeof err), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(record_path_reaches_no_shell),
        cmocka_unit_test(unwritable_outputs_exit_2_naming_the_flag),
        cmocka_unit_test(unwritable_screenshot_is_one_message),
        cmocka_unit_test(a_screenshot_cut_short_leaves_no_file),
        cmocka_unit_test(record_refuses_odd_sizes_and_unknown_formats_before_the_run),
        cmocka_unit_test(record_failure_removes_the_incomplete_file),
        cmocka_unit_test(record_gives_ffmpeg_the_exact_frame_rate),
        cmocka_unit_test(double_dash_ends_the_options),
        cmocka_unit_test(too_many_sets_say_how_many),
        cmocka_unit_test(output_over_the_script_or_another_output_is_refused),
        cmocka_unit_test(numbers_out_of_range_name_the_flag_and_value),
        cmocka_unit_test(radius_pair_is_accepted_in_either_order_and_the_kernel_follows),
        cmocka_unit_test(directory_runs_as_one_suite_with_junit_and_tap_and_late_checks_fail),
        cmocka_unit_test(directory_suite_log_is_in_order_and_names_the_script),
        cmocka_unit_test(reports_give_the_message_once_and_count_frames_in_words),
        cmocka_unit_test(reports_fail_scripts_that_do_not_load),
        cmocka_unit_test(suite_names_read_plainly_and_a_dangling_link_says_why),
        cmocka_unit_test(a_report_never_overwrites_a_script_of_the_suite),
        cmocka_unit_test(control_characters_in_script_names_are_escaped),
        cmocka_unit_test(a_script_that_ends_its_process_fails_alone),
        cmocka_unit_test(a_stopped_suite_still_writes_its_reports),
        cmocka_unit_test(set_key_given_twice_is_refused_naming_it),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
