// Private to engine/script: the eng_script struct, the handles a script holds (objects), the
// queued world edits (commands), and the prototypes of the helpers the files below share.
//
// The files of the Lua host (script.h is its public face, docs/lua-api.md its manual):
//   script.c          the Lua state, its time budget and memory limit (how they hold: the
//                     comment above budget_hook), protected calls with a traceback, loading
//                     the script, callbacks; registers every area
//   script_sandbox.c  the libraries a script gets: the sandbox's allow-list, or all with --trusted
//   script_strlib.c   string.find/match/gmatch/gsub/rep with a work counter (scr_tick)
//   script_tablib.c   table.concat/insert/remove/move/sort with a work counter
//   script_timers.c   timers: a heap by due time, fired after on_step
//   script_args.c     argument readers that name fn, field, value and rule (scr_opt_*, scr_req_*,
//                     scr_arg_*, scr_check_*), vectors, handles and their metamethods
//   script_apply.c    the queues: world edits (scr_push_command, eng_script_apply) and input
//   script_mesh.c     the meshes and scene nodes that draw the script's bodies
//   wrap_scene.c      seiche.scene, the look and the camera
//   wrap_fluid.c      fluid parameters, gravity, blocks, spheres and particle lists
//   wrap_emitter.c    emitters and sinks
//   wrap_body.c       bodies and grabs
//   wrap_joint.c      joints between bodies (hinge, slider, fixed, point)
//   wrap_events.c     on_contact and on_splash, and their thresholds
//   wrap_mesh.c       meshes from files: seiche.body{mesh = ...}'s fields, seiche.fill
//   wrap_interact.c   timers, keys and mouse, screen and ray queries, injected input
//   wrap_query.c      stats, time, counts, check and quit
//   wrap_measure.c    particle measurements: particle_data, region_stats, surface_height, particles_in
//   wrap_render.c     seiche.render: the renderer's look of the water
//
// Each wrap_*.c ends with its luaL_Reg tables and one scr_open_* that hands them to the core
// (scr_api); the bindings reach the eng_script as upvalue 1 (scr_get_script). Shared
// functions carry the scr_ prefix; file-local ones are static and unprefixed.
#ifndef ENG_SCRIPT_INTERNAL_H
#define ENG_SCRIPT_INTERNAL_H

#include "engine/render/mesh_file.h"
#include "engine/render/mesh_physics.h"
#include "engine/script/script.h"

#include <lauxlib.h>
#include <lua.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#define PI 3.14159265358979323846
/// Positions a script may give, m (far beyond any scene; keeps Bullet and the grid sane).
#define MAX_COORD 1.0e5
/// Speeds a script may give, m/s (and rad/s).
#define MAX_SPEED 1.0e4

// ---- objects -------------------------------------------------------------------------

typedef enum obj_kind { OBJ_EMITTER = 0, OBJ_SINK, OBJ_BODY, OBJ_TIMER, OBJ_GRAB, OBJ_JOINT, OBJ_KIND_COUNT } obj_kind;
extern const char *const scr_kind_name[OBJ_KIND_COUNT];   // "emitter", "sink", "body", "timer", "grab", "joint"
extern const char *const scr_kind_meta[OBJ_KIND_COUNT];   // metatable names: "seiche.emitter", ...

typedef enum obj_state {
    OBJ_FREE = 0, // slot unused
    OBJ_PENDING,  // created by the script, its creation still queued
    OBJ_LIVE,     // exists in the world
} obj_state;

typedef enum body_shape {
    SHAPE_BOX = 0, SHAPE_SPHERE, SHAPE_CAPSULE, SHAPE_CYLINDER, SHAPE_PLANE, SHAPE_HULL, SHAPE_MESH, SHAPE_COMPOUND,
    SHAPE_COUNT
} body_shape;
extern const char *const scr_shape_name[SHAPE_COUNT];     // "box", "sphere", ...

