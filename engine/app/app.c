// The frame loop. See app.h and docs/runner.md.
//
// A loaded scene is an `instance`: the script, the fluid world, the Bullet world, the
// coupling between them and the scene-graph nodes that draw the container. Reset and
// reload build a new instance beside the old one and swap only when everything
// succeeded, so a broken script never takes the running scene down with it.
#include "engine/app/app_internal.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "engine/render/camera.h"
#include "engine/gl/context.h"
#include "engine/gl/input.h"
#include "engine/render/mesh.h"
#include "engine/render/renderer.h"
#include "engine/render/scene.h"
#include "engine/gl/screenshot.h"
#include "engine/gl/video.h"
#include "engine/script/script.h"
#include "engine/app/ui.h"
#include "engine/core/progress.h"
#include "fluid/bullet/coupling.h"
#include "fluid/bullet/phys.h"
#include "fluid/pbf.h"

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

// Finds the shaders: the option, then $SEICHE_SHADER_DIR (shader development), else the
// copies embedded in the libraries ("" here). `*from` names where the directory came from,
// for messages. False, with the one message printed, when it is no readable directory:
// checked here, before a window opens, so that the error names the option and the path
// as given rather than the first shader file that could not be opened.
static bool find_shader_dir(app *a, const char **from)
{
    const char *env = getenv("SEICHE_SHADER_DIR");
    const char *dir = a->opt->shader_dir ? a->opt->shader_dir : env ? env : "";
    *from = a->opt->shader_dir ? "--shaders" : "SEICHE_SHADER_DIR";
    a->shader_dir[0] = 0;
    if (!dir[0]) return true;
    if (strlen(dir) >= sizeof a->shader_dir) {
        app_message(a, "seiche: %s: the shader directory's name must be shorter than %zu bytes (got %zu)", *from,
                    sizeof a->shader_dir, strlen(dir));
        return false;
    }
    DIR *d = opendir(dir);
    if (!d) {
        app_message(a, "seiche: %s: cannot read the shader directory '%s': %s", *from, dir, strerror(errno));
        return false;
    }
    closedir(d);
    snprintf(a->shader_dir, sizeof a->shader_dir, "%s", dir);
    return true;
}

static void held_log_fn(void *user, eng_log_level level, const char *msg)
{
    held_log *h = user;
    if (h->hold_errors && level >= ENG_LOG_ERROR) return;
    eng_log(&h->to, level, "%s", msg);
}

// ---- errors ---------------------------------------------------------------------------

#define PROGRAM_PREFIX "seiche: "

// The app's logger: as the default one ("seiche: warning: ..."), but it erases the progress
// line first, and one run of a directory suite names its script ("seiche: DIR/x.lua:
// warning: ...") so that a log of many runs says which one spoke.
static void app_log_fn(void *user, eng_log_level level, const char *msg)
{
    app *a = user;
    eng_progress_end(&a->progress);
    fputs(PROGRAM_PREFIX, stderr);
    if (a->opt->name_script) {
        eng_app_write_name(stderr, a->opt->script);
        fputs(": ", stderr);
    }
    fprintf(stderr, "%s: %s\n", eng_log_level_name(level), msg);
}

// The report's message (--junit, --tap), unless one is there already: the first line of
// what ended the run, without the program's "seiche: " (the report names the run already).
static void note_in_report(app *a, const char *msg)
{
    eng_app_report *r = a->opt->report;
    if (!r || r->message[0]) return;
    if (strncmp(msg, PROGRAM_PREFIX, strlen(PROGRAM_PREFIX)) == 0) msg += strlen(PROGRAM_PREFIX);
    snprintf(r->message, sizeof r->message, "%.*s", (int)strcspn(msg, "\n"), msg);
}

