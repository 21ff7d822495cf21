// Lua host for scene scripts. See script.h and docs/lua-api.md; the files of the host are
// listed in script_internal.h.
//
// Layout of this file:
//   bindings     seiche.* functions and the methods of each handle type
//   running      pcall with a traceback handler, the time budget hook, a memory limit
//   callbacks    on_start, on_step (+ timers), input callbacks, on_reload
#include "engine/script/script_internal.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <lualib.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/// The most memory a script's Lua state may hold.
#define LUA_MEMORY_LIMIT ((size_t)512 << 20)

static const char *const REGISTRY_KEY = "seiche.script";

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + (double)t.tv_nsec * 1e-9;
}

eng_look eng_default_look(void)
{
    eng_look k;
    memset(&k, 0, sizeof k);
    eng_renderer_def rd = eng_default_renderer_def();
    memcpy(k.sky, rd.sky_color, sizeof k.sky);
    k.light = rd.light;
    k.water = eng_default_particle_style();
    k.ground = true;
    k.ground_height = 0.0f;
    k.container = true;
    k.panel = true;
    return k;
}

eng_scene_config eng_default_scene_config(void)
{
    eng_scene_config c;
    memset(&c, 0, sizeof c);
    snprintf(c.name, sizeof c.name, "scene");
    c.params = pbf_default_params();
    c.capacity = 65536;
    c.camera_eye[0] = 2.0f;
    c.camera_eye[1] = 1.5f;
    c.camera_eye[2] = 3.0f;
    c.camera_fov = 50.0f;
    c.camera_mode = ENG_CAMERA_ORBIT;
    c.look = eng_default_look();
    return c;
}

// The script for the budget hook, which has no upvalues (bindings use scr_get_script).
static eng_script *registry_script(lua_State *L)
{
    lua_getfield(L, LUA_REGISTRYINDEX, REGISTRY_KEY);
    eng_script *s = lua_touserdata(L, -1);
    lua_pop(L, 1);
    return s;
}

// ---- seiche.scene and the look -------------------------------------------------------------

static void read_fluid(lua_State *L, int t, pbf_params *p)
{
    int n;
    const pbf_param_info *tab = pbf_param_table(&n);
    const char *known[40];
    int k = 0;
    for (int i = 0; i < n && k < 38; i++) known[k++] = tab[i].name;
    known[k] = NULL;
    scr_check_fields(L, t, "seiche.scene: fluid", known);
    for (int i = 0; i < n; i++) {
        double v;
        if (!scr_opt_number(L, t, "seiche.scene: fluid", tab[i].name, -1e30, 1e30, 0, tab[i].unit, &v)) continue;
        char err[512];
        if (pbf_params_set(p, tab[i].name, v, err, sizeof err) != PBF_OK) scr_raise(L, "seiche.scene: fluid.%s: %s", tab[i].name, err);
    }
}

static const char *const CAMERA_MODES[2] = { "orbit", "fly" };

// camera = {eye, target, fov, mode}: fills what is given; `has` bits: 1 eye, 2 target,
// 4 fov, 8 mode.
static int read_camera(lua_State *L, int t, const char *fn, float eye[3], float target[3], float *fov, int *mode)
{
    static const char *const known[] = { "eye", "target", "fov", "mode", NULL };
    scr_check_fields(L, t, fn, known);
    int has = 0;
    if (scr_opt_position(L, t, fn, "eye", eye)) has |= 1;
    if (scr_opt_position(L, t, fn, "target", target)) has |= 2;
    double f;
    if (scr_opt_number(L, t, fn, "fov", 1, 170, 0, "degrees", &f)) {
        *fov = (float)f;
        has |= 4;
    }
    int m = scr_opt_enum(L, t, fn, "mode", CAMERA_MODES, 2);
    if (m >= 0) {
        *mode = m;
        has |= 8;
    }
    return has;
}

static void read_look(lua_State *L, int t, const char *fn, eng_look *k)
{
    static const char *const known[] = { "sky", "light", "water", "ground", "ground_height", "container", "panel", NULL };
    scr_check_fields(L, t, fn, known);
    scr_opt_color(L, t, fn, "sky", k->sky);
    char sub[96];
    if (scr_field_present(L, t, "light")) {
        int l = lua_gettop(L);
        snprintf(sub, sizeof sub, "%s: light", fn);
        scr_check_table_field(L, l, fn, "light", "direction, color, ambient");
        static const char *const lk[] = { "direction", "color", "ambient", NULL };
        scr_check_fields(L, l, sub, lk);
        float d[3];
        if (scr_opt_vec(L, l, sub, "direction", 3, -1e6, 1e6, 0, "", d)) {
            if (!(fabsf(d[0]) + fabsf(d[1]) + fabsf(d[2]) > 0.0f))
                scr_raise(L, "%s: field 'direction' must not be zero (it points from the scene towards the light)", sub);
            memcpy(k->light.direction, d, sizeof d);
        }
        scr_opt_vec(L, l, sub, "color", 3, 0.0, 4.0, 0, "", k->light.color);
        scr_opt_color(L, l, sub, "ambient", k->light.ambient);
        lua_pop(L, 1);
    }
    if (scr_field_present(L, t, "water")) {
        int w = lua_gettop(L);
        snprintf(sub, sizeof sub, "%s: water", fn);
        scr_check_table_field(L, w, fn, "water", "low, mid, high, specular, shininess");
        static const char *const wk[] = { "low", "mid", "high", "specular", "shininess", NULL };
        scr_check_fields(L, w, sub, wk);
        scr_opt_color(L, w, sub, "low", k->water.color_low);
        scr_opt_color(L, w, sub, "mid", k->water.color_mid);
        scr_opt_color(L, w, sub, "high", k->water.color_high);
        double v;
        if (scr_opt_number(L, w, sub, "specular", 0, 1, 0, "", &v)) k->water.specular = (float)v;
        if (scr_opt_number(L, w, sub, "shininess", 1, 1024, 0, "", &v)) k->water.shininess = (float)v;
        lua_pop(L, 1);
    }
    scr_opt_bool(L, t, fn, "ground", &k->ground);
    double gh;
    if (scr_opt_number(L, t, fn, "ground_height", -MAX_COORD, MAX_COORD, 0, "m", &gh)) k->ground_height = (float)gh;
    scr_opt_bool(L, t, fn, "container", &k->container);
    scr_opt_bool(L, t, fn, "panel", &k->panel);
}

static int l_scene(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    scr_check_table_arg(L, 1, "seiche.scene", "name, preset, fluid, gravity, capacity, container, domain, camera, look");
    if (s->host.world || !s->in_main_chunk)
        scr_raise(L, "seiche.scene: the scene is described once, in the script's main chunk (not inside a callback)");
    if (s->scene_called) scr_raise(L, "seiche.scene: called twice (the first call was at %s)", s->config.scene_where);
    static const char *const known[] = { "name", "preset", "fluid", "gravity", "capacity", "container", "domain", "camera",
                                         "look", NULL };
    scr_check_fields(L, 1, "seiche.scene", known);
    eng_scene_config *c = &s->config;
    static const char *const presets[] = { "default", "seed" };
    int preset = scr_opt_enum(L, 1, "seiche.scene", "preset", presets, 2);
    if (preset == 0) c->params = pbf_default_params();
    if (preset == 1) c->params = pbf_seed_params();
    if (scr_field_present(L, 1, "name")) {
        char got[64];
        if (lua_type(L, -1) != LUA_TSTRING || lua_rawlen(L, -1) == 0 || lua_rawlen(L, -1) >= sizeof c->name)
            scr_raise(L, "seiche.scene: field 'name' must be a string of 1 to %zu characters (got %s)", sizeof c->name - 1,
                      scr_describe(L, -1, got, sizeof got));
        snprintf(c->name, sizeof c->name, "%s", lua_tostring(L, -1));
        lua_pop(L, 1);
    }
    if (scr_field_present(L, 1, "fluid")) {
        char got[64];
        if (!lua_istable(L, -1))
            scr_raise(L, "seiche.scene: field 'fluid' must be a table of fluid parameters {iterations = 3, ...} (got %s)",
                      scr_describe(L, -1, got, sizeof got));
        read_fluid(L, lua_gettop(L), &c->params);
        lua_pop(L, 1);
    }
    scr_opt_vec(L, 1, "seiche.scene", "gravity", 3, -1000, 1000, 0, "m/s^2", c->params.gravity);
    double cap;
    if (scr_opt_number(L, 1, "seiche.scene", "capacity", 1, 67108864, WHOLE, "particles", &cap)) c->capacity = (uint32_t)cap;
    if (scr_field_present(L, 1, "container")) {
        int t = lua_gettop(L);
        scr_check_table_field(L, t, "seiche.scene", "container", "min = {x, y, z}, max = {x, y, z}, closed_top = false");
        static const char *const ck[] = { "min", "max", "closed_top", NULL };
        scr_check_fields(L, t, "seiche.scene: container", ck);
        scr_read_box(L, t, "seiche.scene: container", c->container_min, c->container_max);
        c->closed_top = false;
        scr_opt_bool(L, t, "seiche.scene: container", "closed_top", &c->closed_top);
        c->has_container = true;
        lua_pop(L, 1);
    }
    if (scr_field_present(L, 1, "domain")) {
        int t = lua_gettop(L);
        scr_check_table_field(L, t, "seiche.scene", "domain", "min = {x, y, z}, max = {x, y, z}");
        static const char *const dk[] = { "min", "max", NULL };
        scr_check_fields(L, t, "seiche.scene: domain", dk);
        scr_read_box(L, t, "seiche.scene: domain", c->domain_min, c->domain_max);
        c->has_domain = true;
        lua_pop(L, 1);
    }
    if (c->has_domain && c->has_container) {
        static const char axis[] = "xyz";
        for (int k = 0; k < 3; k++)
            if (c->container_min[k] < c->domain_min[k] || c->container_max[k] > c->domain_max[k])
                scr_raise(L, "seiche.scene: the container's %c range [%g, %g] must lie inside the domain's [%g, %g]", axis[k],
                          (double)c->container_min[k], (double)c->container_max[k], (double)c->domain_min[k],
                          (double)c->domain_max[k]);
    }
    if (scr_field_present(L, 1, "camera")) {
        int t = lua_gettop(L);
        scr_check_table_field(L, t, "seiche.scene", "camera", "eye, target, fov, mode");
        int mode = c->camera_mode;
        read_camera(L, t, "seiche.scene: camera", c->camera_eye, c->camera_target, &c->camera_fov, &mode);
        c->camera_mode = (eng_camera_mode)mode;
        lua_pop(L, 1);
    }
    {
        float d[3] = { c->camera_eye[0] - c->camera_target[0], c->camera_eye[1] - c->camera_target[1],
                       c->camera_eye[2] - c->camera_target[2] };
        if (!(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > 1e-8f))
            scr_raise(L, "seiche.scene: camera eye and target must differ (both at {%g, %g, %g})", (double)c->camera_eye[0],
                      (double)c->camera_eye[1], (double)c->camera_eye[2]);
    }
    if (scr_field_present(L, 1, "look")) {
        int t = lua_gettop(L);
        scr_check_table_field(L, t, "seiche.scene", "look", "sky, light, water, ground, ground_height, container, panel");
        read_look(L, t, "seiche.scene: look", &c->look);
        lua_pop(L, 1);
    }
    luaL_where(L, 1);
    snprintf(c->scene_where, sizeof c->scene_where, "%s", lua_tostring(L, -1));
    lua_pop(L, 1);
    s->scene_called = true;
    return 0;
}

static int l_set_look(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    scr_check_table_arg(L, 1, "seiche.set_look", "sky, light, water, ground, ground_height, container, panel");
    eng_look k = s->config.look;
    read_look(L, 1, "seiche.set_look", &k);
    s->config.look = k; // read by the app every frame; not a world edit
    return 0;
}

static void push_color(lua_State *L, const float c[3])
{
    lua_createtable(L, 3, 0);
    for (int k = 0; k < 3; k++) {
        lua_pushnumber(L, c[k]);
        lua_rawseti(L, -2, k + 1);
    }
}

