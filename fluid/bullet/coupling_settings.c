// The coupling's numeric settings by name (cpl_setting_table, cpl_def_set, cpl_def_get,
// cpl_def_check: fluid/bullet/coupling.h), apart from the coupling itself so that a program
// that only reads settings (a command line, its fuzz harness) links without Bullet.
#include "fluid/bullet/coupling.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

cpl_def cpl_default_def(void)
{
    cpl_def d;
    memset(&d, 0, sizeof d);
    d.force_latency = 1;
    d.force_smoothing = 0.5f;
    d.impulse_limit = 1.0f;
    d.lag_damping = 1.5f;
    d.added_mass = 0.5f;
    d.mesh_cell = 0.02f;
    return d;
}

enum { SET_LATENCY, SET_SMOOTHING, SET_IMPULSE, SET_LAG_DAMPING, SET_ADDED_MASS, SET_MESH_CELL, SET_COUNT };

static const cpl_setting_info settings[SET_COUNT] = {
    [SET_LATENCY] = { "force_latency", 1, 7, false, true, "steps" },
    [SET_SMOOTHING] = { "force_smoothing", 0, 0.95, false, false, "" },
    [SET_IMPULSE] = { "impulse_limit", 0, 100, false, false, "(x the acceleration of full submersion)" },
    [SET_LAG_DAMPING] = { "lag_damping", 0, 4, false, false, "(x the force lag's negative damping)" },
    [SET_ADDED_MASS] = { "added_mass", 0, 2, false, false, "(x the mass of the water the body displaces)" },
    [SET_MESH_CELL] = { "mesh_cell", 0, 1, true, false, "m" },
};

const cpl_setting_info *cpl_setting_table(int *count)
{
    if (count) *count = SET_COUNT;
    return settings;
}

const cpl_setting_info *cpl_setting_find(const char *name)
{
    for (int i = 0; name && i < SET_COUNT; i++)
        if (strcmp(name, settings[i].name) == 0) return &settings[i];
    return NULL;
}

double cpl_def_get(const cpl_def *def, const cpl_setting_info *info)
{
    if (!def || !info) return 0.0;
    switch (info - settings) {
    case SET_LATENCY: return def->force_latency;
    case SET_SMOOTHING: return def->force_smoothing;
    case SET_IMPULSE: return def->impulse_limit;
    case SET_LAG_DAMPING: return def->lag_damping;
    case SET_ADDED_MASS: return def->added_mass;
    case SET_MESH_CELL: return def->mesh_cell;
    default: return 0.0;
    }
}

// Checks one value against its setting; writes the message and returns false when wrong.
static bool check_value(const cpl_setting_info *info, double v, char *err, size_t err_size)
{
    bool ok = isfinite(v) && (info->open_min ? v > info->min : v >= info->min) && v <= info->max &&
              (!info->is_int || v == floor(v));
    if (!ok)
        snprintf(err, err_size, "cpl_def.%s must be %sin %c%g, %g]%s%s (got %g)", info->name,
                 info->is_int ? "a whole number " : "", info->open_min ? '(' : '[', info->min, info->max,
                 info->unit[0] ? " " : "", info->unit, v);
    return ok;
}

cpl_result cpl_def_check(const cpl_def *def, char *err, size_t err_size)
{
    char scratch[8];
    if (!err || !err_size) {
        err = scratch;
        err_size = sizeof scratch;
    }
    if (!def) {
        snprintf(err, err_size, "cpl_def_check: def must not be NULL");
        return CPL_ERR_INVALID_ARG;
    }
    for (int i = 0; i < SET_COUNT; i++)
        if (!check_value(&settings[i], cpl_def_get(def, &settings[i]), err, err_size)) return CPL_ERR_INVALID_ARG;
    return CPL_OK;
}

cpl_result cpl_def_set(cpl_def *def, const char *name, double value, char *err, size_t err_size)
{
    char scratch[8];
    if (!err || !err_size) {
        err = scratch;
        err_size = sizeof scratch;
    }
    err[0] = 0;
    if (!def || !name) {
        snprintf(err, err_size, "cpl_def_set: def and name must not be NULL");
        return CPL_ERR_INVALID_ARG;
    }
    const cpl_setting_info *info = cpl_setting_find(name);
    if (!info) {
        size_t len = (size_t)snprintf(err, err_size, "cpl_def_set: unknown setting '%.64s' (known:", name);
        for (int i = 0; i < SET_COUNT && len < err_size; i++)
            len += (size_t)snprintf(err + len, err_size - len, "%s %s", i ? "," : "", settings[i].name);
        if (len < err_size) snprintf(err + len, err_size - len, ")");
        return CPL_ERR_INVALID_ARG;
    }
    if (!check_value(info, value, err, err_size)) return CPL_ERR_INVALID_ARG;
    // The def holds floats: a value in range may still round out of it (1e-89 is 0).
    char unused[8];
    if (!info->is_int && !check_value(info, (double)(float)value, unused, sizeof unused)) {
        snprintf(err, err_size, "cpl_def.%s: %g is %g as a float, outside %c%g, %g]", info->name, value,
                 (double)(float)value, info->open_min ? '(' : '[', info->min, info->max);
        return CPL_ERR_INVALID_ARG;
    }
    switch (info - settings) {
    case SET_LATENCY: def->force_latency = (int)value; break;
    case SET_SMOOTHING: def->force_smoothing = (float)value; break;
    case SET_IMPULSE: def->impulse_limit = (float)value; break;
    case SET_LAG_DAMPING: def->lag_damping = (float)value; break;
    case SET_ADDED_MASS: def->added_mass = (float)value; break;
    default: def->mesh_cell = (float)value; break;
    }
    return CPL_OK;
}