// One part of a compound body, in the frame the script gave the parts in.
typedef struct body_part {
    body_shape shape;       // box, sphere, capsule or cylinder
    float dims[4];          // as body_rec.dims
    float pos[3];           // m
    float rot[4];           // unit quaternion x, y, z, w
} body_part;

/// Steps of velocity a body remembers for on_splash (the fluid's measurement is a step late).
#define SCR_VELOCITY_HISTORY 8

// The most parts a compound may have: each is a fluid collider, and the fluid has 64.
#define MAX_BODY_PARTS 64
extern const char *const scr_body_kind_name[3];           // "static", "kinematic", "dynamic" = phys_body_type

typedef struct body_rec {
    body_shape shape;
    float dims[4];          // box: half extents; sphere: r; capsule/cylinder: r, half height; plane: n, offset
    float *points;          // hull points / mesh vertices, xyz, m (owned)
    uint32_t point_count;
    uint32_t *indices;      // mesh, 0-based (owned)
    uint32_t index_count;
    body_part *parts;       // compound (owned)
    uint32_t part_count;
    eng_mesh_data *file;    // a mesh from a file (owned; hull or mesh shape), or NULL
    uint32_t hull_points;   // a dynamic file mesh's hull: the most points
    bool has_factors;       // linear_factor / angular_factor / axle given
    float linear_factor[3], angular_factor[3];
    phys_body_def def;      // everything but the shape
    bool two_way;
    bool measure_force;     // the water's force is measured though it is not applied (static, one-way)
    float color[3];
    bool visible;
    phys_body_id id;
    phys_shape_id shape_id;
    eng_node_id node;
    eng_mesh_id mesh;
    bool target_mode;       // moving towards a move_to target
    uint64_t target_step;   // the step (frame + 1) the target was set for
    // on_splash (wrap_events.c): the latest fluid measurement looked at, how many measured
    // steps in a row the body was not wet, and its velocity at the start of recent steps.
    bool splash_seen;
    uint64_t splash_step;
    uint32_t dry_steps;
    float step_velocity[SCR_VELOCITY_HISTORY][3];
    uint64_t step_index[SCR_VELOCITY_HISTORY]; // the step + 1 whose start step_velocity holds (0: none)
    // apply_force / apply_torque for the coming step (script_apply.c): force then torque about the
    // centre of mass, held on the body through the step's Bullet steps, released after it.
    float held[6];
    bool held_on;
} body_rec;

// A joint between two bodies (wrap_joint.c): what the script asked for, world frame at
// creation. Body b is the world when b_slot is NO_SLOT.
#define NO_SLOT UINT32_MAX
extern const char *const scr_joint_kind_name[5];          // by phys_joint_type: "", "hinge", "slider", "fixed", "point"
typedef struct joint_rec {
    phys_joint_type type;
    uint32_t a_slot, a_gen, b_slot, b_gen;
    float pivot[3];         // hinge and point: pivot; slider: anchor (m)
    float axis[3];          // hinge and slider: unit axis
    bool collide;           // the two bodies collide with each other
    bool limit;
    float lo, hi;           // rad (hinge) or m (slider)
    bool motor;
    float speed, max;       // rad/s or m/s; N m or N
    phys_joint_id id;
} joint_rec;

/// Pivot positions a grab remembers, for the throw when it is released (wrap_body.c).
#define GRAB_PATH 32

typedef struct obj {
    obj_kind kind;
    obj_state state;
    uint32_t generation;
    int ref;                // registry reference to the userdata (LUA_NOREF: none yet)
    union {
        struct { pbf_emitter_def def; pbf_emitter_id id; bool full_rate, tinted; float tint[3]; } emitter;
        struct { float min[3], max[3]; pbf_sink_id id; } sink;
        body_rec body;
        struct { double due, period; int fn; } timer;
        struct {
            uint32_t body, body_gen;
            phys_constraint_id id;
            float pivot[3];
            float max_force;
            double path[GRAB_PATH][4]; // the pivot's latest moves: time (s, simulated) and where (m)
            uint32_t path_count;       // moves recorded (the latest GRAB_PATH are kept)
        } grab;
        joint_rec joint;
    } u;
} obj;