static int l_look(lua_State *L)
{
    const eng_look *k = &scr_get_script(L)->config.look;
    lua_createtable(L, 0, 7);
    push_color(L, k->sky);
    lua_setfield(L, -2, "sky");
    lua_createtable(L, 0, 3);
    scr_push_vec3(L, k->light.direction[0], k->light.direction[1], k->light.direction[2]);
    lua_setfield(L, -2, "direction");
    push_color(L, k->light.color);
    lua_setfield(L, -2, "color");
    push_color(L, k->light.ambient);
    lua_setfield(L, -2, "ambient");
    lua_setfield(L, -2, "light");
    lua_createtable(L, 0, 5);
    push_color(L, k->water.color_low);
    lua_setfield(L, -2, "low");
    push_color(L, k->water.color_mid);
    lua_setfield(L, -2, "mid");
    push_color(L, k->water.color_high);
    lua_setfield(L, -2, "high");
    scr_set_num(L, "specular", k->water.specular);
    scr_set_num(L, "shininess", k->water.shininess);
    lua_setfield(L, -2, "water");
    lua_pushboolean(L, k->ground);
    lua_setfield(L, -2, "ground");
    scr_set_num(L, "ground_height", k->ground_height);
    lua_pushboolean(L, k->container);
    lua_setfield(L, -2, "container");
    lua_pushboolean(L, k->panel);
    lua_setfield(L, -2, "panel");
    return 1;
}

static int l_set_camera(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    scr_check_table_arg(L, 1, "seiche.set_camera", "eye, target, fov, mode");
    float eye[3] = { 0 }, target[3] = { 0 }, fov = 0;
    int mode = 0;
    int has = read_camera(L, 1, "seiche.set_camera", eye, target, &fov, &mode);
    if ((has & 3) == 3 && eye[0] == target[0] && eye[1] == target[1] && eye[2] == target[2])
        scr_raise(L, "seiche.set_camera: eye and target must differ (both at {%g, %g, %g})", (double)eye[0], (double)eye[1],
                  (double)eye[2]);
    command *c = scr_push_command(L, s, CMD_CAMERA, "seiche.set_camera");
    memcpy(c->u.camera.eye, eye, sizeof eye);
    memcpy(c->u.camera.target, target, sizeof target);
    c->u.camera.fov = fov;
    c->u.camera.mode = mode;
    c->u.camera.has_eye = has & 1;
    c->u.camera.has_target = has & 2;
    c->u.camera.has_fov = has & 4;
    c->u.camera.has_mode = has & 8;
    return 0;
}

static int l_camera(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const eng_scene_config *c = &s->config;
    const eng_camera *cam = s->host.camera;
    lua_createtable(L, 0, 4);
    if (cam) scr_push_vec3(L, cam->position[0], cam->position[1], cam->position[2]);
    else scr_push_vec3(L, c->camera_eye[0], c->camera_eye[1], c->camera_eye[2]);
    lua_setfield(L, -2, "eye");
    if (cam) scr_push_vec3(L, cam->target[0], cam->target[1], cam->target[2]);
    else scr_push_vec3(L, c->camera_target[0], c->camera_target[1], c->camera_target[2]);
    lua_setfield(L, -2, "target");
    scr_set_num(L, "fov", cam ? cam->fov_y * 180.0 / PI : c->camera_fov);
    lua_pushstring(L, CAMERA_MODES[cam ? (int)cam->mode : (int)c->camera_mode]);
    lua_setfield(L, -2, "mode");
    return 1;
}

// ---- fluid content --------------------------------------------------------------------

static void check_velocity_field(lua_State *L, int t, const char *fn, const char *field, float out[3])
{
    scr_opt_vec(L, t, fn, field, 3, -MAX_SPEED, MAX_SPEED, 0, "m/s", out);
}

static int l_block(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    scr_check_table_arg(L, 1, "seiche.block", "min = {x, y, z}, max = {x, y, z}, velocity = {x, y, z}");
    static const char *const known[] = { "min", "max", "velocity", NULL };
    scr_check_fields(L, 1, "seiche.block", known);
    pbf_block_def b = pbf_default_block_def();
    scr_read_box(L, 1, "seiche.block", b.min, b.max);
    check_velocity_field(L, 1, "seiche.block", "velocity", b.velocity);
    command *c = scr_push_command(L, s, CMD_BLOCK, "seiche.block");
    c->u.block = b;
    return 0;
}

static int l_sphere(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    scr_check_table_arg(L, 1, "seiche.sphere", "center = {x, y, z}, radius = m, velocity = {x, y, z}");
    static const char *const known[] = { "center", "radius", "velocity", NULL };
    scr_check_fields(L, 1, "seiche.sphere", known);
    float center[3], vel[3] = { 0, 0, 0 };
    scr_req_position(L, 1, "seiche.sphere", "center", center);
    double r = scr_req_number(L, 1, "seiche.sphere", "radius", 0, 1000, OPEN_LO, "m");
    check_velocity_field(L, 1, "seiche.sphere", "velocity", vel);
    command *c = scr_push_command(L, s, CMD_SPHERE, "seiche.sphere");
    memcpy(c->u.sphere.center, center, sizeof center);
    c->u.sphere.radius = (float)r;
    memcpy(c->u.sphere.velocity, vel, sizeof vel);
    return 0;
}


static float *copy_floats(lua_State *L, const char *fn, const float *src, size_t count)
{
    float *p = malloc(count * sizeof(float) + 4);
    if (!p) scr_raise(L, "%s: out of memory", fn);
    memcpy(p, src, count * sizeof(float));
    return p;
}

static int l_particles(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    scr_check_table_arg(L, 1, "seiche.particles", "positions = {{x, y, z}, ...}, velocities = {{x, y, z}, ...} or velocity");
    static const char *const known[] = { "positions", "velocities", "velocity", NULL };
    scr_check_fields(L, 1, "seiche.particles", known);
    uint32_t cap = scr_capacity_of(s);
    uint32_t n = 0, nv = 0;
    const float *pos = scr_read_point_list(L, 1, "seiche.particles", "positions", -MAX_COORD, MAX_COORD, "m", &n, 1, cap);
    const float *vel = NULL;
    float v[3] = { 0, 0, 0 };
    lua_getfield(L, 1, "velocities");
    bool has_list = !lua_isnil(L, -1);
    lua_pop(L, 1);
    if (has_list) {
        lua_getfield(L, 1, "velocity");
        bool both = !lua_isnil(L, -1);
        lua_pop(L, 1);
        if (both) scr_raise(L, "seiche.particles: give either 'velocities' (one per point) or 'velocity' (one for all), not both");
        vel = scr_read_point_list(L, 1, "seiche.particles", "velocities", -MAX_SPEED, MAX_SPEED, "m/s", &nv, n, n);
    } else {
        check_velocity_field(L, 1, "seiche.particles", "velocity", v);
    }
    // The command first (scr_push_command may raise), then the arrays it owns.
    command *c = scr_push_command(L, s, CMD_PARTICLES, "seiche.particles");
    c->u.particles.pos = copy_floats(L, "seiche.particles", pos, 3 * (size_t)n);
    if (vel || v[0] != 0 || v[1] != 0 || v[2] != 0) {
        float *q = malloc(3 * (size_t)n * sizeof(float) + 1);
        if (!q) scr_raise(L, "seiche.particles: out of memory");
        for (uint32_t i = 0; i < n; i++) memcpy(q + 3 * i, vel ? vel + 3 * i : v, 3 * sizeof(float));
        c->u.particles.vel = q;
    }
    c->u.particles.n = n;
    return 0;
}

// ---- emitters ----------------------------------------------------------------------------

// Reads the emitter fields of table t over `d` (which holds the current values).
// Returns true when the table gave a rate.
static bool read_emitter(lua_State *L, eng_script *s, int t, const char *fn, pbf_emitter_def *d, bool full_rate)
{
    static const char *const known[] = { "position", "direction", "speed", "rate", "radius", "enabled", NULL };
    scr_check_fields(L, t, fn, known);
    scr_opt_position(L, t, fn, "position", d->position);
    float dir[3];
    if (scr_opt_vec(L, t, fn, "direction", 3, -1e6, 1e6, 0, "", dir)) {
        if (!(fabsf(dir[0]) + fabsf(dir[1]) + fabsf(dir[2]) > 0.0f))
            scr_raise(L, "%s: field 'direction' must not be zero (got {0, 0, 0})", fn);
        memcpy(d->direction, dir, sizeof dir);
    }
    double v;
    if (scr_opt_number(L, t, fn, "speed", 0, 100, OPEN_LO, "m/s", &v)) d->speed = (float)v;
    const pbf_params *p = scr_current_params(s);
    if (scr_opt_number(L, t, fn, "radius", p->particle_radius, 10, 0, "m (the particle radius at least)", &v))
        d->radius = (float)v;
    if (scr_field_present(L, t, "rate")) {
        char got[64];
        double max_rate = s->host.world ? pbf_emitter_max_rate(s->host.world, d->speed, d->radius) : 1e9;
        double r = lua_tonumber(L, -1);
        if (lua_type(L, -1) != LUA_TNUMBER || !(isfinite(r) && r >= 0.0 && r <= max_rate * 1.0001)) {
            if (s->host.world)
                scr_raise(L, "%s: field 'rate' must be a number in [0, %g] particles/s (got %s); %g is the most a nozzle of "
                          "radius %g m pours at speed %g m/s: raise speed or radius for more", fn, max_rate,
                          scr_describe(L, -1, got, sizeof got), max_rate, (double)d->radius, (double)d->speed);
            scr_raise(L, "%s: field 'rate' must be a number >= 0 particles/s, at most seiche.max_emitter_rate(speed, radius) "
                      "(got %s)", fn, scr_describe(L, -1, got, sizeof got));
        }
        d->rate = (float)r;
        lua_pop(L, 1);
        scr_opt_bool(L, t, fn, "enabled", &d->enabled);
        return true;
    } else if (!full_rate && s->host.world && d->rate > pbf_emitter_max_rate(s->host.world, d->speed, d->radius) * 1.0001) {
        double max_rate = pbf_emitter_max_rate(s->host.world, d->speed, d->radius);
        scr_raise(L, "%s: the rate %g particles/s is more than a nozzle of radius %g m pours at speed %g m/s (at most %g); "
                  "raise speed or radius, or lower rate", fn, (double)d->rate, (double)d->radius, (double)d->speed, max_rate);
    }
    scr_opt_bool(L, t, fn, "enabled", &d->enabled);
    return false;
}

static int l_emitter(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    scr_check_table_arg(L, 1, "seiche.emitter", "position, direction, speed, rate, radius, enabled");
    pbf_emitter_def d = pbf_default_emitter_def();
    lua_getfield(L, 1, "position");
    bool has_pos = !lua_isnil(L, -1);
    lua_pop(L, 1);
    if (!has_pos) scr_raise(L, "seiche.emitter: field 'position' is required: a table of 3 numbers {x, y, z} in m (got nil)");
    bool full = !read_emitter(L, s, 1, "seiche.emitter", &d, true);
    uint32_t slot = scr_obj_new(L, s, OBJ_EMITTER);
    s->objs[slot].u.emitter.def = d;
    s->objs[slot].u.emitter.full_rate = full;
    command *c = scr_push_command(L, s, CMD_EMITTER_ADD, "seiche.emitter");
    c->slot = slot;
    c->gen = s->objs[slot].generation;
    c->full_rate = full;
    c->u.emitter = d;
    scr_push_handle(L, s, slot);
    return 1;
}

static int m_emitter_set(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_EMITTER, "emitter:set", &slot);
    scr_check_table_arg(L, 2, "emitter:set", "position, direction, speed, rate, radius, enabled");
    pbf_emitter_def d = o->u.emitter.def;
    if (read_emitter(L, s, 2, "emitter:set", &d, o->u.emitter.full_rate)) o->u.emitter.full_rate = false;
    o->u.emitter.def = d;
    command *c = scr_push_command(L, s, CMD_EMITTER_SET, "emitter:set");
    c->slot = slot;
    c->gen = o->generation;
    c->full_rate = o->u.emitter.full_rate;
    c->u.emitter = d;
    return 0;
}

static int m_emitter_set_enabled(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_EMITTER, "emitter:set_enabled", &slot);
    char got[64];
    if (!lua_isboolean(L, 2))
        scr_raise(L, "emitter:set_enabled: argument #1 'on' must be true or false (got %s)", scr_describe(L, 2, got, sizeof got));
    o->u.emitter.def.enabled = lua_toboolean(L, 2);
    command *c = scr_push_command(L, s, CMD_EMITTER_SET, "emitter:set_enabled");
    c->slot = slot;
    c->gen = o->generation;
    c->full_rate = o->u.emitter.full_rate;
    c->u.emitter = o->u.emitter.def;
    return 0;
}

static int m_emitter_get(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_EMITTER, "emitter:get", NULL);
    const pbf_emitter_def *d = &o->u.emitter.def;
    lua_createtable(L, 0, 6);
    scr_push_vec3(L, d->position[0], d->position[1], d->position[2]);
    lua_setfield(L, -2, "position");
    scr_push_vec3(L, d->direction[0], d->direction[1], d->direction[2]);
    lua_setfield(L, -2, "direction");
    scr_set_num(L, "speed", d->speed);
    eng_script *s = scr_get_script(L);
    if (!o->u.emitter.full_rate) scr_set_num(L, "rate", d->rate);
    else if (s->host.world) scr_set_num(L, "rate", pbf_emitter_max_rate(s->host.world, d->speed, d->radius));
    // else: the most the nozzle can pour, known once the world exists: rate is nil
    scr_set_num(L, "radius", d->radius);
    lua_pushboolean(L, d->enabled);
    lua_setfield(L, -2, "enabled");
    return 1;
}

