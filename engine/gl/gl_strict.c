// The strict GL mode: hooks libepoxy's dispatch, defers clears, checks barriers. See gl_strict.h.
// Sequence numbers order every tracked GPU operation; a barrier or a completed fence covers
// everything numbered up to the moment it was issued.
#include "engine/gl/gl_strict.h"

#include <epoxy/gl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

// The barrier bits the tracker tells apart, in the order of `bit_names`.
enum { B_STORAGE, B_UNIFORM, B_COMMAND, B_VERTEX, B_ELEMENT, B_UPDATE, B_COUNT };
static const GLbitfield bit_values[B_COUNT] = {
    GL_SHADER_STORAGE_BARRIER_BIT, GL_UNIFORM_BARRIER_BIT, GL_COMMAND_BARRIER_BIT,
    GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT, GL_ELEMENT_ARRAY_BARRIER_BIT, GL_BUFFER_UPDATE_BARRIER_BIT,
};
static const char *const bit_names[B_COUNT] = {
    "GL_SHADER_STORAGE_BARRIER_BIT", "GL_UNIFORM_BARRIER_BIT", "GL_COMMAND_BARRIER_BIT",
    "GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT", "GL_ELEMENT_ARRAY_BARRIER_BIT", "GL_BUFFER_UPDATE_BARRIER_BIT",
};

typedef struct buffer_state {
    uint64_t shader_write;  // last write by a shader (0: none)
    uint64_t gpu_fill;      // last clear or copy into it
    GLuint writer;          // the program that wrote it last
    const char *writer_kind; // "dispatch", "draw", ...
} buffer_state;

typedef struct pending_clear {
    GLuint buffer;
    GLenum internal_format, format, type;
    GLintptr offset;
    GLsizeiptr size; // < 0: the whole buffer
    unsigned char data[16];
    bool has_data;
} pending_clear;

typedef struct block_use {
    GLint binding;
    bool written;
} block_use;

typedef struct program_info {
    GLuint name;
    bool analysed;
    char *source;  // the attached shaders' sources, kept at link time
    char *active;  // the same with the lines of inactive #if branches blanked
    block_use storage[32];
    int storage_count;
    GLint uniform[32];
    int uniform_count;
} program_info;

typedef struct fence_seq {
    GLsync sync;
    uint64_t seq;
} fence_seq;

// The driver's functions, and libepoxy's pointers as they were before installation.
#define HOOKED(X) \
    X(glDispatchCompute, PFNGLDISPATCHCOMPUTEPROC) \
    X(glDispatchComputeIndirect, PFNGLDISPATCHCOMPUTEINDIRECTPROC) \
    X(glDrawArrays, PFNGLDRAWARRAYSPROC) \
    X(glDrawElements, PFNGLDRAWELEMENTSPROC) \
    X(glDrawArraysInstanced, PFNGLDRAWARRAYSINSTANCEDPROC) \
    X(glDrawElementsInstanced, PFNGLDRAWELEMENTSINSTANCEDPROC) \
    X(glDrawArraysIndirect, PFNGLDRAWARRAYSINDIRECTPROC) \
    X(glDrawElementsIndirect, PFNGLDRAWELEMENTSINDIRECTPROC) \
    X(glMemoryBarrier, PFNGLMEMORYBARRIERPROC) \
    X(glClearBufferData, PFNGLCLEARBUFFERDATAPROC) \
    X(glClearBufferSubData, PFNGLCLEARBUFFERSUBDATAPROC) \
    X(glBufferData, PFNGLBUFFERDATAPROC) \
    X(glBufferSubData, PFNGLBUFFERSUBDATAPROC) \
    X(glGetBufferSubData, PFNGLGETBUFFERSUBDATAPROC) \
    X(glMapBufferRange, PFNGLMAPBUFFERRANGEPROC) \
    X(glMapBuffer, PFNGLMAPBUFFERPROC) \
    X(glCopyBufferSubData, PFNGLCOPYBUFFERSUBDATAPROC) \
    X(glFenceSync, PFNGLFENCESYNCPROC) \
    X(glClientWaitSync, PFNGLCLIENTWAITSYNCPROC) \
    X(glDeleteSync, PFNGLDELETESYNCPROC) \
    X(glFinish, PFNGLFINISHPROC) \
    X(glReadPixels, PFNGLREADPIXELSPROC) \
    X(glDeleteBuffers, PFNGLDELETEBUFFERSPROC) \
    X(glShaderSource, PFNGLSHADERSOURCEPROC) \
    X(glDeleteShader, PFNGLDELETESHADERPROC) \
    X(glLinkProgram, PFNGLLINKPROGRAMPROC) \
    X(glDeleteProgram, PFNGLDELETEPROGRAMPROC)

