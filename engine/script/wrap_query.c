// Binds the queries (seiche.stats, time, frame, dt, particle_count, capacity, max_emitter_rate,
// renderer, headless) and test support (check, quit). The particle measurements are in
// wrap_measure.c.
#include "engine/script/script_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// ---- queries --------------------------------------------------------------------------

static int l_stats(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const pbf_step_stats *st = s->host.stats;
    lua_createtable(L, 0, 18);
    scr_set_int(L, "particles", st ? st->particles : (s->host.world ? pbf_world_particle_count(s->host.world) : 0));
    scr_set_int(L, "capacity", scr_capacity_of(s));
    scr_set_num(L, "rho0", scr_current_params(s)->rest_density);
    scr_set_num(L, "rho_avg", st ? st->density_avg : 0.0);
    scr_set_num(L, "rho_max", st ? st->density_max : 0.0);
    scr_set_int(L, "nan", st ? st->nan_count : 0);
    scr_set_int(L, "outside", st ? st->outside_count : 0);
    scr_set_int(L, "overflow", st ? st->overflow_count : 0);
    scr_set_num(L, "step_ms", st ? st->step_ms : 0.0);
    scr_set_int(L, "step", st ? (lua_Integer)st->step : -1);
    scr_set_num(L, "time", st ? st->time : 0.0);
    scr_set_num(L, "mass", st ? st->mass : 0.0);
    scr_set_num(L, "kinetic_energy", st ? st->kinetic_energy : 0.0);
    scr_set_num(L, "speed_max", st ? st->speed_max : 0.0);
    lua_pushinteger(L, st ? st->substeps : scr_current_params(s)->substeps);
    lua_setfield(L, -2, "substeps");
    scr_set_num(L, "rho_err_avg", st ? st->density_error_avg : 0.0);
    const double zero[3] = { 0, 0, 0 };
    const double *mom = st ? st->momentum : zero, *com = st ? st->center_of_mass : zero;
    scr_push_vec3(L, mom[0], mom[1], mom[2]);
    lua_setfield(L, -2, "momentum");
    scr_push_vec3(L, com[0], com[1], com[2]);
    lua_setfield(L, -2, "center_of_mass");
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

// ---- test support ----------------------------------------------------------------------

// The record of the calling line's check (NULL when the table is full).
static eng_check_site *check_site(lua_State *L, eng_script *s)
{
    lua_Debug ar;
    const char *src = "";
    int line = 0;
    if (lua_getstack(L, 1, &ar) && lua_getinfo(L, "Sl", &ar)) {
        src = ar.source[0] == '@' ? ar.source + 1 : "";
        line = ar.currentline;
    }
    for (int i = 0; i < s->check_count; i++)
        if (s->checks[i].line == line && strcmp(s->checks[i].source, src) == 0) return &s->checks[i];
    if (s->check_count == ENG_SCRIPT_MAX_CHECK_SITES) return NULL;
    eng_check_site *c = &s->checks[s->check_count++];
    memset(c, 0, sizeof *c);
    snprintf(c->source, sizeof c->source, "%s", src);
    c->line = line;
    return c;
}

static int l_check(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    luaL_checkany(L, 1);
    eng_check_site *site = check_site(L, s);
    if (lua_toboolean(L, 1)) {
        if (site) site->passed++;
        return 0;
    }
    const char *msg = lua_isnoneornil(L, 2) ? "(no message)" : luaL_tolstring(L, 2, NULL);
    if (site && site->failed++ == 0) snprintf(site->message, sizeof site->message, "%s", msg);
    // A stop, not an ordinary error: pcall(seiche.check, false) cannot hide a failed check.
    return scr_stop(L, s, STOP_CHECK, "check failed: %s", msg);
}

static int l_quit(lua_State *L)
{
    scr_get_script(L)->quit = true;
    return 0;
}

static const luaL_Reg functions[] = {
    { "particle_count", l_particle_count }, { "capacity", l_capacity }, { "stats", l_stats },
    { "max_emitter_rate", l_max_emitter_rate },
    { "time", l_time }, { "frame", l_frame }, { "dt", l_dt }, { "renderer", l_renderer }, { "headless", l_headless },
    { "check", l_check }, { "quit", l_quit }, { NULL, NULL },
};

void scr_open_query(scr_api *api) { scr_api_functions(api, functions); }
