// GLSL loading with #include and #line mapping. See pbf_glsl.h.
#include "fluid/pbf_glsl.h"

#include <ctype.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// Mesa (22.x) reports the wrong source-string number for many errors (a bison location
// default that does not copy it), while its line numbers are right. So each file's lines
// are also numbered from id * LINE_STRIDE, and the file is recovered from the line.
#define LINE_STRIDE 100000

typedef struct text {
    char *data;
    size_t len, cap;
    bool too_long; // PBF_GLSL_MAX_SOURCE reached
} text;

static int text_put(text *t, const char *s, size_t n)
{
    if (n > PBF_GLSL_MAX_SOURCE || t->len + n > PBF_GLSL_MAX_SOURCE) {
        t->too_long = true;
        return 0;
    }
    if (t->len + n + 1 > t->cap) {
        size_t cap = t->cap ? t->cap : 4096;
        while (cap < t->len + n + 1) cap *= 2;
        char *d = realloc(t->data, cap);
        if (!d) return 0;
        t->data = d;
        t->cap = cap;
    }
    memcpy(t->data + t->len, s, n);
    t->len += n;
    t->data[t->len] = 0;
    return 1;
}

static int text_printf(text *t, const char *fmt, ...)
{
    char buf[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    return n >= 0 && (size_t)n < sizeof buf && text_put(t, buf, (size_t)n);
}

static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *s = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (s && fread(s, 1, (size_t)n, f) != (size_t)n) {
        free(s);
        s = NULL;
    }
    if (s) s[n] = 0;
    fclose(f);
    return s;
}

// A source file's text (malloc'd), from the directory or the embedded table; NULL if absent.
static char *load_source(const pbf_glsl_source *src, const char *rel)
{
    if (src->dir) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", src->dir, rel);
        return read_file(path);
    }
    for (int i = 0; i < src->file_count; i++)
        if (strcmp(src->files[i].name, rel) == 0) return strdup(src->files[i].text);
    return NULL;
}

static bool source_exists(const pbf_glsl_source *src, const char *rel)
{
    if (src->dir) {
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", src->dir, rel);
        FILE *f = fopen(path, "rb");
        if (f) fclose(f);
        return f != NULL;
    }
    for (int i = 0; i < src->file_count; i++)
        if (strcmp(src->files[i].name, rel) == 0) return true;
    return false;
}

// The name shown in messages for the shader directory: its last path component
// ("shaders" for embedded sources).
static const char *root_name(const char *dir, char *buf, size_t size)
{
    if (!dir) {
        snprintf(buf, size, "shaders");
        return buf;
    }
    size_t n = strlen(dir);
    while (n > 1 && dir[n - 1] == '/') n--;
    size_t b = n;
    while (b > 0 && dir[b - 1] != '/') b--;
    snprintf(buf, size, "%.*s", (int)(n - b), dir + b);
    return buf;
}

// Joins `dir_of` (a file relative to the root; its directory is used) and `name`,
// folding "./" and "../" so that one file always gets one id.
static void join_rel(const char *dir_of, const char *name, char *out, size_t size)
{
    char tmp[512];
    const char *slash = dir_of ? strrchr(dir_of, '/') : NULL;
    if (slash) snprintf(tmp, sizeof tmp, "%.*s/%s", (int)(slash - dir_of), dir_of, name);
    else snprintf(tmp, sizeof tmp, "%s", name);
    // Normalise the components.
    char *parts[64];
    int np = 0;
    for (char *p = strtok(tmp, "/"); p && np < 64; p = strtok(NULL, "/")) {
        if (strcmp(p, ".") == 0) continue;
        if (strcmp(p, "..") == 0) {
            if (np > 0) np--;
            continue;
        }
        parts[np++] = p;
    }
    out[0] = 0;
    size_t len = 0;
    for (int i = 0; i < np; i++) {
        int w = snprintf(out + len, size - len, "%s%s", i ? "/" : "", parts[i]);
        if (w < 0 || (size_t)w >= size - len) break;
        len += (size_t)w;
    }
}

typedef struct pp_state {
    const pbf_glsl_source *src;
    const char *shown_root;
    const char *defines;
    char **files;
    int *file_count;
    char *err;
    size_t err_size;
    int version_seen;
} pp_state;

static int file_id(pp_state *st, const char *rel)
{
    for (int i = 0; i < *st->file_count; i++)
        if (strcmp(st->files[i], rel) == 0) return i;
    if (*st->file_count >= PBF_GLSL_MAX_FILES) return -1;
    st->files[*st->file_count] = strdup(rel);
    return (*st->file_count)++;
}

