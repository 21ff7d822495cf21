// The runner against hostile and careless command lines (docs/runner.md): no shell between
// it and ffmpeg, outputs that fail are reported with the right status, an output never
// overwrites the script or another output, numbers are range-checked; and the scene
// writer's traps: a consistent particle / kernel radius pair is accepted in any order.
#include "tests/support.h"

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

// Runs the runner with `args` (already quoted for sh) from TMP; stderr into `err`.
static int run(const char *args, char *err, size_t err_size)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "cd " TMP " && '%s' --headless --quiet %s 2>" TMP "/stderr.txt >" TMP "/stdout.txt",
             exe, args);
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(record_path_reaches_no_shell),
        cmocka_unit_test(unwritable_outputs_exit_2_naming_the_flag),
        cmocka_unit_test(output_over_the_script_or_another_output_is_refused),
        cmocka_unit_test(numbers_out_of_range_name_the_flag_and_value),
        cmocka_unit_test(radius_pair_is_accepted_in_either_order_and_the_kernel_follows),
        cmocka_unit_test(directory_runs_as_one_suite_with_junit_and_tap_and_late_checks_fail),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
