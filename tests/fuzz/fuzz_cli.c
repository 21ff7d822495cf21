// libFuzzer harness: the runner's command line (engine/app/app_args.h, docs/runner.md).
//
// Each input becomes an argv: option names (every option, near misses, "-", "--", bare
// words), values made to sit at and just past the documented ranges (--frames, --dt,
// --budget, --size, --render), --set KEY=VALUE with every key the runner knows and near
// misses, and raw bytes from the input. eng_app_parse_args reads it without opening a
// file; then eng_app_apply_sets applies the --set overrides to a default scene's settings.
//
// Checked besides crashes, leaks and undefined behaviour:
// - a run is accepted only with every number in its documented range (frames in
//   [0, 100000000] or the default, dt in [0.00001, 1], budget in (0, 3600] or the default,
//   size each in [16, 16384], at most 64 --set, each with '=', --render a known mode);
// - every string the options keep is an element of argv, at the place the documented
//   grammar puts it (a value right after its option, the script in an option's place or
//   right after a "--" there, which ends the options);
// - an option that takes one value is accepted at most once (--set repeats, each KEY
//   once), and --frames, --dt, --budget and --size only as plain numbers (no space, '+' or
//   hexadecimal);
// - an option that takes a value, given last, is an error; --help, -h and --version are
//   answered only where they stand as options; an error always comes with a message;
// - eng_app_apply_sets accepts only a capacity in [1, 67108864], gravity in [-1000, 1000],
//   coupling settings that cpl_def_check accepts and fluid parameters that
//   pbf_params_validate accepts; a refusal names the --set.
// Build and run: make fuzz (docs/testing.md).
#include "engine/app/app_args.h"
#include "fluid/pbf.h"
#include "tests/fuzz/fuzz_input.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ARGS 96
#define MAX_ARG_LEN 256

// Options of the documented grammar that take a value (docs/runner.md).
static const char *const VALUE_OPTIONS[] = { "--frames", "--dt",   "--set",   "--metrics", "--screenshot", "--record",
                                             "--junit",  "--tap",  "--size",  "--shaders", "--budget",     "--render" };
static const char *const FLAG_OPTIONS[] = { "--headless", "--hash", "--quiet", "--no-watch", "--no-ui", "--trusted" };
static const char *const ODD_OPTIONS[] = { "--help", "-h", "--version", "-", "--", "---", "--frame", "--FRAMES",
                                           "--dt=0.1", "--frames=3", "-frames", "--set=", "--", "x.lua", "a/b.lua",
                                           "", " ", "--headles", "--sizes", "-x", "--\xff", "--render\n" };
static const char *const NUMBERS[] = {
    "0", "-0", "1", "-1", "+1", " 1", "1 ", "0x10", "010", "1e3", "1e-5", "0.00001", "0.0000099999", "1e-6", "9.9999e-6",
    "1.0", "1.0000001", "0.5", "1/60", "100000000", "100000001", "99999999", "2147483647", "2147483648",
    "4294967296", "9223372036854775807", "9223372036854775808", "-9223372036854775809", "1e308", "1e309", "-1e309",
    "nan", "NAN", "-nan", "inf", "-inf", "infinity", "3600", "3600.0000001", "3599.9999", "0x1p-17", "0x1.0p0",
    "5e-324", "1e-320", "", " ", "-", ".", "e", "1e", "1.", ".5", "1,5", "1_000", "١", "1\t", "\t1",
};
static const char *const SIZES[] = { "16x16",   "15x16",       "16x15",  "16384x16384", "16385x16", "16x16385",
                                     "1280x720", "x720",       "1280x",  "1280X720",    "1280x720x", " 16x 16",
                                     "+16x+16",  "-16x16",     "16x-16", "4294967312x16", "16x4294967312",
                                     "99999999999999999999x16", "16x99999999999999999999", "0x10x16", "16x0x10",
                                     "x", "", "16x16 ", "1e2x16" };
static const char *const RENDERS[] = { "surface", "spheres", "density", "speed", "Surface", "surface ", "", "none",
                                       "sphere", "speedy" };
static const char *const EXTRA_KEYS[] = { "capacity", "gravity.x", "gravity.y", "gravity.z", "gravity.w", "gravity.",
                                          "gravity.xx", "fluid.", "fluid", "", "=", "fluid.fluid.iterations",
                                          "Capacity", "capacity ", " capacity", "coupling.force_latency",
                                          "coupling.force_smoothing", "coupling.impulse_limit", "coupling.mesh_cell",
                                          "coupling.", "coupling.latency" };

#define COUNT(a) (sizeof(a) / sizeof((a)[0]))

