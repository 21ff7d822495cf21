// The GPU world's services that its parts (world, emitters, colliders) share: error
// messages, buffer creation, the parameter block, buffer bindings and the append pass.
#include "fluid/pbf_internal.h"
#include "fluid/pbf_uniforms.h"

#include <epoxy/gl.h>
#include <math.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

pbf_result pbf_fail(pbf_world *w, pbf_result r, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(w->error, sizeof w->error, fmt, ap);
    va_end(ap);
    if (w->log) w->log(w->log_user, 3, w->error);
    return r;
}

// Two kinds of buffers (docs/architecture.md, "GL synchronisation"):
// - buffers only the GPU writes are zeroed on the GPU once, when made (a clear is a GPU
//   command: every later dispatch or readback is ordered after it);
// - buffers the CPU uploads into are made with their first contents from the CPU and never
//   cleared on the GPU: a real driver may apply a GPU clear after a CPU upload that follows
//   it (NVIDIA does, when it moves a small buffer to host memory), and the upload is lost.
// Both get a label, so driver messages and captures name them.
// The CPU reads no buffer the passes use: what it reads is first copied on the GPU into a
// read-back buffer (pbf_read_buffer, pbf_download). A driver moves a buffer the CPU reads
// to host memory (NVIDIA says so: "is being copied/moved from VIDEO memory to HOST
// memory"), and every pass would then reach the moved buffer across the bus.
static GLuint new_buffer(GLsizeiptr size, const void *data, const char *label, GLenum usage)
{
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, b);
    glBufferData(GL_SHADER_STORAGE_BUFFER, size > 0 ? size : 16, data, usage);
    glObjectLabel(GL_BUFFER, b, -1, label);
    return b;
}

GLuint pbf_gpu_buffer(GLsizeiptr size, const char *label)
{
    // _COPY: written and read by GL only. With _DRAW (the application writes) an NVIDIA
    // H100 moved pbf.forces, cleared and copied on the GPU every step, to host memory
    // ("is being copied/moved from VIDEO memory to HOST memory"), where the collide pass's
    // atomics would reach it across the bus.
    GLuint b = new_buffer(size, NULL, label, GL_DYNAMIC_COPY);
    glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, NULL);
    return b;
}

GLuint pbf_read_buffer(GLsizeiptr size, const char *label)
{
    GLuint b = new_buffer(size, NULL, label, GL_STREAM_READ);
    glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, NULL);
    return b;
}

bool pbf_download(pbf_world *w, GLuint src, GLintptr offset, GLsizeiptr size, void *dst)
{
    if (size <= 0) return true;
    if (size > w->readback_size) {
        GLsizeiptr want = w->readback_size > 0 ? w->readback_size : 4096;
        while (want < size) want *= 2;
        if (w->readback) glDeleteBuffers(1, &w->readback);
        w->readback = new_buffer(want, NULL, "pbf.readback", GL_STREAM_READ);
        if (glGetError() != GL_NO_ERROR) {
            glDeleteBuffers(1, &w->readback);
            w->readback = 0;
            w->readback_size = 0;
            return false;
        }
        w->readback_size = want;
    }
    // Shader writes reach a copy only after this barrier; the read is ordered after the copy.
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glBindBuffer(GL_COPY_READ_BUFFER, src);
    glBindBuffer(GL_COPY_WRITE_BUFFER, w->readback);
    glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, offset, 0, size);
    glGetBufferSubData(GL_COPY_WRITE_BUFFER, 0, size, dst);
    return true;
}

GLuint pbf_cpu_buffer(GLsizeiptr size, const void *data, const char *label)
{
    if (data) return new_buffer(size, data, label, GL_DYNAMIC_DRAW);
    size_t bytes = (size_t)(size > 0 ? size : 16);
    void *zeros = calloc(1, bytes);
    if (!zeros) return 0;
    GLuint b = new_buffer(size, zeros, label, GL_DYNAMIC_DRAW);
    free(zeros);
    return b;
}

float pbf_colour_of(const pbf_world *w, float y)
{
    float t = (y - w->domain_min[1]) / (w->domain_max[1] - w->domain_min[1]);
    return t < 0.0f ? 0.0f : t > 1.0f ? 1.0f : t;
}

