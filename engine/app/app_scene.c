// Building a scene (an instance) from a script: the --set options (app_args.c), the fluid and Bullet
// worlds and their coupling, the container, the look; loading, resetting and reloading.
#include "engine/app/app_internal.h"
#include "engine/app/app_args.h"

#include <epoxy/gl.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "engine/gl/screenshot.h"

// The script's view of the --set options while its main chunk runs (eng_script_host).
static bool overrides_for_script(void *user, eng_scene_config *c)
{
    const app *a = user;
    char err[512];
    return eng_app_apply_sets(a->opt, c, err, sizeof err) == ENG_EXIT_OK;
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
    // As tall as the walls are drawn (container_nodes): a body thrown higher flies over.
    float top = hi[1];
    float cx = 0.5f * (lo[0] + hi[0]), cz = 0.5f * (lo[2] + hi[2]);
    // Side walls from the floor's underside (lo.y - t) to the top, no higher.
    float sx = 0.5f * (hi[0] - lo[0]) + t, sz = 0.5f * (hi[2] - lo[2]) + t, hy = 0.5f * (top - lo[1] + t);
    float cy = 0.5f * (top + lo[1] - t);
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

void app_destroy_instance(app *a, instance *in)
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
    pd.split_impulse_depth = 0.0f; // landings do not hop: one on_contact per hit (phys.h)
    if (phys_world_create(&pd, &in->phys) != PHYS_OK) {
        snprintf(err, err_size, "%sseiche.scene: the Bullet world could not be created", where);
        return ENG_EXIT_USAGE;
    }
    cpl_def cd = c->coupling;
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

void app_update_host(app *a)
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
    h.fluid_look = a->renderer ? eng_renderer_fluid_look(a->renderer) : a->renderer_def.fluid;
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
        held_log *h = rd.logger.user; // run_app's
        h->hold_errors = true;
        eng_renderer *r = eng_renderer_create(&rd, err, sizeof err);
        h->hold_errors = false;
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

bool app_file_stamp(const char *path, struct timespec *mtime, off_t *size)
{
    struct stat st;
    if (stat(path, &st) != 0) return false;
    *mtime = st.st_mtim;
    *size = st.st_size;
    return true;
}

// A script file that cannot be opened, with the reason (the script module says only that it
// cannot): a missing file, a dangling symbolic link (which names where it points), a loop
// of links, a file without read permission. False with the message in err. Anything
// that is not a regular file is left to eng_script_load, which says so (and a FIFO is not
// opened here, where it would block).
static bool script_file_opens(const char *path, char *err, size_t err_size)
{
    struct stat st;
    if (stat(path, &st) == 0) {
        FILE *f = S_ISREG(st.st_mode) ? fopen(path, "rb") : NULL;
        if (f || !S_ISREG(st.st_mode)) {
            if (f) fclose(f);
            return true;
        }
    }
    int e = errno;
    char target[512] = "", link[600] = "";
    ssize_t n = readlink(path, target, sizeof target - 1);
    if (n > 0) {
        target[n] = 0;
        snprintf(link, sizeof link, " (a symbolic link to '%s')", target);
    }
    snprintf(err, err_size, "%s: cannot open the script file%s: %s", path, link, strerror(e));
    return false;
}

// Loads the script and builds a new instance; on success it replaces the running one.
// On failure the running one stays and the message is reported (stderr; on screen in a
// window). `reload`: F5 or a saved file (on_reload is called, the camera kept unless the
// script moved it); otherwise a reset or the first load.
int app_load_scene(app *a, bool reload)
{
    double budget = a->opt->budget_s > 0 ? a->opt->budget_s : a->opt->headless ? 5.0 : 2.0;
    instance in;
    memset(&in, 0, sizeof in);
    eng_script_def sd = eng_default_script_def();
    sd.log = a->log;
    sd.budget_s = budget;
    sd.trusted = a->opt->trusted;
    in.script = eng_script_create(&sd);
    if (!in.script) {
        app_report(a, "seiche: cannot create the Lua state");
        return ENG_EXIT_USAGE;
    }
    app_file_stamp(a->opt->script, &a->watch_mtime, &a->watch_size);
    instance old = a->inst;
    uint64_t old_frame = a->frame;
    double old_time = a->time;
    bool old_have_stats = a->have_stats;
    eng_camera old_camera = a->camera;
    eng_scene_config old_config;
    if (old.script) old_config = *eng_script_config(old.script);

    char err[8192] = "";
    int st = ENG_EXIT_OK;
    // What the main chunk may read before the worlds exist: the frame step (--dt), the
    // renderer and its look (--render), headless or not.
    eng_script_host early;
    memset(&early, 0, sizeof early);
    early.dt = a->opt->dt;
    early.renderer = eng_context_renderer(a->ctx);
    early.headless = a->opt->headless;
    early.fluid_look = a->renderer ? eng_renderer_fluid_look(a->renderer) : a->renderer_def.fluid;
    early.apply_overrides = a->opt->set_count > 0 ? overrides_for_script : NULL;
    early.overrides_user = a;
    eng_script_set_host(in.script, &early);
    eng_script_status ss = ENG_SCRIPT_OK;
    if (!script_file_opens(a->opt->script, err, sizeof err)) st = ENG_EXIT_USAGE;
    else ss = eng_script_load(in.script, a->opt->script);
    if (ss != ENG_SCRIPT_OK) {
        st = ss == ENG_SCRIPT_CHECK_FAILED ? ENG_EXIT_CHECK_FAILED : ENG_EXIT_USAGE;
        snprintf(err, sizeof err, "%s", eng_script_error(in.script));
    }
    if (st == ENG_EXIT_OK) st = eng_app_apply_sets(a->opt, eng_script_config(in.script), err, sizeof err);
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
        a->diverged = a->diverged_reported = false;
        app_update_host(a);
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
        // With no scene running, the checks of the failed load are the run's checks (a check
        // that failed in the main chunk is a test case of the report, app_finish_checks).
        eng_app_report *r = a->opt->report;
        if (r && !old.script) {
            const eng_check_site *sites = NULL;
            r->check_count = eng_script_check_sites(in.script, &sites);
            memcpy(r->checks, sites, (size_t)r->check_count * sizeof *sites);
        }
        app_destroy_instance(a, &in);
        a->frame = old_frame;
        a->time = old_time;
        a->have_stats = old_have_stats;
        a->camera = old_camera;
        app_update_host(a);
        if (!a->opt->headless && st > a->window_status) a->window_status = st; // the file on disk is broken
        if (old.script && (reload || !a->opt->headless)) {
            char msg[8400];
            snprintf(msg, sizeof msg, "%s\n(%s failed; the last good scene keeps running)", err, reload ? "reload" : "reset");
            app_report(a, msg);
        } else {
            app_report(a, err);
        }
        return st;
    }
    app_destroy_instance(a, &old);
    a->inst = in;
    a->frame = 0;
    a->time = 0.0;
    a->have_stats = false;
    a->diverged = a->diverged_reported = false;
    a->halted = false;
    a->error_text[0] = 0;
    a->window_status = ENG_EXIT_OK;
    a->mouse_captured = 0;
    a->applied_fluid_generation = 0;
    if (!a->have_applied_look || c->look.panel != a->applied_look.panel) a->show_panel = c->look.panel;
    apply_look(a, &c->look);
    app_update_host(a);
    return ENG_EXIT_OK;
}
