// seiche-embed-glfw: the fluid in a host that owns its window, its loop and its renderer:
// plain GLFW, the host's own point shader reading the fluid's position buffer (vertex
// pulling), one glDrawArrays of pbf_world_particle_count() points (with no sinks or
// emitters, as here, the CPU's count is exact; the indirect command the GPU writes is for
// instanced quads), the barrier the GL contract of fluid/pbf.h asks for, and the host's GL
// state rebound after each step. No Seiche engine.
//
//     seiche-embed-glfw [--frames N] [--check]
// --frames N  close after N frames (default: when the window is closed)
// --check     after the last frame, read the picture back and exit 1 unless water shows
//             (what tests/test_embed_glfw.c does under Xvfb)
#include <epoxy/gl.h>
#include <GLFW/glfw3.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fluid/pbf.h"

static const char *vertex_src =
    "#version 430\n"
    "layout(std430, binding = 0) readonly buffer Particles { vec4 p[]; };\n"
    "uniform mat4 u_view_proj;\n"
    "out float v_height;\n"
    "void main() {\n"
    "    vec4 c = p[gl_VertexID];\n"
    "    v_height = c.w;\n"
    "    gl_Position = u_view_proj * vec4(c.xyz, 1.0);\n"
    "    gl_PointSize = 6.0;\n"
    "}\n";
static const char *fragment_src =
    "#version 430\n"
    "in float v_height;\n"
    "out vec4 colour;\n"
    "void main() { colour = vec4(0.1, 0.3 + 0.4 * v_height, 0.9, 1.0); }\n";

static GLuint compile(GLenum type, const char *src)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    GLint ok = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[1024];
        glGetShaderInfoLog(s, sizeof log, NULL, log);
        fprintf(stderr, "seiche-embed-glfw: shader: %s\n", log);
    }
    return s;
}

// A fixed camera looking at the tank from the front and above: a column-major matrix.
static void view_proj(float m[16])
{
    // orthographic over x [-0.1, 0.7], y [-0.1, 0.7], looking down -z
    memset(m, 0, 16 * sizeof(float));
    m[0] = 2.0f / 0.8f;
    m[5] = 2.0f / 0.8f;
    m[10] = -1.0f;
    m[12] = -1.0f - 2.0f * -0.1f / 0.8f;
    m[13] = -1.0f - 2.0f * -0.1f / 0.8f;
    m[15] = 1.0f;
}

