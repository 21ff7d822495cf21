// The step records' ring: each step's timestamps, metrics and body forces, read back
// through a fence per step without waiting unless asked (pbf_world_poll_stats), the live
// count they carry (pbf_count_settle), and the fastest speeds the time-step guard reads.
#include "fluid/pbf.h"
#include "fluid/pbf_internal.h"
#include "fluid/pbf_uniforms.h"

#include <epoxy/gl.h>
#include <stdio.h>
#include <string.h>

static void read_slot(pbf_world *w, stats_slot *r, pbf_step_stats *out)
{
    memset(out, 0, sizeof *out);
    out->step = r->step;
    out->time = r->time;
    out->rest_density = w->params.rest_density;
    GLuint64 prev = 0;
    for (int q = 0; q < r->nq; q++) {
        GLuint64 t = 0;
        glGetQueryObjectui64v(r->queries[q], GL_QUERY_RESULT, &t);
        if (q > 0) {
            double ms = (double)(t - prev) * 1e-6;
            out->stage_ms[r->stage_of[q]] += ms;
            if (r->stage_of[q] != PBF_STAGE_METRICS) out->step_ms += ms;
        }
        prev = t;
    }
    int slot = (int)(r - w->ring);
    pbf_gpu_metrics m;
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, w->metrics);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, (GLintptr)slot * (GLintptr)sizeof m, sizeof m, &m);
    out->density_avg = m.density_avg;
    out->density_max = m.density_max;
    out->density_error_avg = m.error_avg;
    out->nan_count = m.nan_count;
    out->outside_count = m.outside_count;
    out->overflow_count = m.overflow_count;
    out->particles = m.count;
    out->mass = (double)m.count * w->k.mass;
    out->kinetic_energy = m.momentum.w;
    out->speed_max = m.center_of_mass.w;
    out->substeps = r->substeps;
    w->speed_of[r->step % PBF_GUARD_HISTORY] = m.center_of_mass.w;
    w->speed_step[r->step % PBF_GUARD_HISTORY] = r->step + 1;
    w->seen_of[r->step % PBF_GUARD_HISTORY] = (pbf_guard_seen){
        .density_error_max = m.density_max / w->params.rest_density - 1.0f,
        .density_error_avg = m.error_avg,
        .substeps = r->substeps,
    };
    for (int k = 0; k < 3; k++) {
        out->momentum[k] = (&m.momentum.x)[k];
        out->center_of_mass[k] = (&m.center_of_mass.x)[k];
    }
    // The count as of this step, plus what was appended after it was issued.
    if (r->step + 1 >= w->known_step) {
        w->known_step = r->step + 1;
        w->known_count = m.count;
        w->known_appended = r->appended_total;
        uint64_t c = w->known_count + (w->appended_total - w->known_appended);
        w->count = c > w->capacity ? w->capacity : (uint32_t)c;
    }
    pbf_colliders_read_forces(w, r);
}

bool pbf_step_done(pbf_world *w, const stats_slot *r, bool wait)
{
    GLenum st = glClientWaitSync(r->fence, GL_SYNC_FLUSH_COMMANDS_BIT, wait ? PBF_STEP_WAIT_NS : 0);
    if (st == GL_ALREADY_SIGNALED || st == GL_CONDITION_SATISFIED) return true;
    if (wait && !w->warned_hang) {
        // Seen once on an NVIDIA H200: runs took 20 s longer, with black screenshots, and
        // nothing said why. A step the GPU has not finished in 10 s is not a slow step.
        w->warned_hang = true;
        if (w->log) {
            char msg[320];
            snprintf(msg, sizeof msg, "the GPU has not finished step %llu after %.0f s (glClientWaitSync: %s): the GL "
                     "context is hung, lost or far behind (on NVIDIA the kernel log names a hang, as an Xid); the "
                     "records of steps not finished in time are dropped, not read", (unsigned long long)r->step, PBF_STEP_WAIT_NS * 1e-9,
                     st == GL_TIMEOUT_EXPIRED ? "GL_TIMEOUT_EXPIRED" : "GL_WAIT_FAILED");
            w->log(w->log_user, 2, msg);
        }
    }
    return false;
}

// A slot whose record was taken (or dropped): free for the next step.
static void release_slot(stats_slot *slot)
{
    glDeleteSync(slot->fence);
    slot->fence = NULL;
    slot->pending = false;
}

int pbf_world_poll_stats(pbf_world *w, pbf_step_stats *out, int max, bool wait)
{
    if (!w) return 0;
    int n = 0;
    // Records read early (ring full) come first: they are older than any pending one.
    int taken = 0;
    while (taken < w->done_count && (!out || n < max)) {
        if (out) out[n] = w->done[taken];
        n++;
        taken++;
    }
    memmove(w->done, w->done + taken, (size_t)(w->done_count - taken) * sizeof w->done[0]);
    w->done_count -= taken;
    if (out && n >= max) return n;
    for (int k = 0; k < RING; k++) {
        // oldest pending first
        int idx = (w->ring_head + k) % RING;
        stats_slot *r = &w->ring[idx];
        if (!r->pending) continue;
        if (!pbf_step_done(w, r, wait)) break;
        pbf_step_stats tmp;
        read_slot(w, r, &tmp);
        if (n < max && out) out[n] = tmp;
        if (n < max || !out) n++;
        release_slot(r);
        if (out && n >= max) break;
    }
    return n;
}

// Reads a pending step record now, waiting for its fence if need be, and keeps it for the
// next poll. With no poll at all, the oldest kept records make room. A step the GPU has not
// finished after PBF_STEP_WAIT_NS is dropped, not read: its slot still holds the record of
// the step RING before it (an NVIDIA H100 handed those out as new while a diverging 1M run
// took seconds a step), so the records polled skip that step (and its forces never come).
void pbf_read_early(pbf_world *w, stats_slot *slot)
{
    if (pbf_step_done(w, slot, true)) {
        if (w->done_count == RING) {
            memmove(w->done, w->done + 1, (RING - 1) * sizeof w->done[0]);
            w->done_count--;
        }
        read_slot(w, slot, &w->done[w->done_count++]);
    }
    release_slot(slot);
}

// The live count made exact: every step in flight read now, oldest first, waiting for it (the
// records stay for the poll). Between steps w->count is an upper bound (sinks remove on the
// GPU); callers use this before refusing for want of room. True when a record was read.
bool pbf_count_settle(pbf_world *w)
{
    bool read = false;
    for (int k = 0; k < RING; k++) {
        stats_slot *r = &w->ring[(w->ring_head + k) % RING];
        if (!r->pending) continue;
        pbf_read_early(w, r);
        read = true;
    }
    return read;
}

// The fastest particle speed of a finished step, read (waiting for it) if not yet; -1 when
// that step's record is gone.
float pbf_speed_of_step(pbf_world *w, uint64_t step)
{
    int k = (int)(step % PBF_GUARD_HISTORY);
    if (w->speed_step[k] == step + 1) return w->speed_of[k];
    for (int i = 0; i < RING; i++) {
        stats_slot *r = &w->ring[i];
        if (r->pending && r->step == step) {
            pbf_read_early(w, r);
            return w->speed_step[k] == step + 1 ? w->speed_of[k] : -1.0f;
        }
    }
    return -1.0f;
}
