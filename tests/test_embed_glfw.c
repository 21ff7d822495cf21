// The second embedding example (demos/embed_glfw: plain GLFW, the host's own shader drawing
// the fluid's position buffer) runs in a real window and shows water. Under Xvfb when there
// is no display.
#include "tests/support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

static void glfw_host_draws_the_water_with_its_own_shader(void **state)
{
    (void)state;
    const char *display = getenv("DISPLAY");
    bool have_display = display && *display;
    if (!have_display) support_skip_unless_on_path("xvfb-run");
    char exe[1200], cmd[1600];
    support_source_path("build/bin/seiche-embed-glfw", exe, sizeof exe);
    snprintf(cmd, sizeof cmd, "%s'%s' --frames 30 --check 2>&1",
             have_display ? "" : "xvfb-run -a -s '-screen 0 640x480x24' ", exe);
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    char out[4096] = "";
    size_t n = fread(out, 1, sizeof out - 1, p);
    out[n] = 0;
    int st = pclose(p);
    print_message("%s", out);
    assert_true(WIFEXITED(st) && WEXITSTATUS(st) == 0);
    assert_non_null(strstr(out, "water pixels"));
}

// Its command line is checked before any window opens: no display needed.
static void bad_arguments_exit_2_naming_them(void **state)
{
    (void)state;
    char exe[1200], cmd[1600], out[1024];
    support_source_path("build/bin/seiche-embed-glfw", exe, sizeof exe);
    const char *cases[][2] = {
        { "--frames abc", "--frames must be a whole number in [1, 100000000] (got 'abc')" },
        { "--frames 0", "(got '0')" },
        { "--frames ' 5'", "(got ' 5')" },
        { "--check", "--check needs --frames N" },
        { "--colour", "usage: seiche-embed-glfw [--frames N] [--check]" },
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        snprintf(cmd, sizeof cmd, "DISPLAY= '%s' %s 2>&1", exe, cases[i][0]);
        FILE *p = popen(cmd, "r");
        assert_non_null(p);
        size_t n = fread(out, 1, sizeof out - 1, p);
        out[n] = 0;
        int st = pclose(p);
        if (!(WIFEXITED(st) && WEXITSTATUS(st) == 2) || !strstr(out, cases[i][1]))
            fail_msg("%s: status %d, output: %s (want exit 2 and: %s)", cases[i][0], WEXITSTATUS(st), out, cases[i][1]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(bad_arguments_exit_2_naming_them),
        cmocka_unit_test(glfw_host_draws_the_water_with_its_own_shader),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
