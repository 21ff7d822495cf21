// seiche: the scene runner. Runs a Lua scene script in a window or headless.
// Command line and exit statuses: docs/runner.md (and `seiche --help`).
// realpath (X/Open): the suite's reports are compared with its scripts by real path.
#define _XOPEN_SOURCE 700
#define _DEFAULT_SOURCE // MAP_ANONYMOUS: the memory a run's process hands its report back in
#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdarg.h>
#include <stdbool.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "demos/seiche/report.h"
#include "engine/app/app.h"
#include "engine/app/app_args.h"
#include "engine/gl/gl_strict.h"
#include "fluid/pbf.h"

static void usage(FILE *f)
{
    fprintf(f,
            "usage: seiche [options] SCRIPT.lua\n"
            "       seiche --headless [options] DIRECTORY   every *.lua in it as one suite, one report\n"
            "  --headless            no window (EGL surfaceless or device platform)\n"
            "  --frames N            run N frames (steps; a paused window waits), then exit\n"
            "                        (headless default: 600)\n"
            "  --dt SECONDS          fixed frame step, [0.00001, 1] (default 1/60)\n"
            "  --set KEY=VALUE       override a scene parameter, e.g. fluid.iterations=4 or\n"
            "                        coupling.force_latency=2 (repeatable)\n"
            "  --metrics FILE.csv    one row per frame: frame, time, particles, rho0, rho_max, rho_avg,\n"
            "                        step_ms, <stage>_ms ..., nan, outside, overflow, rho_err_avg,\n"
            "                        kinetic_energy, speed_max, com_x, com_y, com_z, momentum_x,\n"
            "                        momentum_y, momentum_z, substeps\n"
            "  --screenshot FILE.png the last frame (.png, or .jpg / .jpeg)\n"
            "  --record FILE.mp4     frames to video through ffmpeg (.mp4, .mkv, .mov, .webm or .avi;\n"
            "                        an even --size), at exactly 1/dt frames per second\n"
            "  --junit FILE.xml      a JUnit XML report: each seiche.check call site and the run\n"
            "  --tap FILE            the same report as TAP version 13\n"
            "  --hash                print a hash of the final simulation state\n"
            "  --size WxH            framebuffer size in pixels (default 1280x720)\n"
            "  --render MODE         how the water is drawn: surface (default), spheres (coloured by\n"
            "                        initial height), density or speed (colour maps)\n"
            "  --shaders DIR         read shaders from DIR (default: those built into the program;\n"
            "                        SEICHE_SHADER_DIR sets DIR too)\n"
            "  --budget SECONDS      longest the script's calls of one frame may run together,\n"
            "                        (0, 3600] (default 5 headless, 2 in a window)\n"
            "  --trusted             give the script every standard Lua library (io, os, package,\n"
            "                        debug); default: the sandbox (docs/lua-api.md). Only for scripts\n"
            "                        you trust as you would a program\n"
            "  --no-watch            window: do not reload the script when its file is saved\n"
            "  --no-ui               window: no parameter panel or on-screen error box\n"
            "  --quiet               no summary line\n"
            "  --version             print the version and exit\n"
            "  --help                this text\n"
            "  --                    the end of the options: the next argument is the script\n"
            "an option that takes a value may be given once (--set repeats, each KEY once);\n"
            "numbers are plain\n"
            "keys in a window: space pause, n single step, r reset, F5 reload (on_reload), c camera\n"
            "mode, v water look (surface, spheres, density, speed), F1 panel, Esc quit; orbit with\n"
            "the left mouse button, zoom with the wheel.\n"
            "Saving the script reloads it. The Lua API: docs/lua-api.md; this command: docs/runner.md.\n"
            "exit status: 0 ok, 1 a check in the script failed, 2 usage or script error,\n"
            "             3 no OpenGL 4.3 compute context (or no display without --headless),\n"
            "             4 the solver diverged,\n"
            "             5 a GL error or synchronisation hazard (a bug in Seiche),\n"
            "             6 (a suite or a report) a script's run ended its process: a crash, a kill\n"
            "               or an exit the runner did not make\n");
}

// A path that does not exist (yet) as its directory's real path and its own name, for
// comparing names of files to be written. False when the directory has none either.
static bool real_path_to_be(const char *p, char *out, size_t size)
{
    const char *slash = strrchr(p, '/');
    char dir[4096];
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - p) + 1 : 1, slash ? p : ".");
    char *r = realpath(dir, NULL);
    if (!r) return false;
    int n = snprintf(out, size, "%s/%s", r, slash ? slash + 1 : p);
    free(r);
    return n >= 0 && (size_t)n < size;
}

