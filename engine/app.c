// The frame loop. See app.h.
#include "engine/app.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "engine/camera.h"
#include "engine/context.h"
#include "engine/input.h"
#include "engine/mesh.h"
#include "engine/renderer.h"
#include "engine/scene.h"
#include "engine/screenshot.h"
#include "engine/script.h"
#include "fluid/pbf.h"

typedef struct app {
    const eng_app_options *opt;
    eng_logger log;
    eng_context *ctx;
    eng_input *input;
    eng_renderer *renderer;
    eng_mesh_store *meshes;
    eng_scene *scene;
    eng_camera camera;
    eng_script *script;
    pbf_world *world;
    char shader_dir[1024];
    uint64_t frame;
    double time;
    bool paused, step_once;
    FILE *metrics;
    FILE *video;
    unsigned char *video_pixels;
    pbf_step_stats last_stats;
    bool have_stats;
    uint64_t stats_rows;
    double rho_err_max;   // max over frames of (rho_max / rho0 - 1)
    double step_ms_sum;
    uint64_t step_ms_n;
} app;

eng_app_options eng_default_app_options(void)
{
    eng_app_options o;
    memset(&o, 0, sizeof o);
    o.frames = -1;
    o.dt = 1.0 / 60.0;
    o.width = 1280;
    o.height = 720;
    return o;
}

const char *eng_app_set_keys(void)
{
    static char keys[1024];
    if (keys[0]) return keys;
    int n;
    const pbf_param_info *t = pbf_param_table(&n);
    size_t len = 0;
    for (int i = 0; i < n; i++) len += (size_t)snprintf(keys + len, sizeof keys - len, "fluid.%s, ", t[i].name);
    snprintf(keys + len, sizeof keys - len, "gravity.x, gravity.y, gravity.z, capacity");
    return keys;
}

// Finds the shaders: the option, then $SEICHE_SHADER_DIR, then <exe>/../../shaders
// (build/bin/seiche in a checkout), then ./shaders.
static void find_shader_dir(app *a)
{
    const char *env = getenv("SEICHE_SHADER_DIR");
    if (a->opt->shader_dir) {
        snprintf(a->shader_dir, sizeof a->shader_dir, "%s", a->opt->shader_dir);
        return;
    }
    if (env && *env) {
        snprintf(a->shader_dir, sizeof a->shader_dir, "%s", env);
        return;
    }
    char exe[900];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n > 0) {
        exe[n] = 0;
        char *slash = strrchr(exe, '/');
        if (slash) *slash = 0;
        snprintf(a->shader_dir, sizeof a->shader_dir, "%s/../../shaders", exe);
        char probe[1100];
        snprintf(probe, sizeof probe, "%s/fluid/common.glsl", a->shader_dir);
        if (access(probe, R_OK) == 0) return;
    }
    snprintf(a->shader_dir, sizeof a->shader_dir, "shaders");
}

static int apply_sets(app *a, eng_scene_config *c)
{
    for (int i = 0; i < a->opt->set_count; i++) {
        const char *kv = a->opt->sets[i];
        const char *eq = strchr(kv, '=');
        char key[128];
        if (!eq || eq == kv || (size_t)(eq - kv) >= sizeof key) {
            fprintf(stderr, "seiche: --set expects KEY=VALUE (got '%s')\n", kv);
            return ENG_EXIT_USAGE;
        }
        snprintf(key, sizeof key, "%.*s", (int)(eq - kv), kv);
        char *end;
        errno = 0;
        double v = strtod(eq + 1, &end);
        if (end == eq + 1 || *end || errno || !isfinite(v)) {
            fprintf(stderr, "seiche: --set %s: value must be a finite number (got '%s')\n", key, eq + 1);
            return ENG_EXIT_USAGE;
        }
        char err[512];
        if (strncmp(key, "fluid.", 6) == 0) {
            if (pbf_params_set(&c->params, key + 6, v, err, sizeof err) != PBF_OK) {
                fprintf(stderr, "seiche: --set %s: %s\n", key, err);
                return ENG_EXIT_USAGE;
            }
        } else if (strcmp(key, "capacity") == 0) {
            if (v < 1 || v > 67108864 || v != floor(v)) {
                fprintf(stderr, "seiche: --set capacity must be a whole number in [1, 67108864] (got %s)\n", eq + 1);
                return ENG_EXIT_USAGE;
            }
            c->capacity = (uint32_t)v;
        } else if (strncmp(key, "gravity.", 8) == 0 && key[8] >= 'x' && key[8] <= 'z' && !key[9]) {
            if (fabs(v) > 1000.0) {
                fprintf(stderr, "seiche: --set %s must be in [-1000, 1000] m/s^2 (got %s)\n", key, eq + 1);
                return ENG_EXIT_USAGE;
            }
            c->params.gravity[key[8] - 'x'] = (float)v;
        } else {
            fprintf(stderr, "seiche: --set: unknown key '%s' (known: %s)\n", key, eng_app_set_keys());
            return ENG_EXIT_USAGE;
        }
    }
    return ENG_EXIT_OK;
}