void pbf_bind_particles(pbf_world *w)
{
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_POS, w->pos[w->cur_pos]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_POS_OUT, w->pos[w->cur_pos ^ 1]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_VEL, w->vel[w->cur_vel]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_VEL_OUT, w->vel[w->cur_vel ^ 1]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_PRED, w->pred[w->cur_pred]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_PRED_OUT, w->pred[w->cur_pred ^ 1]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_ID, w->ids[w->cur_ids]);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_ID_OUT, w->ids[w->cur_ids ^ 1]);
}

void pbf_bind_all(pbf_world *w)
{
    pbf_bind_particles(w);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_CELL, w->cell_of);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_CELL_START, w->cell_start);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_CELL_FILL, w->cell_fill);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_SORTED, w->sorted);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_ORDER, w->order);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_LAMBDA, w->lambda);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_OMEGA, w->omega);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_TENSION, w->tension);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_LEVEL, w->level);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_COLLIDERS, w->colliders);
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, PBF_B_FORCES, w->forces, 0, PBF_FORCES_BYTES);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_REDUCE, w->reduce);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_METRICS, w->metrics);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_NB_LIST, w->nb_list);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_NB_COUNT, w->nb_count);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_STATE, w->state);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_DRAW, w->draw);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, w->state);
    glBindBufferBase(GL_UNIFORM_BUFFER, PBF_U_PARAMS, w->params_ubo);
}

void pbf_write_params(pbf_world *w, float dt, int substep, int slot)
{
    const pbf_params *p = &w->params;
    pbf_gpu_params g;
    memset(&g, 0, sizeof g);
    pbf_uniforms_solver(&g, p, &w->k, dt);
    pbf_uniforms_space(&g, w->grid_origin, w->grid_dims, w->cells, p->kernel_radius / (float)w->cells_per_kernel,
                       w->domain_min, w->domain_max,
                       (const float(*)[4])w->planes, (uint32_t)w->plane_count, w->max_neighbours);
    uint32_t ns = 0;
    for (int k = 0; k < PBF_MAX_SINKS; k++) {
        if (!w->sinks[k].used) continue;
        g.sink_min[ns] = (pbf_float4){ w->sinks[k].min[0], w->sinks[k].min[1], w->sinks[k].min[2], 0 };
        g.sink_max[ns] = (pbf_float4){ w->sinks[k].max[0], w->sinks[k].max[1], w->sinks[k].max[2], 0 };
        ns++;
    }
    g.sink_count = ns;
    pbf_uniforms_level(&g, p, w->level_dims, w->level_cell);
    g.capacity = w->capacity;
    g.append_count = 0;
    g.count_mode = 0;
    g.count = w->count;
    g.collider_count = w->gpu_colliders;
    g.metrics_slot = (uint32_t)slot;
    g.substep = (uint32_t)substep;
    glBindBuffer(GL_UNIFORM_BUFFER, w->params_ubo);
    glBufferSubData(GL_UNIFORM_BUFFER, 0, sizeof g, &g);
}

static void grow_staging(pbf_world *w, uint32_t n)
{
    if (n <= w->stage_cap) return;
    uint32_t cap = w->stage_cap ? w->stage_cap : 1024;
    while (cap < n) cap *= 2;
    GLuint old[3] = { w->stage_pos, w->stage_vel, w->stage_id };
    glDeleteBuffers(3, old);
    w->stage_pos = pbf_cpu_buffer((GLsizeiptr)cap * 16, NULL, "pbf.stage_pos");
    w->stage_vel = pbf_cpu_buffer((GLsizeiptr)cap * 16, NULL, "pbf.stage_vel");
    w->stage_id = pbf_cpu_buffer((GLsizeiptr)cap * 4, NULL, "pbf.stage_id");
    w->stage_cap = cap;
}

