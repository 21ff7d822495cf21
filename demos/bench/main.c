// seiche-bench: GPU time of the fluid step on the standard scenes.
//
// The reference scene (docs/performance.md): a dam break of a 1 x 1 x 1 m block of water
// in a 4 x 3 x 1.5 m tank, particle spacing 2r = (1 m^3 / N)^(1/3), kernel radius twice
// the spacing, dt 4 ms, one substep. For each particle count and iteration count it runs
// warm-up steps, then measured steps, and prints the median per-stage and per-step GPU
// milliseconds (GL timer queries), the wall-clock time per step, the density error the
// solver reached, and the GL renderer; --json writes the same. With --render MODE each step
// is also drawn (the renderer's look in that mode, headless at --size, the camera of
// seiche-render-bench), so that the wall-clock time per step is a frame's, rendering
// included: it prints that as frames per second with the renderer's GPU time per frame.
#include <errno.h>
#include <stdbool.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <epoxy/gl.h>

#include "engine/core/progress.h"
#include "engine/gl/context.h"
#include "engine/gl/gpu_timer.h"
#include "engine/render/camera.h"
#include "engine/render/renderer.h"
#include "fluid/pbf.h"

#include "demos/render_bench/bench_camera.h"

#define MAX_LIST 16

typedef struct options {
    long particles[MAX_LIST];
    int particle_count;
    long iterations[MAX_LIST];
    int iteration_count;
    long substeps[MAX_LIST];
    int substep_count;
    int steps, warmup;
    double dt;
    double sor;         // the solver's relaxation factor (pbf_params.sor)
    const char *json;
    const char *shader_dir;
    float tank[3];      // m, the container (and domain) from the origin
    float block;        // m, side of the block of water at the origin
    unsigned grid_cells;  // pbf_world_def.grid_cells_per_kernel (0: the library's default)
    bool tank_test;     // also run each case in a tank 20x wider and deeper
    const char *trace;    // --trace FILE: one CSV line per measured step (appended)
    bool render;          // --render MODE: draw every step
    eng_fluid_mode mode;
    eng_fluid_splat splat;
    int width, height;    // --size
} options;

// What drawing every step needs (--render).
typedef struct drawing {
    eng_context *ctx;
    eng_renderer *renderer;
    eng_camera cam;
} drawing;

typedef struct result {
    long particles_asked;
    uint32_t particles;
    int iterations, substeps;
    double stage_ms[PBF_STAGE_COUNT];
    double step_ms;       // median GPU time of the step (stages but metrics)
    double wall_ms;       // wall-clock per step, GPU synchronised at the end
    double cpu_ms;        // process CPU time per step (on a CPU driver such as llvmpipe this
                          // is the work itself, less sensitive to other load than wall time)
    double rho_err_avg;   // mean over measured steps of (rho_avg / rho0 - 1)
    double err_avg;       // mean over measured steps of mean max(rho / rho0 - 1, 0)
    double rho_err_max;   // max over measured steps of (rho_max / rho0 - 1)
    double memory_mib;    // GPU memory of the world (pbf_world_def_memory)
    double frame_ms;      // --render: median GPU time of the renderer's frame
    uint32_t nan_count, outside_count, overflow_count;
} result;

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static double cpu_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    if (n == 0) return 0.0;
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

static int parse_list(const char *s, long *out, int *count, const char *name, long lo, long hi)
{
    *count = 0;
    const char *p = s;
    while (*p) {
        char *end;
        errno = 0;
        long v = strtol(p, &end, 10);
        if (end == p || errno || v < lo || v > hi || (*end && *end != ',') || *count >= MAX_LIST) {
            fprintf(stderr, "seiche-bench: %s must be a comma-separated list of whole numbers in [%ld, %ld] (got '%s')\n",
                    name, lo, hi, s);
            return 0;
        }
        out[(*count)++] = v;
        p = *end ? end + 1 : end;
    }
    return *count > 0;
}

