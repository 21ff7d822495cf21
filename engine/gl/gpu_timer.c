// Ring-buffered GL timestamp queries per named section. See gpu_timer.h.
#include "engine/gl/gpu_timer.h"

#include <epoxy/gl.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct pair {
    GLuint start, end;
    uint64_t seq;   ///< issue order (1, 2, ...); 0 = never used
    bool open;      ///< start issued, end not yet
    bool pending;   ///< both issued, result not yet read
} pair;

typedef struct section {
    char name[ENG_GPU_TIMER_NAME_MAX];
    pair *ring;
    int next;       ///< slot for the next begin
    int open_slot;  ///< slot of the open measurement, -1 = none
    uint64_t seq, latest_seq;
    double latest_ms;
    long samples;
} section;

struct eng_gpu_timer {
    eng_gpu_timer_def def;
    section *sections;
    int count;
    long dropped;
};

eng_gpu_timer_def eng_default_gpu_timer_def(void)
{
    eng_gpu_timer_def d;
    memset(&d, 0, sizeof d);
    d.max_sections = 64;
    d.ring_size = 8;
    d.logger = eng_default_logger();
    return d;
}

eng_gpu_timer *eng_gpu_timer_create(const eng_gpu_timer_def *def)
{
    if (def->max_sections < 1 || def->max_sections > 256) {
        eng_log(&def->logger, ENG_LOG_ERROR, "eng_gpu_timer_def.max_sections must be 1..256 (got %d)",
                def->max_sections);
        return NULL;
    }
    if (def->ring_size < 2 || def->ring_size > 64) {
        eng_log(&def->logger, ENG_LOG_ERROR, "eng_gpu_timer_def.ring_size must be 2..64 (got %d)", def->ring_size);
        return NULL;
    }
    eng_gpu_timer *t = calloc(1, sizeof *t);
    if (!t) return NULL;
    t->sections = calloc((size_t)def->max_sections, sizeof *t->sections);
    if (!t->sections) {
        free(t);
        return NULL;
    }
    t->def = *def;
    return t;
}

void eng_gpu_timer_destroy(eng_gpu_timer *t)
{
    if (!t) return;
    for (int i = 0; i < t->count; i++) {
        section *s = &t->sections[i];
        for (int k = 0; k < t->def.ring_size; k++) {
            glDeleteQueries(1, &s->ring[k].start);
            glDeleteQueries(1, &s->ring[k].end);
        }
        free(s->ring);
    }
    free(t->sections);
    free(t);
}

static int find(const eng_gpu_timer *t, const char *name)
{
    for (int i = 0; i < t->count; i++)
        if (strcmp(t->sections[i].name, name) == 0) return i;
    return -1;
}

// Reads a finished pair into its section; with `wait`, blocks until it has finished.
static bool harvest(section *s, pair *p, bool wait)
{
    if (!p->pending) return false;
    if (!wait) {
        GLuint ready = 0;
        glGetQueryObjectuiv(p->end, GL_QUERY_RESULT_AVAILABLE, &ready);
        if (!ready) return false;
    }
    GLuint64 a = 0, b = 0;
    glGetQueryObjectui64v(p->start, GL_QUERY_RESULT, &a);
    glGetQueryObjectui64v(p->end, GL_QUERY_RESULT, &b);
    p->pending = false;
    s->samples++;
    if (p->seq > s->latest_seq) {
        s->latest_seq = p->seq;
        s->latest_ms = b >= a ? (double)(b - a) * 1e-6 : 0.0;
    }
    return true;
}

