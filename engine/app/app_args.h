// The runner's command line (docs/runner.md) as functions a program or a test can call
// without running a scene: eng_app_parse_args reads argv into eng_app_options (every
// number checked against its range, nothing opened or written), and eng_app_apply_sets
// applies the --set KEY=VALUE overrides to a scene's configuration, as the app does after
// the script's main chunk ran. demos/seiche/main.c and tests/fuzz/fuzz_cli.c use both.
#ifndef ENG_APP_ARGS_H
#define ENG_APP_ARGS_H

#include <stddef.h>

#include "engine/app/app.h"
#include "engine/script/script.h"

/// What the command line asks for.
typedef enum eng_app_args_action {
    ENG_APP_ARGS_RUN = 0,  ///< run options.script (checked: given, every value in range)
    ENG_APP_ARGS_HELP,     ///< --help or -h: print the usage text, exit 0
    ENG_APP_ARGS_VERSION,  ///< --version: print the version, exit 0
    ENG_APP_ARGS_ERROR,    ///< a usage error: the message is in eng_app_args.error, exit 2
} eng_app_args_action;

typedef struct eng_app_args {
    eng_app_options options; ///< the run's options; strings point into argv
    const char *junit;       ///< --junit FILE.xml, or NULL
    const char *tap;         ///< --tap FILE, or NULL
    /// ENG_APP_ARGS_ERROR: the message without the "seiche: " in front, e.g. "--dt must be a
    /// number of seconds in [0.00001, 1] (got '2')" (malloc'd; NULL when memory ran out).
    /// Release with eng_app_args_free.
    char *error;
} eng_app_args;

/// Reads argv[1..argc-1] (argv[0] is the program) into *out, which it first fills with the
/// defaults (eng_default_app_options). Stops at the first --help, --version or error.
/// Refused: an option that takes one value given twice (--set repeats, up to
/// ENG_APP_MAX_SETS, each KEY once), a number that is not written plainly (" 5", "+5", "0x10"), a
/// --screenshot name without .png/.jpg/.jpeg, a --record name without one of
/// ENG_VIDEO_EXTENSIONS or with an odd --size. "--" ends the options: the argument after
/// it is the script, whatever it looks like, and must be the last.
/// Opens no file: whether the script exists and outputs differ is the caller's check.
eng_app_args_action eng_app_parse_args(int argc, char *const *argv, eng_app_args *out);
void eng_app_args_free(eng_app_args *args);

/// Applies options->sets (the --set KEY=VALUE overrides) to *c: fluid.NAME for every fluid
/// parameter (applied together and checked as a set, pbf_params_apply), gravity.x|y|z in
/// [-1000, 1000] m/s^2, capacity a whole number in [1, 67108864]. ENG_EXIT_OK, or
/// ENG_EXIT_USAGE with "seiche: --set ..." in err (which names the key, the value and what
/// is allowed); *c may then be partly changed (the app drops the scene).
int eng_app_apply_sets(const eng_app_options *options, eng_scene_config *c, char *err, size_t err_size);

#endif