#define DECLARE(name, type) type real_##name; type saved_##name;
typedef struct strict_state {
    bool installed;
    HOOKED(DECLARE)
    uint64_t seq;
    uint64_t barrier[B_COUNT];
    uint64_t complete; // everything up to here is known finished (fence waited, glFinish)
    buffer_state *buffers;
    GLuint buffer_cap;
    pending_clear *clears;
    int clear_count, clear_cap;
    program_info *programs;
    int program_count, program_cap;
    char **shader_src;
    GLuint shader_cap;
    fence_seq fences[64];
    int fence_count;
    uint64_t hazards;
    eng_gl_strict_handler *handler;
    void *handler_user;
} strict_state;
#undef DECLARE

// libepoxy's dispatch is process-wide; so is this (gl_strict.h).
static strict_state S;

// ---- reporting ----------------------------------------------------------------------------

static void default_handler(void *user, const char *message)
{
    (void)user;
    fprintf(stderr, "seiche: %s\n", message);
    fflush(NULL);
    _exit(ENG_GL_EXIT_STATUS);
}

void eng_gl_fail(const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    S.hazards++;
    if (S.handler) S.handler(S.handler_user, msg);
    else default_handler(NULL, msg);
}

void eng_gl_strict_set_handler(eng_gl_strict_handler *handler, void *user,
                               eng_gl_strict_handler **old_handler, void **old_user)
{
    if (old_handler) *old_handler = S.handler;
    if (old_user) *old_user = S.handler_user;
    S.handler = handler;
    S.handler_user = user;
}

uint64_t eng_gl_strict_hazards(void) { return S.hazards; }
bool eng_gl_strict_installed(void) { return S.installed; }

bool eng_gl_strict_requested(void)
{
    const char *v = getenv("SEICHE_GL_STRICT");
    return v && strcmp(v, "1") == 0;
}

// "'label' (buffer 12)" or "buffer 12" when it has no label.
static const char *describe(GLenum kind, GLuint name, char *out, size_t size)
{
    char label[80] = "";
    GLsizei n = 0;
    if (name) glGetObjectLabel(kind, name, sizeof label, &n, label);
    const char *what = kind == GL_PROGRAM ? "program" : "buffer";
    if (n > 0) snprintf(out, size, "'%s' (%s %u)", label, what, name);
    else snprintf(out, size, "%s %u", what, name);
    return out;
}

// ---- per-object state ---------------------------------------------------------------------

static buffer_state *buffer(GLuint name)
{
    if (name >= S.buffer_cap) {
        GLuint cap = S.buffer_cap ? S.buffer_cap : 256;
        while (cap <= name) cap *= 2;
        buffer_state *b = realloc(S.buffers, cap * sizeof *b);
        if (!b) return NULL;
        memset(b + S.buffer_cap, 0, (cap - S.buffer_cap) * sizeof *b);
        S.buffers = b;
        S.buffer_cap = cap;
    }
    return &S.buffers[name];
}

static GLuint bound(GLenum target)
{
    GLenum q;
    switch (target) {
    case GL_ARRAY_BUFFER: q = GL_ARRAY_BUFFER_BINDING; break;
    case GL_ELEMENT_ARRAY_BUFFER: q = GL_ELEMENT_ARRAY_BUFFER_BINDING; break;
    case GL_UNIFORM_BUFFER: q = GL_UNIFORM_BUFFER_BINDING; break;
    case GL_SHADER_STORAGE_BUFFER: q = GL_SHADER_STORAGE_BUFFER_BINDING; break;
    case GL_COPY_READ_BUFFER: q = GL_COPY_READ_BUFFER_BINDING; break;
    case GL_COPY_WRITE_BUFFER: q = GL_COPY_WRITE_BUFFER_BINDING; break;
    case GL_DISPATCH_INDIRECT_BUFFER: q = GL_DISPATCH_INDIRECT_BUFFER_BINDING; break;
    case GL_DRAW_INDIRECT_BUFFER: q = GL_DRAW_INDIRECT_BUFFER_BINDING; break;
    case GL_PIXEL_PACK_BUFFER: q = GL_PIXEL_PACK_BUFFER_BINDING; break;
    case GL_PIXEL_UNPACK_BUFFER: q = GL_PIXEL_UNPACK_BUFFER_BINDING; break;
    case GL_QUERY_BUFFER: q = GL_QUERY_BUFFER_BINDING; break;
    case GL_TEXTURE_BUFFER: q = GL_TEXTURE_BUFFER_BINDING; break;
    case GL_TRANSFORM_FEEDBACK_BUFFER: q = GL_TRANSFORM_FEEDBACK_BUFFER_BINDING; break;
    case GL_ATOMIC_COUNTER_BUFFER: q = GL_ATOMIC_COUNTER_BUFFER_BINDING; break;
    default: return 0;
    }
    GLint b = 0;
    glGetIntegerv(q, &b);
    return (GLuint)b;
}