int eng_gpu_timer_begin(eng_gpu_timer *t, const char *name)
{
    size_t len = name ? strlen(name) : 0;
    if (len == 0 || len >= ENG_GPU_TIMER_NAME_MAX) {
        if (!name)
            eng_log(&t->def.logger, ENG_LOG_ERROR, "eng_gpu_timer_begin: name must be 1..%d bytes (got NULL)",
                    ENG_GPU_TIMER_NAME_MAX - 1);
        else
            eng_log(&t->def.logger, ENG_LOG_ERROR, "eng_gpu_timer_begin: name must be 1..%d bytes (got %zu: '%.20s')",
                    ENG_GPU_TIMER_NAME_MAX - 1, len, name);
        return -1;
    }
    int i = find(t, name);
    if (i < 0) {
        if (t->count == t->def.max_sections) {
            eng_log(&t->def.logger, ENG_LOG_ERROR,
                    "eng_gpu_timer_begin: section '%s' would exceed eng_gpu_timer_def.max_sections = %d", name,
                    t->def.max_sections);
            return -1;
        }
        section *s = &t->sections[t->count];
        s->ring = calloc((size_t)t->def.ring_size, sizeof *s->ring);
        if (!s->ring) return -1;
        for (int k = 0; k < t->def.ring_size; k++) {
            glGenQueries(1, &s->ring[k].start);
            glGenQueries(1, &s->ring[k].end);
        }
        memcpy(s->name, name, len + 1);
        s->open_slot = -1;
        s->latest_ms = -1.0;
        i = t->count++;
    }
    section *s = &t->sections[i];
    if (s->open_slot >= 0) {
        eng_log(&t->def.logger, ENG_LOG_WARN, "eng_gpu_timer_begin: section '%s' is already open; restarting it", name);
        s->ring[s->open_slot].open = false;
        s->open_slot = -1;
    }
    pair *p = &s->ring[s->next];
    if (p->pending && !harvest(s, p, false)) {
        p->pending = false; // still in flight: give it up rather than wait
        t->dropped++;
    }
    glQueryCounter(p->start, GL_TIMESTAMP);
    p->open = true;
    p->seq = ++s->seq;
    s->open_slot = s->next;
    s->next = (s->next + 1) % t->def.ring_size;
    return i;
}

void eng_gpu_timer_end(eng_gpu_timer *t, int index)
{
    if (index < 0 || index >= t->count || t->sections[index].open_slot < 0) {
        eng_log(&t->def.logger, ENG_LOG_ERROR,
                "eng_gpu_timer_end: section must be an index returned by eng_gpu_timer_begin and still open (got %d)",
                index);
        return;
    }
    section *s = &t->sections[index];
    pair *p = &s->ring[s->open_slot];
    glQueryCounter(p->end, GL_TIMESTAMP);
    p->open = false;
    p->pending = true;
    s->open_slot = -1;
}

static void collect(eng_gpu_timer *t, bool wait)
{
    for (int i = 0; i < t->count; i++) {
        section *s = &t->sections[i];
        // Oldest first: after a ready one, the older ones are ready too (GL completes in order).
        for (int k = 0; k < t->def.ring_size; k++) harvest(s, &s->ring[(s->next + k) % t->def.ring_size], wait);
    }
}

void eng_gpu_timer_collect(eng_gpu_timer *t) { collect(t, false); }

void eng_gpu_timer_wait(eng_gpu_timer *t)
{
    glFlush();
    collect(t, true);
}

double eng_gpu_timer_ms(const eng_gpu_timer *t, const char *name)
{
    int i = name ? find(t, name) : -1;
    return i < 0 ? -1.0 : t->sections[i].latest_ms;
}

int eng_gpu_timer_section_count(const eng_gpu_timer *t) { return t->count; }

const char *eng_gpu_timer_section(const eng_gpu_timer *t, int index, double *ms)
{
    if (index < 0 || index >= t->count) return NULL;
    if (ms) *ms = t->sections[index].latest_ms;
    return t->sections[index].name;
}

long eng_gpu_timer_samples(const eng_gpu_timer *t, int index)
{
    return index >= 0 && index < t->count ? t->sections[index].samples : 0;
}

long eng_gpu_timer_dropped(const eng_gpu_timer *t) { return t->dropped; }