// Draws the world's water once (--render).
static void draw(const drawing *dr, pbf_world *w)
{
    eng_renderer_begin(dr->renderer, dr->ctx, &dr->cam);
    eng_fluid_draw fd = eng_fluid_draw_of(w, NULL);
    eng_renderer_draw_fluid(dr->renderer, &fd);
    eng_renderer_end(dr->renderer);
}

static int run_one(const options *o, const drawing *dr, long n, int iterations, int substeps, float tank_scale,
                   result *r, eng_progress *pr, long base)
{
    memset(r, 0, sizeof *r);
    r->particles_asked = n;
    r->iterations = iterations;
    r->substeps = substeps;
    double spacing = (double)o->block / cbrt((double)n);
    pbf_world_def d = pbf_default_world_def();
    d.params.particle_radius = (float)(0.5 * spacing);
    d.params.kernel_radius = (float)(2.0 * spacing);
    d.params.iterations = iterations;
    d.params.substeps = substeps;
    d.params.sor = (float)o->sor;
    d.params.cfl = 0.0f; // each row measures the iterations x substeps it names: no time-step guard
    d.params.guard_compression = 0.0f;
    d.params.vorticity = 0.0f; // the reference solver runs PBF with XSPH viscosity only
    d.max_neighbours = pbf_suggest_max_neighbours(&d.params);
    d.capacity = (uint32_t)(n + n / 4 + 1024);
    const float lo[3] = { 0, 0, 0 }, hi[3] = { o->tank[0] * tank_scale, o->tank[1], o->tank[2] * tank_scale };
    memcpy(d.domain_min, lo, sizeof lo);
    memcpy(d.domain_max, hi, sizeof hi);
    if (o->shader_dir) d.shader_dir = o->shader_dir;
    if (o->grid_cells) d.grid_cells_per_kernel = o->grid_cells;
    r->memory_mib = (double)pbf_world_def_memory(&d) / (1024.0 * 1024.0);
    char err[1024];
    pbf_world *w = pbf_world_create(&d, err, sizeof err);
    if (!w) {
        fprintf(stderr, "seiche-bench: %s\n", err);
        return 0;
    }
    pbf_block_def b = pbf_default_block_def();
    b.max[0] = b.max[1] = b.max[2] = o->block;
    if (pbf_world_set_container(w, lo, hi, false) != PBF_OK || pbf_world_add_block(w, &b, &r->particles) != PBF_OK) {
        fprintf(stderr, "seiche-bench: %s\n", pbf_world_last_error(w));
        pbf_world_destroy(w);
        return 0;
    }
    if (dr) eng_renderer_set_shadow_bounds(dr->renderer, lo, hi);
    for (int i = 0; i < o->warmup; i++, eng_progress_update(pr, base + i, -1.0)) {
        if (pbf_world_step(w, (float)o->dt) != PBF_OK) {
            fprintf(stderr, "seiche-bench: %ld particles: %s\n", n, pbf_world_last_error(w));
            pbf_world_destroy(w);
            return 0;
        }
        if (dr) draw(dr, w);
    }
    pbf_world_poll_stats(w, NULL, 0, true);
    int cap = o->steps;
    double *step = calloc((size_t)cap, sizeof *step);
    double *stage[PBF_STAGE_COUNT];
    for (int s = 0; s < PBF_STAGE_COUNT; s++) stage[s] = calloc((size_t)cap, sizeof(double));
    int got = 0;
    double rho_sum = 0.0, err_sum = 0.0;
    pbf_step_stats st[16];
    double *submit = calloc((size_t)cap, sizeof *submit), *poll = calloc((size_t)cap, sizeof *poll);
    double *rho_max = calloc((size_t)cap, sizeof *rho_max), *frame = calloc((size_t)cap, sizeof *frame);
    int frames = 0;
    eng_gpu_timer *timer = dr ? eng_renderer_gpu_timer(dr->renderer) : NULL;
    long frame_samples = 0;
    uint32_t *overflow = calloc((size_t)cap, sizeof *overflow);
    bool failed = !step || !submit || !poll || !rho_max || !overflow || !frame;
    for (int s = 0; s < PBF_STAGE_COUNT; s++) failed |= !stage[s];
    if (failed) fprintf(stderr, "seiche-bench: %ld particles: out of memory for %d steps' timings\n", n, cap);
    glFinish();
    double t0 = now_s(), c0 = cpu_s();
    for (int i = 0; i < o->steps && !failed; i++) {
        double ts = now_s();
        if (pbf_world_step(w, (float)o->dt) != PBF_OK) {
            fprintf(stderr, "seiche-bench: %ld particles: %s\n", n, pbf_world_last_error(w));
            failed = true;
            break;
        }
        if (dr) {
            draw(dr, w);
            // The frame's GPU time, when a frame's timestamps have come back (never waited for).
            for (int k = 0; k < eng_gpu_timer_section_count(timer); k++) {
                double ms;
                const char *name = eng_gpu_timer_section(timer, k, &ms);
                long samples = eng_gpu_timer_samples(timer, k);
                if (name && strcmp(name, "frame") == 0 && samples > frame_samples && ms >= 0.0 && frames < cap) {
                    frame[frames++] = ms;
                    frame_samples = samples;
                }
            }
        }
        double tp = now_s();
        submit[i] = (tp - ts) * 1000.0;
        eng_progress_update(pr, base + o->warmup + i + 1, -1.0);
        int k;
        while ((k = pbf_world_poll_stats(w, st, 16, i == o->steps - 1)) > 0) {
            for (int j = 0; j < k && got < cap; j++, got++) {
                step[got] = st[j].step_ms;
                for (int s = 0; s < PBF_STAGE_COUNT; s++) stage[s][got] = st[j].stage_ms[s];
                rho_sum += st[j].density_avg / st[j].rest_density - 1.0;
                err_sum += st[j].density_error_avg;
                double e = st[j].density_max / st[j].rest_density - 1.0;
                if (e > r->rho_err_max) r->rho_err_max = e;
                rho_max[got] = e;
                overflow[got] = st[j].overflow_count;
                r->nan_count += st[j].nan_count;
                r->outside_count += st[j].outside_count;
                r->overflow_count += st[j].overflow_count;
            }
            if (k < 16) break;
        }
        poll[i] = (now_s() - tp) * 1000.0;
    }
    glFinish();
    r->wall_ms = (now_s() - t0) * 1000.0 / o->steps;
    r->cpu_ms = (cpu_s() - c0) * 1000.0 / o->steps;
    r->step_ms = median(step, got);
    r->frame_ms = median(frame, frames);
    for (int s = 0; s < PBF_STAGE_COUNT; s++) r->stage_ms[s] = median(stage[s], got);
    r->rho_err_avg = got ? rho_sum / got : 0.0;
    r->err_avg = got ? err_sum / got : 0.0;
    FILE *tf = o->trace && !failed ? fopen(o->trace, "a") : NULL;
    if (o->trace && !failed && !tf) fprintf(stderr, "seiche-bench: cannot append to --trace %s\n", o->trace);
    if (tf) {
        // Where a step's time went: the CPU inside pbf_world_step and inside the statistics
        // poll, against the GPU's own timers of that step.
        if (ftell(tf) == 0) {
            fprintf(tf, "particles,iterations,substeps,step,submit_ms,poll_ms,gpu_ms,rho_max_pct,overflow");
            for (int g = 0; g < PBF_STAGE_COUNT; g++) fprintf(tf, ",%s", pbf_stage_name((pbf_stage)g));
            fprintf(tf, "\n");
        }
        for (int i = 0; i < o->steps; i++) {
            fprintf(tf, "%u,%d,%d,%d,%.4f,%.4f", r->particles, iterations, substeps, i, submit[i], poll[i]);
            if (i < got) {
                fprintf(tf, ",%.4f,%.3f,%u", step[i], 100.0 * rho_max[i], overflow[i]);
                for (int g = 0; g < PBF_STAGE_COUNT; g++) fprintf(tf, ",%.4f", stage[g][i]);
            }
            fprintf(tf, "\n");
        }
        fclose(tf);
    }
    free(submit);
    free(poll);
    free(rho_max);
    free(frame);
    free(overflow);
    free(step);
    for (int s = 0; s < PBF_STAGE_COUNT; s++) free(stage[s]);
    pbf_world_destroy(w);
    if (!failed && got == 0) {
        fprintf(stderr, "seiche-bench: %ld particles: no step statistics came back\n", n);
        failed = true;
    }
    return !failed;
}

