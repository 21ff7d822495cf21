// Binds the particle measurements: seiche.particle_data, region_stats, surface_height and
// particles_in. They share one download of the particle state per frame (positions,
// velocities, densities: pbf_world_read_fields), so several queries in a frame cost one.
#include "engine/script/script_internal.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// Lays the cache out as positions (3n floats), velocities (3n), densities (n).
static void fields_of(eng_script *s, const float **pos, const float **vel, const float **rho)
{
    size_t cap = s->cache_cap;
    *pos = s->cache;
    *vel = s->cache + 3 * cap;
    *rho = s->cache + 6 * cap;
}

// Downloads the particles once per frame for the queries that need them; returns the count.
static uint32_t particle_fields(lua_State *L, eng_script *s, const char *fn, const float **pos, const float **vel,
                                const float **rho)
{
    scr_require_world(L, s, fn);
    if (!s->cache_valid || s->cache_frame != s->host.frame) {
        uint32_t n = pbf_world_particle_count(s->host.world);
        if (n > s->cache_cap || !s->cache) {
            float *c = realloc(s->cache, (size_t)(n ? n : 1) * 7 * sizeof(float));
            if (!c) scr_raise(L, "%s: out of memory for %u particles", fn, n);
            s->cache = c;
            s->cache_cap = n ? n : 1;
        }
        size_t cap = s->cache_cap;
        uint32_t got = 0;
        if (n > 0 && pbf_world_read_fields(s->host.world, NULL, NULL, s->cache, s->cache + 3 * cap, s->cache + 6 * cap,
                                           (uint32_t)cap, &got) != PBF_OK)
            scr_raise(L, "%s: reading the particles failed: %s", fn, pbf_world_last_error(s->host.world));
        s->cache_count = got < cap ? got : (uint32_t)cap;
        s->cache_frame = s->host.frame;
        s->cache_valid = true;
    }
    fields_of(s, pos, vel, rho);
    return s->cache_count;
}

static bool in_box(const float *x, const float mn[3], const float mx[3])
{
    return x[0] >= mn[0] && x[0] <= mx[0] && x[1] >= mn[1] && x[1] <= mx[1] && x[2] >= mn[2] && x[2] <= mx[2];
}

// ---- seiche.particle_data{fields, min, max, flat} -------------------------------------------

enum { F_POSITION = 1, F_VELOCITY = 2, F_DENSITY = 4 };

static int read_field_list(lua_State *L, const char *fn)
{
    static const char *const names[] = { "position", "velocity", "density" };
    lua_getfield(L, 1, "fields");
    if (lua_isnil(L, -1)) {
        lua_pop(L, 1);
        return F_POSITION | F_VELOCITY | F_DENSITY;
    }
    char got[64];
    if (!lua_istable(L, -1))
        scr_raise(L, "%s: field 'fields' must be a list of \"position\", \"velocity\", \"density\" (got %s)", fn,
                  scr_describe(L, -1, got, sizeof got));
    int mask = 0;
    lua_Integer n = scr_len(L, -1, fn, "field 'fields'");
    for (lua_Integer i = 1; i <= n && i <= 8; i++) {
        lua_geti(L, -1, i);
        const char *name = lua_type(L, -1) == LUA_TSTRING ? lua_tostring(L, -1) : NULL;
        int k = 0;
        while (name && k < 3 && strcmp(name, names[k]) != 0) k++;
        if (!name || k == 3)
            scr_raise(L, "%s: fields[%lld] must be \"position\", \"velocity\" or \"density\" (got %s)", fn, (long long)i,
                      scr_describe(L, -1, got, sizeof got));
        mask |= 1 << k;
        lua_pop(L, 1);
    }
    if (mask == 0 || n > 8) scr_raise(L, "%s: field 'fields' must name 1 to 3 fields (got %lld entries)", fn, (long long)n);
    lua_pop(L, 1);
    return mask;
}

// Reads the optional box of an options table at index 1: both corners or neither.
static bool read_opt_box(lua_State *L, const char *fn, float mn[3], float mx[3])
{
    bool has_min = scr_field_present(L, 1, "min");
    if (has_min) lua_pop(L, 1);
    bool has_max = scr_field_present(L, 1, "max");
    if (has_max) lua_pop(L, 1);
    if (!has_min && !has_max) return false;
    scr_read_box(L, 1, fn, mn, mx);
    return true;
}

static void push_triple_list(lua_State *L, const float *v, const uint32_t *sel, uint32_t m)
{
    lua_createtable(L, (int)(3 * m), 0);
    for (uint32_t i = 0; i < m; i++)
        for (int k = 0; k < 3; k++) {
            lua_pushnumber(L, v[3 * (size_t)sel[i] + k]);
            lua_rawseti(L, -2, (lua_Integer)(3 * i + k + 1));
        }
}

