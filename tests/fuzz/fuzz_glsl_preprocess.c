// libFuzzer harness: the GLSL loader's text handling (fluid/pbf_glsl.h), no GL needed.
// Each input is a set of shader files held in an in-memory pbf_glsl_source table (names
// from a small list with nested directories, "..", "." and odd characters; texts with
// #include lines quoted and angled, cycles, fan-outs, #version anywhere or nowhere), the
// defines string, a driver info log in Mesa's and NVIDIA's formats, and the output sizes.
// It runs pbf_glsl_preprocess_from and pbf_glsl_map_log on them.
//
// Besides crashes, leaks, hangs and undefined behaviour (the sanitizers), it checks:
// - preprocess returns a string or NULL with a message in err, NUL-terminated within
//   err_size (err and out are allocated with exactly their size, so writes past are caught);
// - at most PBF_GLSL_MAX_FILES files are reported, each one of the table's names;
// - map_log's output is NUL-terminated within out_size, one line per log line at most.
// Build and run: make fuzz (docs/testing.md).
#include "fluid/pbf_glsl.h"
#include "tests/fuzz/fuzz_input.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const names[] = {
    "a.comp", "b.glsl", "dir/c.glsl", "dir/sub/d.h", "e", "dir/../f.glsl", "./g.glsl", "h h.glsl", "dir/", "",
    "fluid/predict.comp", "fluid/common.glsl", "x/y/z/w/v/u.glsl", "\"q\".glsl", "%s%n.glsl",
};
#define NAME_COUNT (sizeof names / sizeof names[0])
#define MAX_TABLE 12

// Lines that exercise the preprocessor, picked by the input between raw bytes.
static const char *const lines[] = {
    "#version 430\n", "#version 430 core\n", "  #version 450\n", "#include \"b.glsl\"\n", "#include \"dir/c.glsl\"\n",
    "#include \"sub/d.h\"\n", "#include \"../f.glsl\"\n", "#include \"a.comp\"\n", "#include <stdint.h>\n",
    "#include \"unterminated\n", "#include\n", "#include \"\"\n", "#include <a.comp\" \"b.glsl\">\n",
    "  #include \"e\" // comment\n", "void main() {}\n", "#line 5 2\n", "\n", "#include \"f.glsl\"\n",
    "#include \"../../../../../etc/passwd\"\n", "#include \"dir/sub/../../b.glsl\"\n",
};
#define LINE_COUNT (sizeof lines / sizeof lines[0])

// Appends to a growing text: fuzzer-picked lines and raw runs of bytes (no NUL).
static void make_text(fuzz_input *in, char *out, size_t cap)
{
    size_t len = 0;
    int pieces = fuzz_u8(in) % 16;
    for (int i = 0; i < pieces; i++) {
        uint8_t pick = fuzz_u8(in);
        const char *piece;
        char raw[64];
        if (pick < 200) {
            piece = lines[pick % LINE_COUNT];
        } else {
            size_t n = fuzz_u8(in) % (sizeof raw - 1);
            fuzz_bytes(in, raw, n);
            for (size_t k = 0; k < n; k++)
                if (!raw[k]) raw[k] = '\n';
            raw[n] = 0;
            piece = raw;
        }
        size_t n = strlen(piece);
        if (len + n + 1 > cap) break;
        memcpy(out + len, piece, n);
        len += n;
    }
    out[len] = 0;
}

// A driver log: lines in Mesa's "F:L(C): msg" and NVIDIA's "F(L) : msg" formats with
// fuzzer numbers (negative, huge, file ids past the table, lines past the stride), and raw.
static void make_log(fuzz_input *in, char *out, size_t cap)
{
    size_t len = 0;
    int n_lines = fuzz_u8(in) % 12;
    for (int i = 0; i < n_lines && len + 1 < cap; i++) {
        char line[256];
        int32_t fid = (int32_t)fuzz_u32(in), ln = (int32_t)fuzz_u32(in);
        uint8_t form = fuzz_u8(in);
        if (form % 4 != 3) {
            // Small numbers most of the time.
            if (form & 16) fid = (int32_t)((uint32_t)fid % 40u);
            if (form & 32) ln = (int32_t)((uint32_t)ln % 400000u);
        }
        switch (form % 4) {
        case 0: snprintf(line, sizeof line, "%d:%d(%d): error: %s\n", fid, ln, (int)(form >> 2), "x undeclared"); break;
        case 1: snprintf(line, sizeof line, "%d(%d) : error C0000: %s\n", fid, ln, "syntax error"); break;
        case 2: snprintf(line, sizeof line, "%d:%d(%d): %s", fid, ln, (int)(form >> 2), form & 64 ? "\n\n" : " \n"); break;
        default: {
            size_t k = fuzz_u8(in) % 80;
            fuzz_bytes(in, line, k);
            for (size_t j = 0; j < k; j++)
                if (!line[j]) line[j] = ' ';
            line[k] = 0;
            break;
        }
        }
        size_t k = strlen(line);
        if (len + k + 1 > cap) break;
        memcpy(out + len, line, k);
        len += k;
    }
    out[len] = 0;
}

