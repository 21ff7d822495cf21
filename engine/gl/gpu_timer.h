// GPU timing of named sections of a frame with GL timestamp queries (glQueryCounter with
// GL_TIMESTAMP), read back late: a result is taken only once GL_QUERY_RESULT_AVAILABLE
// says so, so timing never stalls the frame. Each section keeps a ring of query pairs;
// eng_gpu_timer_ms() gives the latest completed measurement, typically from a frame or
// two ago. eng_gpu_timer_wait() blocks for everything issued (the end of a run).
//
//   int s = eng_gpu_timer_begin(t, "scene");  ... draw ...  eng_gpu_timer_end(t, s);
//   eng_gpu_timer_collect(t);   // once a frame: picks up finished results
//
// Sections may nest and interleave; a section may be timed several times a frame (each
// measurement is one sample). Needs a current GL context (3.3+ / ARB_timer_query).
#ifndef ENG_GPU_TIMER_H
#define ENG_GPU_TIMER_H

#include <stdbool.h>

#include "engine/core/log.h"

#define ENG_GPU_TIMER_NAME_MAX 48 ///< section names are shorter than this (bytes with the 0)

typedef struct eng_gpu_timer_def {
    int max_sections;  ///< distinct section names: 1..256
    int ring_size;     ///< measurements in flight per section: 2..64
    eng_logger logger; ///< misuse (bad names, end without begin) is reported here
} eng_gpu_timer_def;

/// 64 sections, 8 in flight each.
eng_gpu_timer_def eng_default_gpu_timer_def(void);

typedef struct eng_gpu_timer eng_gpu_timer;

/// NULL with a logged message when the def is out of range.
eng_gpu_timer *eng_gpu_timer_create(const eng_gpu_timer_def *def);
void eng_gpu_timer_destroy(eng_gpu_timer *timer);

/// Records the start of `name` (created on first use) and returns its section index for
/// eng_gpu_timer_end; -1 (logged) for an empty or too long name, or too many sections.
/// When every query pair of the section is still in flight, the oldest is given up
/// (counted by eng_gpu_timer_dropped) rather than waited for.
int eng_gpu_timer_begin(eng_gpu_timer *timer, const char *name);
/// Records the end of the open measurement of `section`. A section that is not open is
/// logged and ignored.
void eng_gpu_timer_end(eng_gpu_timer *timer, int section);
/// Picks up every finished measurement without waiting. Call once a frame.
void eng_gpu_timer_collect(eng_gpu_timer *timer);
/// Waits until every issued measurement has finished and picks them up.
void eng_gpu_timer_wait(eng_gpu_timer *timer);

/// Latest completed duration of the section in ms; -1 when none has completed yet or the
/// name is unknown.
double eng_gpu_timer_ms(const eng_gpu_timer *timer, const char *name);
int eng_gpu_timer_section_count(const eng_gpu_timer *timer);
/// Name and latest ms (-1 if none yet) of section `index` (0..count-1); NULL for others.
const char *eng_gpu_timer_section(const eng_gpu_timer *timer, int index, double *ms);
/// Completed measurements of a section so far (0 for an unknown index).
long eng_gpu_timer_samples(const eng_gpu_timer *timer, int index);
/// Measurements given up because their ring slot was needed again before they finished.
long eng_gpu_timer_dropped(const eng_gpu_timer *timer);

#endif
