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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(glfw_host_draws_the_water_with_its_own_shader),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