typedef struct handle {
    uint32_t slot;
    uint32_t generation;
} handle;

// ---- commands ------------------------------------------------------------------------

typedef enum cmd_type {
    CMD_BLOCK = 1, CMD_SPHERE, CMD_PARTICLES,
    CMD_EMITTER_ADD, CMD_EMITTER_SET, CMD_EMITTER_REMOVE,
    CMD_SINK_ADD, CMD_SINK_REMOVE,
    CMD_BODY_ADD, CMD_BODY_REMOVE, CMD_BODY_IMPULSE, CMD_BODY_ANGULAR_IMPULSE, CMD_BODY_FORCE, CMD_BODY_TORQUE,
    CMD_BODY_VELOCITY,
    CMD_BODY_ANGULAR_VELOCITY, CMD_BODY_MOVE_TO, CMD_BODY_TELEPORT, CMD_BODY_LOOK,
    CMD_GRAB_ADD, CMD_GRAB_MOVE, CMD_GRAB_REMOVE,
    CMD_JOINT_ADD, CMD_JOINT_MOTOR, CMD_JOINT_LIMITS, CMD_JOINT_REMOVE,
    CMD_PARAMS, CMD_GRAVITY, CMD_CAMERA,
    CMD_FILL, CMD_TINT,
} cmd_type;

typedef struct command {
    cmd_type type;
    char where[160];        // "file:line:" of the call
    const char *fn;         // "seiche.block", "body:move_to", ...
    uint32_t slot, gen;     // the object it concerns, if any
    bool full_rate;         // emitters: pour the most the nozzle can (no rate given)
    bool tinted;            // emitters and CMD_TINT: `tint` (else the height parameter)
    float tint[3];
    union {
        pbf_block_def block;    // CMD_BLOCK; CMD_TINT: its box
        struct { float center[3], radius, velocity[3]; } sphere;
        struct { float *pos, *vel; uint32_t n; } particles;
        struct { eng_mesh_data *mesh; float pos[3], rot[4], vel[3], clearance; } fill; // mesh owned
        pbf_emitter_def emitter;
        pbf_emitter_id emitter_id;
        pbf_sink_id sink_id;
        struct { phys_body_id id; phys_shape_id shape; eng_node_id node; eng_mesh_id mesh; } body;
        struct { phys_constraint_id id; uint32_t body, body_gen; bool thrown; float velocity[3]; } release;
        struct { float v[3], p[3]; bool at_point; } vec;
        struct { float pos[3], rot[4]; } pose;
        struct { float color[3]; bool visible; } look;
        phys_constraint_id constraint;
        struct { phys_joint_id id; bool on; float a, b; } joint; // motor: speed, max; limits: lo, hi
        pbf_params params;
        float gravity[3];
        struct { float eye[3], target[3], fov; int mode; bool has_eye, has_target, has_fov, has_mode; } camera;
    } u;
} command;

/// The most memory a script may hold: its Lua state and what the C side keeps for it (queued
/// edits, handles, bodies' shapes, timers).
#define SCR_MEMORY_LIMIT ((size_t)512 << 20)
/// The largest script or module file, bytes.
#define SCR_MAX_SCRIPT_BYTES ((long long)64 << 20)
/// The most timer calls one frame may make.
#define SCR_MAX_TIMER_CALLS 100000
/// Coroutines resumed inside one another that the budget keeps track of.
#define SCR_MAX_THREADS 32
#define SCR_BIG_STRING ((size_t)64 << 10)  // bytes: a string this long counts in hook_interval
#define SCR_MAX_BIG_STRINGS 256

/// Why the running call is being stopped (scr_stop): a stop cannot be caught by pcall.
typedef enum scr_stop_kind { STOP_NONE = 0, STOP_BUDGET, STOP_MEMORY, STOP_CHECK } scr_stop_kind;

