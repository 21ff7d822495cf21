// A progress line for long runs on a terminal: "seiche: frame 120/600, 2.00 s simulated,
// about 8 s left", rewritten in place at most a few times a second, erased at the end.
// Prints nothing when stderr is not a terminal (CI logs, pipes, tests).
#ifndef ENG_PROGRESS_H
#define ENG_PROGRESS_H

#include <stdbool.h>

typedef struct eng_progress {
    bool on;            ///< stderr is a terminal
    long total;         ///< units of work (frames, runs); <= 0: unknown
    double start_s, last_s;
    const char *what;   ///< "frame", "run", ...
    bool shown;
} eng_progress;

/// Starts a progress line for `total` units named `what` (a string that outlives it).
void eng_progress_begin(eng_progress *p, const char *what, long total);
/// `done` units so far; `sim_time` >= 0 adds "x.xx s simulated".
void eng_progress_update(eng_progress *p, long done, double sim_time);
/// Erases the line.
void eng_progress_end(eng_progress *p);

#endif