typedef struct argv_buf {
    char *argv[MAX_ARGS + 1];
    int argc;
} argv_buf;

// A string of at most MAX_ARG_LEN bytes from the input (a byte 0 ends it early).
static char *raw_string(fuzz_input *in)
{
    size_t n = fuzz_u8(in) % MAX_ARG_LEN;
    char *s = malloc(n + 1);
    size_t k = 0;
    for (; k < n && in->size > 0; k++) {
        s[k] = (char)fuzz_u8(in);
        if (!s[k]) break;
    }
    s[k] = 0;
    return s;
}

static char *copy(const char *s)
{
    size_t n = strlen(s);
    char *c = malloc(n + 1);
    memcpy(c, s, n + 1);
    return c;
}

static char *number(fuzz_input *in)
{
    uint8_t how = fuzz_u8(in);
    if (how < 200) return copy(NUMBERS[how % COUNT(NUMBERS)]);
    if (how < 230) { // a printed double from the shared table of hard numbers
        char b[64];
        snprintf(b, sizeof b, how & 1 ? "%.17g" : "%g", fuzz_double(in));
        return copy(b);
    }
    return raw_string(in);
}

// KEY=VALUE for --set: a key the runner knows (or a near miss), then a number.
static char *set_value(fuzz_input *in)
{
    int count = 0;
    const pbf_param_info *table = pbf_param_table(&count);
    uint8_t how = fuzz_u8(in);
    char key[160];
    if (how < 150 && count > 0) snprintf(key, sizeof key, "fluid.%s", table[fuzz_u8(in) % count].name);
    else if (how < 220) snprintf(key, sizeof key, "%s", EXTRA_KEYS[fuzz_u8(in) % COUNT(EXTRA_KEYS)]);
    else {
        char *r = raw_string(in);
        snprintf(key, sizeof key, "%.150s", r);
        free(r);
    }
    if (fuzz_u8(in) == 255) return copy(key); // no '='
    char *v = number(in);
    size_t n = strlen(key) + strlen(v) + 2;
    char *kv = malloc(n);
    snprintf(kv, n, "%s=%s", key, v);
    free(v);
    return kv;
}

static void push(argv_buf *b, char *s)
{
    if (b->argc < MAX_ARGS) b->argv[b->argc++] = s;
    else free(s);
}

static void build_argv(fuzz_input *in, argv_buf *b)
{
    b->argc = 0;
    push(b, copy("seiche"));
    int words = fuzz_u8(in) % MAX_ARGS;
    for (int i = 0; i < words && in->size > 0; i++) {
        uint8_t how = fuzz_u8(in);
        if (how < 110) {
            const char *opt = VALUE_OPTIONS[fuzz_u8(in) % COUNT(VALUE_OPTIONS)];
            push(b, copy(opt));
            if (fuzz_u8(in) == 0) continue; // sometimes no value
            if (!strcmp(opt, "--set")) push(b, set_value(in));
            else if (!strcmp(opt, "--size")) push(b, fuzz_u8(in) < 220 ? copy(SIZES[fuzz_u8(in) % COUNT(SIZES)]) : raw_string(in));
            else if (!strcmp(opt, "--render")) push(b, fuzz_u8(in) < 220 ? copy(RENDERS[fuzz_u8(in) % COUNT(RENDERS)]) : raw_string(in));
            else if (!strcmp(opt, "--frames") || !strcmp(opt, "--dt") || !strcmp(opt, "--budget")) push(b, number(in));
            else push(b, fuzz_u8(in) < 128 ? copy("out.file") : raw_string(in));
        } else if (how < 170) {
            push(b, copy(FLAG_OPTIONS[fuzz_u8(in) % COUNT(FLAG_OPTIONS)]));
        } else if (how < 190) {
            push(b, copy(ODD_OPTIONS[fuzz_u8(in) % COUNT(ODD_OPTIONS)]));
        } else if (how < 215) {
            push(b, copy("scene.lua"));
        } else {
            push(b, raw_string(in));
        }
    }
    b->argv[b->argc] = NULL;
}

static void fail(const argv_buf *b, const char *what)
{
    fprintf(stderr, "fuzz_cli: %s\n  argv:", what);
    for (int i = 0; i < b->argc; i++) fprintf(stderr, " '%s'", b->argv[i]);
    fprintf(stderr, "\n");
    abort();
}

static bool takes_value(const char *a)
{
    for (size_t k = 0; k < COUNT(VALUE_OPTIONS); k++)
        if (!strcmp(a, VALUE_OPTIONS[k])) return true;
    return false;
}