static void world_log(void *user, int level, const char *msg)
{
    app *a = user;
    if (level >= 3) return;
    eng_log(&a->log, level == 2 ? ENG_LOG_WARN : ENG_LOG_DEBUG, "fluid: %s", msg);
}

static int create_world(app *a)
{
    eng_scene_config *c = eng_script_config(a->script);
    pbf_world_def d = pbf_default_world_def();
    d.params = c->params;
    d.capacity = c->capacity;
    d.max_neighbours = pbf_suggest_max_neighbours(&c->params);
    d.shader_dir = a->shader_dir;
    // Errors come back as results and are reported here with the script's context, so
    // the world's own log only carries its warnings and debug notes.
    d.log = world_log;
    d.log_user = a;
    if (c->has_domain) {
        memcpy(d.domain_min, c->domain_min, sizeof d.domain_min);
        memcpy(d.domain_max, c->domain_max, sizeof d.domain_max);
    } else if (c->has_container) {
        // The container plus room above it for splashes.
        for (int k = 0; k < 3; k++) {
            d.domain_min[k] = c->container_min[k];
            d.domain_max[k] = c->container_max[k];
        }
        d.domain_max[1] += 0.5f * (c->container_max[1] - c->container_min[1]);
    }
    char err[1024];
    a->world = pbf_world_create(&d, err, sizeof err);
    if (!a->world) {
        fprintf(stderr, "%s: seiche.scene: %s\n", eng_script_path(a->script), err);
        return ENG_EXIT_USAGE;
    }
    if (c->has_container &&
        pbf_world_set_container(a->world, c->container_min, c->container_max, c->closed_top) != PBF_OK) {
        fprintf(stderr, "%s: seiche.scene: %s\n", eng_script_path(a->script), pbf_world_last_error(a->world));
        return ENG_EXIT_USAGE;
    }
    return ENG_EXIT_OK;
}

// Applies the edits the script queued; an edit that fails is the script's error, at the
// line that asked for it.
static int apply_commands(app *a)
{
    const eng_command *cmds;
    int n = eng_script_commands(a->script, &cmds);
    int status = ENG_EXIT_OK;
    for (int i = 0; i < n && status == ENG_EXIT_OK; i++) {
        const eng_command *c = &cmds[i];
        if (c->type == ENG_CMD_BLOCK) {
            if (pbf_world_add_block(a->world, &c->block, NULL) != PBF_OK) {
                fprintf(stderr, "%sseiche.block: %s\n", c->where, pbf_world_last_error(a->world));
                status = ENG_EXIT_USAGE;
            }
        }
    }
    eng_script_clear_commands(a->script);
    return status;
}

static void update_host(app *a)
{
    eng_script_host h;
    memset(&h, 0, sizeof h);
    h.world = a->world;
    h.stats = a->have_stats ? &a->last_stats : NULL;
    h.frame = a->frame;
    h.time = a->time;
    h.dt = a->opt->dt;
    h.renderer = eng_context_renderer(a->ctx);
    h.headless = a->opt->headless;
    eng_script_set_host(a->script, &h);
}

static int script_status(app *a, eng_script_status st)
{
    if (st == ENG_SCRIPT_OK) return ENG_EXIT_OK;
    fprintf(stderr, "%s\n", eng_script_error(a->script));
    return st == ENG_SCRIPT_CHECK_FAILED ? ENG_EXIT_CHECK_FAILED : ENG_EXIT_USAGE;
}