static int m_emitter_remove(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_EMITTER, "emitter:remove", &slot);
    if (o->state == OBJ_LIVE) {
        command *c = scr_push_command(L, s, CMD_EMITTER_REMOVE, "emitter:remove");
        c->u.emitter_id = o->u.emitter.id;
    }
    scr_obj_release(s, slot);
    return 0;
}

// ---- sinks ----------------------------------------------------------------------------

static int l_sink(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    scr_check_table_arg(L, 1, "seiche.sink", "min = {x, y, z}, max = {x, y, z}");
    static const char *const known[] = { "min", "max", NULL };
    scr_check_fields(L, 1, "seiche.sink", known);
    float mn[3], mx[3];
    scr_read_box(L, 1, "seiche.sink", mn, mx);
    uint32_t slot = scr_obj_new(L, s, OBJ_SINK);
    memcpy(s->objs[slot].u.sink.min, mn, sizeof mn);
    memcpy(s->objs[slot].u.sink.max, mx, sizeof mx);
    command *c = scr_push_command(L, s, CMD_SINK_ADD, "seiche.sink");
    c->slot = slot;
    c->gen = s->objs[slot].generation;
    scr_push_handle(L, s, slot);
    return 1;
}

static int m_sink_get(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_SINK, "sink:get", NULL);
    lua_createtable(L, 0, 2);
    scr_push_vec3(L, o->u.sink.min[0], o->u.sink.min[1], o->u.sink.min[2]);
    lua_setfield(L, -2, "min");
    scr_push_vec3(L, o->u.sink.max[0], o->u.sink.max[1], o->u.sink.max[2]);
    lua_setfield(L, -2, "max");
    return 1;
}

static int m_sink_remove(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_SINK, "sink:remove", &slot);
    if (o->state == OBJ_LIVE) {
        command *c = scr_push_command(L, s, CMD_SINK_REMOVE, "sink:remove");
        c->u.sink_id = o->u.sink.id;
    }
    scr_obj_release(s, slot);
    return 0;
}

// ---- bodies ------------------------------------------------------------------------------

static const float PALETTE[6][3] = {
    { 0.86f, 0.42f, 0.18f }, { 0.90f, 0.76f, 0.26f }, { 0.36f, 0.66f, 0.32f },
    { 0.78f, 0.26f, 0.30f }, { 0.50f, 0.40f, 0.70f }, { 0.62f, 0.46f, 0.30f },
};

static double dims_volume(body_shape shape, const float *d)
{
    switch (shape) {
    case SHAPE_BOX: return 8.0 * d[0] * d[1] * d[2];
    case SHAPE_SPHERE: return 4.0 / 3.0 * PI * d[0] * d[0] * d[0];
    case SHAPE_CAPSULE: return PI * d[0] * d[0] * (2.0 * d[1] + 4.0 / 3.0 * d[0]);
    case SHAPE_CYLINDER: return PI * d[0] * d[0] * 2.0 * d[1];
    default: return 0.0;
    }
}

// Volume of a shape whose dimensions are known here (not hulls or meshes), m^3; a
// compound's is the sum of its parts'.
static double shape_volume(const body_rec *b)
{
    if (b->shape != SHAPE_COMPOUND) return dims_volume(b->shape, b->dims);
    double v = 0.0;
    for (uint32_t i = 0; i < b->part_count; i++) v += dims_volume(b->parts[i].shape, b->parts[i].dims);
    return v;
}

static const char *const BODY_FIELDS[] = { "shape", "size", "radius", "height", "normal", "offset", "points", "vertices",
                                           "indices", "kind", "density", "mass", "position", "rotation", "velocity",
                                           "angular_velocity", "friction", "restitution", "linear_damping",
                                           "angular_damping", "two_way", "color", "visible", "parts", "linear_factor",
                                           "angular_factor", "axle", NULL };

// The fields each shape takes (besides the common ones).
static void check_shape_fields(lua_State *L, body_shape shape)
{
    static const char *const own[SHAPE_COUNT][4] = {
        { "size" }, { "radius" }, { "radius", "height" }, { "radius", "height" },
        { "normal", "offset" }, { "points" }, { "vertices", "indices" }, { "parts" },
    };
    static const char *const geometric[] = { "size", "radius", "height", "normal", "offset", "points", "vertices",
                                             "indices", "parts", NULL };
    for (const char *const *g = geometric; *g; g++) {
        bool mine = false;
        for (int k = 0; k < 4 && own[shape][k]; k++)
            if (strcmp(own[shape][k], *g) == 0) mine = true;
        if (mine) continue;
        lua_getfield(L, 1, *g);
        bool given = !lua_isnil(L, -1);
        lua_pop(L, 1);
        if (given) {
            char list[96] = "";
            size_t n = 0;
            for (int k = 0; k < 4 && own[shape][k]; k++)
                n += (size_t)snprintf(list + n, sizeof list - n, "%s'%s'", k ? ", " : "", own[shape][k]);
            scr_raise(L, "seiche.body: field '%s' does not apply to shape \"%s\" (it takes %s)", *g, scr_shape_name[shape], list);
        }
    }
}

// The geometry fields of a box, sphere, capsule or cylinder in table t: dims as body_rec.
static void read_dims(lua_State *L, int t, const char *fn, body_shape shape, float dims[4])
{
    switch (shape) {
    case SHAPE_BOX: {
        float size[3];
        if (!scr_opt_vec(L, t, fn, "size", 3, 0, 1000, OPEN_LO, "m", size))
            scr_raise(L, "%s: field 'size' is required for a box: edge lengths {x, y, z}, each in (0, 1000] m (got nil)", fn);
        for (int k = 0; k < 3; k++) dims[k] = 0.5f * size[k];
        break;
    }
    case SHAPE_SPHERE: dims[0] = (float)scr_req_number(L, t, fn, "radius", 0, 1000, OPEN_LO, "m"); break;
    case SHAPE_CAPSULE:
    case SHAPE_CYLINDER: {
        double r = scr_req_number(L, t, fn, "radius", 0, 1000, OPEN_LO, "m");
        double h = scr_req_number(L, t, fn, "height", 0, 2000, OPEN_LO, "m");
        if (shape == SHAPE_CAPSULE && !(h > 2.0 * r))
            scr_raise(L, "%s: field 'height' of a capsule is its total height and must exceed 2 radius = %g m (got %g)", fn,
                      2.0 * r, h);
        dims[0] = (float)r;
        dims[1] = shape == SHAPE_CAPSULE ? (float)(0.5 * h - r) : (float)(0.5 * h);
        break;
    }
    default: break;
    }
}

// Field 'parts' of a compound: 1 to MAX_BODY_PARTS tables {shape, size | radius, height,
// position, rotation}. Returns them in garbage-collected userdata (left on the stack).
static body_part *read_parts(lua_State *L, int t, const char *fn, uint32_t *count)
{
    if (!scr_field_present(L, t, "parts"))
        scr_raise(L, "%s: field 'parts' is required for a compound: a list of 1 to %d parts {shape = \"box\", size = "
                  "{x, y, z}, position = {x, y, z}, rotation = ...} (got nil)", fn, MAX_BODY_PARTS);
    int pt = lua_gettop(L);
    char got[64];
    if (!lua_istable(L, pt))
        scr_raise(L, "%s: field 'parts' must be a list of parts {shape, size | radius, height, position, rotation} (got %s)",
                  fn, scr_describe(L, pt, got, sizeof got));
    lua_Integer n = luaL_len(L, pt);
    if (n < 1 || n > MAX_BODY_PARTS)
        scr_raise(L, "%s: field 'parts' must hold 1 to %d parts (each part is one of the fluid's %d colliders; got %lld)", fn,
                  MAX_BODY_PARTS, MAX_BODY_PARTS, (long long)n);
    body_part *parts = lua_newuserdatauv(L, (size_t)n * sizeof *parts, 0);
    static const char *const known[] = { "shape", "size", "radius", "height", "position", "rotation", NULL };
    static const char *const part_shapes[] = { "box", "sphere", "capsule", "cylinder" };
    static const char *const own[4][2] = { { "size" }, { "radius" }, { "radius", "height" }, { "radius", "height" } };
    for (lua_Integer i = 1; i <= n; i++) {
        char sub[96];
        snprintf(sub, sizeof sub, "%s: field 'parts'[%lld]", fn, (long long)i);
        lua_geti(L, pt, i);
        int e = lua_gettop(L);
        if (!lua_istable(L, e))
            scr_raise(L, "%s must be a table {shape, size | radius, height, position, rotation} (got %s)", sub,
                      scr_describe(L, e, got, sizeof got));
        scr_check_fields(L, e, sub, known);
        int shape = scr_opt_enum(L, e, sub, "shape", part_shapes, 4);
        if (shape < 0)
            scr_raise(L, "%s: field 'shape' is required: one of \"box\", \"sphere\", \"capsule\", \"cylinder\" (got nil)",
                      sub);
        static const char *const geometric[] = { "size", "radius", "height" };
        for (int g = 0; g < 3; g++) {
            bool mine = false;
            for (int k = 0; k < 2 && own[shape][k]; k++)
                if (strcmp(own[shape][k], geometric[g]) == 0) mine = true;
            if (!mine && scr_field_present(L, e, geometric[g]))
                scr_raise(L, "%s: field '%s' does not apply to shape \"%s\"", sub, geometric[g], part_shapes[shape]);
        }
        body_part *bp = &parts[i - 1];
        memset(bp, 0, sizeof *bp);
        bp->shape = (body_shape)shape;
        read_dims(L, e, sub, bp->shape, bp->dims);
        scr_opt_position(L, e, sub, "position", bp->pos);
        bp->rot[3] = 1.0f;
        scr_opt_rotation(L, e, sub, "rotation", bp->rot);
        lua_pop(L, 1);
    }
    *count = (uint32_t)n;
    return parts;
}

