// The Lua 5.4 host: runs a scene script, exposes the `seiche` table (docs/lua-api.md),
// queues world edits made by the script and applies them between steps, and calls the
// script's callbacks (on_start, on_step, on_key, on_mouse, on_reload) under a time budget.
#ifndef ENG_SCRIPT_H
#define ENG_SCRIPT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "engine/log.h"
#include "fluid/pbf.h"

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
} eng_scene_config;

eng_scene_config eng_default_scene_config(void);

/// A world edit queued by the script, applied between steps. `where` is "file:line:".
typedef enum eng_command_type {
    ENG_CMD_BLOCK = 1,
} eng_command_type;

typedef struct eng_command {
    eng_command_type type;
    char where[192];
    pbf_block_def block;
} eng_command;

/// What the script may ask of the running engine (filled in by the app each frame).
typedef struct eng_script_host {
    pbf_world *world;           ///< NULL until the world exists
    const pbf_step_stats *stats;///< latest completed step statistics, NULL before the first
    uint64_t frame;
    double time;                ///< s, simulated
    double dt;                  ///< s, frame step
    const char *renderer;       ///< GL renderer string
    bool headless;
} eng_script_host;

typedef enum eng_script_status {
    ENG_SCRIPT_OK = 0,
    ENG_SCRIPT_CHECK_FAILED,  ///< seiche.check failed (exit status 1)
    ENG_SCRIPT_ERROR,         ///< syntax or runtime error (exit status 2)
} eng_script_status;

typedef struct eng_script eng_script;

/// `budget_s`: the longest a callback (or the script's main chunk) may run before it is
/// stopped with an error (an endless loop), in seconds.
eng_script *eng_script_create(const eng_logger *log, double budget_s);
void eng_script_destroy(eng_script *s);

/// Loads and runs the file's main chunk (which describes the scene). On error the message
/// holds file:line and a traceback: see eng_script_error.
eng_script_status eng_script_load(eng_script *s, const char *path);
const char *eng_script_error(const eng_script *s);
const char *eng_script_path(const eng_script *s);

eng_scene_config *eng_script_config(eng_script *s);
void eng_script_set_host(eng_script *s, const eng_script_host *host);

/// The queued commands; the app applies them and then clears the queue.
int eng_script_commands(eng_script *s, const eng_command **out);
void eng_script_clear_commands(eng_script *s);

/// Callbacks; a missing one is not an error.
eng_script_status eng_script_on_start(eng_script *s);
eng_script_status eng_script_on_step(eng_script *s, double dt, double time);
eng_script_status eng_script_on_key(eng_script *s, const char *key, const char *action);
eng_script_status eng_script_on_mouse(eng_script *s, int button, const char *action, double x, double y);
eng_script_status eng_script_on_reload(eng_script *s);

/// True once the script called seiche.quit().
bool eng_script_quit_requested(const eng_script *s);

/// Every function registered in the `seiche` table, NULL-terminated (for the docs test).
const char *const *eng_script_function_names(void);

/// The name a script uses for a GLFW key code ("a", "space", "left", "f5"), or NULL.
const char *eng_key_name(int glfw_key);

#endif