static program_info *program(GLuint name, bool create)
{
    for (int i = 0; i < S.program_count; i++)
        if (S.programs[i].name == name) return &S.programs[i];
    if (!create) return NULL;
    if (S.program_count == S.program_cap) {
        int cap = S.program_cap ? S.program_cap * 2 : 64;
        program_info *p = realloc(S.programs, (size_t)cap * sizeof *p);
        if (!p) return NULL;
        S.programs = p;
        S.program_cap = cap;
    }
    program_info *p = &S.programs[S.program_count++];
    memset(p, 0, sizeof *p);
    p->name = name;
    return p;
}

static void forget_program(GLuint name)
{
    program_info *p = program(name, false);
    if (!p) return;
    free(p->source);
    free(p->active);
    *p = S.programs[--S.program_count];
}

// The source with the lines of inactive #ifdef / #ifndef / #else branches blanked, so that
// declarations in branches the compiler skipped are not read. Only names defined with
// #define in the source itself are known; any other #if counts as taken.
static bool is_ident(char c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'; }

static char *active_source(const char *src)
{
    size_t n = strlen(src);
    char *out = malloc(n + 1);
    if (!out) return NULL;
    memcpy(out, src, n + 1);
    char defined[128][64];
    int ndef = 0;
    bool live[33] = { true }, taken[33] = { true };
    int depth = 0;
    for (char *line = out; *line;) {
        char *eol = strchr(line, '\n');
        size_t len = eol ? (size_t)(eol - line) : strlen(line);
        const char *q = line;
        while (q < line + len && (*q == ' ' || *q == '\t')) q++;
        char word[16] = "", name[64] = "";
        bool uses_defined = false;
        if (*q == '#') {
            q++;
            while (q < line + len && (*q == ' ' || *q == '\t')) q++;
            int k = 0;
            while (q < line + len && is_ident(*q) && k < 15) word[k++] = *q++;
            while (q < line + len && (*q == ' ' || *q == '\t' || *q == '(')) q++;
            if (strncmp(q, "defined", 7) == 0) {
                uses_defined = true;
                q += 7;
                while (q < line + len && (*q == ' ' || *q == '(')) q++;
            }
            k = 0;
            while (q < line + len && is_ident(*q) && k < 63) name[k++] = *q++;
        }
        bool is_def = false;
        for (int i = 0; i < ndef; i++)
            if (strcmp(defined[i], name) == 0) is_def = true;
        bool parent = live[depth];
        bool directive = word[0] != 0;
        if (strcmp(word, "ifdef") == 0 || strcmp(word, "ifndef") == 0 || strcmp(word, "if") == 0) {
            bool cond = strcmp(word, "ifdef") == 0    ? is_def
                      : strcmp(word, "ifndef") == 0 ? !is_def
                      : uses_defined                ? is_def
                                                    : true;
            if (depth < 32) {
                depth++;
                live[depth] = parent && cond;
                taken[depth] = cond;
            }
        } else if (strcmp(word, "elif") == 0 && depth > 0) {
            live[depth] = live[depth - 1] && !taken[depth];
            taken[depth] = true;
        } else if (strcmp(word, "else") == 0 && depth > 0) {
            live[depth] = live[depth - 1] && !taken[depth];
            taken[depth] = true;
        } else if (strcmp(word, "endif") == 0 && depth > 0) {
            depth--;
        } else if (strcmp(word, "define") == 0 && live[depth] && name[0] && !is_def && ndef < 128) {
            snprintf(defined[ndef++], sizeof defined[0], "%s", name);
        } else if (strcmp(word, "undef") == 0 && live[depth]) {
            for (int i = 0; i < ndef; i++)
                if (strcmp(defined[i], name) == 0) defined[i][0] = 0;
        }
        if (directive || !live[depth]) memset(line, ' ', len);
        line = eol ? eol + 1 : line + len;
    }
    return out;
}

// True when the source declares storage block `block` `readonly`: the qualifiers between
// the previous declaration's end (';', '}' or a preprocessor line) and "buffer <block>".
static bool declared_readonly(const char *src, const char *block)
{
    size_t n = strlen(block);
    for (const char *p = src ? strstr(src, block) : NULL; p; p = strstr(p + 1, block)) {
        const char *end = p + n;
        if ((*end >= 'A' && *end <= 'Z') || (*end >= 'a' && *end <= 'z') || (*end >= '0' && *end <= '9') || *end == '_')
            continue;
        const char *q = p;
        while (q > src && (q[-1] == ' ' || q[-1] == '\t' || q[-1] == '\n' || q[-1] == '\r')) q--;
        if (q - src < 6 || strncmp(q - 6, "buffer", 6) != 0) continue;
        const char *start = q - 6;
        while (start > src && start[-1] != ';' && start[-1] != '}' && !(start[-1] == '\n' && start[0] == '#')) start--;
        for (const char *r = start; r < q - 6; r++)
            if (strncmp(r, "readonly", 8) == 0) return true;
        return false;
    }
    return false;
}

static void analyse(program_info *p)
{
    p->analysed = true;
    free(p->active);
    p->active = p->source ? active_source(p->source) : NULL;
    p->storage_count = p->uniform_count = 0;
    GLint count = 0;
    glGetProgramInterfaceiv(p->name, GL_SHADER_STORAGE_BLOCK, GL_ACTIVE_RESOURCES, &count);
    for (GLint i = 0; i < count && p->storage_count < 32; i++) {
        char name[128] = "";
        glGetProgramResourceName(p->name, GL_SHADER_STORAGE_BLOCK, (GLuint)i, sizeof name, NULL, name);
        char *bracket = strchr(name, '[');
        if (bracket) *bracket = 0;
        GLenum prop = GL_BUFFER_BINDING;
        GLint binding = 0;
        glGetProgramResourceiv(p->name, GL_SHADER_STORAGE_BLOCK, (GLuint)i, 1, &prop, 1, NULL, &binding);
        p->storage[p->storage_count].binding = binding;
        p->storage[p->storage_count].written = !declared_readonly(p->active, name);
        p->storage_count++;
    }
    glGetProgramInterfaceiv(p->name, GL_UNIFORM_BLOCK, GL_ACTIVE_RESOURCES, &count);
    for (GLint i = 0; i < count && p->uniform_count < 32; i++) {
        GLenum prop = GL_BUFFER_BINDING;
        glGetProgramResourceiv(p->name, GL_UNIFORM_BLOCK, (GLuint)i, 1, &prop, 1, NULL, &p->uniform[p->uniform_count]);
        p->uniform_count++;
    }
}

// ---- deferred clears ------------------------------------------------------------------------

static void flush_clears(void)
{
    if (S.clear_count == 0) return;
    GLint old = 0;
    glGetIntegerv(GL_COPY_WRITE_BUFFER_BINDING, &old);
    for (int i = 0; i < S.clear_count; i++) {
        pending_clear *c = &S.clears[i];
        glBindBuffer(GL_COPY_WRITE_BUFFER, c->buffer);
        const void *data = c->has_data ? c->data : NULL;
        if (c->size < 0) S.real_glClearBufferData(GL_COPY_WRITE_BUFFER, c->internal_format, c->format, c->type, data);
        else S.real_glClearBufferSubData(GL_COPY_WRITE_BUFFER, c->internal_format, c->offset, c->size, c->format, c->type, data);
    }
    glBindBuffer(GL_COPY_WRITE_BUFFER, (GLuint)old);
    S.clear_count = 0;
}

static bool clear_deferred(GLuint name)
{
    for (int i = 0; i < S.clear_count; i++)
        if (S.clears[i].buffer == name) return true;
    return false;
}

static void defer_clear(GLenum target, GLenum internal_format, GLintptr offset, GLsizeiptr size, GLenum format,
                        GLenum type, const void *data)
{
    GLuint name = bound(target);
    if (!name) { // nothing bound: let the driver raise its error now
        if (size < 0) S.real_glClearBufferData(target, internal_format, format, type, data);
        else S.real_glClearBufferSubData(target, internal_format, offset, size, format, type, data);
        return;
    }
    if (S.clear_count == S.clear_cap) {
        int cap = S.clear_cap ? S.clear_cap * 2 : 32;
        pending_clear *c = realloc(S.clears, (size_t)cap * sizeof *c);
        if (!c) {
            flush_clears();
            if (size < 0) S.real_glClearBufferData(target, internal_format, format, type, data);
            else S.real_glClearBufferSubData(target, internal_format, offset, size, format, type, data);
            return;
        }
        S.clears = c;
        S.clear_cap = cap;
    }
    pending_clear *c = &S.clears[S.clear_count++];
    memset(c, 0, sizeof *c);
    c->buffer = name;
    c->internal_format = internal_format;
    c->format = format;
    c->type = type;
    c->offset = offset;
    c->size = size;
    if (data) { // one texel: at most 4 components of 4 bytes
        memcpy(c->data, data, sizeof c->data);
        c->has_data = true;
    }
    buffer_state *b = buffer(name);
    if (b) b->gpu_fill = ++S.seq;
}

// ---- checks ----------------------------------------------------------------------------------

static const char *pass_name(const char *kind, GLuint prog, char *out, size_t size)
{
    char p[128];
    snprintf(out, size, "%s with %s", kind, describe(GL_PROGRAM, prog, p, sizeof p));
    return out;
}

// A GPU pass (`kind` with `prog`, or a CPU call when prog is 0) reads buffer `name` as
// `use`, which needs barrier `bit` after a shader write.
static void check_read(GLuint name, int bit, const char *kind, GLuint prog, const char *use)
{
    buffer_state *b = name ? buffer(name) : NULL;
    if (!b || !b->shader_write) return;
    if (b->shader_write <= S.barrier[bit] || b->shader_write <= S.complete) return;
    char what[160], who[200], writer[200];
    if (prog) pass_name(kind, prog, who, sizeof who);
    else snprintf(who, sizeof who, "%s", kind);
    eng_gl_fail("GL strict: %s reads %s as %s, written by %s, with no glMemoryBarrier(%s) in between",
                who, describe(GL_BUFFER, name, what, sizeof what), use,
                pass_name(b->writer_kind, b->writer, writer, sizeof writer), bit_names[bit]);
}

// The CPU writes into buffer `name` (`call`).
static void check_upload(GLuint name, const char *call)
{
    buffer_state *b = name ? buffer(name) : NULL;
    if (!b) return;
    char what[160];
    if (clear_deferred(name) || b->gpu_fill > S.complete) {
        eng_gl_fail("GL strict: %s uploads into %s while a GPU clear or copy of it may still be pending "
                    "(no fence waited or glFinish since): a driver may apply the clear after the upload. "
                    "Create a buffer the CPU fills with its data (glBufferData) instead of clearing it on the GPU",
                    call, describe(GL_BUFFER, name, what, sizeof what));
        return;
    }
    char writer[200];
    if (b->shader_write > S.barrier[B_UPDATE] && b->shader_write > S.complete)
        eng_gl_fail("GL strict: %s uploads into %s, written by %s, with no glMemoryBarrier(%s) in between", call,
                    describe(GL_BUFFER, name, what, sizeof what),
                    pass_name(b->writer_kind, b->writer, writer, sizeof writer), bit_names[B_UPDATE]);
}

// The CPU (or a copy) reads buffer `name` (`call`).
static void check_readback(GLuint name, const char *call)
{
    check_read(name, B_UPDATE, call, 0, "a buffer read");
}

// Before a dispatch or draw: deferred clears land, the program's reads are checked, then
// its writes recorded.
static void before_pass(const char *kind, GLenum indirect_binding, bool draw, bool indexed)
{
    flush_clears();
    GLint prog = 0;
    glGetIntegerv(GL_CURRENT_PROGRAM, &prog);
    program_info *p = program((GLuint)prog, true);
    if (!p) return;
    if (!p->analysed) analyse(p);
    GLuint who = (GLuint)prog;
    for (int i = 0; i < p->storage_count; i++) {
        GLint b = 0;
        glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, (GLuint)p->storage[i].binding, &b);
        char use[64];
        snprintf(use, sizeof use, "storage block binding %d", p->storage[i].binding);
        check_read((GLuint)b, B_STORAGE, kind, who, use);
    }
    for (int i = 0; i < p->uniform_count; i++) {
        GLint b = 0;
        glGetIntegeri_v(GL_UNIFORM_BUFFER_BINDING, (GLuint)p->uniform[i], &b);
        char use[64];
        snprintf(use, sizeof use, "uniform block binding %d", p->uniform[i]);
        check_read((GLuint)b, B_UNIFORM, kind, who, use);
    }
    if (indirect_binding) {
        GLint b = 0;
        glGetIntegerv(indirect_binding, &b);
        check_read((GLuint)b, B_COMMAND, kind, who, "indirect command");
    }
    if (draw) {
        GLint attribs = 0;
        glGetIntegerv(GL_MAX_VERTEX_ATTRIBS, &attribs);
        for (GLint a = 0; a < attribs && a < 32; a++) {
            GLint on = 0, b = 0;
            glGetVertexAttribiv((GLuint)a, GL_VERTEX_ATTRIB_ARRAY_ENABLED, &on);
            if (!on) continue;
            glGetVertexAttribiv((GLuint)a, GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING, &b);
            check_read((GLuint)b, B_VERTEX, kind, who, "vertex attributes");
        }
        if (indexed) check_read(bound(GL_ELEMENT_ARRAY_BUFFER), B_ELEMENT, kind, who, "indices");
    }
    uint64_t seq = ++S.seq;
    for (int i = 0; i < p->storage_count; i++) {
        if (!p->storage[i].written) continue;
        GLint b = 0;
        glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, (GLuint)p->storage[i].binding, &b);
        buffer_state *st = b ? buffer((GLuint)b) : NULL;
        if (!st) continue;
        st->shader_write = seq;
        st->writer = who;
        st->writer_kind = kind;
    }
}

