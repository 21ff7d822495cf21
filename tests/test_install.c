// An engine developer's path: install Seiche into a prefix (tools/install.sh, which
// `make install` runs), build demos/embed against it with pkg-config alone, and run it
// headless. Also: one version everywhere (pbf.h, the soname, the .pc, seiche --version).
#include "tests/support.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "fluid/pbf.h"

typedef struct fixture {
    char root[1024];
    char build[1024];
    char prefix[64];
} fixture;

static int sh(const char *cmd)
{
    int st = system(cmd);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

// The first line `cmd` prints, or "" (with the status in *status).
static void first_line(const char *cmd, char *out, size_t size, int *status)
{
    out[0] = 0;
    FILE *p = popen(cmd, "r");
    assert_non_null(p);
    if (fgets(out, (int)size, p)) out[strcspn(out, "\n")] = 0;
    char rest[512];
    while (fgets(rest, sizeof rest, p)) {}
    int st = pclose(p);
    *status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    if (!f) return -1;
    support_source_dir(f->root, sizeof f->root);
    char exe[1024];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0) {
        free(f);
        return -1;
    }
    exe[n] = 0;
    *strrchr(exe, '/') = 0; // build/bin
    *strrchr(exe, '/') = 0; // build
    snprintf(f->build, sizeof f->build, "%s", exe);
    snprintf(f->prefix, sizeof f->prefix, "/tmp/seiche-prefix-XXXXXX");
    if (!mkdtemp(f->prefix)) {
        free(f);
        return -1;
    }
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "'%s/tools/install.sh' '%s' '%s' >/dev/null", f->root, f->prefix, f->build);
    if (sh(cmd) != 0) {
        fprintf(stderr, "tools/install.sh failed\n");
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", f->prefix);
        sh(cmd);
        free(f);
        return -1;
    }
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state; // NULL when the setup failed (it cleaned up after itself)
    if (!f) return 0;
    char cmd[256];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", f->prefix);
    sh(cmd);
    free(f);
    return 0;
}

static void installed_files_carry_one_version(void **state)
{
    fixture *f = *state;
    char cmd[4096], line[512];
    int st;
    snprintf(cmd, sizeof cmd, "PKG_CONFIG_PATH='%s/lib/pkgconfig' pkg-config --modversion seiche-fluid", f->prefix);
    first_line(cmd, line, sizeof line, &st);
    assert_int_equal(st, 0);
    assert_string_equal(line, PBF_VERSION_STRING);
    snprintf(cmd, sizeof cmd, "objdump -p '%s/lib/libseiche_fluid.so' | awk '/SONAME/ {print $2}'", f->prefix);
    first_line(cmd, line, sizeof line, &st);
    char soname[64];
    snprintf(soname, sizeof soname, "libseiche_fluid.so.%d", PBF_VERSION_MAJOR);
    assert_string_equal(line, soname);
    const char *files[] = { "lib/libseiche_fluid.a", "lib/libseiche_coupling.a", "lib/libseiche_phys.a",
                            "lib/pkgconfig/seiche-coupling.pc", "include/seiche/fluid/pbf.h",
                            "include/seiche/fluid/bullet/coupling.h", "bin/seiche", "share/seiche/scenes/dam_break.lua" };
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) {
        char p[1200];
        snprintf(p, sizeof p, "%s/%s", f->prefix, files[i]);
        if (access(p, R_OK) != 0) fail_msg("not installed: %s", files[i]);
    }
    snprintf(cmd, sizeof cmd, "'%s/bin/seiche' --version", f->prefix);
    first_line(cmd, line, sizeof line, &st);
    assert_int_equal(st, 0);
    assert_string_equal(line, "seiche " PBF_VERSION_STRING);
}

static void embed_example_builds_with_pkg_config_alone_and_runs_headless(void **state)
{
    fixture *f = *state;
    char cmd[8192], line[512];
    int st;
    snprintf(cmd, sizeof cmd,
             "export PKG_CONFIG_PATH='%s/lib/pkgconfig'; cc -std=c11 -Wall -Wextra -Werror -o '%s/embed' "
             "'%s/demos/embed/main.c' $(pkg-config --cflags --libs seiche-fluid) 2>&1",
             f->prefix, f->prefix, f->root);
    first_line(cmd, line, sizeof line, &st);
    if (st != 0) fail_msg("the embed example did not build against the prefix: %s", line);
    // Run from the prefix, the checkout nowhere on its paths.
    snprintf(cmd, sizeof cmd, "cd '%s' && LD_LIBRARY_PATH='%s/lib' ./embed", f->prefix, f->prefix);
    first_line(cmd, line, sizeof line, &st);
    assert_int_equal(st, 0);
    if (!strstr(line, "Seiche " PBF_VERSION_STRING) || !strstr(line, "particles on"))
        fail_msg("unexpected first line: %s", line);
    // It linked the installed shared library.
    snprintf(cmd, sizeof cmd, "LD_LIBRARY_PATH='%s/lib' ldd '%s/embed' | grep -c '%s/lib/libseiche_fluid.so'",
             f->prefix, f->prefix, f->prefix);
    first_line(cmd, line, sizeof line, &st);
    assert_string_equal(line, "1");
}

// The coupling's libraries are static archives: `pkg-config --libs seiche-coupling` must
// bring Bullet and the C++ runtime along for a plain (not --static) link of a C host.
static void coupling_host_links_with_pkg_config_alone(void **state)
{
    fixture *f = *state;
    char cmd[8192], line[512];
    int st;
    snprintf(cmd, sizeof cmd, "%s/cpl.c", f->prefix);
    FILE *src = fopen(cmd, "w");
    assert_non_null(src);
    fputs("#include <stdio.h>\n#include \"fluid/bullet/coupling.h\"\n"
          "int main(void) {\n"
          "    phys_world_def wd = phys_default_world_def();\n"
          "    phys_world *w = NULL;\n"
          "    if (phys_world_create(&wd, &w) != PHYS_OK) return 1;\n"
          "    cpl_def d = cpl_default_def();\n"
          "    char err[256];\n"
          "    if (cpl_def_check(&d, err, sizeof err) != CPL_OK) return 2;\n"
          "    phys_world_destroy(w);\n"
          "    puts(\"coupled\");\n"
          "    return 0;\n"
          "}\n", src);
    fclose(src);
    snprintf(cmd, sizeof cmd,
             "export PKG_CONFIG_PATH='%s/lib/pkgconfig'; cc -std=c11 -Wall -Wextra -Werror -o '%s/cpl' '%s/cpl.c' "
             "$(pkg-config --cflags --libs seiche-coupling) 2>&1",
             f->prefix, f->prefix, f->prefix);
    first_line(cmd, line, sizeof line, &st);
    if (st != 0) fail_msg("a coupling host did not link with pkg-config --libs seiche-coupling: %s", line);
    snprintf(cmd, sizeof cmd, "cd '%s' && LD_LIBRARY_PATH='%s/lib' ./cpl", f->prefix, f->prefix);
    first_line(cmd, line, sizeof line, &st);
    assert_int_equal(st, 0);
    assert_string_equal(line, "coupled");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(installed_files_carry_one_version),
        cmocka_unit_test(embed_example_builds_with_pkg_config_alone_and_runs_headless),
        cmocka_unit_test(coupling_host_links_with_pkg_config_alone),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