// True when the two paths name one file: the same text, both exist as one inode (through
// links and other spellings), or neither exists and both name one place in one directory.
static bool same_file(const char *a, const char *b)
{
    if (strcmp(a, b) == 0) return true;
    struct stat sa, sb;
    bool ea = stat(a, &sa) == 0, eb = stat(b, &sb) == 0;
    if (ea || eb) return ea && eb && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    char ra[8192], rb[8192];
    return real_path_to_be(a, ra, sizeof ra) && real_path_to_be(b, rb, sizeof rb) && strcmp(ra, rb) == 0;
}

static int bad(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

static int by_name(const void *x, const void *y) { return strcmp(*(char *const *)x, *(char *const *)y); }

// What a run's process hands back: the report, and whether eng_app_run returned at all.
typedef struct run_outcome {
    eng_app_report report;
    int finished;
} run_outcome;

// In a run's process: a GL failure (the strict mode's hazard, a driver error) ends the
// process at once; its message goes into the report first, then as the default handler does.
static void gl_failure_in_child(void *user, const char *message)
{
    run_outcome *shared = user;
    shared->report.status = ENG_GL_EXIT_STATUS;
    snprintf(shared->report.message, sizeof shared->report.message, "%.*s", (int)strcspn(message, "\n"), message);
    shared->finished = 1;
    fprintf(stderr, "seiche: %s\n", message);
    fflush(NULL);
    _exit(ENG_GL_EXIT_STATUS);
}

// SIGTERM, SIGINT or SIGHUP to the runner during a suite (a CI job's timeout, Ctrl-C): passed
// on to the run in progress, whose end is then recorded; the suite stops there and its
// reports are written before the runner ends by the same signal.
static volatile sig_atomic_t stop_signal;
static volatile sig_atomic_t running_child; // the pid of the run in progress, 0 between runs
static const int STOP_SIGNALS[] = { SIGTERM, SIGINT, SIGHUP };
#define STOP_SIGNAL_COUNT ((int)(sizeof STOP_SIGNALS / sizeof STOP_SIGNALS[0]))

static void forward_stop(int sig)
{
    stop_signal = sig;
    if (running_child > 0) kill((pid_t)running_child, sig);
}

static void stop_signals_mask(sigset_t *set)
{
    sigemptyset(set);
    for (int k = 0; k < STOP_SIGNAL_COUNT; k++) sigaddset(set, STOP_SIGNALS[k]);
}

// Runs one script in a child process, so that a run that ends its process (a crash in a
// driver or a library, the OOM killer, os.exit in a --trusted script) ends only its own run:
// it is recorded with status 6 and the suite goes on, and its report is still written.
// `shared` is memory the child writes its outcome into.
static int run_isolated(const eng_app_options *o, run_outcome *shared, eng_app_report *out)
{
    fflush(stdout);
    fflush(stderr);
    memset(shared, 0, sizeof *shared);
    // The stop signals are held across the fork: the child must not run the runner's
    // handler, and the parent must know the child before it can pass one on.
    sigset_t stops, before;
    stop_signals_mask(&stops);
    sigprocmask(SIG_BLOCK, &stops, &before);
    pid_t parent = getpid();
    pid_t pid = fork();
    if (pid == 0) {
        for (int k = 0; k < STOP_SIGNAL_COUNT; k++) signal(STOP_SIGNALS[k], SIG_DFL);
        prctl(PR_SET_PDEATHSIG, SIGKILL); // a runner killed outright takes its run with it
        if (getppid() != parent) _exit(SEICHE_EXIT_PROCESS_ENDED);
        sigprocmask(SIG_SETMASK, &before, NULL);
        eng_app_options c = *o;
        c.report = &shared->report;
        eng_gl_strict_set_handler(gl_failure_in_child, shared, NULL, NULL);
        int st = eng_app_run(&c);
        shared->finished = 1;
        exit(st);
    }
    if (pid > 0) running_child = (sig_atomic_t)pid;
    sigprocmask(SIG_SETMASK, &before, NULL); // one that came meanwhile is passed on now
    memset(out, 0, sizeof *out);
    if (pid < 0) {
        out->status = ENG_EXIT_USAGE;
        snprintf(out->message, sizeof out->message, "the run could not be started: fork: %s", strerror(errno));
        fprintf(stderr, "seiche: %s\n", out->message);
        return out->status;
    }
    int ws = 0;
    while (waitpid(pid, &ws, 0) < 0 && errno == EINTR) {
    }
    running_child = 0;
    *out = shared->report;
    if (WIFEXITED(ws) && shared->finished && WEXITSTATUS(ws) == shared->report.status) return out->status;
    char why[160];
    if (WIFSIGNALED(ws))
        snprintf(why, sizeof why, "was ended by signal %d (%s)", WTERMSIG(ws), strsignal(WTERMSIG(ws)));
    else if (shared->finished)
        snprintf(why, sizeof why, "exited with status %d after the run's status %d", WEXITSTATUS(ws), shared->report.status);
    else
        snprintf(why, sizeof why, "exited with status %d before the run ended (an exit the runner did not make, "
                 "such as os.exit in a --trusted script)", WIFEXITED(ws) ? WEXITSTATUS(ws) : -1);
    out->status = SEICHE_EXIT_PROCESS_ENDED;
    snprintf(out->message, sizeof out->message, "the run's process %s", why);
    fprintf(stderr, "seiche: ");
    eng_app_write_name(stderr, o->script);
    fprintf(stderr, ": %s\n", out->message);
    return out->status;
}

// One script with a report, or every *.lua of a directory in name order as one suite
// (headless): each runs as its own run; the status is the worst of them.
static int run_suite(const eng_app_options *base, bool dir, const char *junit, const char *tap)
{
    char **scripts = NULL;
    int count = 0, cap = 0;
    if (dir) {
        DIR *d = opendir(base->script);
        if (!d) return bad("cannot read the directory '%s': %s", base->script, strerror(errno));
        // DIR/x.lua, also for a DIR given as "DIR/" (not "DIR//x.lua").
        size_t dir_len = strlen(base->script);
        while (dir_len > 1 && base->script[dir_len - 1] == '/') dir_len--;
        const char *sep = base->script[dir_len - 1] == '/' ? "" : "/";
        for (struct dirent *e; (e = readdir(d)) != NULL;) {
            size_t n = strlen(e->d_name);
            if (n < 5 || strcmp(e->d_name + n - 4, ".lua") != 0) continue;
            if (count == cap) {
                cap = cap ? cap * 2 : 64;
                char **more = realloc(scripts, (size_t)cap * sizeof *more);
                if (!more) break;
                scripts = more;
            }
            size_t len = strlen(base->script) + n + 2;
            scripts[count] = malloc(len);
            if (!scripts[count]) break;
            snprintf(scripts[count++], len, "%.*s%s%s", (int)dir_len, base->script, sep, e->d_name);
        }
        closedir(d);
        qsort(scripts, (size_t)count, sizeof *scripts, by_name);
        if (count == 0) {
            free(scripts);
            return bad("no *.lua scripts in the directory '%s'", base->script);
        }
        // A report may not overwrite a script of the suite (checked before any runs).
        const char *outputs[2][2] = { { "--junit", junit }, { "--tap", tap } };
        for (int k = 0; k < 2; k++)
            for (int i = 0; outputs[k][1] && i < count; i++)
                if (same_file(outputs[k][1], scripts[i])) {
                    bad("%s would overwrite a script of the suite ('%s'): give each output its own file", outputs[k][0],
                        scripts[i]);
                    for (int j = 0; j < count; j++) free(scripts[j]);
                    free(scripts);
                    return 2;
                }
    }
    seiche_run *runs = calloc(dir ? (size_t)count : 1u, sizeof *runs);
    run_outcome *shared = mmap(NULL, sizeof *shared, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
    if (!runs || shared == MAP_FAILED) {
        free(runs);
        if (shared != MAP_FAILED) munmap(shared, sizeof *shared);
        return bad("out of memory");
    }
    if (!dir) count = 1;
    struct sigaction stop, previous[STOP_SIGNAL_COUNT];
    memset(&stop, 0, sizeof stop);
    stop.sa_handler = forward_stop; // no SA_RESTART: waitpid returns, and waits again
    sigemptyset(&stop.sa_mask);
    for (int k = 0; k < STOP_SIGNAL_COUNT; k++) sigaction(STOP_SIGNALS[k], &stop, &previous[k]);
    int worst = 0, failed = 0, ran = 0;
    for (int i = 0; i < count && !stop_signal; i++, ran++) {
        eng_app_options o = *base;
        o.script = runs[i].script = dir ? scripts[i] : base->script;
        o.name_script = dir; // one log holds many runs: each message says whose it is
        int st = run_isolated(&o, shared, &runs[i].report);
        if (st > worst) worst = st;
        failed += st != 0;
        if (dir) { // a name holding a newline stays on its line
            printf("%s  ", st ? "FAILED" : "ok    ");
            eng_app_write_name(stdout, o.script);
            printf(" (exit %d)\n", st);
        }
    }
    if (dir && ran == count) printf("%d passed, %d failed\n", count - failed, failed);
    else if (dir) printf("%d passed, %d failed, %d not run: the runner was stopped by signal %d (%s)\n", ran - failed, failed,
                         count - ran, (int)stop_signal, strsignal(stop_signal));
    char err[1200];
    count = ran; // the reports hold the runs made
    if (junit && !seiche_write_junit(junit, runs, count, err, sizeof err)) {
        fprintf(stderr, "seiche: --junit: %s\n", err);
        worst = worst > 2 ? worst : 2;
    }
    if (tap && !seiche_write_tap(tap, runs, count, err, sizeof err)) {
        fprintf(stderr, "seiche: --tap: %s\n", err);
        worst = worst > 2 ? worst : 2;
    }
    for (int i = 0; dir && i < count; i++) free(scripts[i]);
    free(scripts);
    free(runs);
    munmap(shared, sizeof *shared);
    for (int k = 0; k < STOP_SIGNAL_COUNT; k++) sigaction(STOP_SIGNALS[k], &previous[k], NULL);
    if (stop_signal) { // the reports are written: now end as that signal ends a program
        fflush(NULL);
        signal(stop_signal, SIG_DFL);
        raise(stop_signal);
    }
    return worst;
}

// A usage error: status 2. The message names paths as given, so its control characters (and
// backslashes) are escaped as in the runner's other lines (eng_app_write_name): a name
// holding a newline does not make a second line.
static int bad(const char *fmt, ...)
{
    char msg[8192];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    fprintf(stderr, "seiche: ");
    eng_app_write_name(stderr, msg);
    fprintf(stderr, "\n(try 'seiche --help')\n");
    return 2;
}

int main(int argc, char **argv)
{
    // stdout (results, summaries, the script's print) line by line, as stderr (messages) is
    // unbuffered: piped into one log (`2>&1 | tee`), a script's lines come out in the order
    // they were written, not its results after the next script's errors.
    setvbuf(stdout, NULL, _IOLBF, 0);
    eng_app_args args;
    switch (eng_app_parse_args(argc, argv, &args)) {
    case ENG_APP_ARGS_HELP:
        usage(stdout);
        return 0;
    case ENG_APP_ARGS_VERSION:
        printf("seiche %s\n", pbf_version());
        return 0;
    case ENG_APP_ARGS_ERROR: {
        int st = bad("%s", args.error ? args.error : "out of memory");
        eng_app_args_free(&args);
        return st;
    }
    case ENG_APP_ARGS_RUN: break;
    }
    eng_app_options o = args.options;
    const char *junit = args.junit, *tap = args.tap;
    struct stat st;
    if (stat(o.script, &st) != 0) return bad("cannot open script '%s': %s", o.script, strerror(errno));
    bool dir = S_ISDIR(st.st_mode);
    if (dir && (o.metrics_path || o.screenshot_path || o.record_path))
        return bad("--metrics, --screenshot and --record name one file: they cannot go with a directory of scripts "
                   "('%s')", o.script);
    if (dir && !o.headless) return bad("a directory of scripts runs headless: add --headless ('%s')", o.script);
    if (!dir) {
        FILE *f = fopen(o.script, "rb");
        if (!f) return bad("cannot open script '%s': %s", o.script, strerror(errno));
        fclose(f);
    }
    // No output may overwrite the script or another output.
    const char *names[6] = { "the script", "--metrics", "--screenshot", "--record", "--junit", "--tap" };
    const char *paths[6] = { o.script, o.metrics_path, o.screenshot_path, o.record_path, junit, tap };
    for (int i = 1; i < 6; i++)
        for (int j = 0; j < i; j++)
            if (paths[i] && paths[j] && same_file(paths[i], paths[j])) {
                return bad("%s would overwrite %s ('%s'): give each output its own file", names[i], names[j], paths[i]);
            }
    // A video whose reader (ffmpeg) stops must not kill the runner: writes fail with EPIPE
    // and are reported instead.
    signal(SIGPIPE, SIG_IGN);
    if (!dir && !junit && !tap) return eng_app_run(&o);
    return run_suite(&o, dir, junit, tap);
}
