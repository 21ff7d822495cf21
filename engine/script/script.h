// The Lua 5.4 host: runs a scene script, exposes the `seiche` table (docs/lua-api.md),
// keeps the handles a script holds (emitters, sinks, bodies, timers, grabs), queues the
// world edits the script makes and applies them between steps (eng_script_apply), and
// calls the script's callbacks (on_start, on_step, on_key, on_mouse, on_mouse_move,
// on_scroll, on_reload, timers) under a time budget.
//
// The script never touches a world while it runs: every edit (fluid blocks, emitters,
// sinks, bodies, forces, kinematic targets, parameter, gravity and camera changes)
// becomes a command that eng_script_apply carries out, in order, when the app calls it
// between steps. An edit that the world refuses is the script's error at the line that
// asked for it. Injected input (seiche.inject_*) waits for eng_script_deliver_input at
// the start of the next frame; the look (seiche.set_look) is read by the app each frame.
//
// Ownership: the app owns the worlds (pbf_world, phys_world, cpl_coupling), the scene
// graph and the mesh store and hands them over in eng_script_host. The script owns what
// it created in them: its bodies' shapes, scene nodes and meshes (destroyed with the
// body, or by eng_script_destroy), emitters, sinks and point constraints.
#ifndef ENG_SCRIPT_H
#define ENG_SCRIPT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "engine/render/camera.h"
#include "engine/gl/input.h"
#include "engine/core/log.h"
#include "engine/render/mesh.h"
#include "engine/render/renderer.h"
#include "engine/render/scene.h"
#include "fluid/bullet/coupling.h"
#include "fluid/bullet/phys.h"
#include "fluid/pbf.h"

/// How the scene looks (seiche.scene{look = ...}, seiche.set_look{...}).
typedef struct eng_look {
    float sky[3];                  ///< clear colour, linear RGB 0..1
    eng_light light;               ///< direction, colour, ambient
    eng_particle_style water;      ///< particle colours (by initial height), highlight
    bool ground;                   ///< draw the checkered ground plane
    float ground_height;           ///< m
    bool container;                ///< draw the container's floor and far walls
    bool panel;                    ///< show the parameter panel (window only)
} eng_look;

eng_look eng_default_look(void);

/// What a script's seiche.scene{} describes; the engine builds the world from it.
typedef struct eng_scene_config {
    char name[64];
    pbf_params params;
    uint32_t capacity;          ///< particles
    bool has_container;
    float container_min[3], container_max[3]; ///< m
    bool closed_top;
    float domain_min[3], domain_max[3];       ///< m; derived from the container when not given
    bool has_domain;
    float camera_eye[3], camera_target[3];    ///< m
    float camera_fov;                         ///< degrees
    eng_camera_mode camera_mode;
    eng_look look;
    eng_fluid_look fluid_look;                ///< seiche.render{...}: the renderer's look asked for
    unsigned fluid_look_generation;           ///< counts seiche.render calls (0: none): the app
                                              ///< applies fluid_look when this changes
    char scene_where[192];                    ///< "file:line:" of seiche.scene, "" if none
    cpl_def coupling;                         ///< seiche.coupling{...}: its settings (worlds and
                                              ///< log unset: the app fills them in)
} eng_scene_config;

eng_scene_config eng_default_scene_config(void);

