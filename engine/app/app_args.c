// The runner's command line: see app_args.h and docs/runner.md.
#include "engine/app/app_args.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "engine/gl/screenshot.h"
#include "engine/gl/video.h"
#include "engine/render/renderer.h"
#include "fluid/pbf.h"

// The message of a usage error, formatted into a block of its own size (an argument may be
// long: nothing is cut).
static eng_app_args_action bad(eng_app_args *out, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    free(out->error);
    out->error = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (out->error) {
        va_start(ap, fmt);
        vsnprintf(out->error, (size_t)n + 1, fmt, ap);
        va_end(ap);
    }
    return ENG_APP_ARGS_ERROR;
}

eng_app_options eng_default_app_options(void)
{
    eng_app_options o;
    memset(&o, 0, sizeof o);
    o.frames = -1;
    o.dt = 1.0 / 60.0;
    o.width = 1280;
    o.height = 720;
    o.watch = true;
    o.ui = true;
    return o;
}

const char *eng_app_set_keys(void)
{
    static char keys[1024];
    if (keys[0]) return keys;
    int n;
    const pbf_param_info *t = pbf_param_table(&n);
    size_t len = 0;
    for (int i = 0; i < n && len < sizeof keys; i++)
        len += (size_t)snprintf(keys + len, sizeof keys - len, "fluid.%s, ", t[i].name);
    const cpl_setting_info *ct = cpl_setting_table(&n);
    for (int i = 0; i < n && len < sizeof keys; i++)
        len += (size_t)snprintf(keys + len, sizeof keys - len, "coupling.%s, ", ct[i].name);
    if (len < sizeof keys) snprintf(keys + len, sizeof keys - len, "gravity.x, gravity.y, gravity.z, capacity");
    return keys;
}

int eng_app_name_escape(unsigned char c, char out[5])
{
    if (c == '\\') return snprintf(out, 5, "\\\\"); // so that "\\n" in a name is not read as a newline
    if (c >= 0x20 && c != 0x7f) return 0;
    if (c == '\n') return snprintf(out, 5, "\\n");
    if (c == '\r') return snprintf(out, 5, "\\r");
    if (c == '\t') return snprintf(out, 5, "\\t");
    return snprintf(out, 5, "\\x%02x", c);
}

void eng_app_write_name(FILE *f, const char *name)
{
    char e[5];
    for (; *name; name++) {
        if (eng_app_name_escape((unsigned char)*name, e)) fputs(e, f);
        else fputc(*name, f);
    }
}

void eng_app_args_free(eng_app_args *args)
{
    if (!args) return;
    free(args->error);
    args->error = NULL;
}

// A number as a person types it: it starts with a digit, '.' or '-' (no space, '+', "inf"
// or "nan" in front) and holds no space and no hexadecimal 'x' (strtod and strtol would
// take " 5", "+5" and "0x1p-3"); whether it parses whole is the caller's strto* check.
static bool plain_number(const char *s)
{
    if (!((*s >= '0' && *s <= '9') || *s == '.' || *s == '-')) return false;
    for (; *s; s++)
        if (*s == ' ' || (*s >= '\t' && *s <= '\r') || *s == 'x' || *s == 'X') return false;
    return true;
}

// A whole-string decimal number. A value that underflows (1e-400) is taken as strtod
// rounds it (to zero or a subnormal): it is a number, only smaller than a double holds.
// An overflow (HUGE_VAL) or inf/nan is refused.
static bool parse_real(const char *s, double *v)
{
    char *end;
    errno = 0;
    *v = strtod(s, &end);
    if (!plain_number(s) || end == s || *end || !isfinite(*v)) return false;
    return errno == 0 || errno == ERANGE;
}

// The options that take one value and may be given once; --set is repeatable.
static const char *const SCALAR_OPTIONS[] = { "--frames", "--dt",   "--metrics", "--screenshot", "--record", "--size",
                                              "--shaders", "--budget", "--render", "--junit",     "--tap" };
#define SCALAR_COUNT ((int)(sizeof SCALAR_OPTIONS / sizeof SCALAR_OPTIONS[0]))

static int scalar_index(const char *a)
{
    for (int k = 0; k < SCALAR_COUNT; k++)
        if (strcmp(a, SCALAR_OPTIONS[k]) == 0) return k;
    return -1;
}

