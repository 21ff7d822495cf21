// What a run writes and reports: statistics and the metrics CSV, divergence, the video,
// the screenshot and the summary line.
#include "engine/app/app_internal.h"

#include <epoxy/gl.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "engine/gl/screenshot.h"

void app_write_metrics_header(app *a)
{
    fprintf(a->metrics, "frame,time,particles,rho0,rho_max,rho_avg,step_ms");
    for (int s = 0; s < PBF_STAGE_COUNT; s++) fprintf(a->metrics, ",%s_ms", pbf_stage_name((pbf_stage)s));
    fprintf(a->metrics, ",nan,outside,overflow,rho_err_avg,kinetic_energy,speed_max,com_x,com_y,com_z,momentum_x,"
                       "momentum_y,momentum_z,substeps\n");
}

void app_take_stats(app *a, bool wait)
{
    pbf_step_stats st[16];
    int n;
    while ((n = pbf_world_poll_stats(a->inst.world, st, 16, wait)) > 0) {
        for (int i = 0; i < n; i++) {
            const pbf_step_stats *s = &st[i];
            if (a->metrics) {
                fprintf(a->metrics, "%llu,%.6f,%u,%.3f,%.3f,%.3f,%.4f", (unsigned long long)s->step, s->time,
                        s->particles, (double)s->rest_density, (double)s->density_max, (double)s->density_avg,
                        s->step_ms);
                for (int k = 0; k < PBF_STAGE_COUNT; k++) fprintf(a->metrics, ",%.4f", s->stage_ms[k]);
                fprintf(a->metrics, ",%u,%u,%u,%.6f,%.6g,%.5f,%.6f,%.6f,%.6f,%.6g,%.6g,%.6g,%d\n", s->nan_count,
                        s->outside_count, s->overflow_count, (double)s->density_error_avg, s->kinetic_energy,
                        (double)s->speed_max, s->center_of_mass[0], s->center_of_mass[1], s->center_of_mass[2],
                        s->momentum[0], s->momentum[1], s->momentum[2], s->substeps);
            }
            double e = s->rest_density > 0 ? s->density_max / s->rest_density - 1.0 : 0.0;
            if (e > a->rho_err_max) a->rho_err_max = e;
            a->step_ms_sum += s->step_ms;
            a->step_ms_n++;
            a->stats_rows++;
            a->last_stats = *s;
            a->have_stats = true;
            // A diverged solver: non-finite particles, a density no incompressible solver
            // reaches, or particles through the domain's walls. Reported once.
            if (!a->diverged && (s->nan_count > 0 || s->outside_count > 0 ||
                                 (s->rest_density > 0 && s->density_max > 3.0f * s->rest_density))) {
                a->diverged = true;
                snprintf(a->diverged_text, sizeof a->diverged_text,
                         "seiche: the solver diverged at step %llu (t = %.3f s): rho_max %.2f rho0, %u NaN, %u outside "
                         "the domain (allowed: rho_max up to 3 rho0, none NaN or outside); a smaller --dt or more "
                         "fluid.substeps or fluid.iterations keep it stable",
                         (unsigned long long)s->step, s->time, (double)(s->density_max / s->rest_density),
                         s->nan_count, s->outside_count);
            }
        }
        if (!wait && n < 16) break;
    }
}

// Headless a diverged solver ends the run (ENG_EXIT_DIVERGED); in a window the message is
// shown once and the run goes on, ending with that status when the window closes.
int app_check_diverged(app *a)
{
    if (!a->diverged || a->diverged_reported) return ENG_EXIT_OK;
    a->diverged_reported = true;
    app_report(a, a->diverged_text);
    if (a->opt->headless) return ENG_EXIT_DIVERGED;
    if (a->window_status < ENG_EXIT_DIVERGED) a->window_status = ENG_EXIT_DIVERGED;
    return ENG_EXIT_OK;
}

int app_record_frame(app *a)
{
    char err[1200];
    if (eng_video_frame(a->video, a->ctx, err, sizeof err)) return ENG_EXIT_OK;
    a->video = NULL; // closed by the failure
    app_message(a, "seiche: %s", err);
    return ENG_EXIT_USAGE;
}

int app_open_video(app *a)
{
    char err[1200];
    a->video = eng_video_open(a->ctx, a->opt->record_path, a->opt->dt, err, sizeof err);
    if (!a->video) {
        app_message(a, "seiche: %s", err);
        return ENG_EXIT_USAGE;
    }
    return ENG_EXIT_OK;
}