static int l_body(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.body";
    scr_check_table_arg(L, 1, fn, "shape = \"box\", size = {x, y, z}, position = {x, y, z}, ...");
    scr_check_fields(L, 1, fn, BODY_FIELDS);
    int shape = scr_opt_enum(L, 1, fn, "shape", scr_shape_name, SHAPE_COUNT);
    if (shape < 0)
        scr_raise(L, "seiche.body: field 'shape' is required: one of \"box\", \"sphere\", \"capsule\", \"cylinder\", "
                  "\"plane\", \"hull\", \"mesh\", \"compound\" (got nil)");
    check_shape_fields(L, (body_shape)shape);
    int kind = scr_opt_enum(L, 1, fn, "kind", scr_body_kind_name, 3);
    if (kind < 0) kind = (shape == SHAPE_PLANE || shape == SHAPE_MESH) ? PHYS_BODY_STATIC : PHYS_BODY_DYNAMIC;
    if (kind == PHYS_BODY_DYNAMIC && (shape == SHAPE_PLANE || shape == SHAPE_MESH))
        scr_raise(L, "seiche.body: shape \"%s\" has no volume and must be kind \"static\" or \"kinematic\" (got kind \"dynamic\")",
                  scr_shape_name[shape]);

    body_rec b;
    memset(&b, 0, sizeof b);
    b.shape = (body_shape)shape;
    b.def = phys_default_body_def();
    b.def.type = (phys_body_type)kind;
    b.def.allow_sleep = false; // bodies in fluid must feel it (the coupling keeps them awake anyway)
    b.two_way = true;
    b.visible = true;

    // Common fields.
    double v;
    bool has_mass = scr_opt_number(L, 1, fn, "mass", 0, 1e9, OPEN_LO, "kg", &v);
    if (has_mass) b.def.mass = (float)v;
    bool has_density = scr_opt_number(L, 1, fn, "density", 0, 1e6, OPEN_LO, "kg/m^3", &v);
    if (has_density) b.def.density = (float)v;
    if ((has_mass || has_density) && kind != PHYS_BODY_DYNAMIC)
        scr_raise(L, "seiche.body: fields 'mass' and 'density' apply to dynamic bodies only (this one is %s: its mass is "
                  "infinite)", scr_body_kind_name[kind]);
    if (has_mass && has_density) scr_raise(L, "seiche.body: give 'mass' or 'density', not both");
    float pos[3] = { 0, 0, 0 };
    scr_opt_position(L, 1, fn, "position", pos);
    b.def.position = scr_pv(pos);
    float q[4];
    if (scr_opt_rotation(L, 1, fn, "rotation", q)) b.def.orientation = scr_pq(q);
    float vel[3] = { 0, 0, 0 }, ang[3] = { 0, 0, 0 };
    bool has_v = scr_opt_vec(L, 1, fn, "velocity", 3, -MAX_SPEED, MAX_SPEED, 0, "m/s", vel);
    bool has_w = scr_opt_vec(L, 1, fn, "angular_velocity", 3, -MAX_SPEED, MAX_SPEED, 0, "rad/s", ang);
    if ((has_v || has_w) && kind == PHYS_BODY_STATIC)
        scr_raise(L, "seiche.body: a static body cannot move: fields 'velocity' and 'angular_velocity' need kind "
                  "\"kinematic\" or \"dynamic\"");
    b.def.linear_velocity = scr_pv(vel);
    b.def.angular_velocity = scr_pv(ang);
    if (scr_opt_number(L, 1, fn, "friction", 0, 100, 0, "", &v)) b.def.friction = (float)v;
    if (scr_opt_number(L, 1, fn, "restitution", 0, 1, 0, "", &v)) b.def.restitution = (float)v;
    if (scr_opt_number(L, 1, fn, "linear_damping", 0, 1, 0, "(fraction of velocity removed per second)", &v))
        b.def.linear_damping = (float)v;
    if (scr_opt_number(L, 1, fn, "angular_damping", 0, 1, 0, "(fraction of angular velocity removed per second)", &v))
        b.def.angular_damping = (float)v;
    scr_opt_bool(L, 1, fn, "two_way", &b.two_way);
    // Motion factors: per world axis, [0, 1]; `axle` is the short form of a fixed axle.
    for (int k = 0; k < 3; k++) b.linear_factor[k] = b.angular_factor[k] = 1.0f;
    bool has_lf = scr_opt_vec(L, 1, fn, "linear_factor", 3, 0, 1, 0, "", b.linear_factor);
    bool has_af = scr_opt_vec(L, 1, fn, "angular_factor", 3, 0, 1, 0, "", b.angular_factor);
    static const char *const AXES[3] = { "x", "y", "z" };
    int axle = scr_opt_enum(L, 1, fn, "axle", AXES, 3);
    if (axle >= 0) {
        if (has_lf || has_af)
            scr_raise(L, "seiche.body: give 'axle' or 'linear_factor'/'angular_factor', not both (axle = \"%s\" means "
                      "linear_factor = {0, 0, 0} and angular_factor = 1 about %s only)", AXES[axle], AXES[axle]);
        for (int k = 0; k < 3; k++) {
            b.linear_factor[k] = 0.0f;
            b.angular_factor[k] = k == axle ? 1.0f : 0.0f;
        }
    }
    b.has_factors = has_lf || has_af || axle >= 0;
    if (b.has_factors && kind != PHYS_BODY_DYNAMIC)
        scr_raise(L, "seiche.body: fields 'axle', 'linear_factor' and 'angular_factor' apply to dynamic bodies only (this "
                  "one is %s)", scr_body_kind_name[kind]);
    bool has_color = scr_opt_color(L, 1, fn, "color", b.color);
    scr_opt_bool(L, 1, fn, "visible", &b.visible);

    // The shape. Point lists stay in garbage-collected userdata until everything is checked.
    const float *pts = NULL;
    const uint32_t *idx = NULL;
    const body_part *parts = NULL;
    switch (b.shape) {
    case SHAPE_BOX:
    case SHAPE_SPHERE:
    case SHAPE_CAPSULE:
    case SHAPE_CYLINDER: read_dims(L, 1, fn, b.shape, b.dims); break;
    case SHAPE_COMPOUND: parts = read_parts(L, 1, fn, &b.part_count); b.parts = (body_part *)parts; break;
    case SHAPE_PLANE: {
        float n[3] = { 0, 1, 0 };
        scr_opt_vec(L, 1, fn, "normal", 3, -1e6, 1e6, 0, "", n);
        double len = sqrt((double)n[0] * n[0] + (double)n[1] * n[1] + (double)n[2] * n[2]);
        if (!(len > 1e-9)) scr_raise(L, "seiche.body: field 'normal' must not be zero (got {0, 0, 0})");
        for (int k = 0; k < 3; k++) b.dims[k] = (float)(n[k] / len);
        double off = 0;
        scr_opt_number(L, 1, fn, "offset", -MAX_COORD, MAX_COORD, 0, "m", &off);
        b.dims[3] = (float)off;
        break;
    }
    case SHAPE_HULL:
    case SHAPE_MESH: {
        const char *field = b.shape == SHAPE_HULL ? "points" : "vertices";
        pts = scr_read_point_list(L, 1, fn, field, -MAX_COORD, MAX_COORD, "m", &b.point_count, b.shape == SHAPE_HULL ? 4 : 3,
                                  65536);
        if (b.shape == SHAPE_MESH) {
            if (!scr_field_present(L, 1, "indices"))
                scr_raise(L, "seiche.body: field 'indices' is required for a mesh: vertex numbers (1-based), three per triangle");
            int it = lua_gettop(L);
            char got[64];
            if (!lua_istable(L, it))
                scr_raise(L, "seiche.body: field 'indices' must be a list of vertex numbers (got %s)", scr_describe(L, it, got, sizeof got));
            lua_Integer m = luaL_len(L, it);
            if (m < 3 || m % 3 != 0 || m > 3 * 262144)
                scr_raise(L, "seiche.body: field 'indices' must hold 3 to %d vertex numbers, a multiple of 3 (got %lld)",
                          3 * 262144, (long long)m);
            uint32_t *ix = lua_newuserdatauv(L, (size_t)m * sizeof *ix, 0);
            for (lua_Integer i = 1; i <= m; i++) {
                lua_geti(L, it, i);
                char what[64];
                snprintf(what, sizeof what, "field 'indices'[%lld]", (long long)i);
                ix[i - 1] = (uint32_t)scr_check_number_at(L, -1, fn, what, 1, b.point_count, WHOLE, "(a vertex number)") - 1;
                lua_pop(L, 1);
            }
            idx = ix;
            b.index_count = (uint32_t)m;
        }
        break;
    }
    default: break;
    }
    if (kind == PHYS_BODY_DYNAMIC && !has_mass && b.shape != SHAPE_HULL) {
        double m = shape_volume(&b) * b.def.density;
        if (!(m > 0.0 && m <= 1e9))
            scr_raise(L, "seiche.body: density %g kg/m^3 times volume %g m^3 gives mass %g kg, outside (0, 1e9] kg",
                      (double)b.def.density, shape_volume(&b), m);
    }

    uint32_t slot = scr_obj_new(L, s, OBJ_BODY);
    obj *o = &s->objs[slot];
    if (!has_color) {
        if (kind == PHYS_BODY_DYNAMIC) memcpy(b.color, PALETTE[slot % 6], sizeof b.color);
        else b.color[0] = b.color[1] = b.color[2] = 0.55f;
    }
    command *c = scr_push_command(L, s, CMD_BODY_ADD, fn);
    c->slot = slot;
    c->gen = o->generation;
    b.parts = NULL;
    if (parts) {
        b.parts = malloc((size_t)b.part_count * sizeof *b.parts);
        if (!b.parts) {
            s->command_count--;
            scr_obj_release(s, slot);
            scr_raise(L, "seiche.body: out of memory");
        }
        memcpy(b.parts, parts, (size_t)b.part_count * sizeof *b.parts);
    }
    if (pts) {
        b.points = malloc((size_t)b.point_count * 3 * sizeof(float));
        b.indices = b.index_count ? malloc((size_t)b.index_count * sizeof(uint32_t)) : NULL;
        if (!b.points || (b.index_count && !b.indices)) {
            scr_body_free_data(&b);
            s->command_count--;
            scr_obj_release(s, slot);
            scr_raise(L, "seiche.body: out of memory");
        }
        memcpy(b.points, pts, (size_t)b.point_count * 3 * sizeof(float));
        if (b.index_count) memcpy(b.indices, idx, (size_t)b.index_count * sizeof(uint32_t));
    }
    o->u.body = b;
    scr_push_handle(L, s, slot);
    return 1;
}

// The body's pose and velocities: from Bullet when it is in the world, else from its def.
void scr_body_state(eng_script *s, obj *o, float pos[3], float rot[4], float vel[3], float ang[3])
{
    body_rec *b = &o->u.body;
    phys_vec3 p = b->def.position, v = b->def.linear_velocity, w = b->def.angular_velocity;
    phys_quat q = b->def.orientation;
    if (o->state == OBJ_LIVE && s->host.phys) {
        phys_body_get_pose(s->host.phys, b->id, &p, &q);
        phys_body_get_linear_velocity(s->host.phys, b->id, &v);
        phys_body_get_angular_velocity(s->host.phys, b->id, &w);
    }
    if (pos) pos[0] = p.x, pos[1] = p.y, pos[2] = p.z;
    if (rot) rot[0] = q.x, rot[1] = q.y, rot[2] = q.z, rot[3] = q.w;
    if (vel) vel[0] = v.x, vel[1] = v.y, vel[2] = v.z;
    if (ang) ang[0] = w.x, ang[1] = w.y, ang[2] = w.z;
}

static int m_body_position(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:position", NULL);
    float p[3];
    scr_body_state(scr_get_script(L), o, p, NULL, NULL, NULL);
    scr_push_vec3(L, p[0], p[1], p[2]);
    return 1;
}

static int m_body_rotation(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:rotation", NULL);
    float q[4];
    scr_body_state(scr_get_script(L), o, NULL, q, NULL, NULL);
    scr_push_quat(L, q);
    return 1;
}

static int m_body_velocity(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:velocity", NULL);
    float v[3];
    scr_body_state(scr_get_script(L), o, NULL, NULL, v, NULL);
    scr_push_vec3(L, v[0], v[1], v[2]);
    return 1;
}

static int m_body_angular_velocity(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:angular_velocity", NULL);
    float w[3];
    scr_body_state(scr_get_script(L), o, NULL, NULL, NULL, w);
    scr_push_vec3(L, w[0], w[1], w[2]);
    return 1;
}

static int m_body_velocity_at(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:velocity_at", NULL);
    float pt[3], p[3], v[3], w[3];
    scr_arg_vec(L, 2, "body:velocity_at", "point", -MAX_COORD, MAX_COORD, "m", pt);
    scr_body_state(scr_get_script(L), o, p, NULL, v, w);
    float r[3] = { pt[0] - p[0], pt[1] - p[1], pt[2] - p[2] };
    scr_push_vec3(L, v[0] + w[1] * r[2] - w[2] * r[1], v[1] + w[2] * r[0] - w[0] * r[2], v[2] + w[0] * r[1] - w[1] * r[0]);
    return 1;
}

static int m_body_mass(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    obj *o = scr_check_self(L, OBJ_BODY, "body:mass", NULL);
    body_rec *b = &o->u.body;
    if (b->def.type != PHYS_BODY_DYNAMIC) {
        lua_pushnumber(L, HUGE_VAL);
        return 1;
    }
    if (o->state == OBJ_LIVE && s->host.phys) {
        phys_mass_data md;
        if (phys_body_get_mass_data(s->host.phys, b->id, &md) == PHYS_OK) {
            lua_pushnumber(L, md.mass);
            return 1;
        }
    }
    if (b->def.mass > 0) lua_pushnumber(L, b->def.mass);
    else if (b->shape != SHAPE_HULL) lua_pushnumber(L, shape_volume(b) * b->def.density);
    else scr_raise(L, "body:mass: the hull's mass is known once the body is in the world (after this callback)");
    return 1;
}

static int m_body_kind(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:kind", NULL);
    lua_pushstring(L, scr_body_kind_name[o->u.body.def.type]);
    return 1;
}

static int m_body_shape(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_BODY, "body:shape", NULL);
    lua_pushstring(L, scr_shape_name[o->u.body.shape]);
    return 1;
}

static int m_body_fluid_force(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    obj *o = scr_check_self(L, OBJ_BODY, "body:fluid_force", NULL);
    cpl_body_stats st;
    memset(&st, 0, sizeof st);
    if (o->state == OBJ_LIVE && s->host.coupling) cpl_body_get_stats(s->host.coupling, o->u.body.id, &st);
    scr_push_vec3(L, st.force[0], st.force[1], st.force[2]);
    scr_push_vec3(L, st.torque[0], st.torque[1], st.torque[2]);
    return 2;
}

