// The layout's rules (docs/architecture.md), read from the sources themselves: every
// #include points down (fluid/ knows nothing of the engine, GLFW, Lua or Bullet; the Bullet
// wrapper's header no Bullet; engine rooms include only rooms below them) and no source
// file grows past about a thousand lines.
#define _XOPEN_SOURCE 700
#include "tests/support.h"

#include <ftw.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_LINES 1000
#define MAX_FILES 1024

static char root[1024];
static char files[MAX_FILES][256]; // relative to the root
static int file_count;

static bool is_source(const char *p)
{
    const char *dot = strrchr(p, '.');
    return dot && (!strcmp(dot, ".c") || !strcmp(dot, ".h") || !strcmp(dot, ".cpp") || !strcmp(dot, ".hpp"));
}

static int collect(const char *path, const struct stat *st, int type, struct FTW *ftw)
{
    (void)st;
    (void)ftw;
    if (type != FTW_F || !is_source(path) || file_count >= MAX_FILES) return 0;
    snprintf(files[file_count++], sizeof files[0], "%s", path + strlen(root) + 1);
    return 0;
}

static int setup(void **state)
{
    (void)state;
    support_source_dir(root, sizeof root);
    const char *dirs[] = { "engine", "fluid", "demos", "tests" };
    for (size_t i = 0; i < sizeof dirs / sizeof dirs[0]; i++) {
        char d[1100];
        snprintf(d, sizeof d, "%s/%s", root, dirs[i]);
        if (nftw(d, collect, 16, FTW_PHYS) != 0) return -1;
    }
    return file_count > 20 ? 0 : -1;
}

static FILE *open_source(int i)
{
    char path[1400];
    snprintf(path, sizeof path, "%s/%s", root, files[i]);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    return f;
}

static bool starts(const char *s, const char *prefix) { return strncmp(s, prefix, strlen(prefix)) == 0; }

// The engine's rooms, bottom up; -1 for a file outside them.
static int room_rank(const char *p)
{
    static const char *const rooms[] = { "engine/core/", "engine/gl/", "engine/render/", "engine/script/", "engine/app/" };
    for (int i = 0; i < 5; i++)
        if (starts(p, rooms[i])) return i;
    return -1;
}

static bool std_header(const char *h)
{
    static const char *const ok[] = { "assert.h", "ctype.h", "errno.h", "float.h", "inttypes.h", "limits.h",
                                      "math.h", "stdarg.h", "stdatomic.h", "stdbool.h", "stddef.h", "stdint.h", "stdio.h",
                                      "stdlib.h", "string.h", "time.h" };
    for (size_t i = 0; i < sizeof ok / sizeof ok[0]; i++)
        if (!strcmp(h, ok[i])) return true;
    return false;
}

// NULL when `file` may include `inc` (quoted when `quoted`), else the broken rule.
static const char *rule_broken(const char *file, const char *inc, bool quoted)
{
    bool bullet = starts(inc, "bt") || starts(inc, "Bullet") || starts(inc, "LinearMath/");
    bool engine_only = starts(inc, "GLFW/") || starts(inc, "lua") || starts(inc, "lauxlib") || starts(inc, "imgui");
    if (starts(file, "fluid/") && !starts(file, "fluid/bullet/")) {
        if (quoted && !(starts(inc, "fluid/") && !starts(inc, "fluid/bullet/")) && !starts(inc, "shaders/fluid/"))
            return "the fluid core includes only fluid/ core headers and shaders/fluid/";
        if (!quoted && !std_header(inc) && !starts(inc, "epoxy/"))
            return "the fluid core knows GL through libepoxy and the C library, nothing else";
    }
    if (starts(file, "fluid/bullet/")) {
        if (quoted && starts(inc, "engine/")) return "fluid/bullet knows nothing of the engine";
        if (engine_only) return "fluid/bullet knows nothing of GLFW, Lua or ImGui";
        if (bullet && !strstr(file, ".cpp") && !strstr(file, ".hpp"))
            return "only the wrapper's C++ files include Bullet (phys.h and the coupling stay C)";
        if (starts(file, "fluid/bullet/phys") && quoted && starts(inc, "fluid/") && !starts(inc, "fluid/bullet/phys"))
            return "the Bullet wrapper knows nothing of the fluid";
    }
    if (starts(file, "engine/")) {
        if (bullet) return "the engine reaches Bullet through fluid/bullet/phys.h only";
        int me = room_rank(file), them = quoted && starts(inc, "engine/") ? room_rank(inc) : -1;
        if (me < 0) return "every engine file lives in a room (core, gl, render, script, app)";
        if (them > me) return "an engine room includes only itself and the rooms below it (core < gl < render < script < app)";
    }
    if (starts(file, "demos/") || starts(file, "tests/")) {
        if (quoted && starts(inc, "engine/") && strstr(inc, "_internal")) return "internal headers stay in their room";
    }
    return NULL;
}

static void includes_point_down(void **state)
{
    (void)state;
    int broken = 0;
    for (int i = 0; i < file_count; i++) {
        FILE *f = open_source(i);
        char line[512];
        int n = 0;
        while (fgets(line, sizeof line, f)) {
            n++;
            const char *q = line;
            while (*q == ' ' || *q == '\t') q++;
            if (!starts(q, "#include")) continue;
            q += 8;
            while (*q == ' ') q++;
            char open = *q, close = open == '"' ? '"' : '>';
            if (open != '"' && open != '<') continue;
            const char *end = strchr(q + 1, close);
            if (!end) continue;
            char inc[256];
            snprintf(inc, sizeof inc, "%.*s", (int)(end - q - 1), q + 1);
            const char *why = rule_broken(files[i], inc, open == '"');
            if (why) {
                print_error("%s:%d: #include %c%s%c: %s\n", files[i], n, open, inc, close, why);
                broken++;
            }
        }
        fclose(f);
    }
    assert_int_equal(broken, 0);
}

static void no_source_file_is_over_a_thousand_lines(void **state)
{
    (void)state;
    int big = 0;
    for (int i = 0; i < file_count; i++) {
        FILE *f = open_source(i);
        int lines = 0, c;
        while ((c = fgetc(f)) != EOF) lines += c == '\n';
        fclose(f);
        if (lines > MAX_LINES) {
            print_error("%s: %d lines (at most %d: split it by area)\n", files[i], lines, MAX_LINES);
            big++;
        }
    }
    assert_int_equal(big, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(includes_point_down),
        cmocka_unit_test(no_source_file_is_over_a_thousand_lines),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
