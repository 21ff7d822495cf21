// The engine's frame loop: a context (window or headless), a scene script, the worlds
// built from it (fluid, Bullet, their coupling), the renderer and, in a window, the UI;
// fixed time step, pause, single step, reset / reload (keys, and on saving the script),
// metrics CSV, screenshots, video, and the state hash. The runner (demos/seiche) is a
// thin command line over eng_app_run; docs/runner.md describes both.
#ifndef ENG_APP_H
#define ENG_APP_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "engine/script/script.h"

#define ENG_APP_MAX_SETS 64

/// Exit statuses of a run (the runner's contract, see docs/runner.md).
enum {
    ENG_EXIT_OK = 0,
    ENG_EXIT_CHECK_FAILED = 1,
    ENG_EXIT_USAGE = 2,       ///< usage or script error
    ENG_EXIT_NO_COMPUTE = 3,  ///< no OpenGL 4.3 compute context
    ENG_EXIT_DIVERGED = 4,    ///< the solver diverged: NaN, rho_max over 3 rho0, or particles left the domain
};

/// What a run came to, for reports (--junit, --tap): filled by eng_app_run when
/// eng_app_options.report is set.
typedef struct eng_app_report {
    int status;             ///< the ENG_EXIT_* status returned
    char message[1024];     ///< the first line of what ended the run ("" when nothing did)
    uint64_t frames;
    double sim_time;        ///< s simulated
    double wall_s;          ///< s of wall clock
    eng_check_site checks[ENG_SCRIPT_MAX_CHECK_SITES]; ///< the seiche.check calls that ran
    int check_count;
    int never_ran[64];      ///< lines of the script holding a seiche.check that never ran
    int never_ran_count;
} eng_app_report;

typedef struct eng_app_options {
    const char *script;          ///< scene script path
    bool headless;
    long frames;                 ///< simulation steps to run (paused frames do not count);
                                 ///< < 0: until quit (headless: 600)
    double dt;                   ///< s per frame, (0, 1]
    const char *sets[ENG_APP_MAX_SETS]; ///< "key=value" overrides
    int set_count;
    const char *metrics_path;    ///< CSV, one row per frame
    const char *screenshot_path; ///< PNG of the last frame
    const char *record_path;     ///< MP4 through ffmpeg
    bool hash;                   ///< print the final state hash
    int width, height;           ///< pixels
    const char *shader_dir;      ///< NULL: $SEICHE_SHADER_DIR if set, else the shaders embedded in the libraries
    bool quiet;                  ///< no summary line
    double budget_s;             ///< longest a callback may run, s; 0: 5 headless, 2 in a window
    bool watch;                  ///< window: reload the script when its file changes (default true)
    bool ui;                     ///< window: the on-screen panel and error box (default true)
    bool trusted;                ///< the script gets every standard Lua library (default false: the sandbox)
    eng_app_report *report;      ///< NULL, or filled at the end of the run
    const char *render;          ///< how the water is drawn: "surface" (NULL: the default),
                                 ///< "spheres", "density" or "speed" (eng_fluid_mode_parse)
    bool name_script;            ///< the run's messages name the script ("seiche: DIR/x.lua: ..."):
                                 ///< one run of a directory suite, whose log holds many runs
} eng_app_options;

eng_app_options eng_default_app_options(void);

/// Runs the script to the end; returns an ENG_EXIT_* status. Messages go to stderr.
int eng_app_run(const eng_app_options *options);

/// The keys (all of them, comma separated) that --set accepts, for usage messages.
const char *eng_app_set_keys(void);

/// A file name as the runner writes it into its log lines and reports: each control
/// character (bytes below 0x20, and 0x7f) escaped, so that a name holding a newline stays
/// on its line (and a TAP line stays one line): `\n`, `\r`, `\t`, else `\xNN`; and a
/// backslash as `\\`, so that an escape is never ambiguous (a name holding a backslash and
/// an 'n' is not one holding a newline).
/// eng_app_name_escape writes the escape of byte c into out (NUL-terminated) and returns
/// its length, or returns 0 when c stands for itself.
int eng_app_name_escape(unsigned char c, char out[5]);
/// Writes `name` to f with its control characters escaped (eng_app_name_escape).
void eng_app_write_name(FILE *f, const char *name);

#endif
