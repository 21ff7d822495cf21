// A built runner carries its shaders: copied to another directory, with no checkout in
// reach, it runs a scene; and no path of the shader tree is compiled into it.
#define _XOPEN_SOURCE 700
#include "tests/support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

static void bin_dir(char *out, size_t size)
{
    char exe[1024];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    assert_true(n > 0);
    exe[n] = 0;
    char *slash = strrchr(exe, '/');
    assert_non_null(slash);
    *slash = 0;
    snprintf(out, size, "%s", exe);
}

static int sh(const char *cmd)
{
    int st = system(cmd);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static bool file_contains(const char *path, const char *needle)
{
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    size_t n = strlen(needle), len = 0;
    char *buf = NULL;
    char chunk[65536];
    size_t got;
    while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) {
        buf = realloc(buf, len + got);
        assert_non_null(buf);
        memcpy(buf + len, chunk, got);
        len += got;
    }
    fclose(f);
    bool found = false;
    for (size_t i = 0; !found && n <= len && i <= len - n; i++) found = memcmp(buf + i, needle, n) == 0;
    free(buf);
    return found;
}

static void runner_and_libraries_hold_no_path_of_the_shader_tree(void **state)
{
    (void)state;
    char root[1024], needle[1100], bin[1024], path[1200];
    support_source_dir(root, sizeof root);
    char *abs = realpath(root, NULL);
    assert_non_null(abs);
    snprintf(needle, sizeof needle, "%s/shaders", abs);
    free(abs);
    bin_dir(bin, sizeof bin);
    const char *files[] = { "seiche", "seiche-bench", "seiche-embed", "libseiche_fluid.a", "libseiche_engine.a" };
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", bin, files[i]);
        if (file_contains(path, needle)) fail_msg("%s contains the shader path %s", path, needle);
    }
}

static void copied_runner_runs_a_scene_with_the_checkout_out_of_reach(void **state)
{
    (void)state;
    char bin[1024], root[1024], tmpl[] = "/tmp/seiche-reloc-XXXXXX", cmd[4096];
    bin_dir(bin, sizeof bin);
    support_source_dir(root, sizeof root);
    char *dir = mkdtemp(tmpl);
    assert_non_null(dir);
    snprintf(cmd, sizeof cmd, "cp '%s/seiche' '%s/' && cp '%s/tests/fixtures/tiny_scene.lua' '%s/scene.lua'", bin, dir,
             root, dir);
    assert_int_equal(sh(cmd), 0);
    // From the copy's own directory, with no shader directory given or inherited.
    snprintf(cmd, sizeof cmd,
             "cd '%s' && env -u SEICHE_SHADER_DIR ./seiche --headless --frames 5 --hash --quiet scene.lua "
             ">out.txt 2>err.txt; echo $? > status.txt",
             dir);
    assert_int_equal(sh(cmd), 0);
    char status_path[1100], out_path[1100];
    snprintf(status_path, sizeof status_path, "%s/status.txt", dir);
    snprintf(out_path, sizeof out_path, "%s/out.txt", dir);
    FILE *f = fopen(status_path, "r");
    assert_non_null(f);
    int status = -1;
    assert_int_equal(fscanf(f, "%d", &status), 1);
    fclose(f);
    if (status != 0) {
        snprintf(cmd, sizeof cmd, "cat '%s/err.txt' >&2", dir);
        sh(cmd);
    }
    assert_int_equal(status, 0);
    assert_true(file_contains(out_path, "state hash: "));
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    sh(cmd);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(runner_and_libraries_hold_no_path_of_the_shader_tree),
        cmocka_unit_test(copied_runner_runs_a_scene_with_the_checkout_out_of_reach),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