static int expand(pp_state *st, text *out, const char *rel, const char *from, int from_line,
                  int depth)
{
    if (depth > PBF_GLSL_MAX_INCLUDE_DEPTH) {
        snprintf(st->err, st->err_size, "%s/%s:%d: error: includes nested deeper than %d (a cycle?)",
                 st->shown_root, from, from_line, PBF_GLSL_MAX_INCLUDE_DEPTH);
        return 0;
    }
    char *src = load_source(st->src, rel);
    if (!src) {
        if (from)
            snprintf(st->err, st->err_size, "%s/%s:%d: error: cannot open included file '%s/%s'",
                     st->shown_root, from, from_line, st->shown_root, rel);
        else if (st->src->dir)
            snprintf(st->err, st->err_size, "%s/%s: error: cannot open shader file (looked in '%s/%s')",
                     st->shown_root, rel, st->src->dir, rel);
        else
            snprintf(st->err, st->err_size, "%s/%s: error: no such shader among the %d embedded in the library",
                     st->shown_root, rel, st->src->file_count);
        return 0;
    }
    int id = file_id(st, rel);
    if (id < 0) {
        snprintf(st->err, st->err_size, "%s/%s: error: more than %d files in one shader",
                 st->shown_root, rel, PBF_GLSL_MAX_FILES);
        free(src);
        return 0;
    }
    int ok = 1;
    int line = 1;
    if (st->version_seen) ok = text_printf(out, "#line %d %d\n", id * LINE_STRIDE + 1, id);
    for (char *p = src; *p && ok; line++) {
        char *eol = strchr(p, '\n');
        size_t n = eol ? (size_t)(eol - p) : strlen(p);
        const char *q = p;
        while (q < p + n && isspace((unsigned char)*q)) q++;
        const char *angle = strncmp(q, "#include", 8) == 0 ? strchr(q, '<') : NULL;
        if (angle && angle < p + n && !memchr(q, '"', (size_t)(angle - q))) {
            // A system include belongs to the C side of a shared header: GLSL has none.
            ok = text_printf(out, "// (C only) %.*s\n", (int)(p + n - q), q);
        } else if (strncmp(q, "#include", 8) == 0) {
            const char *a = strchr(q, '"');
            const char *b = a ? strchr(a + 1, '"') : NULL;
            if (!a || !b || b > p + n) {
                snprintf(st->err, st->err_size, "%s/%s:%d: error: malformed #include (expected #include \"file\")",
                         st->shown_root, rel, line);
                ok = 0;
                break;
            }
            char name[256], inc[512];
            snprintf(name, sizeof name, "%.*s", (int)(b - a - 1), a + 1);
            join_rel(rel, name, inc, sizeof inc);
            if (!source_exists(st->src, inc)) join_rel(NULL, name, inc, sizeof inc); // fall back to the root
            ok = expand(st, out, inc, rel, line, depth + 1) &&
                 text_printf(out, "#line %d %d\n", id * LINE_STRIDE + line + 1, id);
        } else if (strncmp(q, "#version", 8) == 0 && !st->version_seen) {
            st->version_seen = 1;
            ok = text_put(out, p, n) && text_put(out, "\n", 1);
            if (ok && st->defines) ok = text_put(out, st->defines, strlen(st->defines));
            if (ok) ok = text_printf(out, "#line %d %d\n", id * LINE_STRIDE + line + 1, id);
        } else {
            ok = text_put(out, p, n) && text_put(out, "\n", 1);
        }
        p = eol ? eol + 1 : p + n;
    }
    free(src);
    if (!ok && !st->err[0] && out->too_long)
        snprintf(st->err, st->err_size, "%s/%s:%d: error: the shader expands to more than %d bytes (a file included "
                 "over and over?)", st->shown_root, rel, line, PBF_GLSL_MAX_SOURCE);
    if (!ok && !st->err[0]) snprintf(st->err, st->err_size, "%s/%s: error: out of memory", st->shown_root, rel);
    return ok;
}

char *pbf_glsl_preprocess(const char *shader_dir, const char *file, const char *defines,
                          char *files[PBF_GLSL_MAX_FILES], int *file_count,
                          char *err, size_t err_size)
{
    pbf_glsl_source src = { shader_dir ? shader_dir : "", NULL, 0 };
    return pbf_glsl_preprocess_from(&src, file, defines, files, file_count, err, err_size);
}

char *pbf_glsl_preprocess_from(const pbf_glsl_source *src, const char *file, const char *defines,
                               char *files[PBF_GLSL_MAX_FILES], int *file_count,
                               char *err, size_t err_size)
{
    char shown[256], scratch[256];
    if (!err || !err_size) { // no room for a message: keep it here
        err = scratch;
        err_size = sizeof scratch;
    }
    pp_state st = { src, root_name(src->dir, shown, sizeof shown), defines,
                    files, file_count, err, err_size, 0 };
    text out = { 0 };
    err[0] = 0;
    *file_count = 0;
    if (!expand(&st, &out, file, NULL, 0, 0)) {
        free(out.data);
        return NULL;
    }
    if (!st.version_seen) {
        snprintf(err, err_size, "%s/%s:1: error: shader has no #version line", shown, file);
        free(out.data);
        return NULL;
    }
    return out.data;
}

void pbf_glsl_free_files(char *files[PBF_GLSL_MAX_FILES], int file_count)
{
    for (int i = 0; i < file_count; i++) {
        free(files[i]);
        files[i] = NULL;
    }
}