// ---- the hooks --------------------------------------------------------------------------------

static void GLAPIENTRY h_glDispatchCompute(GLuint x, GLuint y, GLuint z)
{
    before_pass("dispatch", 0, false, false);
    S.real_glDispatchCompute(x, y, z);
}

static void GLAPIENTRY h_glDispatchComputeIndirect(GLintptr offset)
{
    before_pass("indirect dispatch", GL_DISPATCH_INDIRECT_BUFFER_BINDING, false, false);
    S.real_glDispatchComputeIndirect(offset);
}

static void GLAPIENTRY h_glDrawArrays(GLenum mode, GLint first, GLsizei count)
{
    before_pass("draw", 0, true, false);
    S.real_glDrawArrays(mode, first, count);
}

static void GLAPIENTRY h_glDrawElements(GLenum mode, GLsizei count, GLenum type, const void *indices)
{
    before_pass("draw", 0, true, true);
    S.real_glDrawElements(mode, count, type, indices);
}

static void GLAPIENTRY h_glDrawArraysInstanced(GLenum mode, GLint first, GLsizei count, GLsizei n)
{
    before_pass("draw", 0, true, false);
    S.real_glDrawArraysInstanced(mode, first, count, n);
}

static void GLAPIENTRY h_glDrawElementsInstanced(GLenum mode, GLsizei count, GLenum type, const void *indices, GLsizei n)
{
    before_pass("draw", 0, true, true);
    S.real_glDrawElementsInstanced(mode, count, type, indices, n);
}