eng_app_args_action eng_app_parse_args(int argc, char *const *argv, eng_app_args *out)
{
    memset(out, 0, sizeof *out);
    out->options = eng_default_app_options();
    eng_app_options *o = &out->options;
    const char *given[SCALAR_COUNT] = { 0 }; // each scalar option's value, once given
    int sets_given = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *v = i + 1 < argc ? argv[i + 1] : NULL;
        int scalar = scalar_index(a);
        bool takes = scalar >= 0 || strcmp(a, "--set") == 0;
        if (takes && !v) return bad(out, "option %s needs a value", a);
        if (scalar >= 0 && given[scalar])
            return bad(out, "%s may be given once (got '%s' and '%s')", a, given[scalar], v);
        if (scalar >= 0) given[scalar] = v;
        if (strcmp(a, "--") == 0) {
            // The end of the options: the next argument is the script, whatever it looks like.
            if (i + 1 >= argc) return bad(out, "'--' must be followed by the script");
            if (o->script) return bad(out, "only one script may be given (got '%s' and '%s')", o->script, argv[i + 1]);
            o->script = argv[++i];
            if (i + 1 < argc) return bad(out, "only one script may be given (got '%s' and '%s')", o->script, argv[i + 1]);
            break;
        } else if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
            return ENG_APP_ARGS_HELP;
        } else if (strcmp(a, "--version") == 0) {
            return ENG_APP_ARGS_VERSION;
        } else if (strcmp(a, "--headless") == 0) {
            o->headless = true;
        } else if (strcmp(a, "--hash") == 0) {
            o->hash = true;
        } else if (strcmp(a, "--quiet") == 0) {
            o->quiet = true;
        } else if (strcmp(a, "--no-watch") == 0) {
            o->watch = false;
        } else if (strcmp(a, "--no-ui") == 0) {
            o->ui = false;
        } else if (strcmp(a, "--trusted") == 0) {
            o->trusted = true;
        } else if (strcmp(a, "--budget") == 0) {
            double b;
            if (!parse_real(v, &b) || b <= 0.0 || b > 3600.0)
                return bad(out, "--budget must be a number of seconds in (0, 3600] (got '%s')", v);
            o->budget_s = b;
            i++;
        } else if (strcmp(a, "--frames") == 0) {
            char *end;
            errno = 0;
            long n = strtol(v, &end, 10);
            if (!plain_number(v) || *end || end == v || errno || n < 0 || n > 100000000)
                return bad(out, "--frames must be a whole number in [0, 100000000] (got '%s')", v);
            o->frames = n;
            i++;
        } else if (strcmp(a, "--dt") == 0) {
            double dt;
            if (!parse_real(v, &dt) || dt < 1e-5 || dt > 1.0)
                return bad(out, "--dt must be a number of seconds in [0.00001, 1] (got '%s')", v);
            o->dt = dt;
            i++;
        } else if (strcmp(a, "--set") == 0) {
            if (!strchr(v, '=')) return bad(out, "--set expects KEY=VALUE (got '%s')", v);
            if (o->set_count < ENG_APP_MAX_SETS) o->sets[o->set_count++] = v;
            sets_given++; // more than ENG_APP_MAX_SETS: refused below, saying how many
            i++;
        } else if (strcmp(a, "--junit") == 0) {
            out->junit = v;
            i++;
        } else if (strcmp(a, "--tap") == 0) {
            out->tap = v;
            i++;
        } else if (strcmp(a, "--metrics") == 0) {
            o->metrics_path = v;
            i++;
        } else if (strcmp(a, "--screenshot") == 0) {
            o->screenshot_path = v;
            i++;
        } else if (strcmp(a, "--record") == 0) {
            o->record_path = v;
            i++;
        } else if (strcmp(a, "--render") == 0) {
            eng_fluid_mode mode;
            if (!eng_fluid_mode_parse(v, &mode))
                return bad(out, "--render must be one of surface|spheres|density|speed (got '%s')", v);
            o->render = v;
            i++;
        } else if (strcmp(a, "--shaders") == 0) {
            if (!v[0]) return bad(out, "--shaders must name a directory (got '')");
            o->shader_dir = v;
            i++;
        } else if (strcmp(a, "--size") == 0) {
            // Digits, 'x', digits: strtol alone would take " 16" and "+16".
            const char *vx = strchr(v, 'x');
            bool digits = v[0] >= '0' && v[0] <= '9' && vx && vx[1] >= '0' && vx[1] <= '9';
            char *x = NULL, *end = NULL;
            errno = 0;
            long w = digits ? strtol(v, &x, 10) : -1;
            long h = digits && x == vx ? strtol(vx + 1, &end, 10) : -1;
            if (!digits || errno || x != vx || !end || *end || w < 16 || h < 16 || w > 16384 || h > 16384)
                return bad(out, "--size must be WxH with each a whole number in [16, 16384] (got '%s')", v);
            o->width = (int)w;
            o->height = (int)h;
            i++;
        } else if (a[0] == '-' && a[1]) {
            return bad(out, "unknown option '%s'", a);
        } else if (o->script) {
            return bad(out, "only one script may be given (got '%s' and '%s')", o->script, a);
        } else {
            o->script = a;
        }
    }
    if (sets_given > ENG_APP_MAX_SETS)
        return bad(out, "at most %d --set options may be given (got %d)", ENG_APP_MAX_SETS, sets_given);
    // A key given twice is refused, as an option given twice is: the runner does not guess
    // which of the two values was meant.
    for (int i = 1; i < o->set_count; i++)
        for (int j = 0; j < i; j++) {
            size_t ki = strcspn(o->sets[i], "="), kj = strcspn(o->sets[j], "=");
            if (ki == kj && strncmp(o->sets[i], o->sets[j], ki) == 0)
                return bad(out, "--set %.*s may be given once (got '%s' and '%s')", (int)ki, o->sets[i], o->sets[j],
                           o->sets[i]);
        }
    if (!o->script) return bad(out, "no script given");
    // Outputs whose names or sizes cannot work are refused here, before anything runs.
    if (o->screenshot_path && eng_image_format_of(o->screenshot_path) == ENG_IMAGE_UNKNOWN)
        return bad(out, "--screenshot must name a file ending in " ENG_SCREENSHOT_EXTENSIONS " (got '%s')",
                   o->screenshot_path);
    if (o->record_path && !eng_video_extension_ok(o->record_path))
        return bad(out, "--record must name a file ending in " ENG_VIDEO_EXTENSIONS
                   " (ffmpeg picks the format from it) (got '%s')", o->record_path);
    if (o->record_path && (o->width % 2 || o->height % 2))
        return bad(out, "--record needs an even width and height for the video encoder (got --size %dx%d)", o->width,
                   o->height);
    return ENG_APP_ARGS_RUN;
}

