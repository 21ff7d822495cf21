// Binds seiche.scene (the scene description: fluid, container, domain, camera, look),
// seiche.set_look / look and seiche.set_camera / camera.
#include "engine/script/script_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

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
    // Every given field first, then the set checked as a whole (pbf_params_apply).
    const char *names[64];
    double values[64];
    int given = 0;
    for (int i = 0; i < n && given < 64; i++) {
        double v;
        if (!scr_opt_number(L, t, "seiche.scene: fluid", tab[i].name, -1e30, 1e30, 0, tab[i].unit, &v)) continue;
        names[given] = tab[i].name;
        values[given++] = v;
    }
    char err[512];
    if (pbf_params_apply(p, names, values, given, err, sizeof err) != PBF_OK) {
        // "pbf_params.NAME must be ...": "field 'NAME' must be ...", as the table spells it.
        char lua[512];
        scr_raise(L, "seiche.scene: fluid: %s", scr_lua_wording(err, lua, sizeof lua));
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
        scr_check_table_field(L, l, fn, "light", "direction, colour, ambient");
        static const char *const lk[] = { "direction", "colour", "color", "ambient", NULL };
        scr_check_fields(L, l, sub, lk);
        float d[3];
        if (scr_opt_vec(L, l, sub, "direction", 3, -1e6, 1e6, 0, "", d)) {
            if (!(fabsf(d[0]) + fabsf(d[1]) + fabsf(d[2]) > 0.0f))
                scr_raise(L, "%s: field 'direction' must not be zero (it points from the scene towards the light)", sub);
            memcpy(k->light.direction, d, sizeof d);
        }
        const char *colour = scr_colour_field(L, l, sub);
        if (colour) scr_opt_vec(L, l, sub, colour, 3, 0.0, 4.0, 0, "", k->light.color);
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
    if (s->scene_called) // scene_where is "file:line: "
        scr_raise(L, "seiche.scene: called twice (the first call was at %.*s)",
                  (int)strcspn(s->config.scene_where, " ") - 1, s->config.scene_where);
    static const char *const known[] = { "name", "preset", "fluid", "gravity", "capacity", "container", "domain", "camera",
                                         "look", NULL };
    scr_check_fields(L, 1, "seiche.scene", known);
    eng_scene_config *c = &s->config;
    static const char *const presets[] = { "default", "seed" };
    int preset = scr_opt_enum(L, 1, "seiche.scene", "preset", presets, 2);
    if (preset == 0) c->params = pbf_default_params();
    if (preset == 1) {
        c->params = pbf_seed_params();
        char where[256];
        eng_log(&s->log, ENG_LOG_WARN,
                "%sseiche.scene: preset \"seed\" is the first version's parameter set, kept for comparison, not "
                "for use: one substep of a 1/60 s frame lets particles move about a spacing per solve, so its water "
                "compresses by up to 30 %% where a dam breaks (its time-step guard is off), and its artificial "
                "pressure (s_corr k = 0.1) pushes particles apart; use the default preset (docs/solver.md)",
                scr_where(L, where, sizeof where));
    }
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
    scr_where(L, c->scene_where, sizeof c->scene_where);
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
    lua_pushvalue(L, -1);
    lua_setfield(L, -3, "colour");
    lua_setfield(L, -2, "color"); // both spellings, as the field takes them
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

static const luaL_Reg functions[] = {
    { "scene", l_scene }, { "set_look", l_set_look }, { "look", l_look }, { "set_camera", l_set_camera },
    { "camera", l_camera }, { NULL, NULL },
};

void scr_open_scene(scr_api *api) { scr_api_functions(api, functions); }