static void GLAPIENTRY h_glDrawArraysIndirect(GLenum mode, const void *indirect)
{
    before_pass("indirect draw", GL_DRAW_INDIRECT_BUFFER_BINDING, true, false);
    S.real_glDrawArraysIndirect(mode, indirect);
}

static void GLAPIENTRY h_glDrawElementsIndirect(GLenum mode, GLenum type, const void *indirect)
{
    before_pass("indirect draw", GL_DRAW_INDIRECT_BUFFER_BINDING, true, true);
    S.real_glDrawElementsIndirect(mode, type, indirect);
}

static void GLAPIENTRY h_glMemoryBarrier(GLbitfield bits)
{
    for (int i = 0; i < B_COUNT; i++)
        if (bits & bit_values[i]) S.barrier[i] = S.seq;
    S.real_glMemoryBarrier(bits);
}

static void GLAPIENTRY h_glClearBufferData(GLenum target, GLenum internal_format, GLenum format, GLenum type,
                                           const void *data)
{
    defer_clear(target, internal_format, 0, -1, format, type, data);
}

static void GLAPIENTRY h_glClearBufferSubData(GLenum target, GLenum internal_format, GLintptr offset,
                                              GLsizeiptr size, GLenum format, GLenum type, const void *data)
{
    defer_clear(target, internal_format, offset, size, format, type, data);
}

