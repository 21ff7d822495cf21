// GLSL loading (fluid/pbf_glsl): includes nest, compiler errors point at the file and line
// of the *included* file, missing files are named with who asked for them, and a compute
// shader built through includes really runs. The shader directory is tests/fixtures, so
// messages show the root as "fixtures".
#include "tests/support.h"

#include <epoxy/gl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fluid/pbf_glsl.h"

typedef support_gpu fixture; // fixtures_dir holds the test shaders

static GLuint build_compute(const fixture *f, const char *file, const char *defines, char *err, size_t err_size)
{
    pbf_glsl_stage stage = { GL_COMPUTE_SHADER, file };
    return pbf_glsl_build(f->fixtures_dir, &stage, 1, defines, err, err_size);
}

static void header_including_a_header_compiles(void **state)
{
    fixture *f = *state;
    char err[1024] = "";
    char *files[PBF_GLSL_MAX_FILES] = { 0 };
    int nfiles = 0;
    char *src = pbf_glsl_preprocess(f->fixtures_dir, "fill.comp", NULL, files, &nfiles, err, sizeof err);
    assert_non_null(src);
    assert_int_equal(nfiles, 3);
    assert_string_equal(files[0], "fill.comp");
    assert_string_equal(files[1], "common/outer.glsl");
    assert_string_equal(files[2], "common/inner.glsl");
    assert_non_null(strstr(src, "uint fixture_offset()"));
    free(src);
    pbf_glsl_free_files(files, nfiles);

    GLuint prog = build_compute(f, "fill.comp", NULL, err, sizeof err);
    if (!prog) fail_msg("fill.comp did not build: %s", err);
    glDeleteProgram(prog);
}

static void error_in_included_file_reports_that_file_and_line(void **state)
{
    fixture *f = *state;
    char err[2048] = "";
    GLuint prog = build_compute(f, "broken.comp", NULL, err, sizeof err);
    print_message("broken.comp: %s\n", err);
    assert_int_equal(prog, 0);
    // Line 6 of broken_part.glsl uses an undeclared name; the message starts there.
    assert_true(strncmp(err, "fixtures/broken_part.glsl:6:", strlen("fixtures/broken_part.glsl:6:")) == 0);
    assert_non_null(strstr(err, "this_name_is_not_declared"));
    assert_null(strstr(err, "broken.comp:")); // blamed on the included file only
}

static void missing_include_names_the_including_file_and_line(void **state)
{
    fixture *f = *state;
    char err[1024] = "";
    GLuint prog = build_compute(f, "missing_include.comp", NULL, err, sizeof err);
    print_message("missing_include.comp: %s\n", err);
    assert_int_equal(prog, 0);
    assert_true(strncmp(err, "fixtures/missing_include.comp:3:", strlen("fixtures/missing_include.comp:3:")) == 0);
    assert_non_null(strstr(err, "common/not_there.glsl"));
}

static void missing_top_level_file_is_named(void **state)
{
    fixture *f = *state;
    char err[1024] = "";
    GLuint prog = build_compute(f, "no_such_shader.comp", NULL, err, sizeof err);
    print_message("no_such_shader.comp: %s\n", err);
    assert_int_equal(prog, 0);
    assert_true(strncmp(err, "fixtures/no_such_shader.comp", strlen("fixtures/no_such_shader.comp")) == 0);
    assert_non_null(strstr(err, "cannot open"));
}

static void compute_shader_built_from_includes_writes_expected_values(void **state)
{
    fixture *f = *state;
    enum { N = 256 };
    char err[1024] = "";
    // The define is inserted after #version and seen by the innermost header.
    GLuint prog = build_compute(f, "fill.comp", "#define FIXTURE_EXTRA 100u\n", err, sizeof err);
    if (!prog) fail_msg("fill.comp did not build: %s", err);
    GLuint buf;
    glGenBuffers(1, &buf);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buf);
    GLuint init[N];
    for (int i = 0; i < N; i++) init[i] = 0xdeadbeefu;
    glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof init, init, GL_DYNAMIC_READ);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buf);
    glUseProgram(prog);
    glDispatchCompute(N / 64, 1, 1);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    GLuint out[N];
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof out, out);
    assert_int_equal(glGetError(), GL_NO_ERROR);
    for (GLuint i = 0; i < N; i++) assert_int_equal(out[i], 3u * i + 7u + 100u);
    glUseProgram(0);
    glDeleteBuffers(1, &buf);
    glDeleteProgram(prog);
}

