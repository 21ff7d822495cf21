// The frame loop. See app.h and docs/runner.md.
//
// A loaded scene is an `instance`: the script, the fluid world, the Bullet world, the
// coupling between them and the scene-graph nodes that draw the container. Reset and
// reload build a new instance beside the old one and swap only when everything
// succeeded, so a broken script never takes the running scene down with it.
#include "engine/app/app.h"

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <errno.h>
#include <math.h>
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

typedef struct app {
    const eng_app_options *opt;
    eng_logger log;
    eng_context *ctx;
    eng_input *input;
    eng_renderer *renderer;
    eng_renderer_def renderer_def;
    eng_look applied_look;
    bool have_applied_look;
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
    bool halted;                 // window: the script failed; callbacks stop, the scene runs on
    char error_text[8192];       // window: shown until the next successful reload
    int window_status;           // window: worst status since the last successful load
    int mouse_captured;          // 1-based button the script took with on_mouse, 0: none
    double watch_next;           // monotonic s of the next file check
    struct timespec watch_mtime;
    off_t watch_size;
    FILE *metrics;
    eng_video *video; // --record
    pbf_step_stats last_stats;
    bool have_stats;
    uint64_t stats_rows;
    double rho_err_max;   // max over frames of (rho_max / rho0 - 1)
    double step_ms_sum;
    uint64_t step_ms_n;
    bool screenshot_taken;
} app;

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
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
    for (int i = 0; i < n; i++) len += (size_t)snprintf(keys + len, sizeof keys - len, "fluid.%s, ", t[i].name);
    snprintf(keys + len, sizeof keys - len, "gravity.x, gravity.y, gravity.z, capacity");
    return keys;
}

// Finds the shaders: the option, then $SEICHE_SHADER_DIR (shader development), else the
// copies embedded in the libraries ("" here).
static void find_shader_dir(app *a)
{
    const char *env = getenv("SEICHE_SHADER_DIR");
    const char *dir = a->opt->shader_dir ? a->opt->shader_dir : env ? env : "";
    snprintf(a->shader_dir, sizeof a->shader_dir, "%s", dir);
}

// ---- errors ---------------------------------------------------------------------------

// Reports a message: always on stderr; in a window also on screen.
static void report(app *a, const char *msg)
{
    fprintf(stderr, "%s\n", msg);
    if (a->opt->headless) return;
    size_t n = strlen(msg);
    if (n >= sizeof a->error_text) n = sizeof a->error_text - 1;
    memcpy(a->error_text, msg, n);
    a->error_text[n] = 0;
}

// A failed script step. Headless the run ends with the status; in a window the message is
// shown, the script's callbacks stop and the scene keeps running.
static int script_failed(app *a, eng_script_status st, const char *msg)
{
    int status = st == ENG_SCRIPT_CHECK_FAILED ? ENG_EXIT_CHECK_FAILED : ENG_EXIT_USAGE;
    report(a, msg);
    if (a->opt->headless) return status;
    a->halted = true;
    if (status > a->window_status) a->window_status = status;
    return ENG_EXIT_OK;
}

// ---- building a scene -----------------------------------------------------------------