// Reports a message: always on stderr; in a window also on screen. The report's message
// (--junit, --tap) is its first line without the program's "seiche: " (the report names
// the run already). In a directory suite a message of the runner's own ("seiche: ...")
// names the script after the prefix; a script's messages begin with its file:line.
void app_report(app *a, const char *msg)
{
    eng_progress_end(&a->progress);
    bool ours = strncmp(msg, PROGRAM_PREFIX, strlen(PROGRAM_PREFIX)) == 0;
    if (ours && a->opt->name_script) {
        fputs(PROGRAM_PREFIX, stderr);
        eng_app_write_name(stderr, a->opt->script);
        fprintf(stderr, ": %s\n", msg + strlen(PROGRAM_PREFIX));
    } else {
        fprintf(stderr, "%s\n", msg);
    }
    note_in_report(a, msg);
    if (a->opt->headless) return;
    size_t n = strlen(msg);
    if (n >= sizeof a->error_text) n = sizeof a->error_text - 1;
    memcpy(a->error_text, msg, n);
    a->error_text[n] = 0;
}

void app_message(app *a, const char *fmt, ...)
{
    char msg[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    app_report(a, msg);
}

// Space (the button in the panel too): pause / run. Headless nothing could resume a
// pause: no keyboard, and the script's on_step and timers, which could inject the key
// again, do not run while paused. So headless the pause is ignored, with one warning naming
// where it came from, and every frame steps (--frames counts steps: a paused headless run
// would never end, or end early with its checks unrun).
static void toggle_pause(app *a)
{
    if (!a->opt->headless) {
        a->paused = !a->paused;
        return;
    }
    if (a->pause_warned) return;
    a->pause_warned = true;
    eng_log(&a->log, ENG_LOG_WARN,
            "a pause (the space key, from seiche.inject_key) is ignored headless: nothing could resume it; the run "
            "goes on stepping (the key still reaches on_key)");
}

// A failed script step. Headless the run ends with the status; in a window the message is
// shown, the script's callbacks stop and the scene keeps running.
static int script_failed(app *a, eng_script_status st, const char *msg)
{
    int status = st == ENG_SCRIPT_CHECK_FAILED ? ENG_EXIT_CHECK_FAILED : ENG_EXIT_USAGE;
    app_report(a, msg);
    if (a->opt->headless) return status;
    a->halted = true;
    if (status > a->window_status) a->window_status = status;
    return ENG_EXIT_OK;
}

// ---- building a scene -----------------------------------------------------------------

// ---- the frame ------------------------------------------------------------------------------

// Hides the container walls that stand between the camera and the inside.
static void update_walls(app *a)
{
    instance *in = &a->inst;
    if (!in->script || !in->walls[0].index1) return;
    const eng_scene_config *c = eng_script_config(in->script);
    const float *e = a->camera.position;
    bool show = c->look.container;
    bool vis[WALL_COUNT] = { show, show && e[0] > c->container_min[0], show && e[0] < c->container_max[0],
                             show && e[2] > c->container_min[2], show && e[2] < c->container_max[2] };
    for (int i = 0; i < WALL_COUNT; i++) eng_node_set_visible(a->scene, in->walls[i], vis[i]);
}

// The shadow map covers the container and the domain (where the water can be).
static void shadow_bounds(app *a, const eng_scene_config *c)
{
    float lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = c->has_domain ? c->domain_min[k] : c->container_min[k];
        hi[k] = c->has_domain ? c->domain_max[k] : c->container_max[k];
    }
    if (c->has_container || c->has_domain) eng_renderer_set_shadow_bounds(a->renderer, lo, hi);
}

static void render(app *a)
{
    eng_renderer_begin(a->renderer, a->ctx, &a->camera);
    if (a->inst.script) {
        eng_script_sync_nodes(a->inst.script);
        update_walls(a);
    }
    eng_scene_update(a->scene);
    eng_renderer_draw_scene(a->renderer, a->scene, a->meshes);
    if (a->inst.world) {
        const eng_scene_config *c = eng_script_config(a->inst.script);
        // seiche.render{...}: the script checked the look; apply it once per call.
        if (c->fluid_look_generation != a->applied_fluid_generation) {
            eng_renderer_set_fluid_look(a->renderer, &c->fluid_look);
            a->applied_fluid_generation = c->fluid_look_generation;
        }
        shadow_bounds(a, c);
        eng_fluid_draw d = eng_fluid_draw_of(a->inst.world, &c->look.water);
        if (pbf_world_particle_count(a->inst.world) > 0) eng_renderer_draw_fluid(a->renderer, &d);
    }
    eng_renderer_end(a->renderer);
}