// Loads the script, builds the world and runs on_start. On failure everything it made is
// released and the status returned.
static int load_scene(app *a, bool reload)
{
    eng_script *s = eng_script_create(&a->log, a->opt->headless ? 5.0 : 2.0);
    if (!s) return ENG_EXIT_USAGE;
    eng_script *old_script = a->script;
    pbf_world *old_world = a->world;
    a->script = s;
    a->world = NULL;
    a->frame = 0;
    a->time = 0.0;
    a->have_stats = false;
    update_host(a);
    int st = script_status(a, eng_script_load(s, a->opt->script));
    if (st == ENG_EXIT_OK) st = apply_sets(a, eng_script_config(s));
    if (st == ENG_EXIT_OK) st = create_world(a);
    if (st == ENG_EXIT_OK) st = apply_commands(a);
    if (st == ENG_EXIT_OK) {
        update_host(a);
        st = script_status(a, eng_script_on_start(s));
    }
    if (st == ENG_EXIT_OK && reload) st = script_status(a, eng_script_on_reload(s));
    if (st == ENG_EXIT_OK) st = apply_commands(a);
    if (st != ENG_EXIT_OK) {
        pbf_world_destroy(a->world);
        eng_script_destroy(s);
        a->script = old_script;
        a->world = old_world;
        return st;
    }
    pbf_world_destroy(old_world);
    eng_script_destroy(old_script);
    const eng_scene_config *c = eng_script_config(s);
    eng_camera_look_at(&a->camera, c->camera_eye, c->camera_target);
    a->camera.fov_y = c->camera_fov * 3.14159265f / 180.0f;
    return ENG_EXIT_OK;
}

static void write_metrics_header(app *a)
{
    fprintf(a->metrics, "frame,time,particles,rho0,rho_max,rho_avg,step_ms");
    for (int s = 0; s < PBF_STAGE_COUNT; s++) fprintf(a->metrics, ",%s_ms", pbf_stage_name((pbf_stage)s));
    fprintf(a->metrics, ",nan,outside,overflow\n");
}

static void take_stats(app *a, bool wait)
{
    pbf_step_stats st[16];
    int n;
    while ((n = pbf_world_poll_stats(a->world, st, 16, wait)) > 0) {
        for (int i = 0; i < n; i++) {
            const pbf_step_stats *s = &st[i];
            if (a->metrics) {
                fprintf(a->metrics, "%llu,%.6f,%u,%.3f,%.3f,%.3f,%.4f", (unsigned long long)s->step, s->time,
                        s->particles, (double)s->rest_density, (double)s->density_max, (double)s->density_avg,
                        s->step_ms);
                for (int k = 0; k < PBF_STAGE_COUNT; k++) fprintf(a->metrics, ",%.4f", s->stage_ms[k]);
                fprintf(a->metrics, ",%u,%u,%u\n", s->nan_count, s->outside_count, s->overflow_count);
            }
            double e = s->rest_density > 0 ? s->density_max / s->rest_density - 1.0 : 0.0;
            if (e > a->rho_err_max) a->rho_err_max = e;
            a->step_ms_sum += s->step_ms;
            a->step_ms_n++;
            a->stats_rows++;
            a->last_stats = *s;
            a->have_stats = true;
        }
        if (!wait && n < 16) break;
    }
}

static void render(app *a)
{
    eng_renderer_begin(a->renderer, a->ctx, &a->camera);
    eng_scene_update(a->scene);
    eng_renderer_draw_scene(a->renderer, a->scene, a->meshes);
    if (a->world) {
        pbf_gpu_buffers b = pbf_world_gpu_buffers(a->world);
        if (b.count > 0)
            eng_renderer_draw_particles(a->renderer, &a->camera, b.positions, b.draw_indirect,
                                        pbf_world_params(a->world)->particle_radius, NULL);
    }
    eng_renderer_end(a->renderer);
}

static int record_frame(app *a)
{
    int w, h;
    eng_context_size(a->ctx, &w, &h);
    char err[256];
    if (!eng_read_pixels(a->ctx, a->video_pixels, w, h, err, sizeof err)) {
        fprintf(stderr, "seiche: --record: %s\n", err);
        return ENG_EXIT_USAGE;
    }
    if (fwrite(a->video_pixels, 4, (size_t)w * (size_t)h, a->video) != (size_t)w * (size_t)h) {
        fprintf(stderr, "seiche: --record: ffmpeg stopped taking frames\n");
        return ENG_EXIT_USAGE;
    }
    return ENG_EXIT_OK;
}

