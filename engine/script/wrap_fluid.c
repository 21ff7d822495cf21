// Binds the fluid: its parameters (seiche.set_param, param, params), gravity (set_gravity,
// gravity), the coupling's settings (seiche.coupling) and content (seiche.block, sphere,
// particles).
#include "engine/script/script_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
    char lua[512];
    if (pbf_params_set(&p, info->name, v, err, sizeof err) != PBF_OK)
        scr_raise(L, "%s: %s", fn, scr_lua_wording(err, lua, sizeof lua));
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
    scr_push_value(L, pbf_params_get(scr_current_params(s), info), info->is_int);
    return 1;
}

static int l_params(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    int n;
    const pbf_param_info *tab = pbf_param_table(&n);
    const pbf_params *p = scr_current_params(s);
    lua_createtable(L, 0, n);
    for (int i = 0; i < n; i++) {
        scr_push_value(L, pbf_params_get(p, &tab[i]), tab[i].is_int);
        lua_setfield(L, -2, tab[i].name);
    }
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

// ---- seiche.coupling{...} / seiche.coupling() -------------------------------------------------

static int l_coupling(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.coupling";
    int n;
    const cpl_setting_info *tab = cpl_setting_table(&n);
    if (!lua_isnoneornil(L, 1)) {
        if (s->host.world)
            scr_raise(L, "%s: the coupling is built with the world, from the scene description: set it in the main "
                      "chunk", fn);
        // The fields are the settings' names (cpl_setting_table), listed in messages as
        // "force_latency, force_smoothing, ...".
        const char *known[8] = { NULL };
        char listed[256] = "";
        for (int i = 0, len = 0; i < n && i < 7; i++) {
            known[i] = tab[i].name;
            len += snprintf(listed + len, sizeof listed - (size_t)len, "%s%s", i ? ", " : "", tab[i].name);
            if (len >= (int)sizeof listed) break;
        }
        scr_check_table_arg(L, 1, fn, listed);
        scr_check_fields(L, 1, fn, known);
        cpl_def d = s->config.coupling;
        for (int i = 0; i < n; i++) {
            double v;
            int flags = (tab[i].is_int ? WHOLE : 0) | (tab[i].open_min ? OPEN_LO : 0);
            if (!scr_opt_number(L, 1, fn, tab[i].name, tab[i].min, tab[i].max, flags, tab[i].unit, &v)) continue;
            char err[256];
            char lua[256];
            if (cpl_def_set(&d, tab[i].name, v, err, sizeof err) != CPL_OK)
                scr_raise(L, "%s: %s", fn, scr_lua_wording(err, lua, sizeof lua));
        }
        s->config.coupling = d;
        return 0;
    }
    // The live coupling's settings once it exists, else the description's (with --set).
    cpl_def live;
    const cpl_def *d = s->host.coupling && cpl_get_def(s->host.coupling, &live) == CPL_OK ? &live
                                                                                        : &scr_config_view(s)->coupling;
    lua_createtable(L, 0, n);
    for (int i = 0; i < n; i++) {
        scr_push_value(L, cpl_def_get(d, &tab[i]), tab[i].is_int);
        lua_setfield(L, -2, tab[i].name);
    }
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
    char msg[256];
    if (s->host.world && (!scr_domain_check(s, b.min, "field 'min'", msg, sizeof msg) ||
                          !scr_domain_check(s, b.max, "field 'max'", msg, sizeof msg)))
        scr_raise(L, "seiche.block: %s", msg);
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
    char msg[256];
    if (s->host.world && !scr_points_domain_check(s, pos, n, "positions", msg, sizeof msg))
        scr_raise(L, "seiche.particles: %s", msg);
    if (has_list) {
        lua_getfield(L, 1, "velocity");
        bool both = !lua_isnil(L, -1);
        lua_pop(L, 1);
        if (both) scr_raise(L, "seiche.particles: give either 'velocities' (one per point) or 'velocity' (one for all), not both");
        lua_getfield(L, 1, "velocities");
        lua_Integer nv_given = lua_istable(L, -1) ? scr_len(L, -1, "seiche.particles", "field 'velocities'") : -1;
        lua_pop(L, 1);
        if (nv_given >= 0 && nv_given != (lua_Integer)n)
            scr_raise(L, "seiche.particles: field 'velocities' must hold one velocity per position (%u) (got %lld)", n,
                      (long long)nv_given);
        vel = scr_read_point_list(L, 1, "seiche.particles", "velocities", -MAX_SPEED, MAX_SPEED, "m/s", &nv, n, n);
    } else {
        check_velocity_field(L, 1, "seiche.particles", "velocity", v);
    }
    // The arrays count against the script's memory: refused before anything is made. Then the
    // command (scr_push_command may raise), then the arrays it owns.
    bool has_vel = vel || v[0] != 0 || v[1] != 0 || v[2] != 0;
    size_t bytes = (has_vel ? 2 : 1) * 3 * (size_t)n * sizeof(float);
    scr_charge(L, s, "seiche.particles", bytes);
    scr_uncharge(s, bytes);
    command *c = scr_push_command(L, s, CMD_PARTICLES, "seiche.particles");
    float *p = malloc(3 * (size_t)n * sizeof(float) + 4), *q = has_vel ? malloc(3 * (size_t)n * sizeof(float) + 4) : NULL;
    if (!p || (has_vel && !q)) {
        free(p);
        free(q);
        s->command_count--;
        return scr_raise(L, "seiche.particles: out of memory");
    }
    memcpy(p, pos, 3 * (size_t)n * sizeof(float));
    if (has_vel)
        for (uint32_t i = 0; i < n; i++) memcpy(q + 3 * i, vel ? vel + 3 * i : v, 3 * sizeof(float));
    c->u.particles.pos = p;
    c->u.particles.vel = q;
    c->u.particles.n = n;
    s->c_memory += bytes; // given back when the command is done (free_command)
    return 0;
}

static const luaL_Reg functions[] = {
    { "set_param", l_set_param }, { "param", l_param }, { "params", l_params }, { "set_gravity", l_set_gravity },
    { "gravity", l_gravity }, { "coupling", l_coupling }, { "block", l_block }, { "sphere", l_sphere },
    { "particles", l_particles }, { NULL, NULL },
};

void scr_open_fluid(scr_api *api) { scr_api_functions(api, functions); }