static void draw_ui(app *a)
{
    if (!a->ui) return;
    instance *in = &a->inst;
    int n = 0;
    const pbf_param_info *tab = pbf_param_table(&n);
    eng_ui_param params[40];
    if (n > 40) n = 40;
    const pbf_params *p = in->world ? pbf_world_params(in->world) : NULL;
    for (int i = 0; i < n && p; i++) {
        params[i] = (eng_ui_param){ .name = tab[i].name, .unit = tab[i].unit, .description = tab[i].description,
                                    .min = tab[i].min, .max = tab[i].max, .value = pbf_params_get(p, &tab[i]),
                                    .is_int = tab[i].is_int };
        // Sizes change the lattice and the grid: edit them in the script, not live.
        if (strcmp(tab[i].name, "particle_radius") == 0 || strcmp(tab[i].name, "kernel_radius") == 0) params[i].read_only = true;
        if (params[i].max > 1e5) params[i].max = params[i].min > 0 ? params[i].min * 1e4 : 1e5;
    }
    eng_ui_frame f;
    memset(&f, 0, sizeof f);
    const eng_scene_config *c = in->script ? eng_script_config(in->script) : NULL;
    f.title = c ? c->name : "seiche";
    f.renderer = eng_context_renderer(a->ctx);
    f.frame = a->frame;
    f.time = a->time;
    f.particles = in->world ? pbf_world_particle_count(in->world) : 0;
    f.capacity = in->world ? pbf_world_capacity(in->world) : 0;
    f.bodies = in->coupling ? cpl_body_count(in->coupling) : 0;
    f.rho0 = p ? p->rest_density : 0;
    f.rho_avg = a->have_stats ? a->last_stats.density_avg : 0;
    f.rho_max = a->have_stats ? a->last_stats.density_max : 0;
    f.step_ms = a->have_stats ? a->last_stats.step_ms : 0;
    f.fps = a->fps;
    f.iterations = p ? p->iterations : 0;
    f.substeps = a->have_stats ? a->last_stats.substeps : p ? p->substeps : 0; // the time-step guard may take more
    f.compression = a->have_stats ? a->last_stats.density_error_avg : 0;
    f.worst_over = a->rho_err_max;
    const char *stage_names[PBF_STAGE_COUNT];
    for (int i = 0; i < PBF_STAGE_COUNT; i++) stage_names[i] = pbf_stage_name((pbf_stage)i);
    f.stage_names = stage_names;
    f.stage_ms = a->have_stats ? a->last_stats.stage_ms : NULL;
    f.stage_count = a->have_stats ? PBF_STAGE_COUNT : 0;
    f.paused = a->paused;
    f.show_panel = a->show_panel;
    f.error = a->error_text;
    f.params = params;
    f.param_count = p ? n : 0;
    // The script's HUD (seiche.text) of this frame.
    const eng_script_text *texts = NULL;
    int text_count = in->script ? eng_script_texts(in->script, &texts) : 0;
    eng_ui_text hud[ENG_SCRIPT_MAX_TEXTS];
    for (int i = 0; i < text_count; i++) {
        hud[i] = (eng_ui_text){ .x = texts[i].x, .y = texts[i].y, .size = texts[i].size, .text = texts[i].text };
        memcpy(hud[i].colour, texts[i].colour, sizeof hud[i].colour);
    }
    f.texts = hud;
    f.text_count = text_count;
    eng_context_size(a->ctx, &f.width, &f.height);
    eng_ui_draw(a->ui, &f);
    a->show_panel = f.show_panel;
    if (f.toggle_pause) toggle_pause(a);
    if (f.step) a->step_once = true;
    if (f.dismiss_error) a->error_text[0] = 0;
    for (int i = 0; i < f.param_count; i++) {
        if (!params[i].changed) continue;
        char err[512];
        if (!eng_script_set_param(in->script, params[i].name, params[i].value, err, sizeof err)) app_report(a, err);
    }
    if (f.reset || f.reload) app_load_scene(a, f.reload);
}

