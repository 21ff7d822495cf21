// Binds the renderer's look of the water: seiche.render{...} (set) and seiche.render() (get).
// The script keeps the look it asked for in its config; the app applies it to the renderer
// before the next frame is drawn (headless too: it shows in screenshots and recordings).
#include "engine/script/script_internal.h"

#include <string.h>

#define RENDER_FIELDS \
    "mode, absorption, scatter, refraction, reflection, specular, shininess, smoothing, spray, spray_speed, " \
    "resolution, density_range, speed_max, shadows, view, splat"

static const char *const known_fields[] = { "mode", "absorption", "scatter", "refraction", "reflection",
                                            "specular", "shininess", "smoothing", "spray", "spray_speed",
                                            "resolution", "density_range", "speed_max", "shadows", "view", "splat",
                                            NULL };

static void push_look(lua_State *L, const eng_fluid_look *k)
{
    lua_createtable(L, 0, 16);
    lua_pushstring(L, eng_fluid_mode_name(k->mode));
    lua_setfield(L, -2, "mode");
    scr_push_vec3(L, k->absorption[0], k->absorption[1], k->absorption[2]);
    lua_setfield(L, -2, "absorption");
    scr_push_vec3(L, k->scatter[0], k->scatter[1], k->scatter[2]);
    lua_setfield(L, -2, "scatter");
    scr_set_num(L, "refraction", k->refraction);
    scr_set_num(L, "reflection", k->reflection);
    scr_set_num(L, "specular", k->specular);
    scr_set_num(L, "shininess", k->shininess);
    scr_set_num(L, "smoothing", k->smoothing);
    scr_set_num(L, "spray", k->spray);
    scr_set_num(L, "spray_speed", k->spray_speed);
    scr_set_num(L, "resolution", k->resolution);
    lua_createtable(L, 2, 0);
    for (int i = 0; i < 2; i++) {
        lua_pushnumber(L, k->density_range[i]);
        lua_rawseti(L, -2, i + 1);
    }
    lua_setfield(L, -2, "density_range");
    scr_set_num(L, "speed_max", k->speed_max);
    lua_pushboolean(L, k->shadows);
    lua_setfield(L, -2, "shadows");
    lua_pushstring(L, eng_fluid_view_name(k->view));
    lua_setfield(L, -2, "view");
    lua_pushstring(L, eng_fluid_splat_name(k->splat));
    lua_setfield(L, -2, "splat");
}

static void opt_float(lua_State *L, const char *field, double lo, double hi, int flags, const char *unit, float *out)
{
    double v;
    if (scr_opt_number(L, 1, "seiche.render", field, lo, hi, flags, unit, &v)) *out = (float)v;
}

// seiche.render{fields}: changes the named fields of the look (the rest stay), checks the
// whole, and asks the app to apply it; returns the look. seiche.render(): the look now.
static int l_render(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    eng_scene_config *c = &s->config;
    // The look now: the last one asked for this frame, else the renderer's.
    eng_fluid_look k = c->fluid_look_generation ? c->fluid_look : s->host.fluid_look;
    if (lua_isnoneornil(L, 1)) {
        push_look(L, &k);
        return 1;
    }
    const char *fn = "seiche.render";
    scr_check_table_arg(L, 1, fn, RENDER_FIELDS);
    scr_check_fields(L, 1, fn, known_fields);
    const char *modes[ENG_FLUID_MODE_COUNT], *views[ENG_FLUID_VIEW_COUNT], *splats[ENG_FLUID_SPLAT_COUNT];
    for (int i = 0; i < ENG_FLUID_MODE_COUNT; i++) modes[i] = eng_fluid_mode_name((eng_fluid_mode)i);
    for (int i = 0; i < ENG_FLUID_VIEW_COUNT; i++) views[i] = eng_fluid_view_name((eng_fluid_view)i);
    int mode = scr_opt_enum(L, 1, fn, "mode", modes, ENG_FLUID_MODE_COUNT);
    if (mode >= 0) k.mode = (eng_fluid_mode)mode;
    int view = scr_opt_enum(L, 1, fn, "view", views, ENG_FLUID_VIEW_COUNT);
    if (view >= 0) k.view = (eng_fluid_view)view;
    for (int i = 0; i < ENG_FLUID_SPLAT_COUNT; i++) splats[i] = eng_fluid_splat_name((eng_fluid_splat)i);
    int splat = scr_opt_enum(L, 1, fn, "splat", splats, ENG_FLUID_SPLAT_COUNT);
    if (splat >= 0) k.splat = (eng_fluid_splat)splat;
    scr_opt_vec(L, 1, fn, "absorption", 3, 0.0, 100.0, 0, "1/m", k.absorption);
    scr_opt_vec(L, 1, fn, "scatter", 3, 0.0, 1.0, 0, "", k.scatter);
    opt_float(L, "refraction", 0.0, 4.0, 0, "", &k.refraction);
    opt_float(L, "reflection", 0.0, 1.0, 0, "", &k.reflection);
    opt_float(L, "specular", 0.0, 8.0, 0, "", &k.specular);
    opt_float(L, "shininess", 1.0, 8192.0, 0, "", &k.shininess);
    opt_float(L, "smoothing", 0.0, 16.0, 0, "particle radii", &k.smoothing);
    opt_float(L, "spray", 0.0, 1.0, 0, "", &k.spray);
    opt_float(L, "spray_speed", 0.0, 1000.0, OPEN_LO, "m/s", &k.spray_speed);
    opt_float(L, "resolution", 0.25, 1.0, 0, "", &k.resolution);
    if (scr_opt_vec(L, 1, fn, "density_range", 2, 1e-3, 10.0, 0, "rho/rho0", k.density_range) &&
        !(k.density_range[1] > k.density_range[0])) // Lua's 1-based indices (the C check counts from 0)
        scr_raise(L, "%s: field 'density_range'[2] must be greater than density_range[1] (got {%g, %g})", fn,
                  (double)k.density_range[0], (double)k.density_range[1]);
    opt_float(L, "speed_max", 0.0, 1000.0, OPEN_LO, "m/s", &k.speed_max);
    scr_opt_bool(L, 1, fn, "shadows", &k.shadows);
    // What one field cannot tell (density_range[1] above [0]).
    char err[256];
    if (!eng_fluid_look_check(&k, fn, err, sizeof err)) return scr_raise(L, "%s", err);
    c->fluid_look = k;
    c->fluid_look_generation++;
    push_look(L, &k);
    return 1;
}

static const luaL_Reg functions[] = {
    { "render", l_render },
    { NULL, NULL },
};

void scr_open_render(scr_api *api)
{
    scr_api_functions(api, functions);
}