// A queued edit of a body that must be dynamic (forces) or may not be static (velocities).
static command *body_edit(lua_State *L, const char *fn, cmd_type type, bool dynamic_only)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_BODY, fn, &slot);
    phys_body_type t = o->u.body.def.type;
    if (dynamic_only && t != PHYS_BODY_DYNAMIC)
        scr_raise(L, "%s: the body is %s: forces and impulses move dynamic bodies only (use move_to or set_velocity on a "
                  "kinematic body)", fn, scr_body_kind_name[t]);
    if (t == PHYS_BODY_STATIC)
        scr_raise(L, "%s: the body is static: it never moves (make it kind = \"kinematic\" to move it by script)", fn);
    command *c = scr_push_command(L, s, type, fn);
    c->slot = slot;
    c->gen = o->generation;
    return c;
}

static int vector_edit(lua_State *L, const char *fn, cmd_type type, const char *name, const char *unit, bool dynamic_only,
                       bool point_allowed)
{
    float v[3], p[3] = { 0, 0, 0 };
    // Check the arguments before the handle's kind so that messages name the argument.
    scr_check_self(L, OBJ_BODY, fn, NULL);
    scr_arg_vec(L, 2, fn, name, -1e9, 1e9, unit, v);
    bool at_point = point_allowed && !lua_isnoneornil(L, 3);
    if (at_point) scr_arg_vec(L, 3, fn, "point", -MAX_COORD, MAX_COORD, "m", p);
    command *c = body_edit(L, fn, type, dynamic_only);
    memcpy(c->u.vec.v, v, sizeof v);
    memcpy(c->u.vec.p, p, sizeof p);
    c->u.vec.at_point = at_point;
    return 0;
}

// Forces act over the next step: they are applied as the impulse F dt at its start (the
// coupling steps Bullet several times per frame and Bullet clears forces after each).
static int m_body_apply_force(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    vector_edit(L, "body:apply_force", CMD_BODY_IMPULSE, "force", "N", true, true);
    command *c = &s->commands[s->command_count - 1];
    for (int k = 0; k < 3; k++) c->u.vec.v[k] *= (float)s->host.dt;
    return 0;
}

static int m_body_apply_torque(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    vector_edit(L, "body:apply_torque", CMD_BODY_ANGULAR_IMPULSE, "torque", "N m", true, false);
    command *c = &s->commands[s->command_count - 1];
    for (int k = 0; k < 3; k++) c->u.vec.v[k] *= (float)s->host.dt;
    return 0;
}

static int m_body_apply_impulse(lua_State *L)
{
    return vector_edit(L, "body:apply_impulse", CMD_BODY_IMPULSE, "impulse", "N s", true, true);
}

static int m_body_apply_angular_impulse(lua_State *L)
{
    return vector_edit(L, "body:apply_angular_impulse", CMD_BODY_ANGULAR_IMPULSE, "impulse", "N m s", true, false);
}

static int m_body_set_velocity(lua_State *L)
{
    return vector_edit(L, "body:set_velocity", CMD_BODY_VELOCITY, "velocity", "m/s", false, false);
}

static int m_body_set_angular_velocity(lua_State *L)
{
    return vector_edit(L, "body:set_angular_velocity", CMD_BODY_ANGULAR_VELOCITY, "velocity", "rad/s", false, false);
}

// pose(position [, rotation]) arguments of move_to and teleport.
static void read_pose_args(lua_State *L, const char *fn, obj *o, float pos[3], float rot[4])
{
    scr_arg_vec(L, 2, fn, "position", -MAX_COORD, MAX_COORD, "m", pos);
    if (lua_isnoneornil(L, 3)) {
        scr_body_state(scr_get_script(L), o, NULL, rot, NULL, NULL);
        return;
    }
    // scr_opt_rotation reads a field: wrap the argument in a table.
    lua_createtable(L, 0, 1);
    lua_pushvalue(L, 3);
    lua_setfield(L, -2, "rotation");
    char sub[64];
    snprintf(sub, sizeof sub, "%s: argument #2", fn);
    scr_opt_rotation(L, lua_gettop(L), sub, "rotation", rot);
    lua_pop(L, 1);
}

static int m_body_move_to(lua_State *L)
{
    const char *fn = "body:move_to";
    obj *o = scr_check_self(L, OBJ_BODY, fn, NULL);
    float pos[3], rot[4];
    read_pose_args(L, fn, o, pos, rot);
    if (o->u.body.def.type != PHYS_BODY_KINEMATIC)
        scr_raise(L, "%s: the body is %s: move_to drives kinematic bodies (use teleport, set_velocity or forces)", fn,
                  scr_body_kind_name[o->u.body.def.type]);
    command *c = body_edit(L, fn, CMD_BODY_MOVE_TO, false);
    memcpy(c->u.pose.pos, pos, sizeof pos);
    memcpy(c->u.pose.rot, rot, sizeof rot);
    return 0;
}

static int m_body_teleport(lua_State *L)
{
    const char *fn = "body:teleport";
    obj *o = scr_check_self(L, OBJ_BODY, fn, NULL);
    float pos[3], rot[4];
    read_pose_args(L, fn, o, pos, rot);
    command *c = body_edit(L, fn, CMD_BODY_TELEPORT, false);
    memcpy(c->u.pose.pos, pos, sizeof pos);
    memcpy(c->u.pose.rot, rot, sizeof rot);
    if (o->state == OBJ_PENDING) { // not in the world yet: change its def instead
        o->u.body.def.position = scr_pv(pos);
        o->u.body.def.orientation = scr_pq(rot);
    }
    return 0;
}

static int m_body_set_color(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_BODY, "body:set_color", &slot);
    float c3[3];
    char what[] = "argument #1 'color'";
    scr_check_vec_at(L, 2, "body:set_color", what, 3, 0.0, 1.0, 0, "", c3);
    memcpy(o->u.body.color, c3, sizeof c3);
    command *c = scr_push_command(L, s, CMD_BODY_LOOK, "body:set_color");
    c->slot = slot;
    c->gen = o->generation;
    return 0;
}

static int m_body_set_visible(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_BODY, "body:set_visible", &slot);
    char got[64];
    if (!lua_isboolean(L, 2))
        scr_raise(L, "body:set_visible: argument #1 'visible' must be true or false (got %s)", scr_describe(L, 2, got, sizeof got));
    o->u.body.visible = lua_toboolean(L, 2);
    command *c = scr_push_command(L, s, CMD_BODY_LOOK, "body:set_visible");
    c->slot = slot;
    c->gen = o->generation;
    return 0;
}

// Releases the grabs that hold body `slot` (Bullet destroys their constraints with it).
static void release_grabs_of(eng_script *s, uint32_t slot, uint32_t gen)
{
    for (uint32_t i = 0; i < s->obj_count; i++) {
        obj *g = &s->objs[i];
        if (g->state != OBJ_FREE && g->kind == OBJ_GRAB && g->u.grab.body == slot && g->u.grab.body_gen == gen)
            scr_obj_release(s, i);
    }
}

static int m_body_destroy(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_BODY, "body:destroy", &slot);
    if (o->state == OBJ_LIVE) {
        command *c = scr_push_command(L, s, CMD_BODY_REMOVE, "body:destroy");
        c->u.body.id = o->u.body.id;
        c->u.body.shape = o->u.body.shape_id;
        c->u.body.node = o->u.body.node;
        c->u.body.mesh = o->u.body.mesh;
    }
    release_grabs_of(s, slot, o->generation);
    scr_obj_release(s, slot);
    return 0;
}

static int m_body_grab(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "body:grab";
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_BODY, fn, &slot);
    float p[3];
    scr_arg_vec(L, 2, fn, "point", -MAX_COORD, MAX_COORD, "m", p);
    double max_force = 0;
    if (!lua_isnoneornil(L, 3)) max_force = scr_arg_number(L, 3, fn, "max_force", 0, 1e9, OPEN_LO, "N");
    if (o->u.body.def.type != PHYS_BODY_DYNAMIC)
        scr_raise(L, "%s: the body is %s: only dynamic bodies can be grabbed", fn, scr_body_kind_name[o->u.body.def.type]);
    uint32_t body_gen = o->generation;
    uint32_t g = scr_obj_new(L, s, OBJ_GRAB);
    obj *go = &s->objs[g];
    go->u.grab.body = slot;
    go->u.grab.body_gen = body_gen;
    memcpy(go->u.grab.pivot, p, sizeof p);
    go->u.grab.max_force = (float)max_force;
    command *c = scr_push_command(L, s, CMD_GRAB_ADD, fn);
    c->slot = g;
    c->gen = go->generation;
    scr_push_handle(L, s, g);
    return 1;
}

// ---- grabs ------------------------------------------------------------------------------

static int m_grab_move(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_GRAB, "grab:move", &slot);
    float p[3];
    scr_arg_vec(L, 2, "grab:move", "point", -MAX_COORD, MAX_COORD, "m", p);
    memcpy(o->u.grab.pivot, p, sizeof p);
    command *c = scr_push_command(L, s, CMD_GRAB_MOVE, "grab:move");
    c->slot = slot;
    c->gen = o->generation;
    memcpy(c->u.vec.v, p, sizeof p);
    return 0;
}

static int m_grab_release(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    uint32_t slot;
    obj *o = scr_check_self(L, OBJ_GRAB, "grab:release", &slot);
    if (o->state == OBJ_LIVE) {
        command *c = scr_push_command(L, s, CMD_GRAB_REMOVE, "grab:release");
        c->u.constraint = o->u.grab.id;
    }
    scr_obj_release(s, slot);
    return 0;
}

static int m_grab_body(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    obj *o = scr_check_self(L, OBJ_GRAB, "grab:body", NULL);
    scr_push_handle(L, s, o->u.grab.body);
    return 1;
}

static int m_grab_pivot(lua_State *L)
{
    obj *o = scr_check_self(L, OBJ_GRAB, "grab:pivot", NULL);
    scr_push_vec3(L, o->u.grab.pivot[0], o->u.grab.pivot[1], o->u.grab.pivot[2]);
    return 1;
}

// ---- timers -----------------------------------------------------------------------------

static int new_timer(lua_State *L, const char *fn, bool repeat)
{
    eng_script *s = scr_get_script(L);
    double d = scr_arg_number(L, 1, fn, repeat ? "period" : "delay", repeat ? 0 : 0, 1e9, repeat ? OPEN_LO : 0, "s");
    char got[64];
    if (!lua_isfunction(L, 2))
        scr_raise(L, "%s: argument #2 'callback' must be a function (got %s)", fn, scr_describe(L, 2, got, sizeof got));
    uint32_t slot = scr_obj_new(L, s, OBJ_TIMER);
    obj *o = &s->objs[slot];
    lua_pushvalue(L, 2);
    o->u.timer.fn = luaL_ref(L, LUA_REGISTRYINDEX);
    o->u.timer.due = s->host.time + d;
    o->u.timer.period = repeat ? d : 0.0;
    o->state = OBJ_LIVE; // timers are the script's own: nothing to queue
    scr_push_handle(L, s, slot);
    return 1;
}

static int l_after(lua_State *L) { return new_timer(L, "seiche.after", false); }
static int l_every(lua_State *L) { return new_timer(L, "seiche.every", true); }

static int m_timer_cancel(lua_State *L)
{
    uint32_t slot;
    scr_check_self(L, OBJ_TIMER, "timer:cancel", &slot);
    scr_obj_release(scr_get_script(L), slot);
    return 0;
}

static int m_timer_remaining(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    obj *o = scr_check_self(L, OBJ_TIMER, "timer:remaining", NULL);
    double r = o->u.timer.due - s->host.time;
    lua_pushnumber(L, r > 0 ? r : 0);
    return 1;
}

// ---- runtime settings ------------------------------------------------------------------

static const pbf_param_info *check_param_name(lua_State *L, int idx, const char *fn)
{
    char got[64];
    const pbf_param_info *info = lua_type(L, idx) == LUA_TSTRING ? pbf_param_find(lua_tostring(L, idx)) : NULL;
    if (!info) {
        int n;
        const pbf_param_info *tab = pbf_param_table(&n);
        char list[512] = "";
        size_t len = 0;
        for (int i = 0; i < n && len < sizeof list; i++) len += (size_t)snprintf(list + len, sizeof list - len, "%s%s", i ? ", " : "", tab[i].name);
        scr_raise(L, "%s: argument #%d 'name' must be a fluid parameter name (one of %s) (got %s)", fn, idx, list,
                  scr_describe(L, idx, got, sizeof got));
    }
    return info;
}