// A status from a script callback or an applied edit.
static int script_result(app *a, eng_script_status st)
{
    if (st == ENG_SCRIPT_OK) return ENG_EXIT_OK;
    return script_failed(a, st, eng_script_error(a->inst.script));
}

// The runner's own keys. True when the key was one (it still goes to on_key too).
static void runner_key(app *a, const eng_event *e, int *status)
{
    if (e->action != ENG_PRESS && !(e->action == ENG_REPEAT && e->key == GLFW_KEY_N)) return;
    switch (e->key) {
    case GLFW_KEY_ESCAPE: eng_context_request_close(a->ctx); break;
    case GLFW_KEY_SPACE: toggle_pause(a); break;
    case GLFW_KEY_N: a->step_once = true; break;
    case GLFW_KEY_C:
        eng_camera_set_mode(&a->camera, a->camera.mode == ENG_CAMERA_ORBIT ? ENG_CAMERA_FLY : ENG_CAMERA_ORBIT);
        break;
    case GLFW_KEY_F1: a->show_panel = !a->show_panel; break;
    case GLFW_KEY_V: {
        eng_fluid_mode m = (eng_fluid_mode)((eng_renderer_fluid_mode(a->renderer) + 1) % ENG_FLUID_MODE_COUNT);
        eng_renderer_set_fluid_mode(a->renderer, m);
        eng_log(&a->log, ENG_LOG_INFO, "render: %s", eng_fluid_mode_name(m));
        break;
    }
    case GLFW_KEY_R:
    case GLFW_KEY_F5: {
        int st = app_load_scene(a, e->key == GLFW_KEY_F5);
        if (st != ENG_EXIT_OK && a->opt->headless) *status = st;
        break;
    }
    default: break;
    }
}

static void handle_input(app *a, int *status)
{
    eng_event e;
    bool ui_mouse = eng_ui_wants_mouse(a->ui), ui_keys = eng_ui_wants_keyboard(a->ui);
    // Only the events queued before this frame: events a callback injects (or a reset's
    // on_start) wait for the next frame, so an injected key cannot loop within one frame.
    int count = eng_input_queued(a->input);
    while (*status == ENG_EXIT_OK && count-- > 0 && eng_input_next_event(a->input, &e)) {
        const char *action = e.action == ENG_PRESS ? "press" : e.action == ENG_RELEASE ? "release" : "repeat";
        eng_script_status st = ENG_SCRIPT_OK;
        eng_script *s = a->inst.script;
        bool call = s && !a->halted;
        switch (e.type) {
        case ENG_EVENT_KEY: {
            if (ui_keys) break;
            runner_key(a, &e, status);
            s = a->inst.script; // a reset replaces the script
            const char *name = eng_key_name(e.key);
            // The fly camera's keys move the camera and do not reach the script.
            bool camera_key = a->camera.mode == ENG_CAMERA_FLY &&
                              (e.key == GLFW_KEY_W || e.key == GLFW_KEY_A || e.key == GLFW_KEY_S || e.key == GLFW_KEY_D ||
                               e.key == GLFW_KEY_Q || e.key == GLFW_KEY_E || e.key == GLFW_KEY_LEFT_SHIFT ||
                               e.key == GLFW_KEY_RIGHT_SHIFT);
            double px = 0.0, py = 0.0;
            eng_input_mouse_position(a->input, &px, &py);
            if (name && s && !a->halted && !camera_key) st = eng_script_on_key(s, name, action, px, py);
            break;
        }
        case ENG_EVENT_MOUSE_BUTTON: {
            bool release_of_capture = e.action == ENG_RELEASE && a->mouse_captured == e.button + 1;
            if (release_of_capture) a->mouse_captured = 0;
            if (!call || (ui_mouse && !release_of_capture)) break;
            bool consumed = false;
            st = eng_script_on_mouse(s, e.button + 1, action, e.x, e.y, &consumed);
            if (consumed && e.action == ENG_PRESS) a->mouse_captured = e.button + 1;
            break;
        }
        case ENG_EVENT_MOTION:
            if (call && (!ui_mouse || a->mouse_captured)) st = eng_script_on_mouse_move(s, e.x, e.y, e.dx, e.dy);
            break;
        case ENG_EVENT_SCROLL:
            if (call && !ui_mouse) st = eng_script_on_scroll(s, e.dx, e.dy);
            break;
        }
        if (st != ENG_SCRIPT_OK) *status = script_result(a, st);
    }
}

