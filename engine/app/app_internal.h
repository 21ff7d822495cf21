// The runner's private parts shared by its files: the app and a loaded scene (instance),
// and the functions app.c (the loop), app_scene.c (building a scene) and app_output.c
// (statistics, metrics, video, screenshots) call across.
#ifndef ENG_APP_INTERNAL_H
#define ENG_APP_INTERNAL_H

#include <stdio.h>
#include <sys/types.h>
#include <time.h>

#include "engine/app/app.h"
#include "engine/app/ui.h"
#include "engine/core/progress.h"
#include "engine/gl/context.h"
#include "engine/gl/input.h"
#include "engine/gl/video.h"
#include "engine/render/camera.h"
#include "engine/render/mesh.h"
#include "engine/render/renderer.h"
#include "engine/render/scene.h"
#include "engine/script/script.h"
#include "fluid/bullet/coupling.h"
#include "fluid/bullet/phys.h"
#include "fluid/pbf.h"

/// Thickness of the static Bullet walls that keep bodies in the container, m.
#define WALL_THICKNESS 0.5f

enum { WALL_FLOOR = 0, WALL_XMIN, WALL_XMAX, WALL_ZMIN, WALL_ZMAX, WALL_COUNT };

typedef struct instance {
    eng_script *script;
    pbf_world *world;
    phys_world *phys;
    cpl_coupling *coupling;
    eng_node_id root;              // bodies and container walls hang below it
    eng_node_id walls[WALL_COUNT]; // drawn container (floor and walls)
    eng_mesh_id wall_mesh[WALL_COUNT];
} instance;

// The renderer's logger (app.c, held_log_fn): the app's, except that while a renderer is
// being built its errors are held back, because they come back in `err` too and are printed
// once, with what they mean for the run (the shader directory; the ground kept).
typedef struct held_log {
    eng_logger to;
    bool hold_errors;
} held_log;

typedef struct app {
    const eng_app_options *opt;
    eng_logger log;
    eng_context *ctx;
    eng_input *input;
    eng_renderer *renderer;
    eng_renderer_def renderer_def;
    eng_look applied_look;
    bool have_applied_look;
    unsigned applied_fluid_generation; // the script's seiche.render call last applied (0: none)
    eng_mesh_store *meshes;
    eng_scene *scene;
    eng_camera camera;
    eng_ui *ui;
    bool show_panel;
    instance inst;
    char shader_dir[1024];
    uint64_t frame;
    double time;
    bool paused, step_once;
    bool pause_warned;           // headless: a pause was asked for and ignored (warned once)
    bool halted;                 // window: the script failed; callbacks stop, the scene runs on
    char error_text[8192];       // window: shown until the next successful reload
    int window_status;           // window: worst status since the last successful load
    int mouse_captured;          // 1-based button the script took with on_mouse, 0: none
    double watch_next;           // monotonic s of the next file check
    struct timespec watch_mtime;
    off_t watch_size;
    FILE *metrics;
    eng_video *video; // --record
    eng_progress progress; // headless runs on a terminal
    bool diverged, diverged_reported;
    char diverged_text[400];
    pbf_step_stats last_stats;
    bool have_stats;
    uint64_t stats_rows;
    double rho_err_max;   // max over frames of (rho_max / rho0 - 1)
    double step_ms_sum;
    double start_s;        // monotonic s when the run began (reports)
    double fps;            // frames per wall-clock second, over the last half second
    double fps_since;      // monotonic s where that window began
    uint64_t fps_frames;
    uint64_t step_ms_n;
    bool screenshot_taken;
} app;

void app_destroy_instance(app *a, instance *in);
void app_update_host(app *a);
bool app_file_stamp(const char *path, struct timespec *mtime, off_t *size);
int app_load_scene(app *a, bool reload);
void app_write_metrics_header(app *a);
void app_take_stats(app *a, bool wait);
int app_check_diverged(app *a);
int app_record_frame(app *a);
int app_open_video(app *a);
int app_close_video(app *a, bool quiet);
int app_close_metrics(app *a, bool quiet);
void app_print_summary(app *a);
int app_write_screenshot(app *a);
int app_finish_checks(app *a, int status);
void app_report(app *a, const char *msg);
/// app_report of a formatted message that begins "seiche: ".
void app_message(app *a, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

#endif