/// What the script may use of the running engine. The app fills it in once the worlds
/// exist and refreshes the changing fields (stats, frame, time, view size) every frame.
typedef struct eng_script_host {
    pbf_world *world;           ///< NULL until the world exists
    phys_world *phys;           ///< NULL until the world exists
    cpl_coupling *coupling;     ///< NULL until the world exists
    eng_scene *scene;           ///< bodies are drawn as nodes under `root`
    eng_node_id root;
    eng_mesh_store *meshes;
    eng_input *input;           ///< injected events go here (seiche.inject_*)
    eng_camera *camera;         ///< seiche.set_camera / seiche.camera / seiche.screen_ray
    int view_width, view_height;///< pixels
    const pbf_step_stats *stats;///< latest completed step statistics, NULL before the first
    uint64_t frame;             ///< steps taken
    double time;                ///< s, simulated
    double dt;                  ///< s, frame step
    const char *renderer;       ///< GL renderer string
    eng_fluid_look fluid_look;  ///< the renderer's look now (seiche.render() reads it)
    bool headless;
    /// The host's overrides of the scene description (the runner's --set), applied to a copy
    /// of the config wherever the main chunk reads it back (seiche.param, params, gravity,
    /// capacity), so the script sees the values the world will be built with. Returns false
    /// when they do not apply (the host reports that after loading); NULL: no overrides.
    bool (*apply_overrides)(void *user, eng_scene_config *config);
    void *overrides_user;
} eng_script_host;

typedef enum eng_script_status {
    ENG_SCRIPT_OK = 0,
    ENG_SCRIPT_CHECK_FAILED,  ///< seiche.check failed (exit status 1)
    ENG_SCRIPT_ERROR,         ///< syntax or runtime error, or a refused edit (exit status 2)
} eng_script_status;

typedef struct eng_script eng_script;

/// How a script runs (eng_default_script_def fills it in).
typedef struct eng_script_def {
    eng_logger log;
    /// The longest the calls of one frame may run together before the script is stopped
    /// with an error (an endless loop), in seconds, (0, 3600]: on_key, on_mouse, ..., on_step
    /// and the timers of a frame share it; so do the main chunk, on_start and on_reload.
    /// Default 5.
    double budget_s;
    /// false (the default): the sandbox (docs/lua-api.md, "What a script can and cannot
    /// do"). true: every standard library (io, os, package, debug); for scripts one trusts.
    bool trusted;
} eng_script_def;

eng_script_def eng_default_script_def(void);

/// NULL when def->budget_s is outside (0, 3600] or memory runs out.
eng_script *eng_script_create(const eng_script_def *def);
/// Closes the Lua state (a trusted script's finalisers run then; the API refuses them), then
/// frees everything the script made in the host's scene graph and mesh store (call with the
/// GL context current). Bodies in the phys_world are left to the world's owner (destroying
/// the world frees them).
void eng_script_destroy(eng_script *s);

/// Loads and runs the file's main chunk (which describes the scene). On error the message
/// holds file:line and a traceback: see eng_script_error.
eng_script_status eng_script_load(eng_script *s, const char *path);
/// The same for a chunk in memory; `chunk_name` is what messages show as the file.
eng_script_status eng_script_load_string(eng_script *s, const char *chunk_name, const char *code);
/// The latest error: "file:line: message" plus a traceback for runtime errors.
const char *eng_script_error(const eng_script *s);
const char *eng_script_path(const eng_script *s);

eng_scene_config *eng_script_config(eng_script *s);
void eng_script_set_host(eng_script *s, const eng_script_host *host);

/// Applies the queued edits to the host's worlds, in order. Stops at the first refused
/// edit: ENG_SCRIPT_ERROR with "file:line: seiche.fn: reason" in eng_script_error (the
/// rest of the queue is dropped). Also stops kinematic bodies whose move_to target was
/// not renewed for the coming step. Call between steps, with the worlds in the host.
eng_script_status eng_script_apply(eng_script *s);
/// After each step: the forces and torques the script applied for it (body:apply_force,
/// body:apply_torque, held on their bodies through the step's Bullet steps) are released.
void eng_script_step_taken(eng_script *s);
/// Commands waiting for eng_script_apply.
int eng_script_pending(const eng_script *s);

/// Feeds the input the script injected (seiche.inject_*) since the last call to the
/// host's eng_input, as if it came from the window. Call at the start of every frame,
/// after eng_input_begin_frame, so the camera and the callbacks see it that frame: it also
/// starts the frame's time budget, and ends the load (from then on a script may inject a
/// reset or reload key).
void eng_script_deliver_input(eng_script *s);