static int open_video(app *a)
{
    if (system("command -v ffmpeg >/dev/null 2>&1") != 0) {
        fprintf(stderr, "seiche: --record needs ffmpeg on the PATH (apt-get install ffmpeg)\n");
        return ENG_EXIT_USAGE;
    }
    int w, h;
    eng_context_size(a->ctx, &w, &h);
    char cmd[1400];
    snprintf(cmd, sizeof cmd,
             "ffmpeg -loglevel error -y -f rawvideo -pix_fmt rgba -s %dx%d -r %d -i - -vf vflip -pix_fmt yuv420p '%s'",
             w, h, (int)lround(1.0 / a->opt->dt), a->opt->record_path);
    a->video = popen(cmd, "w");
    a->video_pixels = malloc((size_t)w * (size_t)h * 4);
    if (!a->video || !a->video_pixels) {
        fprintf(stderr, "seiche: --record: cannot start ffmpeg\n");
        return ENG_EXIT_USAGE;
    }
    return ENG_EXIT_OK;
}

static void handle_input(app *a, int *status)
{
    eng_event e;
    while (eng_input_next_event(a->input, &e)) {
        if (e.type == ENG_EVENT_KEY && e.action != ENG_RELEASE) {
            if (e.key == GLFW_KEY_ESCAPE) eng_context_request_close(a->ctx);
            else if (e.key == GLFW_KEY_SPACE && e.action == ENG_PRESS) a->paused = !a->paused;
            else if (e.key == GLFW_KEY_N) a->step_once = true;
            else if (e.key == GLFW_KEY_C && e.action == ENG_PRESS)
                eng_camera_set_mode(&a->camera, a->camera.mode == ENG_CAMERA_ORBIT ? ENG_CAMERA_FLY : ENG_CAMERA_ORBIT);
            else if ((e.key == GLFW_KEY_R || e.key == GLFW_KEY_F5) && e.action == ENG_PRESS) {
                int st = load_scene(a, e.key == GLFW_KEY_F5);
                if (st != ENG_EXIT_OK)
                    eng_log(&a->log, ENG_LOG_ERROR, "reload failed; the last good scene keeps running");
            }
        }
        const char *action = e.action == ENG_PRESS ? "press" : e.action == ENG_RELEASE ? "release" : "repeat";
        eng_script_status st = ENG_SCRIPT_OK;
        if (e.type == ENG_EVENT_KEY) {
            const char *name = eng_key_name(e.key);
            if (name) st = eng_script_on_key(a->script, name, action);
        } else if (e.type == ENG_EVENT_MOUSE_BUTTON) {
            st = eng_script_on_mouse(a->script, e.button + 1, action, e.x, e.y);
        }
        if (st != ENG_SCRIPT_OK) {
            int s = script_status(a, st);
            if (a->opt->headless) *status = s;
        }
    }
}

static void print_summary(app *a)
{
    if (a->opt->quiet) return;
    const pbf_step_stats *s = &a->last_stats;
    printf("seiche: %s: %llu frames, %.2f s simulated, %u particles, rho_avg %.1f rho_max %.1f (rho0 %.0f, worst "
           "%.1f%% over), %.2f ms GPU per step, %s\n",
           eng_script_config(a->script)->name, (unsigned long long)a->frame, a->time,
           a->world ? pbf_world_particle_count(a->world) : 0, a->have_stats ? (double)s->density_avg : 0.0,
           a->have_stats ? (double)s->density_max : 0.0, (double)eng_script_config(a->script)->params.rest_density,
           100.0 * a->rho_err_max, a->step_ms_n ? a->step_ms_sum / (double)a->step_ms_n : 0.0,
           eng_context_renderer(a->ctx));
}

static void shutdown_app(app *a)
{
    if (a->metrics) fclose(a->metrics);
    if (a->video) pclose(a->video);
    free(a->video_pixels);
    pbf_world_destroy(a->world);
    eng_script_destroy(a->script);
    eng_scene_destroy(a->scene);
    eng_mesh_store_destroy(a->meshes);
    eng_renderer_destroy(a->renderer);
    eng_input_destroy(a->input);
    eng_context_destroy(a->ctx);
}