static int l_set_param(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.set_param";
    const pbf_param_info *info = check_param_name(L, 1, fn);
    char what[96];
    snprintf(what, sizeof what, "argument #2 'value' (%s)", info->name);
    double v = scr_check_number_at(L, 2, fn, what, info->min, info->max, info->is_int ? WHOLE : 0, info->unit);
    pbf_params p = *scr_current_params(s);
    char err[512];
    if (pbf_params_set(&p, info->name, v, err, sizeof err) != PBF_OK) scr_raise(L, "%s: %s", fn, err);
    if (!s->host.world) { // main chunk: part of the scene description
        s->config.params = p;
        return 0;
    }
    s->pending_params = p;
    s->have_pending_params = true;
    command *c = scr_push_command(L, s, CMD_PARAMS, fn);
    c->u.params = p;
    return 0;
}

static int l_param(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const pbf_param_info *info = check_param_name(L, 1, "seiche.param");
    lua_pushnumber(L, pbf_params_get(scr_current_params(s), info));
    return 1;
}

static int l_params(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    int n;
    const pbf_param_info *tab = pbf_param_table(&n);
    const pbf_params *p = scr_current_params(s);
    lua_createtable(L, 0, n);
    for (int i = 0; i < n; i++) scr_set_num(L, tab[i].name, pbf_params_get(p, &tab[i]));
    return 1;
}

static int l_set_gravity(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    float g[3];
    scr_arg_vec(L, 1, "seiche.set_gravity", "gravity", -1000, 1000, "m/s^2", g);
    if (!s->host.world) {
        memcpy(s->config.params.gravity, g, sizeof g);
        return 0;
    }
    pbf_params p = *scr_current_params(s);
    memcpy(p.gravity, g, sizeof g);
    s->pending_params = p;
    s->have_pending_params = true;
    command *c = scr_push_command(L, s, CMD_GRAVITY, "seiche.set_gravity");
    memcpy(c->u.gravity, g, sizeof g);
    return 0;
}

static int l_gravity(lua_State *L)
{
    const float *g = scr_current_params(scr_get_script(L))->gravity;
    scr_push_vec3(L, g[0], g[1], g[2]);
    return 1;
}

// ---- queries --------------------------------------------------------------------------

static int l_stats(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const pbf_step_stats *st = s->host.stats;
    lua_createtable(L, 0, 12);
    scr_set_num(L, "particles", st ? st->particles : (s->host.world ? pbf_world_particle_count(s->host.world) : 0));
    scr_set_num(L, "capacity", scr_capacity_of(s));
    scr_set_num(L, "rho0", scr_current_params(s)->rest_density);
    scr_set_num(L, "rho_avg", st ? st->density_avg : 0.0);
    scr_set_num(L, "rho_max", st ? st->density_max : 0.0);
    scr_set_num(L, "nan", st ? st->nan_count : 0);
    scr_set_num(L, "outside", st ? st->outside_count : 0);
    scr_set_num(L, "overflow", st ? st->overflow_count : 0);
    scr_set_num(L, "step_ms", st ? st->step_ms : 0.0);
    scr_set_num(L, "step", st ? (double)st->step : -1.0);
    scr_set_num(L, "time", st ? st->time : 0.0);
    lua_createtable(L, 0, PBF_STAGE_COUNT);
    for (int k = 0; k < PBF_STAGE_COUNT; k++) scr_set_num(L, pbf_stage_name((pbf_stage)k), st ? st->stage_ms[k] : 0.0);
    lua_setfield(L, -2, "stage_ms");
    return 1;
}

static int l_time(lua_State *L)
{
    lua_pushnumber(L, scr_get_script(L)->host.time);
    return 1;
}

static int l_frame(lua_State *L)
{
    lua_pushinteger(L, (lua_Integer)scr_get_script(L)->host.frame);
    return 1;
}

static int l_dt(lua_State *L)
{
    lua_pushnumber(L, scr_get_script(L)->host.dt);
    return 1;
}

static int l_renderer(lua_State *L)
{
    const char *r = scr_get_script(L)->host.renderer;
    lua_pushstring(L, r ? r : "");
    return 1;
}

static int l_headless(lua_State *L)
{
    lua_pushboolean(L, scr_get_script(L)->host.headless);
    return 1;
}

static int l_particle_count(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    lua_pushinteger(L, s->host.world ? (lua_Integer)pbf_world_particle_count(s->host.world) : 0);
    return 1;
}

static int l_capacity(lua_State *L)
{
    lua_pushinteger(L, scr_capacity_of(scr_get_script(L)));
    return 1;
}

static int l_max_emitter_rate(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.max_emitter_rate";
    double speed = scr_arg_number(L, 1, fn, "speed", 0, 100, OPEN_LO, "m/s");
    double radius = scr_arg_number(L, 2, fn, "radius", scr_current_params(s)->particle_radius, 10, 0, "m (the particle radius at least)");
    scr_require_world(L, s, fn);
    lua_pushnumber(L, pbf_emitter_max_rate(s->host.world, (float)speed, (float)radius));
    return 1;
}

// Downloads the particle positions once per frame for the queries that need them.
static const float *particle_positions(lua_State *L, eng_script *s, const char *fn, uint32_t *count)
{
    scr_require_world(L, s, fn);
    if (!s->cache_valid || s->cache_frame != s->host.frame) {
        uint32_t n = pbf_world_particle_count(s->host.world);
        if (n > s->cache_cap) {
            float *c = realloc(s->cache, (size_t)n * 4 * sizeof(float));
            if (!c) scr_raise(L, "%s: out of memory for %u particles", fn, n);
            s->cache = c;
            s->cache_cap = n;
        }
        s->cache_count = n ? pbf_world_read_particles(s->host.world, s->cache, NULL, NULL, n) : 0;
        s->cache_frame = s->host.frame;
        s->cache_valid = true;
    }
    *count = s->cache_count;
    return s->cache;
}

static int l_surface_height(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.surface_height";
    double x = scr_arg_number(L, 1, fn, "x", -MAX_COORD, MAX_COORD, 0, "m");
    double z = scr_arg_number(L, 2, fn, "z", -MAX_COORD, MAX_COORD, 0, "m");
    const pbf_params *p = scr_current_params(s);
    double r = p->kernel_radius;
    if (!lua_isnoneornil(L, 3)) r = scr_arg_number(L, 3, fn, "radius", 0, 100, OPEN_LO, "m");
    uint32_t n;
    const float *pos = particle_positions(L, s, fn, &n);
    double best = -HUGE_VAL;
    for (uint32_t i = 0; i < n; i++) {
        double dx = pos[4 * i] - x, dz = pos[4 * i + 2] - z;
        if (dx * dx + dz * dz <= r * r && pos[4 * i + 1] > best) best = pos[4 * i + 1];
    }
    if (best == -HUGE_VAL) lua_pushnil(L);
    else lua_pushnumber(L, best + p->particle_radius);
    return 1;
}

static int l_particles_in(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.particles_in";
    float mn[3], mx[3];
    scr_arg_vec(L, 1, fn, "min", -MAX_COORD, MAX_COORD, "m", mn);
    scr_arg_vec(L, 2, fn, "max", -MAX_COORD, MAX_COORD, "m", mx);
    uint32_t n;
    const float *pos = particle_positions(L, s, fn, &n);
    lua_Integer count = 0;
    for (uint32_t i = 0; i < n; i++) {
        const float *q = pos + 4 * i;
        if (q[0] >= mn[0] && q[0] <= mx[0] && q[1] >= mn[1] && q[1] <= mx[1] && q[2] >= mn[2] && q[2] <= mx[2]) count++;
    }
    lua_pushinteger(L, count);
    return 1;
}

static int find_body_slot(eng_script *s, phys_body_id id)
{
    for (uint32_t i = 0; i < s->obj_count; i++) {
        obj *o = &s->objs[i];
        if (o->state == OBJ_LIVE && o->kind == OBJ_BODY && o->u.body.id.index1 == id.index1 &&
            o->u.body.id.generation == id.generation && o->u.body.id.world0 == id.world0)
            return (int)i;
    }
    return -1;
}

static int l_ray_cast(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.ray_cast";
    float a[3], b[3];
    scr_arg_vec(L, 1, fn, "from", -MAX_COORD, MAX_COORD, "m", a);
    scr_arg_vec(L, 2, fn, "to", -MAX_COORD, MAX_COORD, "m", b);
    if (a[0] == b[0] && a[1] == b[1] && a[2] == b[2]) scr_raise(L, "%s: arguments 'from' and 'to' must differ", fn);
    scr_require_world(L, s, fn);
    // The container's walls are thick Bullet boxes: a ray from a camera outside the
    // container would stop at the near wall's outer face. Rays that start outside begin
    // where they enter the container instead (they still hit its floor and far walls).
    double t0 = 0.0;
    const eng_scene_config *cf = &s->config;
    if (cf->has_container) {
        bool outside = false;
        double enter = 0.0, leave = 1.0;
        for (int k = 0; k < 3; k++) {
            double o = a[k], d = (double)b[k] - a[k], lo = cf->container_min[k], hi = cf->container_max[k];
            if (o < lo || o > hi) outside = true;
            if (fabs(d) < 1e-12) {
                if (o < lo || o > hi) enter = 2.0; // parallel and outside: never enters
                continue;
            }
            double t1 = (lo - o) / d, t2 = (hi - o) / d;
            if (t1 > t2) { double tmp = t1; t1 = t2; t2 = tmp; }
            if (t1 > enter) enter = t1;
            if (t2 < leave) leave = t2;
        }
        if (outside && enter <= leave && enter < 1.0) t0 = enter + 1e-6;
    }
    float a0[3] = { (float)(a[0] + t0 * (b[0] - a[0])), (float)(a[1] + t0 * (b[1] - a[1])), (float)(a[2] + t0 * (b[2] - a[2])) };
    phys_ray_hit hit;
    if (phys_world_ray_cast(s->host.phys, scr_pv(a0), scr_pv(b), &hit) != PHYS_OK) scr_raise(L, "%s: %s", fn, phys_world_last_error(s->host.phys));
    if (!hit.hit) {
        lua_pushnil(L);
        return 1;
    }
    lua_createtable(L, 0, 4);
    int slot = find_body_slot(s, hit.body);
    if (slot >= 0) {
        scr_push_handle(L, s, (uint32_t)slot);
        lua_setfield(L, -2, "body");
    }
    scr_push_vec3(L, hit.point.x, hit.point.y, hit.point.z);
    lua_setfield(L, -2, "point");
    scr_push_vec3(L, hit.normal.x, hit.normal.y, hit.normal.z);
    lua_setfield(L, -2, "normal");
    scr_set_num(L, "fraction", t0 + hit.fraction * (1.0 - t0));
    return 1;
}

static int l_screen_ray(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.screen_ray";
    int w = s->host.view_width > 0 ? s->host.view_width : 1, h = s->host.view_height > 0 ? s->host.view_height : 1;
    double x = scr_arg_number(L, 1, fn, "x", -1e6, 1e6, 0, "pixels");
    double y = scr_arg_number(L, 2, fn, "y", -1e6, 1e6, 0, "pixels");
    if (!s->host.camera) scr_raise(L, "%s: there is no camera yet; call this from a callback", fn);
    mat4 view, proj, vp, inv;
    eng_camera_view(s->host.camera, view);
    eng_camera_projection(s->host.camera, (float)w / (float)h, proj);
    glm_mat4_mul(proj, view, vp);
    glm_mat4_inv(vp, inv);
    float nx = (float)(2.0 * x / w - 1.0), ny = (float)(1.0 - 2.0 * y / h);
    vec4 pn = { nx, ny, -1.0f, 1.0f }, pf = { nx, ny, 1.0f, 1.0f }, wn, wf;
    glm_mat4_mulv(inv, pn, wn);
    glm_mat4_mulv(inv, pf, wf);
    float o[3], d[3];
    for (int k = 0; k < 3; k++) {
        o[k] = wn[k] / wn[3];
        d[k] = wf[k] / wf[3] - o[k];
    }
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (int k = 0; k < 3; k++) d[k] /= len;
    scr_push_vec3(L, o[0], o[1], o[2]);
    scr_push_vec3(L, d[0], d[1], d[2]);
    return 2;
}

// The pixel where a world point appears: x, y from the top-left corner, and whether the
// point is in front of the camera.
static int l_screen_point(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.screen_point";
    float p[3];
    scr_arg_vec(L, 1, fn, "point", -MAX_COORD, MAX_COORD, "m", p);
    if (!s->host.camera) scr_raise(L, "%s: there is no camera yet; call this from a callback", fn);
    int w = s->host.view_width > 0 ? s->host.view_width : 1, h = s->host.view_height > 0 ? s->host.view_height : 1;
    mat4 view, proj, vp;
    eng_camera_view(s->host.camera, view);
    eng_camera_projection(s->host.camera, (float)w / (float)h, proj);
    glm_mat4_mul(proj, view, vp);
    vec4 q = { p[0], p[1], p[2], 1.0f }, c;
    glm_mat4_mulv(vp, q, c);
    bool front = c[3] > 1e-6f;
    float iw = front ? 1.0f / c[3] : 0.0f;
    lua_pushnumber(L, (c[0] * iw * 0.5 + 0.5) * w);
    lua_pushnumber(L, (0.5 - c[1] * iw * 0.5) * h);
    lua_pushboolean(L, front);
    return 3;
}

