// GLSL program loading for Seiche: files from a shader directory or from a table of
// sources embedded in the library at build time, `#include "file"` expanded recursively, and compiler messages mapped back to the file and line they
// came from ("shaders/fluid/density.comp:42: error: ..."), whatever the driver's format.
//
// Only needs a current GL 4.3 context and libepoxy. Used by the fluid core and the engine.
#ifndef PBF_GLSL_H
#define PBF_GLSL_H

#include <epoxy/gl.h>
#include <stddef.h>

#define PBF_GLSL_MAX_FILES 32
#define PBF_GLSL_MAX_INCLUDE_DEPTH 8
/// Bytes a shader may expand to with its includes (a file included over and over, each
/// time including others, would otherwise grow exponentially).
#define PBF_GLSL_MAX_SOURCE (1 << 20)

/// One stage of a program: the GL stage (GL_VERTEX_SHADER, GL_COMPUTE_SHADER, ...) and
/// the file, relative to the shader directory ("fluid/predict.comp").
typedef struct pbf_glsl_stage {
    GLenum type;
    const char *file;
} pbf_glsl_stage;

/// One embedded source file: its name relative to the shader root ("fluid/predict.comp")
/// and its text. The build embeds shaders/fluid/ into the fluid library
/// (pbf_glsl_fluid_sources) and shaders/render/ into the engine.
typedef struct pbf_glsl_file {
    const char *name;
    const char *text;
} pbf_glsl_file;

/// Where sources come from: a directory when `dir` is set (shader development, hot reload;
/// messages show its last component), else the embedded `files` (messages show "shaders").
typedef struct pbf_glsl_source {
    const char *dir;
    const pbf_glsl_file *files;
    int file_count;
} pbf_glsl_source;

/// The fluid passes' sources (shaders/fluid/*), embedded in libseiche_fluid.
pbf_glsl_source pbf_glsl_fluid_sources(void);

/// Builds a program from `count` stages found in `src` (see pbf_glsl_build).
GLuint pbf_glsl_build_from(const pbf_glsl_source *src, const pbf_glsl_stage *stages, int count,
                           const char *defines, char *err, size_t err_size);

/// Builds a program from `count` stages found under `shader_dir`. `defines` (may be
/// NULL) is inserted after each file's `#version` line, e.g. "#define FOO 1\n".
/// Returns the program, or 0 with a message in `err` that names the file and line:
/// "shaders/fluid/predict.comp:12: error: ..." (the directory's last component is kept).
GLuint pbf_glsl_build(const char *shader_dir, const pbf_glsl_stage *stages, int count,
                      const char *defines, char *err, size_t err_size);

/// Expands the includes of one file into a single source string (malloc'd, caller frees),
/// with `#line` directives whose source-string numbers index `files` (also malloc'd
/// strings, to be freed by pbf_glsl_free_files). Exposed for tests.
char *pbf_glsl_preprocess(const char *shader_dir, const char *file, const char *defines,
                          char *files[PBF_GLSL_MAX_FILES], int *file_count,
                          char *err, size_t err_size);
char *pbf_glsl_preprocess_from(const pbf_glsl_source *src, const char *file, const char *defines,
                               char *files[PBF_GLSL_MAX_FILES], int *file_count,
                               char *err, size_t err_size);
void pbf_glsl_free_files(char *files[PBF_GLSL_MAX_FILES], int file_count);

/// Rewrites a driver info log so that each "N:L(C): msg" (Mesa) or "N(L) : msg"
/// (NVIDIA) becomes "shaders/<file>:L: msg". Output is truncated to out_size.
void pbf_glsl_map_log(const char *log, char *const *files, int file_count,
                      const char *shown_root, char *out, size_t out_size);

#endif