void pbf_glsl_map_log(const char *log, char *const *files, int file_count,
                      const char *shown_root, char *out, size_t out_size)
{
    size_t len = 0;
    if (!out || !out_size) return;
    out[0] = 0;
    if (!log) return;
    for (const char *p = log; *p;) {
        const char *eol = strchr(p, '\n');
        size_t n = eol ? (size_t)(eol - p) : strlen(p);
        int fid = -1, line = -1, consumed = 0;
        // Mesa: "0:12(5): error: ..."   NVIDIA: "0(12) : error C0000: ..."
        if (sscanf(p, "%d:%d(%*d): %n", &fid, &line, &consumed) < 2 || consumed == 0) {
            consumed = 0;
            if (sscanf(p, "%d(%d) : %n", &fid, &line, &consumed) < 2 || consumed == 0) consumed = 0;
        }
        // The blank after ':' in the formats also matches newlines: the message starts
        // on this line or not at all.
        if ((size_t)consumed > n) consumed = (int)n;
        if (consumed > 0 && line >= LINE_STRIDE) { // the file from the line (see LINE_STRIDE)
            fid = line / LINE_STRIDE;
            line %= LINE_STRIDE;
        }
        int w;
        if (consumed > 0 && fid >= 0 && fid < file_count)
            w = snprintf(out + len, out_size - len, "%s/%s:%d: %.*s\n", shown_root, files[fid],
                         line, (int)(n - (size_t)consumed), p + consumed);
        else if (n > 0)
            w = snprintf(out + len, out_size - len, "%.*s\n", (int)n, p);
        else
            w = 0;
        if (w < 0 || (size_t)w >= out_size - len) break;
        len += (size_t)w;
        p = eol ? eol + 1 : p + n;
    }
    while (len > 0 && out[len - 1] == '\n') out[--len] = 0;
}

GLuint pbf_glsl_build(const char *shader_dir, const pbf_glsl_stage *stages, int count,
                      const char *defines, char *err, size_t err_size)
{
    pbf_glsl_source src = { shader_dir ? shader_dir : "", NULL, 0 };
    return pbf_glsl_build_from(&src, stages, count, defines, err, err_size);
}

GLuint pbf_glsl_build_from(const pbf_glsl_source *source, const pbf_glsl_stage *stages, int count,
                           const char *defines, char *err, size_t err_size)
{
    char shown[256], scratch[256];
    if (!err || !err_size) {
        err = scratch;
        err_size = sizeof scratch;
    }
    root_name(source->dir, shown, sizeof shown);
    GLuint prog = glCreateProgram();
    GLuint shaders[8] = { 0 };
    int ok = count > 0 && count <= 8;
    if (!ok) snprintf(err, err_size, "pbf_glsl_build: count must be 1..8 (got %d)", count);
    for (int i = 0; ok && i < count; i++) {
        char *files[PBF_GLSL_MAX_FILES] = { 0 };
        int nfiles = 0;
        char *src = pbf_glsl_preprocess_from(source, stages[i].file, defines, files, &nfiles, err, err_size);
        if (!src) {
            pbf_glsl_free_files(files, nfiles);
            ok = 0;
            break;
        }
        GLuint sh = glCreateShader(stages[i].type);
        shaders[i] = sh;
        glObjectLabel(GL_SHADER, sh, -1, stages[i].file);
        const GLchar *s = src;
        glShaderSource(sh, 1, &s, NULL);
        glCompileShader(sh);
        GLint status = 0;
        glGetShaderiv(sh, GL_COMPILE_STATUS, &status);
        if (!status) {
            GLint loglen = 0;
            glGetShaderiv(sh, GL_INFO_LOG_LENGTH, &loglen);
            char *log = malloc((size_t)loglen + 1);
            if (log) {
                log[0] = 0;
                glGetShaderInfoLog(sh, loglen, NULL, log);
                pbf_glsl_map_log(log, files, nfiles, shown, err, err_size);
                free(log);
            }
            if (!err[0]) snprintf(err, err_size, "%s/%s: error: compile failed (no log)", shown, stages[i].file);
            ok = 0;
        } else {
            glAttachShader(prog, sh);
        }
        free(src);
        pbf_glsl_free_files(files, nfiles);
    }
    if (ok) {
        glLinkProgram(prog);
        GLint status = 0;
        glGetProgramiv(prog, GL_LINK_STATUS, &status);
        if (!status) {
            char log[2048] = { 0 };
            glGetProgramInfoLog(prog, sizeof log, NULL, log);
            snprintf(err, err_size, "%s/%s: link error: %s", shown, stages[0].file, log);
            ok = 0;
        }
    }
    for (int i = 0; i < count && i < 8; i++)
        if (shaders[i]) glDeleteShader(shaders[i]);
    if (!ok) {
        glDeleteProgram(prog);
        return 0;
    }
    glObjectLabel(GL_PROGRAM, prog, -1, stages[0].file);
    err[0] = 0;
    return prog;
}