// One line of the table (and one JSON object); `scale` is the tank's x and z scale.
static void print_row(const result *r, float scale, bool rendered, FILE *js, int *first)
{
    printf("%9u %5d %4d %4.0fx %8.1f %9.2f %9.2f %9.2f %9.3f %9.3f %9.3f", r->particles, r->iterations, r->substeps,
           (double)scale, r->memory_mib, r->step_ms, r->wall_ms, r->cpu_ms, 100.0 * r->rho_err_avg, 100.0 * r->err_avg,
           100.0 * r->rho_err_max);
    for (int s = 0; s < PBF_STAGE_COUNT; s++) printf(" %.2f", r->stage_ms[s]);
    if (rendered) printf("  frame_ms %.2f, %.1f frames/s", r->frame_ms, r->wall_ms > 0.0 ? 1000.0 / r->wall_ms : 0.0);
    printf("%s\n", r->nan_count || r->outside_count ? "  (NaN or lost particles!)" : "");
    fflush(stdout);
    if (!js) return;
    fprintf(js, "%s\n    {\"particles\": %u, \"iterations\": %d, \"substeps\": %d, \"tank_scale\": %g, "
                "\"memory_mib\": %.3f, \"step_ms\": %.4f, \"wall_ms\": %.4f, \"cpu_ms\": %.4f, \"rho_err_avg\": %.6f, "
                "\"err_avg\": %.6f, \"rho_err_max\": %.6f, \"nan\": %u, \"outside\": %u, \"overflow\": %u, \"stage_ms\": {",
            *first ? "" : ",", r->particles, r->iterations, r->substeps, (double)scale, r->memory_mib, r->step_ms,
            r->wall_ms, r->cpu_ms, r->rho_err_avg, r->err_avg, r->rho_err_max, r->nan_count, r->outside_count,
            r->overflow_count);
    for (int s = 0; s < PBF_STAGE_COUNT; s++)
        fprintf(js, "%s\"%s\": %.4f", s ? ", " : "", pbf_stage_name((pbf_stage)s), r->stage_ms[s]);
    fprintf(js, "}");
    if (rendered) fprintf(js, ", \"frame_ms\": %.4f, \"frames_per_s\": %.3f", r->frame_ms,
                          r->wall_ms > 0.0 ? 1000.0 / r->wall_ms : 0.0);
    fprintf(js, "}");
    *first = 0;
}

