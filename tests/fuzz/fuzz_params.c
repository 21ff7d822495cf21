// libFuzzer harness: the solver parameters by name and as a whole (fluid/pbf.h):
// pbf_params_set, pbf_params_apply, pbf_params_validate, pbf_param_find, pbf_params_get,
// pbf_derive_constants, pbf_suggest_max_neighbours and pbf_world_def_memory, with names and
// values the fuzzer makes (unknown and near-miss names, NULLs, NaN, infinities, huge and
// negative numbers, whole and fractional values for integer fields, raw parameter blocks).
//
// Besides crashes, leaks and undefined behaviour (the sanitizers), it checks the contract:
// - a call that succeeds leaves a set that pbf_params_validate accepts;
// - a call that fails changes nothing and writes a message into err, NUL-terminated within
//   err_size (err is allocated with exactly err_size bytes, so a write past it is caught);
// - results are PBF_OK or PBF_ERR_INVALID_ARG.
// Build and run: make fuzz (docs/testing.md).
#include "fluid/pbf.h"
#include "tests/fuzz/fuzz_input.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const known_names[] = {
    "particle_radius", "kernel_radius", "rest_density", "iterations", "substeps", "relaxation", "sor",
    "scorr_k",         "scorr_n",       "scorr_dq",     "vorticity",  "viscosity", "damping", "max_speed",
    "gravity",         "cfl",           "max_substeps", "guard_compression", "wall_friction", "surface_fill",
    "surface_tension", "",              "PARTICLE_RADIUS", "iterations ", "kernel_radiu",
};

// A name: one of the known ones, or a string made of input bytes (NUL-terminated copy in buf).
static const char *fuzz_name(fuzz_input *in, char *buf, size_t size)
{
    uint8_t how = fuzz_u8(in);
    if (how < 200) return known_names[how % (sizeof known_names / sizeof known_names[0])];
    if (how == 255) return NULL;
    size_t n = fuzz_u8(in) % (size - 1);
    fuzz_bytes(in, buf, n);
    buf[n] = 0;
    return buf;
}

// err of exactly `size` bytes (NULL when size is 0 and the input says so).
static char *fuzz_err(fuzz_input *in, size_t *size)
{
    uint8_t s = fuzz_u8(in);
    *size = s < 16 ? s : s < 200 ? 256 : (size_t)s;
    if (*size == 0 && fuzz_bool(in)) return NULL;
    return fuzz_alloc_exact(*size);
}

static void check_err(const char *err, size_t size, pbf_result r)
{
    if (r != PBF_OK && r != PBF_ERR_INVALID_ARG) {
        fprintf(stderr, "unexpected result %d\n", (int)r);
        abort();
    }
    if (r != PBF_OK && err && size > 0) {
        if (!memchr(err, 0, size)) {
            fprintf(stderr, "err is not NUL-terminated within err_size %zu\n", size);
            abort();
        }
        if (size > 1 && err[0] == 0) {
            fprintf(stderr, "a failure with an empty message\n");
            abort();
        }
    }
}

