// The strict GL mode (engine/gl/gl_strict.h) catches what an in-order driver hides: each
// test sets up one ordering bug on purpose and sees the mode name it, and sees the correct
// version of the same code pass.
#include "tests/support.h"

#include <epoxy/egl.h>
#include <epoxy/gl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine/gl/gl_strict.h"

typedef struct fixture {
    eng_context *ctx;
    int hazards;
    char last[1024];
    eng_gl_strict_handler *old_handler;
    void *old_user;
} fixture;

static void record(void *user, const char *message)
{
    fixture *f = user;
    f->hazards++;
    snprintf(f->last, sizeof f->last, "%s", message);
}

static eng_gl_proc egl_proc(const char *name) { return (eng_gl_proc)eglGetProcAddress(name); }

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    if (!f) return -1;
    f->ctx = support_headless_context(32, 32);
    char err[256];
    if (!eng_gl_strict_install(egl_proc, err, sizeof err)) {
        fprintf(stderr, "install: %s\n", err);
        return -1;
    }
    eng_gl_strict_set_handler(record, f, &f->old_handler, &f->old_user);
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    eng_gl_strict_set_handler(f->old_handler, f->old_user, NULL, NULL);
    eng_context_destroy(f->ctx);
    free(f);
    return 0;
}

static void reset(fixture *f)
{
    f->hazards = 0;
    f->last[0] = 0;
}

static GLuint buffer_with(const char *label, GLsizeiptr size, const void *data)
{
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, b);
    glBufferData(GL_SHADER_STORAGE_BUFFER, size, data, GL_DYNAMIC_DRAW);
    glObjectLabel(GL_BUFFER, b, -1, label);
    return b;
}

static GLuint compute(const char *label, const char *body)
{
    char src[2048];
    snprintf(src, sizeof src, "#version 430\nlayout(local_size_x = 4) in;\n%s", body);
    const char *s = src;
    GLuint sh = glCreateShader(GL_COMPUTE_SHADER);
    glShaderSource(sh, 1, &s, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    assert_true(ok);
    GLuint p = glCreateProgram();
    glAttachShader(p, sh);
    glLinkProgram(p);
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    assert_true(ok);
    glDeleteShader(sh);
    glObjectLabel(GL_PROGRAM, p, -1, label);
    return p;
}

static const char *writer_src =
    "layout(std430, binding = 0) buffer Data { uint v[]; };\n"
    "void main() { v[gl_GlobalInvocationID.x] = 7u; }\n";
static const char *reader_src =
    "layout(std430, binding = 0) readonly buffer Data { uint v[]; };\n"
    "layout(std430, binding = 1) buffer Out { uint o[]; };\n"
    "void main() { o[gl_GlobalInvocationID.x] = v[gl_GlobalInvocationID.x] + 1u; }\n";

// The NVIDIA bug of the first version: a buffer cleared on the GPU, then filled from the CPU.
static void gpu_clear_then_cpu_upload_is_caught_and_loses_the_upload_as_on_nvidia(void **state)
{
    fixture *f = *state;
    reset(f);
    GLuint b = buffer_with("test.staging", 16, NULL);
    glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, NULL);
    uint32_t up[4] = { 1, 2, 3, 4 }, back[4] = { 9, 9, 9, 9 };
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof up, up);
    assert_int_equal(f->hazards, 1);
    assert_non_null(strstr(f->last, "'test.staging'"));
    assert_non_null(strstr(f->last, "GPU clear"));
    // The held-back clear lands before the readback, after the upload: the data is gone,
    // exactly what the H100 showed (the first block of water read back as zeros).
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof back, back);
    for (int i = 0; i < 4; i++) assert_int_equal(back[i], 0);
    glDeleteBuffers(1, &b);
}

static void buffer_created_with_its_data_is_not_a_hazard(void **state)
{
    fixture *f = *state;
    reset(f);
    uint32_t zeros[4] = { 0 }, up[4] = { 1, 2, 3, 4 }, back[4] = { 0 };
    GLuint b = buffer_with("test.filled", 16, zeros);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof up, up);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof back, back);
    assert_int_equal(f->hazards, 0);
    for (int i = 0; i < 4; i++) assert_int_equal(back[i], up[i]);
    glDeleteBuffers(1, &b);
}