static void usage(FILE *f)
{
    fprintf(f, "usage: seiche-bench [--particles N[,N...]] [--iterations K[,K...]] [--substeps S[,S...]]\n"
               "                    [--steps M] [--warmup W] [--dt SECONDS] [--sor W] [--json FILE] [--shaders DIR]\n"
               "                    [--tank X,Y,Z] [--block S] [--tank-test] [--trace FILE]\n"
               "                    [--grid-cells K] [--render surface|spheres|density|speed]\n"
               "                    [--splat raster|compute] [--size WxH]\n"
               "defaults: --particles 16000,64000 --iterations 3 --substeps 1 --steps 60 --warmup 10 --dt 0.004\n"
               "          --sor 0 (the library's default, pbf_params.sor: the relaxation schedule; W in (0, 2):\n"
               "          that constant factor on every iteration)\n"
               "          --tank 4,3,1.5 (m) --block 1 (m: a block S x S x S at the tank's corner)\n"
               "--tank-test runs each case again in a tank 20x wider and deeper (x, z) and prints the\n"
               "ratios of GPU time per step and of memory: cost should follow the water, not the tank\n"
               "--trace appends one CSV line per measured step to FILE: CPU ms inside the step and the\n"
               "statistics poll, the GPU's ms of that step and of each stage, rho_max, overflows\n"
               "--grid-cells K: neighbour grid cells per kernel radius (default: the library's, 2)\n"
               "--render MODE draws every step in that mode (headless, --size, default 1280x720; --splat:\n"
               "the look's way of drawing the particle passes, default compute): wall_ms is then a frame,\n"
               "simulation and drawing, printed as frames/s beside the renderer's GPU ms per frame\n"
               "lists (comma-separated) of particles, iterations and substeps run every combination\n"
               "exit status: 0 ok, 1 a run lost particles or produced NaN, 2 a usage, world or write error,\n"
               "             3 no OpenGL 4.3 compute context\n");
}