static void check_terminated(const char *buf, size_t size, const char *what)
{
    if (size > 0 && !memchr(buf, 0, size)) {
        fprintf(stderr, "%s is not NUL-terminated within its size %zu\n", what, size);
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = { data, size };
    pbf_glsl_file table[MAX_TABLE];
    char texts[MAX_TABLE][1024];
    int count = 1 + fuzz_u8(&in) % MAX_TABLE;
    for (int i = 0; i < count; i++) {
        table[i].name = names[fuzz_u8(&in) % NAME_COUNT];
        make_text(&in, texts[i], sizeof texts[i]);
        table[i].text = texts[i];
    }
    pbf_glsl_source src = { NULL, table, count };
    char defines[128];
    make_text(&in, defines, sizeof defines);
    size_t err_size = fuzz_u8(&in);
    if (err_size > 64) err_size = 512;
    char *err = fuzz_alloc_exact(err_size);
    const char *entry = fuzz_bool(&in) ? names[fuzz_u8(&in) % NAME_COUNT] : table[0].name;

    char *files[PBF_GLSL_MAX_FILES] = { 0 };
    int file_count = -1;
    char *out = pbf_glsl_preprocess_from(&src, entry, fuzz_bool(&in) ? defines : NULL, files, &file_count, err,
                                         err_size);
    if (file_count < 0 || file_count > PBF_GLSL_MAX_FILES) {
        fprintf(stderr, "file_count %d\n", file_count);
        abort();
    }
    for (int i = 0; i < file_count; i++) {
        bool known = false;
        for (int k = 0; k < count; k++) known |= files[i] && strcmp(files[i], table[k].name) == 0;
        if (!known) {
            fprintf(stderr, "files[%d] = \"%s\" is not in the table\n", i, files[i] ? files[i] : "(null)");
            abort();
        }
    }
    if (!out) {
        check_terminated(err, err_size, "err");
        if (err_size > 1 && !err[0]) {
            fprintf(stderr, "preprocess failed without a message\n");
            abort();
        }
    }

    // The driver's log mapped back through the files found (or fuzzer-named ones).
    char log[2048];
    make_log(&in, log, sizeof log);
    char *fake[4] = { (char *)"a.comp", (char *)"b.glsl", (char *)"", (char *)"dir/c.glsl" };
    bool use_fake = out == NULL || fuzz_bool(&in);
    size_t out_size = fuzz_u8(&in);
    if (out_size > 128) out_size = 4096;
    char *mapped = fuzz_alloc_exact(out_size);
    pbf_glsl_map_log(log, use_fake ? fake : files, use_fake ? 4 : file_count, fuzz_bool(&in) ? "shaders" : "",
                     mapped, out_size);
    check_terminated(mapped, out_size, "map_log's output");
    // One output line per non-empty log line at most (a line is rewritten, never repeated).
    if (out_size > 0) {
        int in_lines = 0, out_lines = mapped[0] ? 1 : 0;
        for (const char *p = log; *p; p++)
            if (*p != '\n' && (p[1] == '\n' || p[1] == 0)) in_lines++;
        for (const char *p = mapped; *p; p++) out_lines += *p == '\n';
        if (out_lines > in_lines) {
            fprintf(stderr, "map_log made %d lines of a log of %d:\n--- log\n%s\n--- mapped\n%s\n", out_lines,
                    in_lines, log, mapped);
            abort();
        }
    }
    fuzz_free_exact(mapped, out_size);

    free(out);
    pbf_glsl_free_files(files, file_count);
    fuzz_free_exact(err, err_size);
    return 0;
}