static void forget_buffer(GLuint name)
{
    for (int i = 0; i < S.clear_count;)
        if (S.clears[i].buffer == name) S.clears[i] = S.clears[--S.clear_count];
        else i++;
    buffer_state *b = name < S.buffer_cap ? &S.buffers[name] : NULL;
    if (b) memset(b, 0, sizeof *b);
}

static void GLAPIENTRY h_glBufferData(GLenum target, GLsizeiptr size, const void *data, GLenum usage)
{
    // New storage: whatever was pending or written belonged to the old one.
    GLuint name = bound(target);
    if (name) forget_buffer(name);
    S.real_glBufferData(target, size, data, usage);
}

static void GLAPIENTRY h_glBufferSubData(GLenum target, GLintptr offset, GLsizeiptr size, const void *data)
{
    check_upload(bound(target), "glBufferSubData");
    S.real_glBufferSubData(target, offset, size, data);
}

static void GLAPIENTRY h_glGetBufferSubData(GLenum target, GLintptr offset, GLsizeiptr size, void *data)
{
    flush_clears();
    check_readback(bound(target), "glGetBufferSubData");
    S.real_glGetBufferSubData(target, offset, size, data);
}

static void check_map(GLenum target, GLbitfield access, const char *call)
{
    flush_clears();
    GLuint name = bound(target);
    if (access & GL_MAP_READ_BIT) check_readback(name, call);
    if ((access & GL_MAP_WRITE_BIT) && !(access & (GL_MAP_INVALIDATE_BUFFER_BIT | GL_MAP_INVALIDATE_RANGE_BIT)))
        check_upload(name, call);
}