int main(int argc, char **argv)
{
    options o;
    memset(&o, 0, sizeof o);
    o.particles[0] = 16000;
    o.particles[1] = 64000;
    o.particle_count = 2;
    o.iterations[0] = 3;
    o.iteration_count = 1;
    o.substeps[0] = 1;
    o.substep_count = 1;
    o.steps = 60;
    o.warmup = 10;
    o.dt = 0.004;
    o.sor = pbf_default_params().sor;
    o.tank[0] = 4.0f;
    o.tank[1] = 3.0f;
    o.tank[2] = 1.5f;
    o.block = 1.0f;
    o.splat = eng_default_fluid_look().splat;
    o.width = 1280;
    o.height = 720;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (strcmp(a, "--help") == 0) {
            usage(stdout);
            return 0;
        }
        if (strcmp(a, "--tank-test") == 0) {
            o.tank_test = true;
            continue;
        }
        if (!v) {
            fprintf(stderr, "seiche-bench: unknown option or missing value: '%s'\n", a);
            usage(stderr);
            return 2;
        }
        long tmp[MAX_LIST];
        int cnt;
        if (strcmp(a, "--particles") == 0) {
            if (!parse_list(v, o.particles, &o.particle_count, "--particles", 1, 1 << 26)) return 2;
        } else if (strcmp(a, "--iterations") == 0) {
            if (!parse_list(v, o.iterations, &o.iteration_count, "--iterations", 1, 100)) return 2;
        } else if (strcmp(a, "--substeps") == 0) {
            if (!parse_list(v, o.substeps, &o.substep_count, "--substeps", 1, 64)) return 2;
        } else if (strcmp(a, "--steps") == 0) {
            if (!parse_list(v, tmp, &cnt, "--steps", 1, 100000) || cnt != 1) return 2;
            o.steps = (int)tmp[0];
        } else if (strcmp(a, "--warmup") == 0) {
            if (!parse_list(v, tmp, &cnt, "--warmup", 0, 100000) || cnt != 1) return 2;
            o.warmup = (int)tmp[0];
        } else if (strcmp(a, "--dt") == 0) {
            char *end;
            o.dt = strtod(v, &end);
            if (*end || !(o.dt > 0.0 && o.dt <= 1.0)) {
                fprintf(stderr, "seiche-bench: --dt must be in (0, 1] s (got '%s')\n", v);
                return 2;
            }
        } else if (strcmp(a, "--sor") == 0) {
            char *end;
            o.sor = strtod(v, &end);
            if (*end || !(o.sor >= 0.0 && o.sor < 2.0)) {
                fprintf(stderr, "seiche-bench: --sor must be 0 (the relaxation schedule) or in (0, 2) (got '%s')\n", v);
                return 2;
            }
        } else if (strcmp(a, "--tank") == 0) {
            float t[3];
            char tail;
            if (sscanf(v, "%f,%f,%f%c", &t[0], &t[1], &t[2], &tail) != 3 || !(t[0] > 0.0f && t[1] > 0.0f && t[2] > 0.0f) ||
                t[0] > 1e4f || t[1] > 1e4f || t[2] > 1e4f) {
                fprintf(stderr, "seiche-bench: --tank must be X,Y,Z in (0, 10000] m (got '%s')\n", v);
                return 2;
            }
            memcpy(o.tank, t, sizeof t);
        } else if (strcmp(a, "--grid-cells") == 0) {
            char *end;
            long k = strtol(v, &end, 10);
            if (*end || k < 1 || k > 4) {
                fprintf(stderr, "seiche-bench: --grid-cells must be 1, 2, 3 or 4 neighbour grid cells per kernel radius "
                                "(pbf_world_def.grid_cells_per_kernel; got '%s')\n", v);
                return 2;
            }
            o.grid_cells = (unsigned)k;
        } else if (strcmp(a, "--block") == 0) {
            char *end;
            double b = strtod(v, &end);
            if (*end || !(b > 0.0 && b <= 1e3)) {
                fprintf(stderr, "seiche-bench: --block must be a side in (0, 1000] m (got '%s')\n", v);
                return 2;
            }
            o.block = (float)b;
        } else if (strcmp(a, "--json") == 0) {
            o.json = v;
        } else if (strcmp(a, "--trace") == 0) {
            o.trace = v;
        } else if (strcmp(a, "--shaders") == 0) {
            o.shader_dir = v;
        } else if (strcmp(a, "--render") == 0) {
            if (!eng_fluid_mode_parse(v, &o.mode)) {
                fprintf(stderr, "seiche-bench: --render must be one of %s (got '%s')\n", eng_fluid_mode_names(), v);
                return 2;
            }
            o.render = true;
        } else if (strcmp(a, "--splat") == 0) {
            if (!eng_fluid_splat_parse(v, &o.splat)) {
                fprintf(stderr, "seiche-bench: --splat must be raster or compute (got '%s')\n", v);
                return 2;
            }
        } else if (strcmp(a, "--size") == 0) {
            char tail;
            if (sscanf(v, "%dx%d%c", &o.width, &o.height, &tail) != 2 || o.width < 16 || o.height < 16 ||
                o.width > 16384 || o.height > 16384) {
                fprintf(stderr, "seiche-bench: --size must be WxH, each in [16, 16384] (got '%s')\n", v);
                return 2;
            }
        } else {
            fprintf(stderr, "seiche-bench: unknown option '%s'\n", a);
            usage(stderr);
            return 2;
        }
        i++;
    }
    eng_context_def cd = eng_default_context_def();
    cd.mode = ENG_CONTEXT_HEADLESS;
    cd.width = o.render ? o.width : 64;
    cd.height = o.render ? o.height : 64;
    eng_context_status cst;
    char err[2048];
    eng_context *ctx = eng_context_create(&cd, &cst, err, sizeof err);
    if (!ctx) return cst == ENG_CONTEXT_NO_COMPUTE || cst == ENG_CONTEXT_NO_GL ? 3 : 2;
    printf("renderer: %s\n", eng_context_renderer(ctx));
    drawing dr;
    memset(&dr, 0, sizeof dr);
    if (o.render) {
        eng_renderer_def rd = eng_default_renderer_def();
        rd.shader_dir = o.shader_dir;
        rd.fluid.mode = o.mode;
        rd.fluid.splat = o.splat;
        dr.ctx = ctx;
        dr.renderer = eng_renderer_create(&rd, err, sizeof err);
        if (!dr.renderer || !bench_camera(&dr.cam, err, sizeof err)) {
            fprintf(stderr, "seiche-bench: %s\n", err);
            eng_renderer_destroy(dr.renderer);
            eng_context_destroy(ctx);
            return 2;
        }
        printf("drawing every step: %s mode, %s splats, %dx%d (the camera of seiche-render-bench)\n",
               eng_fluid_mode_name(o.mode), eng_fluid_splat_name(o.splat), o.width, o.height);
    }
    printf("scene: dam break, a %g m cube of water in a %g x %g x %g m tank, h = 2 spacings, dt %.4g s, sor %g%s, "
           "wall friction %g, XSPH on, vorticity off; median of %d steps after %d warm-up\n",
           (double)o.block, (double)o.tank[0], (double)o.tank[1], (double)o.tank[2], o.dt, o.sor,
           o.sor == 0.0 ? " (the relaxation schedule)" : "", (double)pbf_default_params().wall_friction, o.steps, o.warmup);
    FILE *js = NULL;
    if (o.json) {
        js = fopen(o.json, "w");
        if (!js) {
            fprintf(stderr, "seiche-bench: cannot write '%s': %s\n", o.json, strerror(errno));
            eng_context_destroy(ctx);
            return 2;
        }
        fprintf(js, "{\n  \"renderer\": \"%s\",\n  \"dt\": %g,\n  \"sor\": %g,\n  \"steps\": %d,\n  \"warmup\": %d,\n  \"runs\": [",
                eng_context_renderer(ctx), o.dt, o.sor, o.steps, o.warmup);
    }
    printf("%9s %5s %4s %5s %8s %9s %9s %9s %9s %9s %9s", "particles", "iter", "sub", "tank", "mem_MiB", "step_ms",
           "wall_ms", "cpu_ms", "rho_avg%", "err_avg%", "rho_max%");
    for (int s = 0; s < PBF_STAGE_COUNT; s++) printf(" %s", pbf_stage_name((pbf_stage)s));
    printf("\n");
    int ok = 1, first = 1, diverged = 0;
    long runs = (long)o.particle_count * o.substep_count * o.iteration_count * (o.tank_test ? 2 : 1), run_index = 0;
    eng_progress pr;
    eng_progress_begin(&pr, "bench step", runs * (o.warmup + o.steps));
    for (int pi = 0; pi < o.particle_count && ok; pi++)
        for (int si = 0; si < o.substep_count && ok; si++)
        for (int ii = 0; ii < o.iteration_count && ok; ii++) {
            result r[2];
            int scales = o.tank_test ? 2 : 1;
            for (int t = 0; t < scales && ok; t++) {
                long base = run_index++ * (o.warmup + o.steps);
                float scale = t == 0 ? 1.0f : 20.0f;
                int done = run_one(&o, o.render ? &dr : NULL, o.particles[pi], (int)o.iterations[ii],
                                   (int)o.substeps[si], scale, &r[t], &pr, base);
                eng_progress_end(&pr);
                if (!done) {
                    ok = 0;
                    break;
                }
                print_row(&r[t], scale, o.render, js, &first);
                if (r[t].nan_count || r[t].outside_count) diverged = 1;
            }
            if (ok && scales == 2) {
                double tr = r[0].step_ms > 0 ? r[1].step_ms / r[0].step_ms : 0.0;
                double mr = r[0].memory_mib > 0 ? r[1].memory_mib / r[0].memory_mib : 0.0;
                printf("tank x20 wider and deeper at %u particles: GPU time per step x%.3f, memory x%.3f "
                       "(the same block; both should stay under x1.25)\n", r[0].particles, tr, mr);
                if (js) fprintf(js, ",\n    {\"tank_test\": true, \"particles\": %u, \"time_ratio\": %.4f, "
                                    "\"memory_ratio\": %.4f}", r[0].particles, tr, mr);
            }
        }
    if (js) {
        fprintf(js, "\n  ]\n}\n");
        bool bad = ferror(js) != 0;
        if (fclose(js) != 0) bad = true;
        if (bad) {
            fprintf(stderr, "seiche-bench: writing '%s' failed: %s\n", o.json, strerror(errno));
            ok = 0;
        }
    }
    eng_renderer_destroy(dr.renderer);
    eng_context_destroy(ctx);
    if (ok && diverged) fprintf(stderr, "seiche-bench: a run lost particles or produced NaN (marked above)\n");
    if (ok && fflush(stdout) != 0) ok = 0;
    return !ok ? 2 : diverged ? 1 : 0;
}
