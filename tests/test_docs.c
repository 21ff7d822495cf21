// The documents say what the programs do: every option `seiche --help` prints is in
// docs/runner.md's option table, every metrics column the runner writes is in --help and in
// docs/runner.md's column table, and every shipped scene is listed in README.md. (The Lua
// API's coverage is tests/test_lua.c's.)
#include "tests/support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = malloc((size_t)n + 1);
    if (s && fread(s, 1, (size_t)n, f) != (size_t)n) n = 0;
    if (s) s[n] = 0;
    fclose(f);
    return s;
}

static char *command_output(const char *cmd)
{
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    size_t cap = 65536, len = 0;
    char *s = malloc(cap);
    assert_non_null(s);
    size_t got;
    while ((got = fread(s + len, 1, cap - 1 - len, p)) > 0) len += got;
    s[len] = 0;
    pclose(p);
    return s;
}

static char *doc(const char *rel)
{
    char path[1200];
    support_source_path(rel, path, sizeof path);
    char *s = slurp(path);
    if (!s) fail_msg("cannot read %s", rel);
    return s;
}

static void every_runner_option_is_documented(void **state)
{
    (void)state;
    char exe[1200], cmd[1300];
    support_bin_path("seiche", exe, sizeof exe);
    snprintf(cmd, sizeof cmd, "'%s' --help", exe);
    char *help = command_output(cmd), *runner = doc("docs/runner.md");
    int missing = 0, seen = 0;
    for (const char *p = help; (p = strstr(p, "  --")) != NULL; p += 4) {
        char opt[64];
        int n = 0;
        const char *q = p + 2;
        while (n < 63 && (q[n] == '-' || (q[n] >= 'a' && q[n] <= 'z'))) {
            opt[n] = q[n];
            n++;
        }
        opt[n] = 0;
        char cell[80];
        snprintf(cell, sizeof cell, "`%s", opt);
        seen++;
        if (!strstr(runner, cell)) {
            print_error("docs/runner.md does not document %s\n", opt);
            missing++;
        }
    }
    assert_true(seen >= 15);
    assert_int_equal(missing, 0);
    free(help);
    free(runner);
}

static void every_metrics_column_is_in_help_and_docs(void **state)
{
    (void)state;
    char exe[1200], scene[1200], cmd[3000];
    support_bin_path("seiche", exe, sizeof exe);
    support_source_path("tests/fixtures/tiny_scene.lua", scene, sizeof scene);
    snprintf(cmd, sizeof cmd, "'%s' --headless --quiet --frames 1 --metrics /tmp/seiche-docs-metrics.csv '%s' && "
             "head -n 1 /tmp/seiche-docs-metrics.csv; rm -f /tmp/seiche-docs-metrics.csv", exe, scene);
    char *header = command_output(cmd);
    snprintf(cmd, sizeof cmd, "'%s' --help", exe);
    char *help = command_output(cmd), *runner = doc("docs/runner.md");
    header[strcspn(header, "\r\n")] = 0;
    assert_true(strlen(header) > 20);
    int missing = 0;
    for (char *col = strtok(header, ","); col; col = strtok(NULL, ",")) {
        char cell[80];
        size_t n = strlen(col);
        bool stage = n > 3 && strcmp(col + n - 3, "_ms") == 0 && strcmp(col, "step_ms") != 0;
        if (stage) {
            snprintf(cell, sizeof cell, "`%.*s`", (int)(n - 3), col); // in the <stage>_ms row
            if (!strstr(runner, cell) || !strstr(help, "<stage>_ms")) {
                print_error("stage column %s is not documented (docs/runner.md lists stages, --help <stage>_ms)\n", col);
                missing++;
            }
            continue;
        }
        snprintf(cell, sizeof cell, "`%s`", col);
        if (!strstr(runner, cell)) {
            print_error("docs/runner.md's column table lacks %s\n", col);
            missing++;
        }
        if (!strstr(help, col)) {
            print_error("seiche --help does not name the metrics column %s\n", col);
            missing++;
        }
    }
    assert_int_equal(missing, 0);
    free(header);
    free(help);
    free(runner);
}

static void every_shipped_scene_is_in_the_readme(void **state)
{
    (void)state;
    char dir[1200], cmd[1400];
    support_source_path("scripts/scenes", dir, sizeof dir);
    snprintf(cmd, sizeof cmd, "ls '%s' | sed -n 's/\\.lua$//p'", dir);
    char *names = command_output(cmd), *readme = doc("README.md");
    int missing = 0, seen = 0;
    for (char *name = strtok(names, "\n"); name; name = strtok(NULL, "\n")) {
        char cell[128];
        snprintf(cell, sizeof cell, "`%s`", name);
        seen++;
        if (!strstr(readme, cell)) {
            print_error("README.md does not list the scene %s\n", name);
            missing++;
        }
    }
    assert_true(seen >= 7);
    assert_int_equal(missing, 0);
    free(names);
    free(readme);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(every_runner_option_is_documented),
        cmocka_unit_test(every_metrics_column_is_in_help_and_docs),
        cmocka_unit_test(every_shipped_scene_is_in_the_readme),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