static int l_particle_data(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.particle_data";
    if (lua_isnoneornil(L, 1)) {
        lua_settop(L, 0);
        lua_newtable(L);
    }
    scr_check_table_arg(L, 1, fn, "fields, min, max, flat");
    static const char *const known[] = { "fields", "min", "max", "flat", NULL };
    scr_check_fields(L, 1, fn, known);
    int mask = read_field_list(L, fn);
    float mn[3], mx[3];
    bool boxed = read_opt_box(L, fn, mn, mx);
    bool flat = false;
    scr_opt_bool(L, 1, fn, "flat", &flat);
    const float *pos, *vel, *rho;
    uint32_t n = particle_fields(L, s, fn, &pos, &vel, &rho);
    uint32_t *sel = lua_newuserdatauv(L, (size_t)(n ? n : 1) * sizeof *sel, 0); // collected if a push raises
    uint32_t m = 0;
    for (uint32_t i = 0; i < n; i++)
        if (!boxed || in_box(pos + 3 * (size_t)i, mn, mx)) sel[m++] = i;
    if (flat) {
        lua_createtable(L, 0, 4);
        lua_pushinteger(L, m);
        lua_setfield(L, -2, "count");
        if (mask & F_POSITION) push_triple_list(L, pos, sel, m), lua_setfield(L, -2, "position");
        if (mask & F_VELOCITY) push_triple_list(L, vel, sel, m), lua_setfield(L, -2, "velocity");
        if (mask & F_DENSITY) {
            lua_createtable(L, (int)m, 0);
            for (uint32_t i = 0; i < m; i++) {
                lua_pushnumber(L, rho[sel[i]]);
                lua_rawseti(L, -2, (lua_Integer)i + 1);
            }
            lua_setfield(L, -2, "density");
        }
        return 1;
    }
    lua_createtable(L, (int)m, 0);
    for (uint32_t i = 0; i < m; i++) {
        uint32_t j = sel[i];
        lua_createtable(L, 0, 3);
        if (mask & F_POSITION) {
            scr_push_vec3(L, pos[3 * (size_t)j], pos[3 * (size_t)j + 1], pos[3 * (size_t)j + 2]);
            lua_setfield(L, -2, "position");
        }
        if (mask & F_VELOCITY) {
            scr_push_vec3(L, vel[3 * (size_t)j], vel[3 * (size_t)j + 1], vel[3 * (size_t)j + 2]);
            lua_setfield(L, -2, "velocity");
        }
        if (mask & F_DENSITY) scr_set_num(L, "density", rho[j]);
        lua_rawseti(L, -2, (lua_Integer)i + 1);
    }
    return 1;
}

// ---- seiche.region_stats(min, max) -----------------------------------------------------------

static int l_region_stats(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.region_stats";
    float mn[3], mx[3];
    scr_arg_vec(L, 1, fn, "min", -MAX_COORD, MAX_COORD, "m", mn);
    scr_arg_vec(L, 2, fn, "max", -MAX_COORD, MAX_COORD, "m", mx);
    static const char axis[] = "xyz";
    for (int k = 0; k < 3; k++)
        if (!(mx[k] >= mn[k]))
            scr_raise(L, "%s: max.%c must be at least min.%c (got min %g, max %g)", fn, axis[k], axis[k], (double)mn[k],
                      (double)mx[k]);
    const float *pos, *vel, *rho;
    uint32_t n = particle_fields(L, s, fn, &pos, &vel, &rho);
    pbf_region_stats r;
    pbf_region_stats_of(pos, vel, rho, n, pbf_world_particle_mass(s->host.world), mn, mx, &r);
    lua_createtable(L, 0, 10);
    scr_set_int(L, "particles", r.particles);
    scr_set_num(L, "mass", r.mass);
    scr_set_num(L, "rho_avg", r.density_avg);
    scr_set_num(L, "rho_max", r.density_max);
    scr_set_num(L, "kinetic_energy", r.kinetic_energy);
    scr_set_num(L, "speed_max", r.speed_max);
    scr_push_vec3(L, r.velocity[0], r.velocity[1], r.velocity[2]);
    lua_setfield(L, -2, "velocity");
    scr_push_vec3(L, r.momentum[0], r.momentum[1], r.momentum[2]);
    lua_setfield(L, -2, "momentum");
    scr_push_vec3(L, r.center_of_mass[0], r.center_of_mass[1], r.center_of_mass[2]);
    lua_setfield(L, -2, "center_of_mass");
    return 1;
}