/// Moves the scene nodes of the script's bodies to their bodies' poses (before drawing).
void eng_script_sync_nodes(eng_script *s);

/// Callbacks, looked up as raw globals (no __index metamethod of _G runs); a missing one is
/// not an error, a value that cannot be called is. A function or a table with a __call
/// metamethod is called. eng_script_on_step also fires the timers that are due at `time`.
eng_script_status eng_script_on_start(eng_script *s);
eng_script_status eng_script_on_step(eng_script *s, double dt, double time);
eng_script_status eng_script_on_key(eng_script *s, const char *key, const char *action, double x, double y);
/// `consumed` (may be NULL) is set when on_mouse returned true: the camera should leave
/// this press (until its release) alone.
eng_script_status eng_script_on_mouse(eng_script *s, int button, const char *action, double x, double y,
                                      bool *consumed);
eng_script_status eng_script_on_mouse_move(eng_script *s, double x, double y, double dx, double dy);
eng_script_status eng_script_on_scroll(eng_script *s, double dx, double dy);
eng_script_status eng_script_on_reload(eng_script *s);

/// True once the script called seiche.quit().
bool eng_script_quit_requested(const eng_script *s);

/// One place in the scripts that calls seiche.check, and what came of its calls.
#define ENG_SCRIPT_MAX_CHECK_SITES 128
typedef struct eng_check_site {
    char source[256];   ///< the chunk's file ("" for chunks that are not files)
    int line;           ///< line of the call
    uint32_t passed, failed;
    char message[256];  ///< the first failure's message
} eng_check_site;

/// The seiche.check call sites that ran, in the order first reached (at most
/// ENG_SCRIPT_MAX_CHECK_SITES; later new sites are not recorded).
int eng_script_check_sites(const eng_script *s, const eng_check_site **out);

/// seiche.text: what the script's HUD shows. The app draws the list over the frame (the
/// window's UI: Dear ImGui's foreground draw list); headless runs check the calls and draw
/// nothing. The list is cleared by eng_script_begin_frame.
#define ENG_SCRIPT_MAX_TEXTS 256     ///< texts one frame may show
#define ENG_SCRIPT_TEXT_BYTES 256    ///< the longest text, bytes (UTF-8)
typedef struct eng_script_text {
    float x, y;          ///< pixels of the window from its top-left corner (the text's top-left)
    float size;          ///< pixels, the font's height
    float colour[4];     ///< rgba, each in [0, 1]
    char text[ENG_SCRIPT_TEXT_BYTES + 1];
} eng_script_text;
/// The texts the frame's callbacks asked for, in call order.
int eng_script_texts(const eng_script *s, const eng_script_text **out);
/// A new frame whose simulation steps: forgets the previous frame's texts. (A paused frame
/// keeps them, so a HUD drawn from on_step stays while the scene is paused.)
void eng_script_begin_frame(eng_script *s);

/// Changes a fluid parameter as seiche.set_param would (the parameter panel uses it).
/// False with a message in err when the name or value is refused.
bool eng_script_set_param(eng_script *s, const char *name, double value, char *err, size_t err_size);

/// Every name the script API defines, NULL-terminated, for the docs test: functions of the
/// `seiche` table as "seiche.NAME", methods as "emitter:NAME", "sink:NAME", "body:NAME",
/// "timer:NAME", "grab:NAME", and the callbacks as "on_NAME".
const char *const *eng_script_api_names(void);
/// Only the functions registered in the `seiche` table (bare names), NULL-terminated.
const char *const *eng_script_function_names(void);

/// The name a script uses for a GLFW key code ("a", "space", "left", "f5"), or NULL.
const char *eng_key_name(int glfw_key);
/// The GLFW key code of a key name (the inverse of eng_key_name), or -1.
int eng_key_code(const char *name);

#endif