static int l_bodies(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    lua_newtable(L);
    lua_Integer n = 0;
    for (uint32_t i = 0; i < s->obj_count; i++)
        if (s->objs[i].state != OBJ_FREE && s->objs[i].kind == OBJ_BODY) {
            scr_push_handle(L, s, i);
            lua_rawseti(L, -2, ++n);
        }
    return 1;
}

static int check_key_name(lua_State *L, int idx, const char *fn)
{
    char got[64];
    int code = lua_type(L, idx) == LUA_TSTRING ? eng_key_code(lua_tostring(L, idx)) : -1;
    if (code < 0)
        scr_raise(L, "%s: argument #%d 'key' must be a key name: \"a\"..\"z\", \"0\"..\"9\", \"f1\"..\"f12\", \"space\", "
                  "\"enter\", \"escape\", \"tab\", \"backspace\", \"left\", \"right\", \"up\", \"down\", \"shift\", \"ctrl\" (got %s)",
                  fn, idx, scr_describe(L, idx, got, sizeof got));
    return code;
}

static int l_key_down(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    int code = check_key_name(L, 1, "seiche.key_down");
    bool down = s->host.input && eng_input_key_down(s->host.input, code);
    if (!down && code == GLFW_KEY_LEFT_SHIFT && s->host.input) down = eng_input_key_down(s->host.input, GLFW_KEY_RIGHT_SHIFT);
    if (!down && code == GLFW_KEY_LEFT_CONTROL && s->host.input) down = eng_input_key_down(s->host.input, GLFW_KEY_RIGHT_CONTROL);
    lua_pushboolean(L, down);
    return 1;
}

static int l_mouse_down(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    int b = (int)scr_arg_number(L, 1, "seiche.mouse_down", "button", 1, ENG_INPUT_MAX_BUTTONS, WHOLE, "(1 left, 2 right, 3 middle)");
    lua_pushboolean(L, s->host.input && eng_input_mouse_down(s->host.input, b - 1));
    return 1;
}

static int l_mouse_position(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    double x = 0, y = 0;
    if (s->host.input) eng_input_mouse_position(s->host.input, &x, &y);
    lua_pushnumber(L, x);
    lua_pushnumber(L, y);
    return 2;
}

// ---- test support ----------------------------------------------------------------------

static int l_check(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    luaL_checkany(L, 1);
    if (lua_toboolean(L, 1)) return 0;
    const char *msg = lua_isnoneornil(L, 2) ? "(no message)" : luaL_tolstring(L, 2, NULL);
    s->check_failed = true;
    luaL_where(L, 1);
    lua_pushfstring(L, "%scheck failed: %s", lua_tostring(L, -1), msg);
    return lua_error(L);
}

static int l_quit(lua_State *L)
{
    scr_get_script(L)->quit = true;
    return 0;
}

static const char *const ACTIONS[3] = { "release", "press", "repeat" }; // = eng_action

static int read_action(lua_State *L, int idx, const char *fn)
{
    if (lua_isnoneornil(L, idx)) return ENG_PRESS;
    if (lua_type(L, idx) == LUA_TSTRING)
        for (int k = 0; k < 3; k++)
            if (strcmp(lua_tostring(L, idx), ACTIONS[k]) == 0) return k;
    char got[64];
    return scr_raise(L, "%s: argument #%d 'action' must be \"press\", \"release\" or \"repeat\" (got %s)", fn, idx,
                     scr_describe(L, idx, got, sizeof got));
}

// Injected input is not a world edit: it waits in its own queue for the start of the
// next frame (eng_script_deliver_input).
static eng_event *push_event(lua_State *L, eng_script *s, const char *fn)
{
    if (s->event_count == s->event_cap) {
        int cap = s->event_cap ? 2 * s->event_cap : 16;
        if (cap > ENG_INPUT_QUEUE_CAPACITY) scr_raise(L, "%s: more than %d events injected in one frame", fn, ENG_INPUT_QUEUE_CAPACITY);
        eng_event *e = realloc(s->events, (size_t)cap * sizeof *e);
        if (!e) scr_raise(L, "%s: out of memory", fn);
        s->events = e;
        s->event_cap = cap;
    }
    eng_event *e = &s->events[s->event_count++];
    memset(e, 0, sizeof *e);
    return e;
}

static int l_inject_key(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.inject_key";
    int code = check_key_name(L, 1, fn);
    int action = read_action(L, 2, fn);
    eng_event *e = push_event(L, s, fn);
    e->type = ENG_EVENT_KEY;
    e->key = code;
    e->action = action;
    return 0;
}

static int l_inject_mouse(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.inject_mouse";
    int b = (int)scr_arg_number(L, 1, fn, "button", 1, ENG_INPUT_MAX_BUTTONS, WHOLE, "(1 left, 2 right, 3 middle)");
    int action = read_action(L, 2, fn);
    if (action == ENG_REPEAT) scr_raise(L, "%s: argument #2 'action' must be \"press\" or \"release\" (got \"repeat\")", fn);
    double x = 0, y = 0;
    if (s->host.input) eng_input_mouse_position(s->host.input, &x, &y);
    if (!lua_isnoneornil(L, 3)) x = scr_arg_number(L, 3, fn, "x", -1e6, 1e6, 0, "pixels");
    if (!lua_isnoneornil(L, 4)) y = scr_arg_number(L, 4, fn, "y", -1e6, 1e6, 0, "pixels");
    // A button event happens where the pointer is: move it there first.
    eng_event *e = push_event(L, s, fn);
    e->type = ENG_EVENT_MOTION;
    e->x = x;
    e->y = y;
    e = push_event(L, s, fn);
    e->type = ENG_EVENT_MOUSE_BUTTON;
    e->button = b - 1;
    e->action = action;
    e->x = x;
    e->y = y;
    return 0;
}

static int l_inject_motion(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.inject_motion";
    double x = scr_arg_number(L, 1, fn, "x", -1e6, 1e6, 0, "pixels");
    double y = scr_arg_number(L, 2, fn, "y", -1e6, 1e6, 0, "pixels");
    eng_event *e = push_event(L, s, fn);
    e->type = ENG_EVENT_MOTION;
    e->x = x;
    e->y = y;
    return 0;
}

static int l_inject_scroll(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.inject_scroll";
    double dx = scr_arg_number(L, 1, fn, "dx", -1e4, 1e4, 0, "steps");
    double dy = scr_arg_number(L, 2, fn, "dy", -1e4, 1e4, 0, "steps");
    eng_event *e = push_event(L, s, fn);
    e->type = ENG_EVENT_SCROLL;
    e->dx = dx;
    e->dy = dy;
    return 0;
}

// ---- registration ------------------------------------------------------------------------

static const luaL_Reg seiche_functions[] = {
    // scene setup
    { "scene", l_scene }, { "set_look", l_set_look }, { "look", l_look }, { "set_camera", l_set_camera },
    { "camera", l_camera }, { "set_param", l_set_param }, { "param", l_param }, { "params", l_params },
    { "set_gravity", l_set_gravity }, { "gravity", l_gravity },
    // content
    { "block", l_block }, { "sphere", l_sphere }, { "particles", l_particles }, { "emitter", l_emitter },
    { "sink", l_sink }, { "body", l_body }, { "bodies", l_bodies },
    // interaction
    { "after", l_after }, { "every", l_every }, { "key_down", l_key_down }, { "mouse_down", l_mouse_down },
    { "mouse_position", l_mouse_position }, { "screen_ray", l_screen_ray }, { "screen_point", l_screen_point },
    { "ray_cast", l_ray_cast },
    // queries
    { "particle_count", l_particle_count }, { "capacity", l_capacity }, { "stats", l_stats },
    { "surface_height", l_surface_height }, { "particles_in", l_particles_in }, { "max_emitter_rate", l_max_emitter_rate },
    { "time", l_time }, { "frame", l_frame }, { "dt", l_dt }, { "renderer", l_renderer }, { "headless", l_headless },
    // test support
    { "check", l_check }, { "quit", l_quit }, { "inject_key", l_inject_key }, { "inject_mouse", l_inject_mouse },
    { "inject_motion", l_inject_motion }, { "inject_scroll", l_inject_scroll },
    { NULL, NULL },
};

static const luaL_Reg emitter_methods[] = {
    { "set", m_emitter_set }, { "set_enabled", m_emitter_set_enabled }, { "get", m_emitter_get },
    { "remove", m_emitter_remove }, { "is_valid", scr_is_valid }, { NULL, NULL },
};

static const luaL_Reg sink_methods[] = {
    { "get", m_sink_get }, { "remove", m_sink_remove }, { "is_valid", scr_is_valid }, { NULL, NULL },
};

static const luaL_Reg body_methods[] = {
    { "position", m_body_position }, { "rotation", m_body_rotation }, { "velocity", m_body_velocity },
    { "angular_velocity", m_body_angular_velocity }, { "velocity_at", m_body_velocity_at }, { "mass", m_body_mass },
    { "kind", m_body_kind }, { "shape", m_body_shape }, { "fluid_force", m_body_fluid_force },
    { "apply_force", m_body_apply_force }, { "apply_torque", m_body_apply_torque },
    { "apply_impulse", m_body_apply_impulse }, { "apply_angular_impulse", m_body_apply_angular_impulse },
    { "set_velocity", m_body_set_velocity }, { "set_angular_velocity", m_body_set_angular_velocity },
    { "move_to", m_body_move_to }, { "teleport", m_body_teleport }, { "set_color", m_body_set_color },
    { "set_visible", m_body_set_visible }, { "grab", m_body_grab }, { "destroy", m_body_destroy },
    { "is_valid", scr_is_valid }, { NULL, NULL },
};

static const luaL_Reg timer_methods[] = {
    { "cancel", m_timer_cancel }, { "remaining", m_timer_remaining }, { "is_valid", scr_is_valid }, { NULL, NULL },
};

static const luaL_Reg grab_methods[] = {
    { "move", m_grab_move }, { "release", m_grab_release }, { "body", m_grab_body }, { "pivot", m_grab_pivot },
    { "is_valid", scr_is_valid }, { NULL, NULL },
};

static const luaL_Reg *const METHODS[OBJ_KIND_COUNT] = { emitter_methods, sink_methods, body_methods, timer_methods,
                                                         grab_methods };

static const char *const CALLBACKS[] = { "on_start", "on_step", "on_key", "on_mouse", "on_mouse_move", "on_scroll",
                                         "on_reload", NULL };

const char *const *eng_script_function_names(void)
{
    static const char *names[sizeof seiche_functions / sizeof seiche_functions[0]];
    for (size_t i = 0; i < sizeof seiche_functions / sizeof seiche_functions[0]; i++) names[i] = seiche_functions[i].name;
    return names;
}

const char *const *eng_script_api_names(void)
{
    static char storage[4096];
    static const char *names[160];
    if (names[0]) return names;
    size_t used = 0;
    int n = 0;
    for (const luaL_Reg *r = seiche_functions; r->name; r++) {
        names[n++] = storage + used;
        used += (size_t)snprintf(storage + used, sizeof storage - used, "seiche.%s", r->name) + 1;
    }
    for (int k = 0; k < OBJ_KIND_COUNT; k++)
        for (const luaL_Reg *r = METHODS[k]; r->name; r++) {
            names[n++] = storage + used;
            used += (size_t)snprintf(storage + used, sizeof storage - used, "%s:%s", scr_kind_name[k], r->name) + 1;
        }
    for (const char *const *c = CALLBACKS; *c; c++) names[n++] = *c;
    names[n] = NULL;
    return names;
}


static void register_api(eng_script *s)
{
    lua_State *L = s->L;
    lua_newtable(L);
    lua_pushlightuserdata(L, s);
    luaL_setfuncs(L, seiche_functions, 1);
    lua_pushstring(L, "0.1");
    lua_setfield(L, -2, "version");
    lua_setglobal(L, "seiche");
    for (int k = 0; k < OBJ_KIND_COUNT; k++) scr_new_handle_type(L, s, (obj_kind)k, METHODS[k]);
}

// ---- running Lua ---------------------------------------------------------------------

static void budget_hook(lua_State *L, lua_Debug *ar)
{
    (void)ar;
    eng_script *s = registry_script(L);
    if (s->deadline > 0.0 && now_s() > s->deadline)
        scr_raise(L, "%s ran longer than its budget of %g s (an endless loop?)", s->running ? s->running : "the script",
                  s->budget_s);
}

