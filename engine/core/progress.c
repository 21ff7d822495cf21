// The terminal progress line. See progress.h.
#include "engine/core/progress.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

void eng_progress_begin(eng_progress *p, const char *what, long total)
{
    p->on = isatty(2) == 1;
    p->total = total;
    p->what = what;
    p->start_s = p->last_s = now_s();
    p->shown = false;
}

void eng_progress_update(eng_progress *p, long done, double sim_time)
{
    if (!p->on) return;
    double t = now_s();
    if (t - p->last_s < 0.25 && done < p->total) return;
    p->last_s = t;
    char line[160];
    int n = snprintf(line, sizeof line, "seiche: %s %ld", p->what, done);
    if (p->total > 0) n += snprintf(line + n, sizeof line - (size_t)n, "/%ld", p->total);
    if (sim_time >= 0.0) n += snprintf(line + n, sizeof line - (size_t)n, ", %.2f s simulated", sim_time);
    if (p->total > 0 && done > 0 && done < p->total) {
        double left = (t - p->start_s) * (double)(p->total - done) / (double)done;
        snprintf(line + n, sizeof line - (size_t)n, ", about %.0f s left", left);
    }
    fprintf(stderr, "\r%s\033[K", line);
    fflush(stderr);
    p->shown = true;
}

void eng_progress_end(eng_progress *p)
{
    if (p->on && p->shown) {
        fprintf(stderr, "\r\033[K");
        fflush(stderr);
    }
    p->shown = false;
}
