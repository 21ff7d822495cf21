// Reports of one or more scene-script runs in the formats CI systems display: JUnit XML
// (--junit) and TAP 13 (--tap). Each script is a test suite; each of its seiche.check call
// sites is a test case (failed if any call failed, or if it never ran), and the run itself
// is one more (failed on any status but 0, with its message). Names are written with their
// control characters escaped (eng_app_name_escape), and in TAP a '#' as "\#".
#ifndef SEICHE_REPORT_H
#define SEICHE_REPORT_H

#include <stdbool.h>
#include <stddef.h>

#include "engine/app/app.h"

/// The status of a run (of a suite, or with a report: each runs in its own process) whose
/// process ended before the run did: a signal (a crash, a kill), or an exit the runner did
/// not make (os.exit in a --trusted script).
#define SEICHE_EXIT_PROCESS_ENDED 6

typedef struct seiche_run {
    const char *script;
    eng_app_report report;
} seiche_run;

/// Writes the runs as JUnit XML to `path`. False with a message in err when the file could
/// not be written completely.
bool seiche_write_junit(const char *path, const seiche_run *runs, int count, char *err, size_t err_size);
/// The same as TAP version 13.
bool seiche_write_tap(const char *path, const seiche_run *runs, int count, char *err, size_t err_size);

#endif