// Window: reloads the script when its file changed (checked twice a second).
static void watch_file(app *a)
{
    if (a->opt->headless || !a->opt->watch) return;
    double t = now_s();
    if (t < a->watch_next) return;
    a->watch_next = t + 0.5;
    struct timespec m;
    off_t size;
    if (!app_file_stamp(a->opt->script, &m, &size)) return;
    if (m.tv_sec == a->watch_mtime.tv_sec && m.tv_nsec == a->watch_mtime.tv_nsec && size == a->watch_size) return;
    eng_log(&a->log, ENG_LOG_INFO, "%s changed: reloading", a->opt->script);
    app_load_scene(a, true);
    a->watch_mtime = m; // also after a failed load: wait for the next save
    a->watch_size = size;
}

static void shutdown_app(app *a)
{
    app_close_metrics(a, true);
    app_close_video(a, true);
    app_destroy_instance(a, &a->inst);
    eng_ui_destroy(a->ui);
    eng_scene_destroy(a->scene);
    eng_mesh_store_destroy(a->meshes);
    eng_renderer_destroy(a->renderer);
    eng_input_destroy(a->input);
    eng_context_destroy(a->ctx);
}

// The run from the shader directory to the last frame's outputs; every way out returns its
// status here, and eng_app_run records it (and the message, app_report) in the report.
// `renderer_log` is the renderer's logger, which must outlive the renderer (shutdown_app).
static int run_app(app *a, held_log *renderer_log)
{
    const eng_app_options *o = a->opt;
    const char *shaders_from;
    if (!find_shader_dir(a, &shaders_from)) return ENG_EXIT_USAGE;

    eng_context_def cd = eng_default_context_def();
    cd.mode = o->headless ? ENG_CONTEXT_HEADLESS : ENG_CONTEXT_WINDOW;
    cd.width = o->width;
    cd.height = o->height;
    cd.title = o->script;
    cd.logger = a->log;
    eng_context_status cst;
    char err[1024];
    a->ctx = eng_context_create(&cd, &cst, err, sizeof err);
    // No display for a window is a machine without the GL context the run asks for, as is
    // no GL at all (status 3); the message (eng_context_create's, already printed) says to
    // use --headless. Anything else is a bad request (status 2).
    if (!a->ctx) {
        note_in_report(a, err);
        return cst == ENG_CONTEXT_NO_COMPUTE || cst == ENG_CONTEXT_NO_GL || cst == ENG_CONTEXT_NO_DISPLAY
                   ? ENG_EXIT_NO_COMPUTE
                   : ENG_EXIT_USAGE;
    }
    a->input = eng_input_create(a->ctx);
    a->renderer_def = eng_default_renderer_def();
    a->renderer_def.shader_dir = a->shader_dir[0] ? a->shader_dir : NULL;
    *renderer_log = (held_log){ a->log, true };
    a->renderer_def.logger = (eng_logger){ held_log_fn, renderer_log, ENG_LOG_DEBUG };
    if (o->render && !eng_fluid_mode_parse(o->render, &a->renderer_def.fluid.mode)) {
        app_message(a, "seiche: --render must be one of %s (got '%s')", eng_fluid_mode_names(), o->render);
        return ENG_EXIT_USAGE;
    }
    a->renderer = eng_renderer_create(&a->renderer_def, err, sizeof err);
    renderer_log->hold_errors = false;
    if (!a->renderer) {
        if (a->shader_dir[0]) app_message(a, "seiche: %s '%s': %s", shaders_from, a->shader_dir, err);
        else app_message(a, "seiche: %s", err);
        return ENG_EXIT_USAGE;
    }
    eng_mesh_store_def md = eng_default_mesh_store_def();
    a->meshes = eng_mesh_store_create(&md);
    eng_scene_def sd = eng_default_scene_def();
    a->scene = eng_scene_create(&sd);
    eng_camera_def camd = eng_default_camera_def();
    eng_camera_init(&a->camera, &camd, err, sizeof err);
    // Headless, the UI only draws the script's HUD text into screenshots and videos.
    if (o->ui && (!o->headless || o->screenshot_path || o->record_path)) {
        a->ui = eng_ui_create(o->headless ? NULL : eng_context_window(a->ctx), err, sizeof err);
        if (!a->ui) eng_log(&a->log, ENG_LOG_WARN, "no on-screen UI: %s", err);
    }

    int status = app_load_scene(a, false);
    if (status != ENG_EXIT_OK) {
        // Headless the run ends here: its checks (those that ran in the main chunk, and the
        // lines that never ran) still go into the report.
        if (o->headless) return app_finish_checks(a, status);
        // A window waits for the script to be fixed (it is watched) with the error shown.
        a->window_status = status;
        status = ENG_EXIT_OK;
    }
    if (o->metrics_path) {
        a->metrics = fopen(o->metrics_path, "w");
        if (!a->metrics) {
            app_message(a, "seiche: --metrics: cannot write '%s': %s", o->metrics_path, strerror(errno));
            return ENG_EXIT_USAGE;
        }
        app_write_metrics_header(a);
    }
    if (o->record_path && (status = app_open_video(a)) != ENG_EXIT_OK) return status;
    long frames = o->frames >= 0 ? o->frames : o->headless ? 600 : -1;
    bool done = frames == 0;
    long steps = 0, idle = 0;
    eng_progress_begin(&a->progress, "frame", frames);
    a->progress.on &= o->headless;
    while (status == ENG_EXIT_OK && !done) {
        eng_input_begin_frame(a->input);
        eng_context_poll(a->ctx);
        // seiche.text draws for one frame: a frame that steps starts the HUD afresh (a paused
        // one keeps the last, and adds what its input callbacks draw).
        if (a->inst.script && (!a->paused || a->step_once)) eng_script_begin_frame(a->inst.script);
        if (a->inst.script) eng_script_deliver_input(a->inst.script);
        handle_input(a, &status);
        if (status != ENG_EXIT_OK) break;
        bool camera_input = !a->mouse_captured && !eng_ui_wants_mouse(a->ui) && !eng_ui_wants_keyboard(a->ui);
        eng_camera_update(&a->camera, camera_input ? a->input : NULL, (float)o->dt);
        instance *in = &a->inst;
        if (in->script) {
            app_update_host(a);
            status = script_result(a, eng_script_apply(in->script));
            if (status != ENG_EXIT_OK) break;
            if (!a->paused || a->step_once) {
                a->step_once = false;
                if (cpl_step(in->coupling, (float)o->dt) != CPL_OK) {
                    app_message(a, "seiche: %s", cpl_last_error(in->coupling));
                    status = ENG_EXIT_USAGE;
                    break;
                }
                eng_script_step_taken(in->script);
                a->frame++;
                steps++;
                a->time = (double)a->frame * o->dt; // exact multiples, no running sum
                app_take_stats(a, false);
                status = app_check_diverged(a);
                if (status != ENG_EXIT_OK) break;
                app_update_host(a);
                if (!a->halted) status = script_result(a, eng_script_on_step(in->script, o->dt, a->time));
            }
        }
        watch_file(a);
        bool quit = a->inst.script && eng_script_quit_requested(a->inst.script);
        // --frames counts steps, over resets (which restart the frame number, so a script
        // that resets every frame still ends). A paused window does not count: it waits for
        // the user (space, n, or closing it). Headless nothing pauses (toggle_pause), so
        // every frame steps. A window without a scene (its script failed to load and it waits
        // for a fix) counts the frames it draws instead, so such a run still ends.
        if (!a->inst.script) idle++;
        done = (frames >= 0 && (steps >= frames || idle >= frames)) || quit ||
               eng_context_should_close(a->ctx) || status != ENG_EXIT_OK;
        bool shot = done && o->screenshot_path && (status == ENG_EXIT_OK || status == ENG_EXIT_CHECK_FAILED);
        if (!o->headless || a->video || shot) {
            render(a);
            draw_ui(a);
        }
        if (shot && app_write_screenshot(a) != ENG_EXIT_OK) status = ENG_EXIT_USAGE;
        if (a->video && status == ENG_EXIT_OK) status = app_record_frame(a);
        eng_context_present(a->ctx);
        eng_progress_update(&a->progress, (long)a->frame, a->time);
        a->fps_frames++;
        double t = now_s();
        if (a->fps_since == 0.0) a->fps_since = t;
        else if (t - a->fps_since >= 0.5) {
            a->fps = (double)a->fps_frames / (t - a->fps_since);
            a->fps_since = t;
            a->fps_frames = 0;
        }
    }
    eng_progress_end(&a->progress);
    if (a->inst.world) app_take_stats(a, true);
    if (status == ENG_EXIT_OK) status = app_check_diverged(a);
    if (status == ENG_EXIT_OK && !o->headless) status = a->window_status;
    if (status == ENG_EXIT_OK || status == ENG_EXIT_CHECK_FAILED) {
        if (o->screenshot_path && !a->screenshot_taken) {
            render(a);
            if (app_write_screenshot(a) != ENG_EXIT_OK) status = ENG_EXIT_USAGE;
        }
        if (o->hash && a->inst.world) printf("state hash: %016llx\n", (unsigned long long)pbf_world_state_hash(a->inst.world));
    }
    // Every output is complete and checked before the run counts as a success.
    int out = app_close_metrics(a, false);
    int vid = app_close_video(a, status != ENG_EXIT_OK && status != ENG_EXIT_CHECK_FAILED);
    if (status == ENG_EXIT_OK || status == ENG_EXIT_CHECK_FAILED) {
        if (out != ENG_EXIT_OK) status = out;
        else if (vid != ENG_EXIT_OK) status = vid;
        else if (fflush(stdout) != 0) {
            app_message(a, "seiche: writing standard output failed: %s", strerror(errno));
            status = ENG_EXIT_USAGE;
        }
    }
    status = app_finish_checks(a, status);
    if (status == ENG_EXIT_OK) app_print_summary(a);
    return status;
}

int eng_app_run(const eng_app_options *o)
{
    app a_;
    app *a = &a_;
    memset(a, 0, sizeof *a);
    a->opt = o;
    a->log = (eng_logger){ app_log_fn, a, ENG_LOG_INFO };
    a->start_s = now_s();
    if (o->report) memset(o->report, 0, sizeof *o->report);
    held_log renderer_log;
    int status = run_app(a, &renderer_log);
    // Here, not at the end of the frame loop: a run that ends early (a script that does not
    // load, a context, shader or output that fails) is as much a result as one that ran.
    if (o->report) {
        o->report->status = status;
        o->report->frames = a->frame;
        o->report->sim_time = a->time;
        o->report->wall_s = now_s() - a->start_s;
    }
    shutdown_app(a);
    return status;
}