static void check_set_is_valid(const pbf_params *p, const char *what)
{
    char err[256];
    if (pbf_params_validate(p, err, sizeof err) != PBF_OK) {
        fprintf(stderr, "%s succeeded but left an invalid set: %s\n", what, err);
        abort();
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_input in = { data, size };
    pbf_params p = fuzz_bool(&in) ? pbf_default_params() : pbf_seed_params();
    for (int op = 0; op < 64 && in.size > 0; op++) {
        char name_buf[64];
        size_t err_size;
        char *err = fuzz_err(&in, &err_size);
        pbf_params before = p;
        switch (fuzz_u8(&in) % 8) {
        case 0: { // one parameter by name
            const char *name = fuzz_name(&in, name_buf, sizeof name_buf);
            double v = fuzz_double(&in);
            pbf_params *target = fuzz_u8(&in) == 0 ? NULL : &p;
            pbf_result r = pbf_params_set(target, name, v, err, err_size);
            check_err(err, err_size, r);
            if (r == PBF_OK) check_set_is_valid(&p, "pbf_params_set");
            else if (memcmp(&before, &p, sizeof p) != 0) {
                fprintf(stderr, "pbf_params_set failed but changed the set\n");
                abort();
            }
            break;
        }
        case 1: { // several at once
            int count = (int)(fuzz_u8(&in) % 10) - 1; // -1 .. 8
            const char *names[8];
            char bufs[8][32];
            double values[8];
            for (int i = 0; i < count; i++) {
                names[i] = fuzz_name(&in, bufs[i], sizeof bufs[i]);
                values[i] = fuzz_double(&in);
            }
            uint8_t nulls = fuzz_u8(&in);
            pbf_result r = pbf_params_apply(nulls == 1 ? NULL : &p, nulls == 2 ? NULL : names,
                                            nulls == 3 ? NULL : values, count, err, err_size);
            check_err(err, err_size, r);
            if (r == PBF_OK) check_set_is_valid(&p, "pbf_params_apply");
            else if (memcmp(&before, &p, sizeof p) != 0) {
                fprintf(stderr, "pbf_params_apply failed but changed the set\n");
                abort();
            }
            break;
        }
        case 2: { // a raw block
            pbf_params raw;
            memcpy(&raw, &p, sizeof raw);
            fuzz_bytes(&in, &raw, sizeof raw);
            pbf_result r = pbf_params_validate(fuzz_u8(&in) == 0 ? NULL : &raw, err, err_size);
            check_err(err, err_size, r);
            // Functions of any block, valid or not, must not crash, hang or overflow.
            pbf_constants k = pbf_derive_constants(&raw);
            (void)k;
            (void)pbf_suggest_max_neighbours(&raw);
            if (r == PBF_OK) p = raw;
            break;
        }
        case 3: { // lookup and read back
            const char *name = fuzz_name(&in, name_buf, sizeof name_buf);
            const pbf_param_info *info = pbf_param_find(name);
            bool null_params = fuzz_u8(&in) == 0;
            double v = pbf_params_get(null_params ? NULL : &p, info);
            if ((!info || null_params) != (isnan(v) != 0)) {
                fprintf(stderr, "pbf_params_get gave %g (info %p, params %s)\n", v, (const void *)info,
                        null_params ? "NULL" : "set");
                abort();
            }
            int count = 0;
            const pbf_param_info *table = pbf_param_table(fuzz_bool(&in) ? &count : NULL);
            if (!table) abort();
            break;
        }
        case 4: { // read every field back and set it again: the same set
            int count = 0;
            const pbf_param_info *table = pbf_param_table(&count);
            for (int i = 0; i < count; i++) {
                char e[256];
                double v = pbf_params_get(&p, &table[i]);
                if (pbf_params_set(&p, table[i].name, v, e, sizeof e) != PBF_OK) {
                    fprintf(stderr, "setting %s to its own value %.17g failed: %s\n", table[i].name, v, e);
                    abort();
                }
            }
            if (memcmp(&before, &p, sizeof p) != 0) {
                fprintf(stderr, "setting every field to its own value changed the set\n");
                abort();
            }
            break;
        }
        case 5: { // derived constants of the current (valid) set are finite
            pbf_constants k = pbf_derive_constants(&p);
            if (!isfinite(k.mass) || !isfinite(k.mass_density) || !isfinite(k.poly6) || !isfinite(k.epsilon) ||
                !(k.spacing > 0.0f)) {
                fprintf(stderr, "non-finite constants from a valid set\n");
                abort();
            }
            uint32_t nb = pbf_suggest_max_neighbours(&p);
            if (nb < 8 || nb > 512) abort();
            break;
        }
        case 6: { // the memory a world of a raw def would need
            pbf_world_def def = pbf_default_world_def();
            def.params = p;
            fuzz_bytes(&in, &def.capacity, sizeof def.capacity);
            fuzz_bytes(&in, &def.max_neighbours, sizeof def.max_neighbours);
            fuzz_bytes(&in, &def.grid_cells_per_kernel, sizeof def.grid_cells_per_kernel);
            for (int k = 0; k < 3; k++) {
                def.domain_min[k] = fuzz_float(&in);
                def.domain_max[k] = fuzz_float(&in);
            }
            if (fuzz_bool(&in)) def.params.kernel_radius = fuzz_float(&in);
            (void)pbf_world_def_memory(fuzz_u8(&in) == 0 ? NULL : &def);
            break;
        }
        default: { // names of stages, the version
            (void)pbf_stage_name((pbf_stage)(int)(int8_t)fuzz_u8(&in));
            if (strcmp(pbf_version(), PBF_VERSION_STRING) != 0) abort();
            break;
        }
        }
        fuzz_free_exact(err, err_size);
    }
    return 0;
}