static void clear_covered_by_a_waited_fence_is_not_a_hazard(void **state)
{
    fixture *f = *state;
    reset(f);
    GLuint b = buffer_with("test.fenced", 16, NULL);
    glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, NULL);
    GLsync s = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    GLenum r = glClientWaitSync(s, GL_SYNC_FLUSH_COMMANDS_BIT, 10000000000ull);
    assert_true(r == GL_ALREADY_SIGNALED || r == GL_CONDITION_SATISFIED);
    glDeleteSync(s);
    uint32_t up[4] = { 5, 6, 7, 8 }, back[4] = { 0 };
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof up, up);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof back, back);
    assert_int_equal(f->hazards, 0);
    for (int i = 0; i < 4; i++) assert_int_equal(back[i], up[i]);
    glDeleteBuffers(1, &b);
}

static void pass_reading_without_a_storage_barrier_names_both_passes_and_the_buffer(void **state)
{
    fixture *f = *state;
    uint32_t zeros[4] = { 0 };
    GLuint data = buffer_with("test.data", 16, zeros), out = buffer_with("test.out", 16, zeros);
    GLuint w = compute("test/writer.comp", writer_src), r = compute("test/reader.comp", reader_src);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, data);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out);

    reset(f);
    glUseProgram(w);
    glDispatchCompute(1, 1, 1);
    glUseProgram(r);
    glDispatchCompute(1, 1, 1); // no barrier: a hazard
    assert_int_equal(f->hazards, 1);
    assert_non_null(strstr(f->last, "'test/reader.comp'"));
    assert_non_null(strstr(f->last, "'test/writer.comp'"));
    assert_non_null(strstr(f->last, "'test.data'"));
    assert_non_null(strstr(f->last, "GL_SHADER_STORAGE_BARRIER_BIT"));

    reset(f);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(w);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(r);
    glDispatchCompute(1, 1, 1);
    // A barrier of the wrong bit does not cover a readback.
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    uint32_t back[4];
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, out);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof back, back);
    assert_int_equal(f->hazards, 1);
    assert_non_null(strstr(f->last, "glGetBufferSubData"));
    assert_non_null(strstr(f->last, "GL_BUFFER_UPDATE_BARRIER_BIT"));

    reset(f);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof back, back);
    assert_int_equal(f->hazards, 0);
    for (int i = 0; i < 4; i++) assert_int_equal(back[i], 8);

    glUseProgram(0);
    glDeleteProgram(w);
    glDeleteProgram(r);
    glDeleteBuffers(1, &data);
    glDeleteBuffers(1, &out);
}

static void indirect_dispatch_needs_the_command_bit(void **state)
{
    fixture *f = *state;
    uint32_t cmd[4] = { 0 }, zeros[4] = { 0 };
    GLuint args = buffer_with("test.args", 16, cmd), out = buffer_with("test.out", 16, zeros);
    GLuint w = compute("test/args.comp",
                       "layout(std430, binding = 0) buffer Args { uint g[4]; };\n"
                       "void main() { if (gl_GlobalInvocationID.x == 0u) { g[0] = 1u; g[1] = 1u; g[2] = 1u; } }\n");
    GLuint r = compute("test/consumer.comp",
                       "layout(std430, binding = 1) buffer Out { uint o[]; };\n"
                       "void main() { o[gl_GlobalInvocationID.x] = 3u; }\n");
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, args);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, out);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, args);

    reset(f);
    glUseProgram(w);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT); // the wrong bit for a command
    glUseProgram(r);
    glDispatchComputeIndirect(0);
    assert_int_equal(f->hazards, 1);
    assert_non_null(strstr(f->last, "indirect command"));
    assert_non_null(strstr(f->last, "GL_COMMAND_BARRIER_BIT"));

    reset(f);
    glMemoryBarrier(GL_ALL_BARRIER_BITS); // covers the first round's writes of test.out
    glUseProgram(w);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_COMMAND_BARRIER_BIT);
    glUseProgram(r);
    glDispatchComputeIndirect(0);
    assert_int_equal(f->hazards, 0);

    glUseProgram(0);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
    glDeleteProgram(w);
    glDeleteProgram(r);
    glDeleteBuffers(1, &args);
    glDeleteBuffers(1, &out);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(gpu_clear_then_cpu_upload_is_caught_and_loses_the_upload_as_on_nvidia),
        cmocka_unit_test(buffer_created_with_its_data_is_not_a_hazard),
        cmocka_unit_test(clear_covered_by_a_waited_fence_is_not_a_hazard),
        cmocka_unit_test(pass_reading_without_a_storage_barrier_names_both_passes_and_the_buffer),
        cmocka_unit_test(indirect_dispatch_needs_the_command_bit),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