pbf_result pbf_append(pbf_world *w, const float *pos4, const float *vel4, uint32_t n)
{
    if (n == 0) return PBF_OK;
    // The time-step guard sees these before the metrics of a step do.
    float *fastest = &w->added_speed[w->step_index % PBF_GUARD_HISTORY];
    for (uint32_t i = 0; i < n; i++) {
        const float *v = vel4 + 4 * (size_t)i;
        float s = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
        if (s > *fastest) *fastest = s; // NaN is never larger
    }
    uint32_t *ids = malloc((size_t)n * 4);
    if (!ids) return pbf_fail(w, PBF_ERR_OUT_OF_MEMORY, "pbf_world_add_particles: out of memory");
    for (uint32_t i = 0; i < n; i++) ids[i] = w->next_id + i;
    grow_staging(w, n);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->stage_pos);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)n * 16, pos4);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->stage_vel);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)n * 16, vel4);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->stage_id);
    glBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)n * 4, ids);
    free(ids);
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    pbf_write_params(w, 1.0f / 60.0f, 0, 0);
    // append_count and count_mode ride in the same uniform block.
    uint32_t extra[2] = { n, 1u };
    glBindBuffer(GL_UNIFORM_BUFFER, w->params_ubo);
    glBufferSubData(GL_UNIFORM_BUFFER, offsetof(pbf_gpu_params, append_count), sizeof extra, extra);
    pbf_bind_all(w);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_STAGE_POS, w->stage_pos);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_STAGE_VEL, w->stage_vel);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PBF_B_STAGE_ID, w->stage_id);
    glUseProgram(w->programs[PROG_APPEND]);
    glDispatchCompute((n + PBF_WG - 1) / PBF_WG, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    glUseProgram(w->programs[PROG_LIVE_COUNT]);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
    w->next_id += n;
    w->appended_total += n;
    uint64_t c = w->known_count + (w->appended_total - w->known_appended);
    w->count = c > w->capacity ? w->capacity : (uint32_t)c;
    return PBF_OK;
}

bool pbf_without_context(pbf_world *w, const char *fn)
{
    // With no context current a GL call does nothing (libglvnd's stubs), so a step or an
    // upload would "succeed" and a read would return nothing. glGetString is answered by
    // the driver on the CPU, with no wait on the GPU.
    if (glGetString(GL_VERSION)) return false;
    pbf_fail(w, PBF_ERR_GL, "%s: no OpenGL context is current on this thread (make the context the world was created "
             "in current before calling)", fn);
    return true;
}

bool pbf_refused_in_step(pbf_world *w, const char *fn, const char *tail)
{
    if (!w->in_step) return false;
    pbf_fail(w, PBF_ERR_INVALID_ARG, "%s: called from inside a step (the substep hook)%s", fn, tail);
    return true;
}

// ---- the worlds alive -----------------------------------------------------------------
//
// Each world made gets a serial no other will have; a holder that may outlive the world (a
// coupling) keeps the pair and asks before touching it. A world's memory may be reused for
// the next one, so the pointer alone would not tell.

typedef struct live_world {
    const pbf_world *world;
    uint64_t serial;
} live_world;

static atomic_flag live_busy = ATOMIC_FLAG_INIT; // held for a few instructions: a spin lock
static live_world *live;
static size_t live_count, live_cap;
static uint64_t live_next = 1;

static void live_lock(void)
{
    while (atomic_flag_test_and_set_explicit(&live_busy, memory_order_acquire)) {
    }
}

static void live_unlock(void) { atomic_flag_clear_explicit(&live_busy, memory_order_release); }

bool pbf_live_add(const pbf_world *w)
{
    live_lock();
    bool ok = true;
    if (live_count == live_cap) {
        size_t cap = live_cap ? 2 * live_cap : 16;
        live_world *grown = realloc(live, cap * sizeof *grown);
        if (grown) {
            live = grown;
            live_cap = cap;
        } else {
            ok = false;
        }
    }
    if (ok) live[live_count++] = (live_world){ w, live_next++ };
    live_unlock();
    return ok;
}

void pbf_live_remove(const pbf_world *w)
{
    live_lock();
    for (size_t i = 0; i < live_count; i++)
        if (live[i].world == w) {
            live[i] = live[--live_count];
            break;
        }
    if (live_count == 0) { // the last world gone: nothing left for a leak check to find
        free(live);
        live = NULL;
        live_cap = 0;
    }
    live_unlock();
}

uint64_t pbf_world_serial(const pbf_world *w)
{
    uint64_t serial = 0;
    live_lock();
    for (size_t i = 0; i < live_count && w; i++)
        if (live[i].world == w) serial = live[i].serial;
    live_unlock();
    return serial;
}

bool pbf_world_alive(const pbf_world *w, uint64_t serial)
{
    return w && serial && pbf_world_serial(w) == serial;
}