static int apply_sets(app *a, eng_scene_config *c, char *err, size_t err_size)
{
    // The fluid.* options apply together, checked as a set (pbf_params_apply), so that any
    // consistent particle_radius / kernel_radius pair is accepted in any order.
    char fluid_keys[ENG_APP_MAX_SETS][128];
    const char *fluid_names[ENG_APP_MAX_SETS];
    double fluid_values[ENG_APP_MAX_SETS];
    int fluid_count = 0;
    for (int i = 0; i < a->opt->set_count; i++) {
        const char *kv = a->opt->sets[i];
        const char *eq = strchr(kv, '=');
        char key[128];
        if (!eq || eq == kv || (size_t)(eq - kv) >= sizeof key) {
            snprintf(err, err_size, "seiche: --set expects KEY=VALUE (got '%s')", kv);
            return ENG_EXIT_USAGE;
        }
        snprintf(key, sizeof key, "%.*s", (int)(eq - kv), kv);
        char *end;
        errno = 0;
        double v = strtod(eq + 1, &end);
        if (end == eq + 1 || *end || errno || !isfinite(v)) {
            snprintf(err, err_size, "seiche: --set %s: value must be a finite number (got '%s')", key, eq + 1);
            return ENG_EXIT_USAGE;
        }
        if (strncmp(key, "fluid.", 6) == 0) {
            snprintf(fluid_keys[fluid_count], sizeof fluid_keys[0], "%s", key + 6);
            fluid_names[fluid_count] = fluid_keys[fluid_count];
            fluid_values[fluid_count++] = v;
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

static void world_log(void *user, int level, const char *msg)
{
    app *a = user;
    if (level >= 3) return;
    eng_log(&a->log, level == 2 ? ENG_LOG_WARN : ENG_LOG_DEBUG, "fluid: %s", msg);
}

static void phys_log(void *user, phys_log_level level, const char *msg)
{
    app *a = user;
    if (level == PHYS_LOG_ERROR) return; // errors come back as results, reported with the script's line
    eng_log(&a->log, level == PHYS_LOG_WARNING ? ENG_LOG_WARN : ENG_LOG_DEBUG, "bullet: %s", msg);
}

static void cpl_log(void *user, const char *msg)
{
    app *a = user;
    eng_log(&a->log, ENG_LOG_DEBUG, "coupling: %s", msg);
}

// Memory the GL implementation can give, bytes, or 0 when it does not say. NVIDIA and
// AMD report it through extensions; a software rasteriser (llvmpipe) uses system memory.
static double gpu_memory_bytes(void)
{
    if (epoxy_has_gl_extension("GL_NVX_gpu_memory_info")) {
        GLint kb = 0;
        glGetIntegerv(0x9048, &kb); // GPU_MEMORY_INFO_TOTAL_AVAILABLE_MEMORY_NVX
        glGetError();
        if (kb > 0) return (double)kb * 1024.0;
    }
    if (epoxy_has_gl_extension("GL_ATI_meminfo")) {
        GLint kb[4] = { 0 };
        glGetIntegerv(0x87FB, kb); // VBO_FREE_MEMORY_ATI
        glGetError();
        if (kb[0] > 0) return (double)kb[0] * 1024.0;
    }
    const char *r = (const char *)glGetString(GL_RENDERER);
    if (r && (strstr(r, "llvmpipe") || strstr(r, "softpipe") || strstr(r, "SWR"))) {
        long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
        if (pages > 0 && page > 0) return 0.5 * (double)pages * (double)page; // leave half to everything else
    }
    return 0.0;
}

// Static Bullet boxes around the container, so bodies stay in it as the fluid does.
static int container_bodies(instance *in, const eng_scene_config *c, char *err, size_t err_size)
{
    const float *lo = c->container_min, *hi = c->container_max;
    float t = WALL_THICKNESS;
    float top = c->domain_max[1] > hi[1] ? c->domain_max[1] : hi[1];
    float cx = 0.5f * (lo[0] + hi[0]), cz = 0.5f * (lo[2] + hi[2]);
    float sx = 0.5f * (hi[0] - lo[0]) + t, sz = 0.5f * (hi[2] - lo[2]) + t, hy = 0.5f * (top - lo[1]) + t;
    float cy = 0.5f * (top + lo[1]);
    float boxes[6][6] = {
        { cx, lo[1] - 0.5f * t, cz, sx, 0.5f * t, sz },              // floor
        { lo[0] - 0.5f * t, cy, cz, 0.5f * t, hy, sz },              // x min
        { hi[0] + 0.5f * t, cy, cz, 0.5f * t, hy, sz },              // x max
        { cx, cy, lo[2] - 0.5f * t, sx, hy, 0.5f * t },              // z min
        { cx, cy, hi[2] + 0.5f * t, sx, hy, 0.5f * t },              // z max
        { cx, hi[1] + 0.5f * t, cz, sx, 0.5f * t, sz },              // lid
    };
    int n = c->closed_top ? 6 : 5;
    for (int i = 0; i < n; i++) {
        phys_box box = { { boxes[i][3], boxes[i][4], boxes[i][5] } };
        phys_shape_id shape = { 0, 0, 0 };
        phys_body_def bd = phys_default_body_def();
        bd.type = PHYS_BODY_STATIC;
        bd.position = (phys_vec3){ boxes[i][0], boxes[i][1], boxes[i][2] };
        phys_body_id body;
        bool ok = phys_shape_create_box(in->phys, &box, &shape) == PHYS_OK;
        bd.shape = shape;
        if (!ok || phys_body_create(in->phys, &bd, &body) != PHYS_OK) {
            snprintf(err, err_size, "%sseiche.scene: container walls for bodies: %s", c->scene_where,
                     phys_world_last_error(in->phys));
            return ENG_EXIT_USAGE;
        }
    }
    return ENG_EXIT_OK;
}

// Thin slabs that draw the container: the floor and the four walls (the walls between
// the camera and the fluid are hidden each frame, see update_walls).
static void container_nodes(app *a, instance *in, const eng_scene_config *c)
{
    const float *lo = c->container_min, *hi = c->container_max;
    float t = 0.01f;
    float cx = 0.5f * (lo[0] + hi[0]), cy = 0.5f * (lo[1] + hi[1]), cz = 0.5f * (lo[2] + hi[2]);
    float sx = 0.5f * (hi[0] - lo[0]), sy = 0.5f * (hi[1] - lo[1]), sz = 0.5f * (hi[2] - lo[2]);
    // The floor's top sits a hair above the container floor so it covers the ground plane.
    float slabs[WALL_COUNT][6] = {
        { cx, lo[1] - t + 0.0015f, cz, sx + 2 * t, t, sz + 2 * t },
        { lo[0] - t, cy, cz, t, sy, sz + 2 * t },
        { hi[0] + t, cy, cz, t, sy, sz + 2 * t },
        { cx, cy, lo[2] - t, sx, sy, t },
        { cx, cy, hi[2] + t, sx, sy, t },
    };
    for (int i = 0; i < WALL_COUNT; i++) {
        float half[3] = { slabs[i][3], slabs[i][4], slabs[i][5] };
        in->wall_mesh[i] = eng_mesh_create_box(a->meshes, half);
        eng_node_def nd = eng_default_node_def();
        nd.parent = in->root;
        nd.mesh = in->wall_mesh[i];
        nd.local.translation[0] = slabs[i][0];
        nd.local.translation[1] = slabs[i][1];
        nd.local.translation[2] = slabs[i][2];
        float shade = i == WALL_FLOOR ? 0.70f : 0.80f;
        nd.color[0] = shade, nd.color[1] = shade + 0.02f, nd.color[2] = shade + 0.06f;
        in->walls[i] = eng_node_create(a->scene, &nd);
    }
}

static void destroy_instance(app *a, instance *in)
{
    eng_script_destroy(in->script); // its body nodes and meshes first (they hang below root)
    if (in->root.index1 && eng_node_is_valid(a->scene, in->root)) eng_node_destroy(a->scene, in->root);
    for (int i = 0; i < WALL_COUNT; i++)
        if (in->wall_mesh[i].index1) eng_mesh_destroy(a->meshes, in->wall_mesh[i]);
    cpl_destroy(in->coupling);
    phys_world_destroy(in->phys);
    pbf_world_destroy(in->world);
    memset(in, 0, sizeof *in);
}

static int create_worlds(app *a, instance *in, char *err, size_t err_size)
{
    eng_scene_config *c = eng_script_config(in->script);
    pbf_world_def d = pbf_default_world_def();
    d.params = c->params;
    d.capacity = c->capacity;
    d.max_neighbours = pbf_suggest_max_neighbours(&c->params);
    d.shader_dir = a->shader_dir[0] ? a->shader_dir : NULL;
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
    memcpy(c->domain_min, d.domain_min, sizeof d.domain_min); // what the world uses, for the script's checks
    memcpy(c->domain_max, d.domain_max, sizeof d.domain_max);
    // Messages start with "file:line: " of seiche.scene (or the file when there is none).
    char where[600];
    if (c->scene_where[0]) snprintf(where, sizeof where, "%s", c->scene_where);
    else snprintf(where, sizeof where, "%s: ", eng_script_path(in->script));
    double need = (double)pbf_world_def_memory(&d), have = gpu_memory_bytes();
    if (have > 0 && need > have) {
        snprintf(err, err_size, "%sseiche.scene: field 'capacity' %u needs about %.1f GiB of GPU memory for particle "
                 "buffers (%u neighbours each), but this GPU has about %.1f GiB; lower capacity (or kernel_radius)",
                 where, d.capacity, need / 1073741824.0, d.max_neighbours, have / 1073741824.0);
        return ENG_EXIT_USAGE;
    }
    char werr[1024];
    in->world = pbf_world_create(&d, werr, sizeof werr);
    if (!in->world) {
        snprintf(err, err_size, "%sseiche.scene: %s", where, werr);
        return ENG_EXIT_USAGE;
    }
    if (c->has_container &&
        pbf_world_set_container(in->world, c->container_min, c->container_max, c->closed_top) != PBF_OK) {
        snprintf(err, err_size, "%sseiche.scene: %s", where, pbf_world_last_error(in->world));
        return ENG_EXIT_USAGE;
    }
    phys_world_def pd = phys_default_world_def();
    pd.gravity = (phys_vec3){ c->params.gravity[0], c->params.gravity[1], c->params.gravity[2] };
    pd.log = phys_log;
    pd.log_user = a;
    if (phys_world_create(&pd, &in->phys) != PHYS_OK) {
        snprintf(err, err_size, "%sseiche.scene: the Bullet world could not be created", where);
        return ENG_EXIT_USAGE;
    }
    cpl_def cd = cpl_default_def();
    cd.phys = in->phys;
    cd.fluid = in->world;
    cd.log = cpl_log;
    cd.log_user = a;
    char cerr[512];
    in->coupling = cpl_create(&cd, cerr, sizeof cerr);
    if (!in->coupling) {
        snprintf(err, err_size, "%sseiche.scene: %s", where, cerr);
        return ENG_EXIT_USAGE;
    }
    eng_node_def root = eng_default_node_def();
    in->root = eng_node_create(a->scene, &root);
    if (c->has_container) {
        int st = container_bodies(in, c, err, err_size);
        if (st != ENG_EXIT_OK) return st;
        container_nodes(a, in, c);
    }
    return ENG_EXIT_OK;
}

static void update_host(app *a)
{
    instance *in = &a->inst;
    if (!in->script) return;
    eng_script_host h;
    memset(&h, 0, sizeof h);
    h.world = in->world;
    h.phys = in->phys;
    h.coupling = in->coupling;
    h.scene = a->scene;
    h.root = in->root;
    h.meshes = a->meshes;
    h.input = a->input;
    h.camera = &a->camera;
    eng_context_size(a->ctx, &h.view_width, &h.view_height);
    h.stats = a->have_stats ? &a->last_stats : NULL;
    h.frame = a->frame;
    h.time = a->time;
    h.dt = a->opt->dt;
    h.renderer = eng_context_renderer(a->ctx);
    h.headless = a->opt->headless;
    eng_script_set_host(in->script, &h);
}

// Applies the renderer's part of the look: sky and light now, and a new renderer when the
// ground changed (it is part of the renderer's def).
static void apply_look(app *a, const eng_look *k)
{
    if (a->have_applied_look && memcmp(k, &a->applied_look, sizeof *k) == 0) return;
    if (a->renderer && (k->ground != a->renderer_def.ground || k->ground_height != a->renderer_def.ground_height)) {
        eng_renderer_def rd = a->renderer_def;
        rd.fluid = eng_renderer_fluid_look(a->renderer); // the mode the user picked stays
        rd.ground = k->ground;
        rd.ground_height = k->ground_height;
        char err[1024];
        eng_renderer *r = eng_renderer_create(&rd, err, sizeof err);
        if (r) {
            eng_renderer_destroy(a->renderer);
            a->renderer = r;
            a->renderer_def = rd;
        } else {
            eng_log(&a->log, ENG_LOG_WARN, "look: the renderer could not be rebuilt (%s); keeping the old ground", err);
        }
    }
    if (a->renderer) {
        eng_renderer_set_sky(a->renderer, k->sky);
        eng_renderer_set_light(a->renderer, &k->light);
    }
    a->applied_look = *k;
    a->have_applied_look = true;
}

static bool file_stamp(const char *path, struct timespec *mtime, off_t *size)
{
    struct stat st;
    if (stat(path, &st) != 0) return false;
    *mtime = st.st_mtim;
    *size = st.st_size;
    return true;
}

// Loads the script and builds a new instance; on success it replaces the running one.
// On failure the running one stays and the message is reported (stderr; on screen in a
// window). `reload`: F5 or a saved file (on_reload is called, the camera kept unless the
// script moved it); otherwise a reset or the first load.
static int load_scene(app *a, bool reload)
{
    double budget = a->opt->budget_s > 0 ? a->opt->budget_s : a->opt->headless ? 5.0 : 2.0;
    instance in;
    memset(&in, 0, sizeof in);
    in.script = eng_script_create(&a->log, budget);
    if (!in.script) {
        report(a, "seiche: cannot create the Lua state");
        return ENG_EXIT_USAGE;
    }
    file_stamp(a->opt->script, &a->watch_mtime, &a->watch_size);
    instance old = a->inst;
    uint64_t old_frame = a->frame;
    double old_time = a->time;
    bool old_have_stats = a->have_stats;
    eng_camera old_camera = a->camera;
    eng_scene_config old_config;
    if (old.script) old_config = *eng_script_config(old.script);

    char err[8192] = "";
    int st = ENG_EXIT_OK;
    eng_script_status ss = eng_script_load(in.script, a->opt->script);
    if (ss != ENG_SCRIPT_OK) {
        st = ss == ENG_SCRIPT_CHECK_FAILED ? ENG_EXIT_CHECK_FAILED : ENG_EXIT_USAGE;
        snprintf(err, sizeof err, "%s", eng_script_error(in.script));
    }
    if (st == ENG_EXIT_OK) st = apply_sets(a, eng_script_config(in.script), err, sizeof err);
    if (st == ENG_EXIT_OK) st = create_worlds(a, &in, err, sizeof err);
    const eng_scene_config *c = eng_script_config(in.script);
    if (st == ENG_EXIT_OK) {
        // The camera first: on_start may move it (seiche.set_camera).
        bool keep = reload && old.script && memcmp(c->camera_eye, old_config.camera_eye, sizeof c->camera_eye) == 0 &&
                    memcmp(c->camera_target, old_config.camera_target, sizeof c->camera_target) == 0 &&
                    c->camera_fov == old_config.camera_fov && c->camera_mode == old_config.camera_mode;
        if (!keep) {
            eng_camera_look_at(&a->camera, c->camera_eye, c->camera_target);
            a->camera.fov_y = c->camera_fov * 3.14159265f / 180.0f;
            eng_camera_set_mode(&a->camera, c->camera_mode);
        }
        a->inst = in;
        a->frame = 0;
        a->time = 0.0;
        a->have_stats = false;
        update_host(a);
        // The edits of the main chunk, then on_start (and on_reload) and theirs.
        for (int k = 0; k < 3 && st == ENG_EXIT_OK; k++) {
            ss = k == 1 ? eng_script_on_start(in.script) : k == 2 && reload ? eng_script_on_reload(in.script) : ENG_SCRIPT_OK;
            if (ss == ENG_SCRIPT_OK) ss = eng_script_apply(in.script);
            if (ss != ENG_SCRIPT_OK) {
                st = ss == ENG_SCRIPT_CHECK_FAILED ? ENG_EXIT_CHECK_FAILED : ENG_EXIT_USAGE;
                snprintf(err, sizeof err, "%s", eng_script_error(in.script));
            }
        }
        a->inst = old;
    }
    if (st != ENG_EXIT_OK) {
        destroy_instance(a, &in);
        a->frame = old_frame;
        a->time = old_time;
        a->have_stats = old_have_stats;
        a->camera = old_camera;
        update_host(a);
        if (!a->opt->headless && st > a->window_status) a->window_status = st; // the file on disk is broken
        if (old.script && (reload || !a->opt->headless)) {
            char msg[8400];
            snprintf(msg, sizeof msg, "%s\n(%s failed; the last good scene keeps running)", err, reload ? "reload" : "reset");
            report(a, msg);
        } else {
            report(a, err);
        }
        return st;
    }
    destroy_instance(a, &old);
    a->inst = in;
    a->frame = 0;
    a->time = 0.0;
    a->have_stats = false;
    a->halted = false;
    a->error_text[0] = 0;
    a->window_status = ENG_EXIT_OK;
    a->mouse_captured = 0;
    if (!a->have_applied_look || c->look.panel != a->applied_look.panel) a->show_panel = c->look.panel;
    apply_look(a, &c->look);
    update_host(a);
    return ENG_EXIT_OK;
}

// ---- the frame ------------------------------------------------------------------------------

static void write_metrics_header(app *a)
{
    fprintf(a->metrics, "frame,time,particles,rho0,rho_max,rho_avg,step_ms");
    for (int s = 0; s < PBF_STAGE_COUNT; s++) fprintf(a->metrics, ",%s_ms", pbf_stage_name((pbf_stage)s));
    fprintf(a->metrics, ",nan,outside,overflow,rho_err_avg\n");
}

static void take_stats(app *a, bool wait)
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
                fprintf(a->metrics, ",%u,%u,%u,%.6f\n", s->nan_count, s->outside_count, s->overflow_count,
                        (double)s->density_error_avg);
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
    f.paused = a->paused;
    f.show_panel = a->show_panel;
    f.error = a->error_text;
    f.params = params;
    f.param_count = p ? n : 0;
    eng_ui_draw(a->ui, &f);
    a->show_panel = f.show_panel;
    if (f.toggle_pause) a->paused = !a->paused;
    if (f.step) a->step_once = true;
    if (f.dismiss_error) a->error_text[0] = 0;
    for (int i = 0; i < f.param_count; i++) {
        if (!params[i].changed) continue;
        char err[512];
        if (!eng_script_set_param(in->script, params[i].name, params[i].value, err, sizeof err)) report(a, err);
    }
    if (f.reset || f.reload) load_scene(a, f.reload);
}

static int record_frame(app *a)
{
    char err[1200];
    if (eng_video_frame(a->video, a->ctx, err, sizeof err)) return ENG_EXIT_OK;
    a->video = NULL; // closed by the failure
    fprintf(stderr, "seiche: %s\n", err);
    return ENG_EXIT_USAGE;
}

static int open_video(app *a)
{
    char err[1200];
    a->video = eng_video_open(a->ctx, a->opt->record_path, (int)lround(1.0 / a->opt->dt), err, sizeof err);
    if (!a->video) {
        fprintf(stderr, "seiche: %s\n", err);
        return ENG_EXIT_USAGE;
    }
    return ENG_EXIT_OK;
}

// Ends the video; ENG_EXIT_USAGE with a message (unless `quiet`) when ffmpeg failed.
static int close_video(app *a, bool quiet)
{
    char err[1200];
    bool ok = eng_video_close(a->video, err, sizeof err);
    a->video = NULL;
    if (!ok && !quiet) fprintf(stderr, "seiche: %s\n", err);
    return ok ? ENG_EXIT_OK : ENG_EXIT_USAGE;
}

// Closes the metrics file; ENG_EXIT_USAGE with a message if any row could not be written.
static int close_metrics(app *a, bool quiet)
{
    if (!a->metrics) return ENG_EXIT_OK;
    bool failed = ferror(a->metrics) != 0;
    int e = errno;
    if (fclose(a->metrics) != 0 && !failed) {
        failed = true;
        e = errno;
    }
    a->metrics = NULL;
    if (failed && !quiet) fprintf(stderr, "seiche: --metrics: writing '%s' failed: %s\n", a->opt->metrics_path, strerror(e));
    return failed ? ENG_EXIT_USAGE : ENG_EXIT_OK;
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
    case GLFW_KEY_SPACE: a->paused = !a->paused; break;
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
        int st = load_scene(a, e->key == GLFW_KEY_F5);
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
            if (name && s && !a->halted) st = eng_script_on_key(s, name, action);
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
    if (!file_stamp(a->opt->script, &m, &size)) return;
    if (m.tv_sec == a->watch_mtime.tv_sec && m.tv_nsec == a->watch_mtime.tv_nsec && size == a->watch_size) return;
    eng_log(&a->log, ENG_LOG_INFO, "%s changed: reloading", a->opt->script);
    load_scene(a, true);
    a->watch_mtime = m; // also after a failed load: wait for the next save
    a->watch_size = size;
}

static void print_summary(app *a)
{
    if (a->opt->quiet || !a->inst.script) return;
    const pbf_step_stats *s = &a->last_stats;
    printf("seiche: %s: %llu frames, %.2f s simulated, %u particles, %u bodies, rho_avg %.1f rho_max %.1f (rho0 %.0f, "
           "worst %.1f%% over), %.2f ms GPU per step, %s\n",
           eng_script_config(a->inst.script)->name, (unsigned long long)a->frame, a->time,
           a->inst.world ? pbf_world_particle_count(a->inst.world) : 0, a->inst.coupling ? cpl_body_count(a->inst.coupling) : 0,
           a->have_stats ? (double)s->density_avg : 0.0, a->have_stats ? (double)s->density_max : 0.0,
           (double)pbf_world_params(a->inst.world)->rest_density, 100.0 * a->rho_err_max,
           a->step_ms_n ? a->step_ms_sum / (double)a->step_ms_n : 0.0, eng_context_renderer(a->ctx));
}

static void shutdown_app(app *a)
{
    close_metrics(a, true);
    close_video(a, true);
    destroy_instance(a, &a->inst);
    eng_ui_destroy(a->ui);
    eng_scene_destroy(a->scene);
    eng_mesh_store_destroy(a->meshes);
    eng_renderer_destroy(a->renderer);
    eng_input_destroy(a->input);
    eng_context_destroy(a->ctx);
}

static int write_screenshot(app *a)
{
    char err[1024];
    a->screenshot_taken = true;
    if (!eng_screenshot_write_png(a->ctx, a->opt->screenshot_path, err, sizeof err)) {
        fprintf(stderr, "seiche: --screenshot: %s\n", err);
        return ENG_EXIT_USAGE;
    }
    return ENG_EXIT_OK;
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
    if (!a->ctx) return cst == ENG_CONTEXT_NO_COMPUTE || cst == ENG_CONTEXT_NO_GL ? ENG_EXIT_NO_COMPUTE : ENG_EXIT_USAGE;
    a->input = eng_input_create(a->ctx);
    a->renderer_def = eng_default_renderer_def();
    a->renderer_def.shader_dir = a->shader_dir[0] ? a->shader_dir : NULL;
    a->renderer_def.logger = a->log;
    if (o->render && !eng_fluid_mode_parse(o->render, &a->renderer_def.fluid.mode)) {
        fprintf(stderr, "seiche: --render must be one of %s (got '%s')\n", eng_fluid_mode_names(), o->render);
        shutdown_app(a);
        return ENG_EXIT_USAGE;
    }
    a->renderer = eng_renderer_create(&a->renderer_def, err, sizeof err);
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
    if (!o->headless && o->ui) {
        a->ui = eng_ui_create(eng_context_window(a->ctx), err, sizeof err);
        if (!a->ui) eng_log(&a->log, ENG_LOG_WARN, "seiche: no on-screen UI: %s", err);
    }

    int status = load_scene(a, false);
    if (status != ENG_EXIT_OK) {
        if (o->headless) {
            shutdown_app(a);
            return status;
        }
        // A window waits for the script to be fixed (it is watched) with the error shown.
        a->window_status = status;
        status = ENG_EXIT_OK;
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
    bool done = frames == 0;
    long idle_frames = 0;
    while (status == ENG_EXIT_OK && !done) {
        eng_input_begin_frame(a->input);
        eng_context_poll(a->ctx);
        if (a->inst.script) eng_script_deliver_input(a->inst.script);
        handle_input(a, &status);
        if (status != ENG_EXIT_OK) break;
        bool camera_input = !a->mouse_captured && !eng_ui_wants_mouse(a->ui) && !eng_ui_wants_keyboard(a->ui);
        eng_camera_update(&a->camera, camera_input ? a->input : NULL, (float)o->dt);
        instance *in = &a->inst;
        if (in->script) {
            update_host(a);
            status = script_result(a, eng_script_apply(in->script));
            if (status != ENG_EXIT_OK) break;
            if (!a->paused || a->step_once) {
                a->step_once = false;
                if (cpl_step(in->coupling, (float)o->dt) != CPL_OK) {
                    fprintf(stderr, "seiche: %s\n", cpl_last_error(in->coupling));
                    status = ENG_EXIT_USAGE;
                    break;
                }
                a->frame++;
                a->time = (double)a->frame * o->dt; // exact multiples, no running sum
                take_stats(a, false);
                update_host(a);
                if (!a->halted) status = script_result(a, eng_script_on_step(in->script, o->dt, a->time));
            }
        }
        watch_file(a);
        bool quit = a->inst.script && eng_script_quit_requested(a->inst.script);
        // Without a scene (it failed to load; a window waits for the fix) --frames counts
        // the frames drawn, so a run with a broken script still ends.
        if (!a->inst.script) idle_frames++;
        done = (frames >= 0 && ((long)a->frame >= frames || idle_frames >= frames)) || quit ||
               eng_context_should_close(a->ctx) || status != ENG_EXIT_OK;
        bool shot = done && o->screenshot_path && (status == ENG_EXIT_OK || status == ENG_EXIT_CHECK_FAILED);
        if (!o->headless || a->video || shot) {
            render(a);
            draw_ui(a);
        }
        if (shot && write_screenshot(a) != ENG_EXIT_OK) status = ENG_EXIT_USAGE;
        if (a->video && status == ENG_EXIT_OK) status = record_frame(a);
        eng_context_present(a->ctx);
    }
    if (a->inst.world) take_stats(a, true);
    if (status == ENG_EXIT_OK && !o->headless) status = a->window_status;
    if (status == ENG_EXIT_OK || status == ENG_EXIT_CHECK_FAILED) {
        if (o->screenshot_path && !a->screenshot_taken) {
            render(a);
            if (write_screenshot(a) != ENG_EXIT_OK) status = ENG_EXIT_USAGE;
        }
        if (o->hash && a->inst.world) printf("state hash: %016llx\n", (unsigned long long)pbf_world_state_hash(a->inst.world));
    }
    // Every output is complete and checked before the run counts as a success.
    int out = close_metrics(a, false);
    int vid = close_video(a, status != ENG_EXIT_OK && status != ENG_EXIT_CHECK_FAILED);
    if (status == ENG_EXIT_OK || status == ENG_EXIT_CHECK_FAILED) {
        if (out != ENG_EXIT_OK) status = out;
        else if (vid != ENG_EXIT_OK) status = vid;
        else if (fflush(stdout) != 0) {
            fprintf(stderr, "seiche: writing standard output failed: %s\n", strerror(errno));
            status = ENG_EXIT_USAGE;
        }
    }
    if (status == ENG_EXIT_OK) print_summary(a);
    shutdown_app(a);
    return status;
}