// ---- seiche.surface_height(x, z [, radius [, mode]]) -----------------------------------------

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

enum { SURF_LEVEL, SURF_MEAN, SURF_TOP };

static int l_surface_height(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.surface_height";
    double x = scr_arg_number(L, 1, fn, "x", -MAX_COORD, MAX_COORD, 0, "m");
    double z = scr_arg_number(L, 2, fn, "z", -MAX_COORD, MAX_COORD, 0, "m");
    const pbf_params *p = scr_current_params(s);
    double r = p->kernel_radius;
    if (!lua_isnoneornil(L, 3)) r = scr_arg_number(L, 3, fn, "radius", 0, 100, OPEN_LO, "m");
    static const char *const modes[] = { "level", "mean", "top" };
    int mode = SURF_LEVEL;
    if (!lua_isnoneornil(L, 4)) {
        const char *m = lua_type(L, 4) == LUA_TSTRING ? lua_tostring(L, 4) : NULL;
        while (m && mode < 3 && strcmp(m, modes[mode]) != 0) mode++;
        char got[64];
        if (!m || mode == 3)
            scr_raise(L, "%s: mode must be \"level\", \"mean\" or \"top\" (got %s)", fn, scr_describe(L, 4, got, sizeof got));
    }
    const float *pos, *vel, *rho;
    uint32_t n = particle_fields(L, s, fn, &pos, &vel, &rho);
    // Columns one spacing wide: each keeps its highest particle. "level" is the median of the
    // column tops (a few spray drops above the water do not move it), "mean" their mean,
    // "top" the highest particle.
    double cell = 2.0 * p->particle_radius;
    int side = (int)ceil(r / cell);
    if (side > 256) side = 256; // radius / spacing; more columns change nothing a median sees
    int width = 2 * side + 1;
    float *top = lua_newuserdatauv(L, (size_t)width * width * sizeof(float), 0);
    for (int i = 0; i < width * width; i++) top[i] = -HUGE_VALF;
    // A column counts when its centre is within the radius, with every particle in it (a
    // column cut by the circle would lose its top to the cut now and then).
    for (uint32_t i = 0; i < n; i++) {
        const float *q = pos + 3 * (size_t)i;
        double dx = q[0] - x, dz = q[2] - z;
        double fx = floor(dx / cell + 0.5), fz = floor(dz / cell + 0.5);
        if (fx < -side || fz < -side || fx > side || fz > side) continue;
        if (mode != SURF_TOP ? (fx * fx + fz * fz) * cell * cell > r * r : dx * dx + dz * dz > r * r) continue;
        int cx = (int)fx + side, cz = (int)fz + side;
        float *t = &top[cz * width + cx];
        if (q[1] > *t) *t = q[1];
    }
    int used = 0;
    for (int i = 0; i < width * width; i++)
        if (top[i] > -HUGE_VALF) top[used++] = top[i];
    if (used == 0) {
        lua_pushnil(L);
        return 1;
    }
    double h;
    if (mode == SURF_TOP) {
        h = top[0];
        for (int i = 1; i < used; i++) h = top[i] > h ? top[i] : h;
    } else if (mode == SURF_MEAN) {
        h = 0.0;
        for (int i = 0; i < used; i++) h += top[i];
        h /= used;
    } else {
        qsort(top, (size_t)used, sizeof *top, cmp_float);
        h = used % 2 ? top[used / 2] : 0.5 * ((double)top[used / 2 - 1] + top[used / 2]);
    }
    lua_pushnumber(L, h + p->particle_radius);
    return 1;
}

static int l_particles_in(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.particles_in";
    float mn[3], mx[3];
    scr_arg_vec(L, 1, fn, "min", -MAX_COORD, MAX_COORD, "m", mn);
    scr_arg_vec(L, 2, fn, "max", -MAX_COORD, MAX_COORD, "m", mx);
    const float *pos, *vel, *rho;
    uint32_t n = particle_fields(L, s, fn, &pos, &vel, &rho);
    lua_Integer count = 0;
    for (uint32_t i = 0; i < n; i++)
        if (in_box(pos + 3 * (size_t)i, mn, mx)) count++;
    lua_pushinteger(L, count);
    return 1;
}

static const luaL_Reg functions[] = {
    { "particle_data", l_particle_data }, { "region_stats", l_region_stats },
    { "surface_height", l_surface_height }, { "particles_in", l_particles_in }, { NULL, NULL },
};

void scr_open_measure(scr_api *api) { scr_api_functions(api, functions); }