typedef struct timer_entry {
    double due;             // s, simulated
    uint32_t slot, gen;     // the timer; stale once its slot was released or reused
} timer_entry;

/// A body pair that reported a hit (on_contact), by Bullet ids.
typedef struct scr_hit_pair {
    phys_body_id a, b;
} scr_hit_pair;

struct eng_script {
    lua_State *L;
    eng_logger log;
    bool trusted;           // --trusted: every standard library
    bool closing;           // eng_script_destroy is closing the Lua state: the API refuses
    bool loaded;            // the load (main chunk, on_start, on_reload) is over: a frame began
    double budget_s;        // for the main chunk with on_start and on_reload, and for each frame
    double frame_used;      // s of the budget used by this frame's (or the load's) calls so far
    double deadline;        // monotonic seconds; 0 when no call runs
    const char *running;    // name of the running callback, for messages
    size_t memory;          // bytes held by the Lua state
    size_t c_memory;        // bytes the C side holds for the script (counted with `memory`)
    bool out_of_memory;     // the allocator refused a block
    size_t ticks;           // work units since the clock was last read (scr_tick)
    size_t allocated;       // bytes allocated since the clock was last read
    // Live strings of at least SCR_BIG_STRING bytes (script.c, hook_interval): one instruction can
    // walk a whole string (comparing two: strcoll once per NUL byte), so the longer the longest,
    // the more often the hook looks at the clock. big_untracked counts those that did not fit.
    struct { const void *at; size_t size; } big_strings[SCR_MAX_BIG_STRINGS];
    int big_string_count, big_untracked;
    lua_State *threads[SCR_MAX_THREADS]; // the coroutines resumed now, innermost last (script_sandbox.c)
    int thread_depth;       // how many (may pass SCR_MAX_THREADS: those are not kept)
    scr_stop_kind stop_kind;
    char stop[1024];        // the stop's message, raised again at every instruction
    timer_entry *timers;    // a binary heap by (due, slot)
    uint32_t timer_count, timer_cap;
    char path[512];
    char error[8192];
    bool quit;
    eng_check_site checks[ENG_SCRIPT_MAX_CHECK_SITES]; // seiche.check call sites (junit, tap)
    int check_count;
    bool scene_called;
    bool in_main_chunk;
    eng_scene_config config;
    eng_scene_config config_view; // config with the host's overrides (scr_config_view)
    command *commands;
    int command_count, command_cap;
    obj *objs;
    uint32_t obj_count, obj_cap;
    eng_script_host host;
    pbf_params pending_params;   // the parameters after the queued set_param calls
    bool have_pending_params;
    float pending_gravity[3];
    bool have_pending_gravity;
    bool capacity_warned;
    eng_event *events;           // injected input, handed to the app's input next frame
    int event_count, event_cap;
    // on_contact and on_splash (wrap_events.c).
    double contact_threshold;    // N s: a pair's impulse in a frame above it is a hit
    double splash_speed;         // m/s: the least downward speed of a splash
    phys_contact *contacts;      // the frame's contact sums (SCR_MAX_CONTACTS)
    scr_hit_pair *hits;          // pairs that hit and have not dropped to half the threshold since
    uint32_t hit_count, hit_cap;
    // The particle download shared by the queries of one frame (wrap_measure.c): positions
    // (3 cache_cap floats), velocities (3 cache_cap), densities (cache_cap).
    float *cache;
    uint32_t cache_count, cache_cap;
    uint64_t cache_frame;
    bool cache_valid;
    // seiche.text (wrap_look.c): what the HUD shows this frame (ENG_SCRIPT_MAX_TEXTS at most).
    eng_script_text *texts;
    int text_count;
    // "file:line: " of the instruction the budget hook last ran at (script.c): where a memory
    // error that Lua raises itself (no message handler runs for it) happened.
    char hook_where[320];
    // warn() and the state's own warnings (an error in a trusted script's finaliser): the
    // pieces of the message being built (script.c, script_warn), and "@off" / "@on".
    char warning[1024];
    size_t warning_len;
    bool warnings_off;
};