// The documented grammar's reading of argv: role[i] is 'o' for an option (or a script) at
// an option's place, 'v' for the value of the option before it, 's' for the argument after
// a "--" in an option's place (the script, whatever it looks like) and 'x' for any after
// that. Returns false when an option that takes a value is last.
static bool roles(const argv_buf *b, char *role)
{
    role[0] = 'p';
    for (int i = 1; i < b->argc; i++) {
        role[i] = 'o';
        if (!strcmp(b->argv[i], "--")) {
            for (int k = i + 1; k < b->argc; k++) role[k] = k == i + 1 ? 's' : 'x';
            return true;
        }
        if (takes_value(b->argv[i])) {
            if (i + 1 >= b->argc) return false;
            role[++i] = 'v';
        }
    }
    return true;
}

// `s` must be NULL or argv[k] with role[k] == 'v' and argv[k - 1] equal to `option`.
static void check_value(const argv_buf *b, const char *role, const char *s, const char *option)
{
    if (!s) return;
    for (int k = 2; k < b->argc; k++)
        if (b->argv[k] == s && role[k] == 'v' && !strcmp(b->argv[k - 1], option)) return;
    char msg[128];
    snprintf(msg, sizeof msg, "the value kept for %s is not the argument after an %s", option, option);
    fail(b, msg);
}

static bool appears_as_option(const argv_buf *b, const char *role, const char *name, int before)
{
    for (int k = 1; k < b->argc && k < before; k++)
        if (role[k] == 'o' && !strcmp(b->argv[k], name)) return true;
    return false;
}

static void check_sets(const argv_buf *b, const eng_app_options *o)
{
    pbf_params defaults = pbf_default_params();
    eng_scene_config c;
    memset(&c, 0, sizeof c);
    c.params = defaults;
    c.capacity = 12345;
    c.coupling = cpl_default_def();
    char err[2048];
    memset(err, 0, sizeof err);
    int st = eng_app_apply_sets(o, &c, err, sizeof err);
    if (st != ENG_EXIT_OK) {
        if (st != ENG_EXIT_USAGE) fail(b, "eng_app_apply_sets returned neither ENG_EXIT_OK nor ENG_EXIT_USAGE");
        if (strncmp(err, "seiche: --set", 13) != 0) fail(b, "a refused --set without a message naming --set");
        if (!memchr(err, 0, sizeof err)) fail(b, "the message of a refused --set is not NUL-terminated");
        return;
    }
    if (c.capacity != 12345 && (c.capacity < 1 || c.capacity > 67108864)) fail(b, "--set capacity out of range accepted");
    for (int k = 0; k < 3; k++)
        if (!(fabsf(c.params.gravity[k]) <= 1000.0f) && c.params.gravity[k] != defaults.gravity[k])
            fail(b, "--set gravity out of [-1000, 1000] accepted");
    char perr[512];
    if (cpl_def_check(&c.coupling, perr, sizeof perr) != CPL_OK) {
        fprintf(stderr, "fuzz_cli: cpl_def_check: %s\n", perr);
        fail(b, "--set coupling.* left settings that cpl_def_check refuses");
    }
    if (pbf_params_validate(&c.params, perr, sizeof perr) != PBF_OK) {
        fprintf(stderr, "fuzz_cli: pbf_params_validate: %s\n", perr);
        fail(b, "--set fluid.* left parameters that pbf_params_validate refuses");
    }
}