int main(int argc, char **argv)
{
    long frames = -1;
    bool check = false;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--frames") == 0 && i + 1 < argc) {
            char *end;
            errno = 0;
            frames = strtol(argv[++i], &end, 10);
            if (errno || end == argv[i] || *end || argv[i][0] < '0' || argv[i][0] > '9' || frames < 1 ||
                frames > 100000000) {
                fprintf(stderr, "seiche-embed-glfw: --frames must be a whole number in [1, 100000000] (got '%s')\n",
                        argv[i]);
                return 2;
            }
        } else if (strcmp(argv[i], "--check") == 0) {
            check = true;
        } else {
            fprintf(stderr, "usage: seiche-embed-glfw [--frames N] [--check]\n");
            return 2;
        }
    }
    if (check && frames < 0) {
        fprintf(stderr, "seiche-embed-glfw: --check needs --frames N (it reads the picture after the last frame)\n");
        return 2;
    }
    if (!glfwInit()) {
        fprintf(stderr, "seiche-embed-glfw: no display for a window\n");
        return 3;
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 4);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    GLFWwindow *win = glfwCreateWindow(480, 480, "seiche-embed-glfw", NULL, NULL);
    if (!win) {
        fprintf(stderr, "seiche-embed-glfw: no OpenGL 4.3 window\n");
        glfwTerminate();
        return 3;
    }
    glfwMakeContextCurrent(win);

    // The host's renderer: its program and an empty VAO (positions come from the buffer).
    GLuint prog = glCreateProgram();
    GLuint vs = compile(GL_VERTEX_SHADER, vertex_src), fs = compile(GL_FRAGMENT_SHADER, fragment_src);
    glAttachShader(prog, vs);
    glAttachShader(prog, fs);
    glLinkProgram(prog);
    glDeleteShader(vs);
    glDeleteShader(fs);
    GLuint vao;
    glGenVertexArrays(1, &vao);
    float m[16];
    view_proj(m);

    // The fluid: a block of water in a box.
    char err[1024];
    pbf_world_def def = pbf_default_world_def();
    const char *names[] = { "particle_radius" };
    const double values[] = { 0.01 };
    pbf_params_apply(&def.params, names, values, 1, err, sizeof err); // the kernel follows (4 r)
    def.max_neighbours = pbf_suggest_max_neighbours(&def.params);
    def.capacity = 16384;
    const float lo[3] = { 0, 0, 0 }, hi[3] = { 0.6f, 0.6f, 0.2f };
    memcpy(def.domain_min, lo, sizeof lo);
    memcpy(def.domain_max, hi, sizeof hi);
    pbf_world *w = pbf_world_create(&def, err, sizeof err);
    if (!w) {
        fprintf(stderr, "seiche-embed-glfw: %s\n", err);
        return 2;
    }
    pbf_world_set_container(w, lo, hi, false);
    pbf_block_def block = pbf_default_block_def();
    block.max[0] = 0.2f;
    block.max[1] = 0.4f;
    block.max[2] = 0.2f;
    if (pbf_world_add_block(w, &block, NULL) != PBF_OK) {
        fprintf(stderr, "seiche-embed-glfw: %s\n", pbf_world_last_error(w));
        return 2;
    }
    printf("seiche-embed-glfw: Seiche %s, %u particles on %s\n", pbf_version(), pbf_world_particle_count(w),
           (const char *)glGetString(GL_RENDERER));

    for (long f = 0; (frames < 0 || f < frames) && !glfwWindowShouldClose(win); f++) {
        pbf_world_step(w, 1.0f / 60.0f);
        // The contract: the fluid changed the program and buffer bindings; the host binds
        // its own, and issues the barrier bits of its uses of the fluid's buffers.
        pbf_gpu_buffers b = pbf_world_gpu_buffers(w);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
        int fw, fh;
        glfwGetFramebufferSize(win, &fw, &fh);
        glViewport(0, 0, fw, fh);
        glClearColor(0.92f, 0.94f, 0.96f, 1.0f);
        glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
        glEnable(GL_PROGRAM_POINT_SIZE);
        glUseProgram(prog);
        glUniformMatrix4fv(glGetUniformLocation(prog, "u_view_proj"), 1, GL_FALSE, m);
        glBindVertexArray(vao);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, b.positions);
        // One point per particle. (b.draw_indirect holds {4, live count, 0, 0}, the command
        // for four-vertex quads instanced per particle; with no sinks or emitters, as here,
        // the CPU's count is exact and plain points need no indirect draw.)
        glDrawArrays(GL_POINTS, 0, (GLsizei)pbf_world_particle_count(w));
        glBindVertexArray(0);
        if (check && f + 1 == frames) {
            int water = 0;
            unsigned char *px = malloc((size_t)fw * (size_t)fh * 4);
            glReadPixels(0, 0, fw, fh, GL_RGBA, GL_UNSIGNED_BYTE, px);
            for (long k = 0; k < (long)fw * fh; k++)
                if (px[4 * k + 2] > 180 && px[4 * k] < 60) water++;
            free(px);
            printf("seiche-embed-glfw: %d water pixels of %d\n", water, fw * fh);
            if (water < fw * fh / 50) return 1;
        }
        glfwSwapBuffers(win);
        glfwPollEvents();
    }
    pbf_world_destroy(w);
    glDeleteProgram(prog);
    glDeleteVertexArrays(1, &vao);
    glfwDestroyWindow(win);
    glfwTerminate();
    return 0;
}