// ---- registration (script.c) -----------------------------------------------------------

/// The most API areas (wrap_*.c files).
#define SCR_MAX_AREAS 16

/// What the API areas bind, as their scr_open_* functions declare it: the core registers it
/// in the Lua state and lists its names for the docs test (eng_script_api_names).
typedef struct scr_api {
    const luaL_Reg *functions[SCR_MAX_AREAS]; ///< each area's seiche.* functions, in registration order
    int area_count;
    const luaL_Reg *methods[OBJ_KIND_COUNT];  ///< each handle kind's methods, from the area that owns it
} scr_api;

void scr_api_functions(scr_api *api, const luaL_Reg *functions);
void scr_api_methods(scr_api *api, obj_kind kind, const luaL_Reg *methods);

void scr_open_scene(scr_api *api);    // wrap_scene.c
void scr_open_fluid(scr_api *api);    // wrap_fluid.c
void scr_open_emitter(scr_api *api);  // wrap_emitter.c
void scr_open_body(scr_api *api);     // wrap_body.c
void scr_open_interact(scr_api *api); // wrap_interact.c
void scr_open_render(scr_api *api);   // wrap_render.c
void scr_open_query(scr_api *api);    // wrap_query.c
void scr_open_measure(scr_api *api);  // wrap_measure.c
void scr_open_joint(scr_api *api);    // wrap_joint.c
void scr_open_events(scr_api *api);   // wrap_events.c
void scr_open_mesh(scr_api *api);     // wrap_mesh.c
void scr_open_look(scr_api *api);     // wrap_look.c

// ---- callbacks (script.c) ------------------------------------------------------------------

/// The most arguments a callback gets.
#define SCR_MAX_CALLBACK_ARGS 6
/// One argument of a callback: 'n' a number, 'i' an integer (both in `number`), 's' a string,
/// 'h' the handle of object `slot` (nil when NO_SLOT; the slot must hold a live object), 'v'
/// the vector `vec` (a table as scr_push_vec3 makes).
typedef struct scr_arg {
    char type;
    double number;
    const char *string;
    uint32_t slot;
    double vec[3];
} scr_arg;
/// Calls the global callback `name` with `nargs` arguments as the runner's callbacks are
/// called (looked up raw; nothing when undefined), protected, under the frame's budget.
eng_script_status scr_callback(eng_script *s, const char *name, int nargs, const scr_arg *args);

// ---- limits (script.c) --------------------------------------------------------------------