// Found by tests/fuzz/fuzz_glsl_preprocess (regressions/map_log_message_across_lines): the
// blank after "N:L(C):" matched the newline, so the next log line was printed twice.
static void map_log_writes_each_log_line_once(void **state)
{
    (void)state;
    char *files[2] = { (char *)"fluid/a.comp", (char *)"fluid/b.glsl" };
    char out[512];
    pbf_glsl_map_log("0:3(1): \n\n1:7(2): error: x undeclared\n", files, 2, "shaders", out, sizeof out);
    assert_string_equal(out, "shaders/fluid/a.comp:3: \nshaders/fluid/b.glsl:7: error: x undeclared");
}

// Found by tests/fuzz/fuzz_glsl_preprocess (regressions/err_size_zero): err_size 0 (or out_size
// 0) was written to all the same.
static void no_room_for_a_message_writes_nothing(void **state)
{
    (void)state;
    pbf_glsl_file table[1] = { { "a.comp", "void main() {}\n" } }; // no #version: an error
    pbf_glsl_source src = { NULL, table, 1 };
    char *files[PBF_GLSL_MAX_FILES] = { 0 };
    int nfiles = 0;
    char err[4] = "abc", out[4] = "abc";
    assert_null(pbf_glsl_preprocess_from(&src, "a.comp", NULL, files, &nfiles, err, 0));
    pbf_glsl_free_files(files, nfiles);
    assert_null(pbf_glsl_preprocess_from(&src, "a.comp", NULL, files, &nfiles, NULL, 0));
    pbf_glsl_free_files(files, nfiles);
    pbf_glsl_map_log("0:1(1): error: x\n", files, 0, "shaders", out, 0);
    pbf_glsl_map_log(NULL, files, 0, "shaders", out, sizeof out);
    assert_string_equal(err, "abc");
    assert_string_equal(out, "");
}

// Nine files, each including the next 40 times, expand to 40^8 copies: refused at
// PBF_GLSL_MAX_SOURCE with a message instead of running for hours.
static void include_fan_out_is_refused_not_expanded(void **state)
{
    (void)state;
    static char texts[9][1024];
    static char names[9][16];
    pbf_glsl_file table[9];
    for (int i = 0; i < 9; i++) {
        snprintf(names[i], sizeof names[i], "f%d", i);
        snprintf(texts[i], sizeof texts[i], "%s", i == 0 ? "#version 430\n" : "");
        for (int k = 0; i < 8 && k < 40; k++)
            snprintf(texts[i] + strlen(texts[i]), sizeof texts[i] - strlen(texts[i]), "#include \"f%d\"\n", i + 1);
        table[i] = (pbf_glsl_file){ names[i], texts[i] };
    }
    pbf_glsl_source src = { NULL, table, 9 };
    char *files[PBF_GLSL_MAX_FILES] = { 0 };
    int nfiles = 0;
    char err[512] = "";
    char *out = pbf_glsl_preprocess_from(&src, "f0", NULL, files, &nfiles, err, sizeof err);
    pbf_glsl_free_files(files, nfiles);
    print_message("%s\n", err);
    assert_null(out);
    assert_non_null(strstr(err, "expands to more than"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(header_including_a_header_compiles),
        cmocka_unit_test(error_in_included_file_reports_that_file_and_line),
        cmocka_unit_test(missing_include_names_the_including_file_and_line),
        cmocka_unit_test(missing_top_level_file_is_named),
        cmocka_unit_test(compute_shader_built_from_includes_writes_expected_values),
        cmocka_unit_test(map_log_writes_each_log_line_once),
        cmocka_unit_test(no_room_for_a_message_writes_nothing),
        cmocka_unit_test(include_fan_out_is_refused_not_expanded),
    };
    return cmocka_run_group_tests(tests, support_gpu_setup, support_gpu_teardown);
}