int eng_app_apply_sets(const eng_app_options *options, eng_scene_config *c, char *err, size_t err_size)
{
    // The fluid.* options apply together, checked as a set (pbf_params_apply), so that any
    // consistent particle_radius / kernel_radius pair is accepted in any order.
    char fluid_keys[ENG_APP_MAX_SETS][128];
    const char *fluid_names[ENG_APP_MAX_SETS];
    double fluid_values[ENG_APP_MAX_SETS];
    int fluid_count = 0;
    for (int i = 0; i < options->set_count; i++) {
        const char *kv = options->sets[i];
        const char *eq = strchr(kv, '=');
        char key[128];
        if (!eq || eq == kv || (size_t)(eq - kv) >= sizeof key) {
            snprintf(err, err_size, "seiche: --set expects KEY=VALUE (got '%s')", kv);
            return ENG_EXIT_USAGE;
        }
        snprintf(key, sizeof key, "%.*s", (int)(eq - kv), kv);
        double v;
        if (!parse_real(eq + 1, &v)) {
            snprintf(err, err_size, "seiche: --set %s: value must be a finite number (got '%s')", key, eq + 1);
            return ENG_EXIT_USAGE;
        }
        if (strncmp(key, "fluid.", 6) == 0) {
            snprintf(fluid_keys[fluid_count], sizeof fluid_keys[0], "%s", key + 6);
            fluid_names[fluid_count] = fluid_keys[fluid_count];
            fluid_values[fluid_count++] = v;
        } else if (strncmp(key, "coupling.", 9) == 0) {
            char cerr[256];
            if (cpl_def_set(&c->coupling, key + 9, v, cerr, sizeof cerr) != CPL_OK) {
                snprintf(err, err_size, "seiche: --set %s: %s", key, cerr);
                return ENG_EXIT_USAGE;
            }
        } else if (strcmp(key, "capacity") == 0) {
            if (v < 1 || v > 67108864 || v != floor(v)) {
                snprintf(err, err_size, "seiche: --set capacity must be a whole number in [1, 67108864] (got %s)", eq + 1);
                return ENG_EXIT_USAGE;
            }
            c->capacity = (uint32_t)v;
        } else if (strncmp(key, "gravity.", 8) == 0 && key[8] >= 'x' && key[8] <= 'z' && !key[9]) {
            if (fabs(v) > 1000.0) {
                snprintf(err, err_size, "seiche: --set %s must be in [-1000, 1000] m/s^2 (got %s)", key, eq + 1);
                return ENG_EXIT_USAGE;
            }
            c->params.gravity[key[8] - 'x'] = (float)v;
        } else {
            snprintf(err, err_size, "seiche: --set: unknown key '%s' (known: %s)", key, eng_app_set_keys());
            return ENG_EXIT_USAGE;
        }
    }
    char perr[512];
    if (pbf_params_apply(&c->params, fluid_names, fluid_values, fluid_count, perr, sizeof perr) != PBF_OK) {
        snprintf(err, err_size, "seiche: --set fluid: %s", perr);
        return ENG_EXIT_USAGE;
    }
    return ENG_EXIT_OK;
}