int eng_app_run(const eng_app_options *o)
{
    app a_;
    app *a = &a_;
    memset(a, 0, sizeof *a);
    a->opt = o;
    a->log = eng_default_logger();
    find_shader_dir(a);

    eng_context_def cd = eng_default_context_def();
    cd.mode = o->headless ? ENG_CONTEXT_HEADLESS : ENG_CONTEXT_WINDOW;
    cd.width = o->width;
    cd.height = o->height;
    cd.title = o->script;
    cd.logger = a->log;
    eng_context_status cst;
    char err[1024];
    a->ctx = eng_context_create(&cd, &cst, err, sizeof err);
    if (!a->ctx) return cst == ENG_CONTEXT_NO_COMPUTE ? ENG_EXIT_NO_COMPUTE : cst == ENG_CONTEXT_NO_GL ? ENG_EXIT_NO_COMPUTE : ENG_EXIT_USAGE;
    a->input = eng_input_create(a->ctx);
    eng_renderer_def rd = eng_default_renderer_def();
    rd.shader_dir = a->shader_dir;
    rd.logger = a->log;
    a->renderer = eng_renderer_create(&rd, err, sizeof err);
    if (!a->renderer) {
        fprintf(stderr, "seiche: %s\n", err);
        shutdown_app(a);
        return ENG_EXIT_USAGE;
    }
    eng_mesh_store_def md = eng_default_mesh_store_def();
    a->meshes = eng_mesh_store_create(&md);
    eng_scene_def sd = eng_default_scene_def();
    a->scene = eng_scene_create(&sd);
    eng_camera_def camd = eng_default_camera_def();
    eng_camera_init(&a->camera, &camd, err, sizeof err);

    int status = load_scene(a, false);
    if (status != ENG_EXIT_OK) {
        shutdown_app(a);
        return status;
    }
    if (o->metrics_path) {
        a->metrics = fopen(o->metrics_path, "w");
        if (!a->metrics) {
            fprintf(stderr, "seiche: --metrics: cannot write '%s': %s\n", o->metrics_path, strerror(errno));
            shutdown_app(a);
            return ENG_EXIT_USAGE;
        }
        write_metrics_header(a);
    }
    if (o->record_path && (status = open_video(a)) != ENG_EXIT_OK) {
        shutdown_app(a);
        return status;
    }
    long frames = o->frames >= 0 ? o->frames : o->headless ? 600 : -1;
    while (status == ENG_EXIT_OK && (frames < 0 || (long)a->frame < frames) && !eng_context_should_close(a->ctx) &&
           !eng_script_quit_requested(a->script)) {
        eng_context_poll(a->ctx);
        eng_input_begin_frame(a->input);
        handle_input(a, &status);
        if (status != ENG_EXIT_OK) break;
        eng_camera_update(&a->camera, a->input, (float)o->dt);
        if (!a->paused || a->step_once) {
            a->step_once = false;
            status = apply_commands(a);
            if (status != ENG_EXIT_OK) break;
            if (pbf_world_step(a->world, (float)o->dt) != PBF_OK) {
                fprintf(stderr, "seiche: %s\n", pbf_world_last_error(a->world));
                status = ENG_EXIT_USAGE;
                break;
            }
            a->frame++;
            a->time += o->dt;
            take_stats(a, false);
            update_host(a);
            eng_script_status st = eng_script_on_step(a->script, o->dt, a->time);
            if (st != ENG_SCRIPT_OK) {
                int s = script_status(a, st);
                if (o->headless || s == ENG_EXIT_CHECK_FAILED) status = s;
            }
        }
        bool last = frames >= 0 && (long)a->frame >= frames;
        if (!o->headless || a->video || (last && o->screenshot_path)) render(a);
        if (a->video && status == ENG_EXIT_OK) status = record_frame(a);
        eng_context_present(a->ctx);
    }
    if (a->world) take_stats(a, true);
    if (status == ENG_EXIT_OK || status == ENG_EXIT_CHECK_FAILED) {
        // Final checks that the script may do in on_step see the last stats; the hash and
        // the screenshot describe the final state.
        if (o->screenshot_path) {
            if (o->headless && !(frames >= 0)) render(a);
            if (!eng_screenshot_write_png(a->ctx, o->screenshot_path, err, sizeof err)) {
                fprintf(stderr, "seiche: --screenshot: %s\n", err);
                status = ENG_EXIT_USAGE;
            }
        }
        if (o->hash) printf("state hash: %016llx\n", (unsigned long long)pbf_world_state_hash(a->world));
        if (status == ENG_EXIT_OK) print_summary(a);
    }
    shutdown_app(a);
    return status;
}