static void *GLAPIENTRY h_glMapBufferRange(GLenum target, GLintptr offset, GLsizeiptr length, GLbitfield access)
{
    check_map(target, access, "glMapBufferRange");
    return S.real_glMapBufferRange(target, offset, length, access);
}

static void *GLAPIENTRY h_glMapBuffer(GLenum target, GLenum access)
{
    GLbitfield bits = access == GL_READ_ONLY ? GL_MAP_READ_BIT
                    : access == GL_WRITE_ONLY ? GL_MAP_WRITE_BIT : GL_MAP_READ_BIT | GL_MAP_WRITE_BIT;
    check_map(target, bits, "glMapBuffer");
    return S.real_glMapBuffer(target, access);
}

static void GLAPIENTRY h_glCopyBufferSubData(GLenum read_target, GLenum write_target, GLintptr read_offset,
                                             GLintptr write_offset, GLsizeiptr size)
{
    flush_clears();
    check_readback(bound(read_target), "glCopyBufferSubData");
    S.real_glCopyBufferSubData(read_target, write_target, read_offset, write_offset, size);
    GLuint dst = bound(write_target);
    buffer_state *b = dst ? buffer(dst) : NULL;
    if (b) b->gpu_fill = ++S.seq;
}

static GLsync GLAPIENTRY h_glFenceSync(GLenum condition, GLbitfield flags)
{
    flush_clears();
    GLsync s = S.real_glFenceSync(condition, flags);
    if (s) {
        if (S.fence_count == (int)(sizeof S.fences / sizeof S.fences[0])) {
            memmove(S.fences, S.fences + 1, sizeof S.fences - sizeof S.fences[0]);
            S.fence_count--;
        }
        S.fences[S.fence_count].sync = s;
        S.fences[S.fence_count].seq = S.seq;
        S.fence_count++;
    }
    return s;
}

static GLenum GLAPIENTRY h_glClientWaitSync(GLsync sync, GLbitfield flags, GLuint64 timeout)
{
    GLenum r = S.real_glClientWaitSync(sync, flags, timeout);
    if (r == GL_ALREADY_SIGNALED || r == GL_CONDITION_SATISFIED)
        for (int i = 0; i < S.fence_count; i++)
            if (S.fences[i].sync == sync && S.fences[i].seq > S.complete) S.complete = S.fences[i].seq;
    return r;
}

static void GLAPIENTRY h_glDeleteSync(GLsync sync)
{
    for (int i = 0; i < S.fence_count; i++)
        if (S.fences[i].sync == sync) {
            memmove(S.fences + i, S.fences + i + 1, (size_t)(S.fence_count - i - 1) * sizeof S.fences[0]);
            S.fence_count--;
            break;
        }
    S.real_glDeleteSync(sync);
}

static void GLAPIENTRY h_glFinish(void)
{
    flush_clears();
    S.real_glFinish();
    S.complete = S.seq;
}

static void GLAPIENTRY h_glReadPixels(GLint x, GLint y, GLsizei w, GLsizei h, GLenum format, GLenum type, void *data)
{
    flush_clears();
    S.real_glReadPixels(x, y, w, h, format, type, data);
}