/// Counts `units` of work done in C (a step of pattern matching, an element moved): every
/// 2^16 units the clock and the memory are looked at and the call stops when over.
void scr_tick(lua_State *L, eng_script *s, size_t units);
/// Looks at the clock and the memory now (as the hook does): raises when the call is over its
/// budget. For a C function about to start work that takes the budget left as its time limit.
void scr_check_now(lua_State *L, eng_script *s);
/// Stops the running call: raises "file:line: message" now and again at every Lua
/// instruction and every scr_tick until the host's protected call returns, so no pcall
/// in the script can swallow it.
int scr_stop(lua_State *L, eng_script *s, scr_stop_kind kind, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
/// Bytes the script may still allocate under SCR_MEMORY_LIMIT.
size_t scr_memory_room(const eng_script *s);
/// Counts `bytes` the C side keeps for the script against its memory limit; raises naming
/// fn when they do not fit. scr_uncharge gives them back.
void scr_charge(lua_State *L, eng_script *s, const char *fn, size_t bytes);
void scr_uncharge(eng_script *s, size_t bytes);

// ---- libraries (script_sandbox.c, script_strlib.c, script_tablib.c) ---------------------------

/// The libraries of a script (the sandbox, or all of them when trusted); in both, the bounded
/// string, utf8 and table functions and coroutine.resume/wrap that keep s->threads.
void scr_open_libraries(lua_State *L, bool trusted);
void scr_open_bounded_string(lua_State *L);
void scr_open_bounded_table(lua_State *L);
/// The path of a file the scene names (a mesh), into `out`: `rel` relative to the folder of the
/// file whose code is running. In the sandbox `rel` may not be absolute or pass through '..',
/// and the file must be a regular file of at most 64 MiB whose real path (links followed) lies
/// in the scene's folder or below, as for require; --trusted takes any file. NULL when found,
/// else why not ("missing", "outside the scene's folder (a link?)", ...).
const char *scr_scene_file(lua_State *L, const eng_script *s, const char *rel, char *out, size_t size);

// ---- timers (script_timers.c) ------------------------------------------------------------------

/// Makes room in the heap for one more firing (raises when the memory limit says no), so
/// that scr_timer_schedule cannot fail.
void scr_timer_reserve(lua_State *L, eng_script *s);
/// Adds the timer's next firing (its `due`) to the heap.
void scr_timer_schedule(eng_script *s, uint32_t slot);
/// Fires the timers due at `time`, earliest first, each through `call` (a protected call).
eng_script_status scr_fire_timers(eng_script *s, double time,
                                  eng_script_status (*call)(eng_script *s, int fn_ref, double time));

// ---- arguments (script_args.c) -----------------------------------------------------------

enum { OPEN_LO = 1, OPEN_HI = 2, WHOLE = 4 };

/// The script of a binding (its upvalue 1); raises while the script is closing (a finaliser
/// that runs in lua_close cannot use the API).
eng_script *scr_get_script(lua_State *L);
/// The script of any function, from the Lua state's extra space.
static inline eng_script *scr_state_script(lua_State *L) { return *(eng_script **)lua_getextraspace(L); }
/// "file:line:" of the innermost Lua function running (the caller of a binding, also when
/// pcall stands between), or "" when none runs.
const char *scr_where(lua_State *L, char *buf, size_t size);
// Raises a Lua error with the caller's file:line, formatted by printf rules (luaL_error's
// own formatter knows no %g).
int scr_raise(lua_State *L, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;
const char *scr_describe(lua_State *L, int idx, char *buf, size_t size);
// #t of the table at idx (its __len may run): a length that is not a whole number raises,
// naming fn and what ("field 'positions'").
lua_Integer scr_len(lua_State *L, int idx, const char *fn, const char *what);
/// A number as messages write it: whole numbers in full ("1000000000"), others in %g style.
const char *scr_fmt_number(double v, char *buf, size_t size);
/// The number messages give argument `idx` of `fn`: a method ("body:grab") does not count self.
int scr_arg_position(const char *fn, int idx);
double scr_check_number_at(lua_State *L, int idx, const char *fn, const char *what, double lo, double hi, int flags,
                           const char *unit);
bool scr_field_present(lua_State *L, int t, const char *field);
bool scr_opt_number(lua_State *L, int t, const char *fn, const char *field, double lo, double hi, int flags,
                    const char *unit, double *out);
double scr_req_number(lua_State *L, int t, const char *fn, const char *field, double lo, double hi, int flags,
                      const char *unit);
double scr_arg_number(lua_State *L, int idx, const char *fn, const char *name, double lo, double hi, int flags,
                      const char *unit);
void scr_check_vec_at(lua_State *L, int idx, const char *fn, const char *what, int n, double lo, double hi, int flags,
                      const char *unit, float *out);
bool scr_opt_vec(lua_State *L, int t, const char *fn, const char *field, int n, double lo, double hi, int flags,
                 const char *unit, float *out);
bool scr_opt_position(lua_State *L, int t, const char *fn, const char *field, float out[3]);
void scr_req_position(lua_State *L, int t, const char *fn, const char *field, float out[3]);
void scr_arg_vec(lua_State *L, int idx, const char *fn, const char *name, double lo, double hi, const char *unit,
                 float out[3]);
bool scr_opt_bool(lua_State *L, int t, const char *fn, const char *field, bool *out);
bool scr_opt_color(lua_State *L, int t, const char *fn, const char *field, float out[3]);
/// "colour" or "color" (both spellings name one field), whichever table t gives, or NULL;
/// raises when it gives both.
const char *scr_colour_field(lua_State *L, int t, const char *fn);
bool scr_opt_tint(lua_State *L, int t, const char *fn, const char *field, bool *tinted, float rgb[3]);
int scr_opt_enum(lua_State *L, int t, const char *fn, const char *field, const char *const *names, int n);
void scr_check_table_arg(lua_State *L, int idx, const char *fn, const char *fields);
void scr_check_table_field(lua_State *L, int idx, const char *fn, const char *field, const char *fields);
void scr_check_fields(lua_State *L, int t, const char *fn, const char *const *known);
bool scr_opt_rotation(lua_State *L, int t, const char *fn, const char *field, float q[4]);
void scr_read_box(lua_State *L, int t, const char *fn, float mn[3], float mx[3]);
float *scr_read_point_list(lua_State *L, int t, const char *fn, const char *field, double lo, double hi,
                           const char *unit, uint32_t *n_out, uint32_t min_n, uint32_t max_n);

/// A C API message (pbf_, cpl_, phys_) in the script's words: no leading C function name, struct
/// fields as Lua fields ("pbf_emitter_def.radius" -> "field 'radius'"). Returns out.
const char *scr_lua_wording(const char *msg, char *out, size_t size);

void scr_quat_mul(const float a[4], const float b[4], float out[4]);
void scr_quat_rotate(const float q[4], const float v[3], float out[3]);
static inline phys_vec3 scr_pv(const float v[3]) { return (phys_vec3){ v[0], v[1], v[2] }; }
static inline phys_quat scr_pq(const float q[4]) { return (phys_quat){ q[0], q[1], q[2], q[3] }; }
void scr_push_vec3(lua_State *L, double x, double y, double z);
void scr_push_quat(lua_State *L, const float q[4]);
void scr_set_num(lua_State *L, const char *k, double v);
/// A count or other whole number: a Lua integer (2, not 2.0).
void scr_set_int(lua_State *L, const char *k, lua_Integer v);
/// Pushes v as an integer when `whole` (an integer-valued setting), else as a float.
void scr_push_value(lua_State *L, double v, bool whole);

obj *scr_obj_at(eng_script *s, uint32_t slot, uint32_t gen);
uint32_t scr_obj_new(lua_State *L, eng_script *s, obj_kind kind);
/// The bytes of a body's shape data (points, indices, parts), as charged to the script.
size_t scr_body_data_bytes(const body_rec *b);
void scr_body_free_data(eng_script *s, body_rec *b);
void scr_obj_release(eng_script *s, uint32_t slot);
void scr_push_handle(lua_State *L, eng_script *s, uint32_t slot);
// The method's object (argument 1), checked live and of `kind`. SCR_SELF_AGAIN: the pointer is
// into s->objs, which scr_obj_new reallocates, and reading an argument can run Lua (a table's
// __index or __len calling seiche.after, a sink, ...), which may make or remove objects: a method
// that reads arguments after this looks its object up again (call this again) before it uses it.
obj *scr_check_self(lua_State *L, obj_kind kind, const char *fn, uint32_t *slot_out);
int scr_is_valid(lua_State *L);
/// Makes the metatable of a handle kind: its methods (upvalue s) and the shared metamethods.
void scr_new_handle_type(lua_State *L, eng_script *s, obj_kind kind, const luaL_Reg *methods);

const pbf_params *scr_current_params(eng_script *s);
const eng_scene_config *scr_config_view(eng_script *s);
void scr_require_world(lua_State *L, eng_script *s, const char *fn);
uint32_t scr_capacity_of(eng_script *s);

// ---- commands and queues (script_apply.c) -----------------------------------------------------

command *scr_push_command(lua_State *L, eng_script *s, cmd_type type, const char *fn);
void scr_clear_commands(eng_script *s);
/// An applied edit the world refused: "file:line: fn: message" into s->error; ENG_SCRIPT_ERROR.
eng_script_status scr_refuse(eng_script *s, const command *c, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/// Whether point p lies inside the world's domain; else "WHAT.x must be in [a, b] m, inside the
/// domain (got v)" into msg. scr_points_domain_check: each of n points, named "field 'FIELD'[i]"
/// with Lua's 1-based i.
bool scr_domain_check(const eng_script *s, const float p[3], const char *what, char *msg, size_t size);
bool scr_points_domain_check(const eng_script *s, const float *points, uint32_t n, const char *field, char *msg,
                             size_t size);

// ---- events (wrap_events.c) ------------------------------------------------------------------

/// The default of seiche.set_contact_threshold, N s, and of seiche.set_splash_threshold, m/s.
#define SCR_DEFAULT_CONTACT_THRESHOLD 0.2
#define SCR_DEFAULT_SPLASH_SPEED 0.5
/// Body pairs one frame's contacts can hold: every pair of 64 bodies and the container's walls.
#define SCR_MAX_CONTACTS 4096
/// Calls on_contact and on_splash for what the step just taken did (after the step, before
/// on_step), and notes the bodies' velocities for the next.
eng_script_status scr_fire_events(eng_script *s);

// ---- meshes from files (wrap_mesh.c) ----------------------------------------------------------

/// A mesh file a call names, found but not read yet.
typedef struct scr_mesh_request {
    char path[1200];                 // where it was found
    char name[256];                  // as the script wrote it, for messages
    eng_mesh_file_options options;   // scale, centre; in the sandbox the root and the time left
    char root[512];                  // the scene's folder: what the file (and what it names) may read
    uint32_t hull_points;            // for a dynamic body's hull
    bool has_hull_points;            // given
} scr_mesh_request;
/// Reads the fields mesh, scale, centre and hull_points (when allowed) of table t and finds the
/// file (raising, naming the field, when it is refused or missing). False when there is no
/// 'mesh' (and then none of the others may be given).
bool scr_read_mesh_fields(lua_State *L, eng_script *s, int t, const char *fn, bool hull_points_allowed,
                          scr_mesh_request *out);
/// The scene's folder (that of the script the runner loaded), as scene files are found from it.
void scr_scene_root(const eng_script *s, char *out, size_t size);
/// Seconds left of the running call's budget (0 when none runs).
double scr_budget_left(const eng_script *s);
/// Reads the file into a new mesh (*out, free with scr_free_mesh); false with a message in err.
bool scr_load_mesh(const scr_mesh_request *r, eng_mesh_data **out, char *err, size_t size);
/// The bytes a loaded mesh holds (charged to the script), 0 for NULL.
size_t scr_mesh_bytes(const eng_mesh_data *m);
void scr_free_mesh(eng_mesh_data *m);
/// Applies a CMD_FILL edit.
eng_script_status scr_apply_fill(eng_script *s, const command *c);

// ---- joints (wrap_joint.c) ------------------------------------------------------------------

/// Applies a CMD_JOINT_* edit.
eng_script_status scr_apply_joint(eng_script *s, const command *c);
/// Releases the handles of the joints that hold body `slot` (Bullet destroys the joints
/// with the body).
void scr_release_joints_of(eng_script *s, uint32_t slot, uint32_t gen);

// ---- bodies (wrap_body.c, script_mesh.c) --------------------------------------------------------

void scr_body_state(eng_script *s, obj *o, float pos[3], float rot[4], float vel[3], float ang[3]);
eng_mesh_id scr_body_mesh(eng_script *s, body_rec *b);
void scr_body_transform(const body_rec *b, const float pos[3], const float rot[4], eng_transform *t);

#endif