// Ends the video; ENG_EXIT_USAGE with a message (unless `quiet`) when ffmpeg failed.
int app_close_video(app *a, bool quiet)
{
    char err[1200];
    bool ok = eng_video_close(a->video, err, sizeof err);
    a->video = NULL;
    if (!ok && !quiet) app_message(a, "seiche: %s", err);
    return ok ? ENG_EXIT_OK : ENG_EXIT_USAGE;
}

// Closes the metrics file; ENG_EXIT_USAGE with a message if any row could not be written.
int app_close_metrics(app *a, bool quiet)
{
    if (!a->metrics) return ENG_EXIT_OK;
    bool failed = ferror(a->metrics) != 0;
    int e = errno;
    if (fclose(a->metrics) != 0 && !failed) {
        failed = true;
        e = errno;
    }
    a->metrics = NULL;
    if (failed && !quiet) app_message(a, "seiche: --metrics: writing '%s' failed: %s", a->opt->metrics_path, strerror(e));
    return failed ? ENG_EXIT_USAGE : ENG_EXIT_OK;
}

void app_print_summary(app *a)
{
    if (a->opt->quiet || !a->inst.script) return;
    const pbf_step_stats *s = &a->last_stats;
    printf("seiche: %s: %llu frame%s, %.2f s simulated, %u particles, %u bodies, rho_avg %.1f rho_max %.1f (rho0 %.0f, "
           "worst %.1f%% over), %.2f ms GPU per step, %s\n",
           eng_script_config(a->inst.script)->name, (unsigned long long)a->frame, a->frame == 1 ? "" : "s", a->time,
           a->inst.world ? pbf_world_particle_count(a->inst.world) : 0, a->inst.coupling ? cpl_body_count(a->inst.coupling) : 0,
           a->have_stats ? (double)s->density_avg : 0.0, a->have_stats ? (double)s->density_max : 0.0,
           (double)pbf_world_params(a->inst.world)->rest_density, 100.0 * a->rho_err_max,
           a->step_ms_n ? a->step_ms_sum / (double)a->step_ms_n : 0.0, eng_context_renderer(a->ctx));
}

int app_write_screenshot(app *a)
{
    char err[1024];
    a->screenshot_taken = true;
    if (!eng_screenshot_write(a->ctx, a->opt->screenshot_path, err, sizeof err)) {
        app_message(a, "seiche: --screenshot: %s", err);
        return ENG_EXIT_USAGE;
    }
    return ENG_EXIT_OK;
}

// True when line `text` calls seiche.check outside a comment.
static bool calls_check(const char *text)
{
    const char *c = strstr(text, "seiche.check");
    const char *comment = strstr(text, "--");
    return c && (!comment || c < comment);
}

// The checks of the run: copied into the report, and every line of the script that calls
// seiche.check and never ran is a failure of a headless run that otherwise passed ("a check
// scheduled after the last frame never runs" must not pass silently). A script that did not
// load has no instance: its checks are those app_load_scene kept in the report.
int app_finish_checks(app *a, int status)
{
    eng_app_report *r = a->opt->report;
    const eng_check_site *sites = NULL;
    int n = 0;
    if (a->inst.script) {
        n = eng_script_check_sites(a->inst.script, &sites);
        if (r) {
            r->check_count = n;
            memcpy(r->checks, sites, (size_t)n * sizeof *sites);
        }
    } else if (r) {
        n = r->check_count;
        sites = r->checks;
    }
    if ((!a->inst.script && !r) || !a->opt->headless) return status;
    struct stat st; // a script that did not load may be no file to read (a FIFO would block)
    FILE *f = stat(a->opt->script, &st) == 0 && S_ISREG(st.st_mode) ? fopen(a->opt->script, "r") : NULL;
    if (!f) return status;
    char text[4096];
    int line = 0, missing = 0;
    char first[1200] = "";
    while (fgets(text, sizeof text, f)) {
        line++;
        if (!calls_check(text)) continue;
        bool ran = false; // a call spread over lines reports one of its first few
        for (int i = 0; i < n && !ran; i++)
            ran = strcmp(sites[i].source, a->opt->script) == 0 && sites[i].line >= line && sites[i].line <= line + 5;
        if (ran) continue;
        if (r && r->never_ran_count < (int)(sizeof r->never_ran / sizeof r->never_ran[0]))
            r->never_ran[r->never_ran_count++] = line;
        if (missing++ == 0)
            snprintf(first, sizeof first, "%s:%d: seiche.check never ran (the run ended at frame %llu, %.3f s, first)",
                     a->opt->script, line, (unsigned long long)a->frame, a->time);
    }
    fclose(f);
    if (missing == 0 || status != ENG_EXIT_OK) return status;
    app_report(a, first);
    if (missing > 1) app_message(a, "seiche: %d lines with seiche.check never ran in all", missing);
    return ENG_EXIT_CHECK_FAILED;
}