static void GLAPIENTRY h_glDeleteBuffers(GLsizei n, const GLuint *names)
{
    for (GLsizei i = 0; names && i < n; i++) forget_buffer(names[i]);
    S.real_glDeleteBuffers(n, names);
}

static void GLAPIENTRY h_glShaderSource(GLuint shader, GLsizei count, const GLchar *const *strings, const GLint *lengths)
{
    S.real_glShaderSource(shader, count, strings, lengths);
    if (shader >= S.shader_cap) {
        GLuint cap = S.shader_cap ? S.shader_cap : 64;
        while (cap <= shader) cap *= 2;
        char **p = realloc(S.shader_src, cap * sizeof *p);
        if (!p) return;
        memset(p + S.shader_cap, 0, (cap - S.shader_cap) * sizeof *p);
        S.shader_src = p;
        S.shader_cap = cap;
    }
    size_t total = 1;
    for (GLsizei i = 0; i < count; i++) total += lengths && lengths[i] >= 0 ? (size_t)lengths[i] : strlen(strings[i]);
    char *text = malloc(total);
    if (!text) return;
    size_t len = 0;
    for (GLsizei i = 0; i < count; i++) {
        size_t n = lengths && lengths[i] >= 0 ? (size_t)lengths[i] : strlen(strings[i]);
        memcpy(text + len, strings[i], n);
        len += n;
    }
    text[len] = 0;
    free(S.shader_src[shader]);
    S.shader_src[shader] = text;
}

// A linked program keeps its own copy of the sources: the shader's can go. (Kept, every
// world made and destroyed grew this table by its shaders' text: 0.5 MB each.)
static void GLAPIENTRY h_glDeleteShader(GLuint shader)
{
    if (shader < S.shader_cap) {
        free(S.shader_src[shader]);
        S.shader_src[shader] = NULL;
    }
    S.real_glDeleteShader(shader);
}

static void GLAPIENTRY h_glLinkProgram(GLuint prog)
{
    S.real_glLinkProgram(prog);
    program_info *p = program(prog, true);
    if (!p) return;
    free(p->source);
    p->source = NULL;
    p->analysed = false;
    GLuint shaders[8];
    GLsizei n = 0;
    glGetAttachedShaders(prog, 8, &n, shaders);
    size_t total = 1;
    for (GLsizei i = 0; i < n; i++)
        if (shaders[i] < S.shader_cap && S.shader_src[shaders[i]]) total += strlen(S.shader_src[shaders[i]]) + 1;
    p->source = malloc(total);
    if (!p->source) return;
    p->source[0] = 0;
    for (GLsizei i = 0; i < n; i++)
        if (shaders[i] < S.shader_cap && S.shader_src[shaders[i]]) {
            strcat(p->source, S.shader_src[shaders[i]]);
            strcat(p->source, "\n");
        }
}

static void GLAPIENTRY h_glDeleteProgram(GLuint prog)
{
    forget_program(prog);
    S.real_glDeleteProgram(prog);
}

// ---- installation -----------------------------------------------------------------------------

bool eng_gl_strict_install(eng_gl_get_proc *get_proc, char *err, size_t err_size)
{
    if (S.installed) return true;
    if (!get_proc) {
        snprintf(err, err_size, "eng_gl_strict_install: get_proc must not be NULL");
        return false;
    }
#define RESOLVE(name, type) \
    S.real_##name = (type)get_proc(#name); \
    if (!S.real_##name) { \
        snprintf(err, err_size, "GL strict mode: the driver does not give %s", #name); \
        return false; \
    }
    HOOKED(RESOLVE)
#undef RESOLVE
#define SWAP(name, type) \
    S.saved_##name = epoxy_##name; \
    epoxy_##name = h_##name;
    HOOKED(SWAP)
#undef SWAP
    S.installed = true;
    return true;
}

void eng_gl_strict_uninstall(void)
{
    if (!S.installed) return;
    flush_clears();
#define RESTORE(name, type) epoxy_##name = S.saved_##name;
    HOOKED(RESTORE)
#undef RESTORE
    for (int i = 0; i < S.program_count; i++) {
        free(S.programs[i].source);
        free(S.programs[i].active);
    }
    for (GLuint i = 0; i < S.shader_cap; i++) free(S.shader_src[i]);
    free(S.programs);
    free(S.shader_src);
    free(S.buffers);
    free(S.clears);
    eng_gl_strict_handler *h = S.handler;
    void *u = S.handler_user;
    uint64_t hazards = S.hazards;
    memset(&S, 0, sizeof S);
    S.handler = h;
    S.handler_user = u;
    S.hazards = hazards;
}