static void check(const argv_buf *b, eng_app_args_action action, const eng_app_args *r)
{
    char role[MAX_ARGS + 1];
    bool complete = roles(b, role);
    int help_at = b->argc, version_at = b->argc;
    for (int k = 1; k < b->argc; k++) {
        if (role[k] != 'o') continue;
        if (help_at == b->argc && (!strcmp(b->argv[k], "--help") || !strcmp(b->argv[k], "-h"))) help_at = k;
        if (version_at == b->argc && !strcmp(b->argv[k], "--version")) version_at = k;
    }
    switch (action) {
    case ENG_APP_ARGS_HELP:
        if (help_at == b->argc) fail(b, "help without --help or -h in an option's place");
        return;
    case ENG_APP_ARGS_VERSION:
        if (version_at == b->argc) fail(b, "version without --version in an option's place");
        return;
    case ENG_APP_ARGS_ERROR:
        if (!r->error || !r->error[0]) fail(b, "an error without a message");
        return;
    case ENG_APP_ARGS_RUN: break;
    default: fail(b, "an action that is not an eng_app_args_action");
    }
    const eng_app_options *o = &r->options;
    if (!complete) fail(b, "accepted with an option that takes a value given last, without one");
    if (help_at < b->argc || version_at < b->argc) fail(b, "--help / --version in an option's place did not answer");
    if (!o->script) fail(b, "accepted without a script");
    if (!(o->frames == -1 || (o->frames >= 0 && o->frames <= 100000000))) fail(b, "--frames out of [0, 100000000] accepted");
    if (!(o->dt == 1.0 / 60.0 || (o->dt >= 1e-5 && o->dt <= 1.0))) fail(b, "--dt out of [0.00001, 1] accepted");
    if (!(o->budget_s == 0.0 || (o->budget_s > 0.0 && o->budget_s <= 3600.0))) fail(b, "--budget out of (0, 3600] accepted");
    if (!((o->width == 1280 && o->height == 720) ||
          (o->width >= 16 && o->width <= 16384 && o->height >= 16 && o->height <= 16384)))
        fail(b, "--size out of [16, 16384] accepted");
    if (o->set_count < 0 || o->set_count > ENG_APP_MAX_SETS) fail(b, "more --set than ENG_APP_MAX_SETS");
    eng_fluid_mode mode;
    if (o->render && !eng_fluid_mode_parse(o->render, &mode)) fail(b, "an unknown --render mode accepted");
    check_value(b, role, o->metrics_path, "--metrics");
    check_value(b, role, o->screenshot_path, "--screenshot");
    check_value(b, role, o->record_path, "--record");
    check_value(b, role, o->shader_dir, "--shaders");
    check_value(b, role, o->render, "--render");
    check_value(b, role, r->junit, "--junit");
    check_value(b, role, r->tap, "--tap");
    for (int i = 0; i < o->set_count; i++) {
        check_value(b, role, o->sets[i], "--set");
        if (!strchr(o->sets[i], '=')) fail(b, "a --set without '=' accepted");
        for (int j = 0; j < i; j++) {
            size_t ki = strcspn(o->sets[i], "="), kj = strcspn(o->sets[j], "=");
            if (ki == kj && !strncmp(o->sets[i], o->sets[j], ki)) fail(b, "a --set KEY accepted twice");
        }
    }
    // The script: an argument in an option's place that is no option, or the one after "--".
    int script_at = 0;
    for (int k = 1; k < b->argc && !script_at; k++)
        if (b->argv[k] == o->script && (role[k] == 'o' || role[k] == 's')) script_at = k;
    if (!script_at) fail(b, "the script is not an argument in an option's place or after '--'");
    if (role[script_at] == 'o' && o->script[0] == '-' && o->script[1]) fail(b, "an option taken for the script");
    for (int k = 1; k < b->argc; k++)
        if (role[k] == 'x') fail(b, "accepted with an argument after the script that follows '--'");
    // Each option that takes one value at most once; numbers plain.
    for (size_t n = 0; n < COUNT(VALUE_OPTIONS); n++) {
        if (!strcmp(VALUE_OPTIONS[n], "--set")) continue;
        int times = 0;
        for (int k = 1; k < b->argc; k++) times += role[k] == 'o' && !strcmp(b->argv[k], VALUE_OPTIONS[n]);
        if (times > 1) fail(b, "an option that takes one value accepted twice");
    }
    for (int k = 2; k < b->argc; k++) {
        if (role[k] != 'v') continue;
        const char *opt = b->argv[k - 1], *v = b->argv[k];
        bool number = !strcmp(opt, "--frames") || !strcmp(opt, "--dt") || !strcmp(opt, "--budget") ||
                      !strcmp(opt, "--size");
        if (number && (strpbrk(v, " \t\n\v\f\r+xX") != NULL) && strcmp(opt, "--size") != 0)
            fail(b, "a number with a space, '+' or hexadecimal accepted");
        if (number && !strcmp(opt, "--size") && strpbrk(v, " \t\n\v\f\r+") != NULL)
            fail(b, "a --size with a space or '+' accepted");
    }
    // Flags seen as options are set.
    if (appears_as_option(b, role, "--headless", b->argc) != o->headless) fail(b, "--headless not as given");
    if (appears_as_option(b, role, "--trusted", b->argc) != o->trusted) fail(b, "--trusted not as given");
    if (appears_as_option(b, role, "--no-watch", b->argc) == o->watch) fail(b, "--no-watch not as given");
    check_sets(b, o);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = { data, size };
    argv_buf b;
    build_argv(&in, &b);
    eng_app_args r;
    eng_app_args_action action = eng_app_parse_args(b.argc, b.argv, &r);
    check(&b, action, &r);
    eng_app_args_free(&r);
    for (int i = 0; i < b.argc; i++) free(b.argv[i]);
    return 0;
}