static void *limited_alloc(void *ud, void *ptr, size_t osize, size_t nsize)
{
    eng_script *s = ud;
    if (ptr == NULL) osize = 0;
    if (nsize == 0) {
        free(ptr);
        s->memory -= osize;
        return NULL;
    }
    if (nsize > osize && s->memory + (nsize - osize) > LUA_MEMORY_LIMIT) {
        s->out_of_memory = true;
        return NULL;
    }
    void *p = realloc(ptr, nsize);
    if (p) s->memory = s->memory - osize + nsize;
    return p;
}

static int traceback(lua_State *L)
{
    const char *msg = lua_tostring(L, 1);
    if (!msg) msg = lua_pushfstring(L, "(error object is a %s value)", luaL_typename(L, 1));
    luaL_traceback(L, L, msg, 1);
    return 1;
}

// Calls the function below the nargs arguments on the stack with `nresults` results left
// on the stack on success.
static eng_script_status run(eng_script *s, int nargs, int nresults, const char *what)
{
    lua_State *L = s->L;
    int base = lua_gettop(L) - nargs;
    lua_pushcfunction(L, traceback);
    lua_insert(L, base);
    s->running = what;
    s->deadline = now_s() + s->budget_s;
    s->out_of_memory = false;
    int rc = lua_pcall(L, nargs, nresults, base);
    s->deadline = 0.0;
    s->running = NULL;
    lua_remove(L, base);
    if (rc == LUA_OK) return ENG_SCRIPT_OK;
    if (rc == LUA_ERRMEM || s->out_of_memory)
        snprintf(s->error, sizeof s->error, "%s: %s used more than the script's %zu MiB of memory (%s)", s->path, what,
                 LUA_MEMORY_LIMIT >> 20, lua_tostring(L, -1) ? lua_tostring(L, -1) : "not enough memory");
    else
        snprintf(s->error, sizeof s->error, "%s", lua_tostring(L, -1) ? lua_tostring(L, -1) : "(unknown error)");
    lua_pop(L, 1);
    return s->check_failed ? ENG_SCRIPT_CHECK_FAILED : ENG_SCRIPT_ERROR;
}

eng_script *eng_script_create(const eng_logger *log, double budget_s)
{
    if (!(budget_s > 0.0 && budget_s <= 3600.0)) return NULL;
    eng_script *s = calloc(1, sizeof *s);
    if (!s) return NULL;
    s->log = log ? *log : eng_default_logger();
    s->budget_s = budget_s;
    s->config = eng_default_scene_config();
    s->host.dt = 1.0 / 60.0;
    s->L = lua_newstate(limited_alloc, s);
    if (!s->L) {
        free(s);
        return NULL;
    }
    luaL_openlibs(s->L);
    lua_pushlightuserdata(s->L, s);
    lua_setfield(s->L, LUA_REGISTRYINDEX, REGISTRY_KEY);
    register_api(s);
    lua_sethook(s->L, budget_hook, LUA_MASKCOUNT, 10000);
    return s;
}

void eng_script_destroy(eng_script *s)
{
    if (!s) return;
    for (uint32_t i = 0; i < s->obj_count; i++) {
        obj *o = &s->objs[i];
        if (o->state == OBJ_FREE || o->kind != OBJ_BODY) continue;
        if (s->host.scene && o->u.body.node.index1) eng_node_destroy(s->host.scene, o->u.body.node);
        if (s->host.meshes && o->u.body.mesh.index1) eng_mesh_destroy(s->host.meshes, o->u.body.mesh);
        scr_body_free_data(&o->u.body);
    }
    scr_clear_commands(s);
    lua_close(s->L);
    free(s->commands);
    free(s->objs);
    free(s->cache);
    free(s->events);
    free(s);
}

static eng_script_status load_chunk(eng_script *s, int rc)
{
    if (rc != LUA_OK) {
        snprintf(s->error, sizeof s->error, "%s", lua_tostring(s->L, -1) ? lua_tostring(s->L, -1) : "(load error)");
        lua_pop(s->L, 1);
        return ENG_SCRIPT_ERROR;
    }
    s->in_main_chunk = true;
    eng_script_status st = run(s, 0, 0, "the script's main chunk");
    s->in_main_chunk = false;
    return st;
}

eng_script_status eng_script_load(eng_script *s, const char *path)
{
    snprintf(s->path, sizeof s->path, "%s", path);
    FILE *f = fopen(path, "rb");
    if (!f) {
        snprintf(s->error, sizeof s->error, "%s: cannot open the script file", path);
        return ENG_SCRIPT_ERROR;
    }
    fclose(f);
    return load_chunk(s, luaL_loadfile(s->L, path));
}

eng_script_status eng_script_load_string(eng_script *s, const char *chunk_name, const char *code)
{
    snprintf(s->path, sizeof s->path, "%s", chunk_name);
    char name[520];
    snprintf(name, sizeof name, "@%s", chunk_name);
    return load_chunk(s, luaL_loadbuffer(s->L, code, strlen(code), name));
}

const char *eng_script_error(const eng_script *s) { return s->error; }
const char *eng_script_path(const eng_script *s) { return s->path; }
eng_scene_config *eng_script_config(eng_script *s) { return &s->config; }
void eng_script_set_host(eng_script *s, const eng_script_host *host) { s->host = *host; }
bool eng_script_quit_requested(const eng_script *s) { return s->quit; }
int eng_script_pending(const eng_script *s) { return s->command_count; }

bool eng_script_set_param(eng_script *s, const char *name, double value, char *err, size_t err_size)
{
    pbf_params p = *scr_current_params(s);
    if (pbf_params_set(&p, name, value, err, err_size) != PBF_OK) return false;
    if (s->host.world) {
        if (pbf_world_set_params(s->host.world, &p) != PBF_OK) {
            snprintf(err, err_size, "%s", pbf_world_last_error(s->host.world));
            return false;
        }
        if (s->have_pending_params) s->pending_params = p;
    } else {
        s->config.params = p;
    }
    return true;
}

// ---- callbacks --------------------------------------------------------------------------

static bool get_callback(eng_script *s, const char *name)
{
    lua_getglobal(s->L, name);
    if (lua_isfunction(s->L, -1)) return true;
    lua_pop(s->L, 1);
    return false;
}

eng_script_status eng_script_on_start(eng_script *s)
{
    if (!get_callback(s, "on_start")) return ENG_SCRIPT_OK;
    return run(s, 0, 0, "on_start");
}

// Fires the timers due at `time`, earliest first (a repeating timer as often as it is
// due, so a period shorter than the frame step still fires the right number of times).
static eng_script_status fire_timers(eng_script *s, double time)
{
    for (int fired = 0; fired < 100000; fired++) {
        uint32_t best = UINT32_MAX;
        for (uint32_t i = 0; i < s->obj_count; i++) {
            obj *o = &s->objs[i];
            if (o->state != OBJ_LIVE || o->kind != OBJ_TIMER || o->u.timer.due > time + 1e-9) continue;
            if (best == UINT32_MAX || o->u.timer.due < s->objs[best].u.timer.due) best = i;
        }
        if (best == UINT32_MAX) return ENG_SCRIPT_OK;
        obj *o = &s->objs[best];
        lua_rawgeti(s->L, LUA_REGISTRYINDEX, o->u.timer.fn);
        lua_pushnumber(s->L, time);
        if (o->u.timer.period > 0) o->u.timer.due += o->u.timer.period;
        else scr_obj_release(s, best); // one-shot: done before it runs (it may make new timers)
        eng_script_status st = run(s, 1, 0, "a timer callback");
        if (st != ENG_SCRIPT_OK) return st;
    }
    return ENG_SCRIPT_OK;
}

eng_script_status eng_script_on_step(eng_script *s, double dt, double time)
{
    if (!s->capacity_warned && s->host.world && pbf_world_particle_count(s->host.world) >= pbf_world_capacity(s->host.world)) {
        for (uint32_t i = 0; i < s->obj_count; i++)
            if (s->objs[i].state == OBJ_LIVE && s->objs[i].kind == OBJ_EMITTER && s->objs[i].u.emitter.def.enabled) {
                eng_log(&s->log, ENG_LOG_WARN, "%s: the fluid is at its capacity of %u particles: emitters pour nothing "
                        "until sinks make room (raise seiche.scene{capacity = ...})", s->path,
                        pbf_world_capacity(s->host.world));
                s->capacity_warned = true;
                break;
            }
    }
    eng_script_status st = ENG_SCRIPT_OK;
    if (get_callback(s, "on_step")) {
        lua_pushnumber(s->L, dt);
        lua_pushnumber(s->L, time);
        st = run(s, 2, 0, "on_step");
    }
    if (st == ENG_SCRIPT_OK) st = fire_timers(s, time);
    return st;
}

eng_script_status eng_script_on_key(eng_script *s, const char *key, const char *action)
{
    if (!get_callback(s, "on_key")) return ENG_SCRIPT_OK;
    lua_pushstring(s->L, key);
    lua_pushstring(s->L, action);
    return run(s, 2, 0, "on_key");
}

eng_script_status eng_script_on_mouse(eng_script *s, int button, const char *action, double x, double y, bool *consumed)
{
    if (consumed) *consumed = false;
    if (!get_callback(s, "on_mouse")) return ENG_SCRIPT_OK;
    lua_pushinteger(s->L, button);
    lua_pushstring(s->L, action);
    lua_pushnumber(s->L, x);
    lua_pushnumber(s->L, y);
    eng_script_status st = run(s, 4, 1, "on_mouse");
    if (st == ENG_SCRIPT_OK) {
        if (consumed) *consumed = lua_toboolean(s->L, -1);
        lua_pop(s->L, 1);
    }
    return st;
}

eng_script_status eng_script_on_mouse_move(eng_script *s, double x, double y, double dx, double dy)
{
    if (!get_callback(s, "on_mouse_move")) return ENG_SCRIPT_OK;
    lua_pushnumber(s->L, x);
    lua_pushnumber(s->L, y);
    lua_pushnumber(s->L, dx);
    lua_pushnumber(s->L, dy);
    return run(s, 4, 0, "on_mouse_move");
}

eng_script_status eng_script_on_scroll(eng_script *s, double dx, double dy)
{
    if (!get_callback(s, "on_scroll")) return ENG_SCRIPT_OK;
    lua_pushnumber(s->L, dx);
    lua_pushnumber(s->L, dy);
    return run(s, 2, 0, "on_scroll");
}

eng_script_status eng_script_on_reload(eng_script *s)
{
    if (!get_callback(s, "on_reload")) return ENG_SCRIPT_OK;
    return run(s, 0, 0, "on_reload");
}

// ---- key names ------------------------------------------------------------------------------

const char *eng_key_name(int key)
{
    static const char *const letters[26] = { "a", "b", "c", "d", "e", "f", "g", "h", "i", "j", "k", "l", "m",
                                             "n", "o", "p", "q", "r", "s", "t", "u", "v", "w", "x", "y", "z" };
    if (key >= GLFW_KEY_A && key <= GLFW_KEY_Z) return letters[key - GLFW_KEY_A];
    static const char *const digits[] = { "0", "1", "2", "3", "4", "5", "6", "7", "8", "9" };
    if (key >= GLFW_KEY_0 && key <= GLFW_KEY_9) return digits[key - GLFW_KEY_0];
    static const char *const fkeys[] = { "f1", "f2", "f3", "f4", "f5", "f6", "f7", "f8", "f9", "f10", "f11", "f12" };
    if (key >= GLFW_KEY_F1 && key <= GLFW_KEY_F12) return fkeys[key - GLFW_KEY_F1];
    switch (key) {
    case GLFW_KEY_SPACE: return "space";
    case GLFW_KEY_ENTER: return "enter";
    case GLFW_KEY_ESCAPE: return "escape";
    case GLFW_KEY_TAB: return "tab";
    case GLFW_KEY_BACKSPACE: return "backspace";
    case GLFW_KEY_LEFT: return "left";
    case GLFW_KEY_RIGHT: return "right";
    case GLFW_KEY_UP: return "up";
    case GLFW_KEY_DOWN: return "down";
    case GLFW_KEY_LEFT_SHIFT: case GLFW_KEY_RIGHT_SHIFT: return "shift";
    case GLFW_KEY_LEFT_CONTROL: case GLFW_KEY_RIGHT_CONTROL: return "ctrl";
    default: return NULL;
    }
}

int eng_key_code(const char *name)
{
    if (!name) return -1;
    for (int k = 0; k <= GLFW_KEY_LAST; k++) {
        const char *n = eng_key_name(k);
        if (n && strcmp(n, name) == 0) return k;
    }
    return -1;
}
