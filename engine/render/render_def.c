// The renderer's settings: defaults, the fluid modes' names, and the checks of every def,
// look and style field (messages name the field, the value and the range). See renderer.h.
#include "engine/render/render_internal.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fluid/pbf.h"

static const char *const mode_names[ENG_FLUID_MODE_COUNT] = { "surface", "spheres", "density", "speed" };

// The index of `name` in names[0..count-1]; -1 for any other text (NULL included).
static int name_index(const char *const *names, int count, const char *name)
{
    for (int i = 0; name && i < count; i++)
        if (strcmp(name, names[i]) == 0) return i;
    return -1;
}

const char *eng_fluid_mode_name(eng_fluid_mode mode)
{
    return (int)mode >= 0 && mode < ENG_FLUID_MODE_COUNT ? mode_names[mode] : NULL;
}

bool eng_fluid_mode_parse(const char *name, eng_fluid_mode *mode)
{
    int i = name_index(mode_names, ENG_FLUID_MODE_COUNT, name);
    if (i >= 0) *mode = (eng_fluid_mode)i;
    return i >= 0;
}

const char *eng_fluid_mode_names(void) { return "surface|spheres|density|speed"; }

eng_fluid_look eng_default_fluid_look(void)
{
    eng_fluid_look k = {
        .mode = ENG_FLUID_SURFACE,
        .absorption = { 3.0f, 1.0f, 0.45f },
        .scatter = { 0.02f, 0.13f, 0.28f },
        .refraction = 1.0f,
        .reflection = 0.02f,
        .specular = 2.0f,
        .shininess = 900.0f,
        .smoothing = 6.0f,
        .spray = 0.6f,
        .spray_speed = 1.5f,
        .resolution = 0.5f,
        .density_range = { 0.9f, 1.1f },
        .speed_max = 2.0f,
        .shadows = true,
        .view = ENG_FLUID_VIEW_SHADED,
        .splat = ENG_FLUID_SPLAT_COMPUTE,
    };
    return k;
}

eng_renderer_def eng_default_renderer_def(void)
{
    eng_renderer_def d;
    memset(&d, 0, sizeof d);
    d.shader_dir = NULL;
    d.logger = eng_default_logger();
    d.sky_color[0] = 0.62f, d.sky_color[1] = 0.76f, d.sky_color[2] = 0.90f;
    d.light.direction[0] = 0.35f, d.light.direction[1] = 0.85f, d.light.direction[2] = 0.40f;
    d.light.color[0] = 0.95f, d.light.color[1] = 0.92f, d.light.color[2] = 0.85f;
    d.light.ambient[0] = 0.28f, d.light.ambient[1] = 0.30f, d.light.ambient[2] = 0.34f;
    d.specular = 0.25f;
    d.shininess = 32.0f;
    d.ground = true;
    d.ground_height = 0.0f;
    d.ground_size = 200.0f;
    d.ground_cell = 1.0f;
    d.ground_color[0] = 0.58f, d.ground_color[1] = 0.58f, d.ground_color[2] = 0.56f;
    d.fog_start = 40.0f;
    d.fog_end = 100.0f;
    d.fluid = eng_default_fluid_look();
    d.shadow_size = 2048;
    return d;
}

eng_particle_style eng_default_particle_style(void)
{
    eng_particle_style s = {
        .color_low = { 0.04f, 0.22f, 0.62f },
        .color_mid = { 0.10f, 0.66f, 0.86f },
        .color_high = { 0.86f, 0.96f, 1.00f },
        .specular = 0.6f,
        .shininess = 64.0f,
    };
    return s;
}

eng_fluid_draw eng_default_fluid_draw(void)
{
    eng_fluid_draw d;
    memset(&d, 0, sizeof d);
    d.radius = 0.02f;
    d.particle_mass = 0.064f;
    d.rest_density = 1000.0f;
    return d;
}

eng_fluid_draw eng_fluid_draw_of(const pbf_world *world, const eng_particle_style *style)
{
    eng_fluid_draw d = eng_default_fluid_draw();
    const pbf_params *p = pbf_world_params(world);
    if (!p) return d;
    pbf_gpu_buffers b = pbf_world_gpu_buffers(world);
    d.positions = b.positions;
    d.velocities = b.velocities; // w: the particle's volume, so density = mass / volume
    d.draw_indirect = b.draw_indirect;
    d.radius = p->particle_radius;
    d.particle_mass = pbf_derive_constants(p).mass;
    d.rest_density = p->rest_density;
    d.style = style;
    return d;
}

// ---- input checks ------------------------------------------------------------------

static bool fail(const eng_logger *log, char *err, size_t err_size, const char *fmt, const char *field, double got)
{
    char msg[256];
    snprintf(msg, sizeof msg, fmt, field, got);
    eng_log(log, ENG_LOG_ERROR, "%s", msg);
    if (err && err_size > 0) snprintf(err, err_size, "%s", msg);
    return false;
}

static bool check_range(const eng_logger *log, char *err, size_t err_size, const char *field, float v, float lo,
                        float hi)
{
    if (v >= lo && v <= hi) return true;
    char fmt[96];
    snprintf(fmt, sizeof fmt, "%%s must be %g..%g (got %%g)", (double)lo, (double)hi);
    return fail(log, err, err_size, fmt, field, (double)v);
}

bool eng_render_check_rgb(const eng_logger *log, char *err, size_t err_size, const char *field, const float c[3], float hi)
{
    for (int k = 0; k < 3; k++) {
        char f[96];
        snprintf(f, sizeof f, "%.80s[%d]", field, k);
        if (!check_range(log, err, err_size, f, c[k], 0.0f, hi)) return false;
    }
    return true;
}

bool eng_render_check_light(const eng_logger *log, char *err, size_t err_size, const char *field, const eng_light *l)
{
    const float *d = l->direction;
    float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    char f[96];
    snprintf(f, sizeof f, "%s.direction", field);
    if (!(len > 1e-6f) || !isfinite(len))
        return fail(log, err, err_size, "%s must be a finite non-zero vector (got length %g)", f, (double)len);
    snprintf(f, sizeof f, "%s.color", field);
    if (!eng_render_check_rgb(log, err, err_size, f, l->color, 4.0f)) return false;
    snprintf(f, sizeof f, "%s.ambient", field);
    return eng_render_check_rgb(log, err, err_size, f, l->ambient, 1.0f);
}

bool eng_render_check_look(const eng_logger *log, char *err, size_t err_size, const char *field, const eng_fluid_look *k)
{
    char f[96];
#define FIELD(name) (snprintf(f, sizeof f, "%s." name, field), f)
    if ((int)k->mode < 0 || k->mode >= ENG_FLUID_MODE_COUNT)
        return fail(log, err, err_size, "%s must be an eng_fluid_mode, 0..3 (got %g)", FIELD("mode"), (double)k->mode);
    if (!eng_render_check_rgb(log, err, err_size, FIELD("absorption"), k->absorption, 100.0f)) return false;
    if (!eng_render_check_rgb(log, err, err_size, FIELD("scatter"), k->scatter, 1.0f)) return false;
    if (!check_range(log, err, err_size, FIELD("refraction"), k->refraction, 0.0f, 4.0f)) return false;
    if (!check_range(log, err, err_size, FIELD("reflection"), k->reflection, 0.0f, 1.0f)) return false;
    if (!check_range(log, err, err_size, FIELD("specular"), k->specular, 0.0f, 8.0f)) return false;
    if (!check_range(log, err, err_size, FIELD("shininess"), k->shininess, 1.0f, 8192.0f)) return false;
    if (!check_range(log, err, err_size, FIELD("smoothing"), k->smoothing, 0.0f, 16.0f)) return false;
    if (!check_range(log, err, err_size, FIELD("spray"), k->spray, 0.0f, 1.0f)) return false;
    if (!(k->spray_speed > 0.0f && k->spray_speed <= 1000.0f))
        return fail(log, err, err_size, "%s must be in (0, 1000] m/s (got %g)", FIELD("spray_speed"),
                    (double)k->spray_speed);
    if (!check_range(log, err, err_size, FIELD("resolution"), k->resolution, 0.25f, 1.0f)) return false;
    if (!check_range(log, err, err_size, FIELD("density_range[0]"), k->density_range[0], 1e-3f, 10.0f)) return false;
    if (!(k->density_range[1] > k->density_range[0] && k->density_range[1] <= 10.0f))
        return fail(log, err, err_size, "%s must be > density_range[0] and <= 10 (got %g)", FIELD("density_range[1]"),
                    (double)k->density_range[1]);
    if (!(k->speed_max > 0.0f && k->speed_max <= 1000.0f))
        return fail(log, err, err_size, "%s must be in (0, 1000] m/s (got %g)", FIELD("speed_max"), (double)k->speed_max);
    if ((int)k->view < 0 || k->view >= ENG_FLUID_VIEW_COUNT)
        return fail(log, err, err_size, "%s must be an eng_fluid_view, 0..3 (got %g)", FIELD("view"), (double)k->view);
    if ((int)k->splat < 0 || k->splat >= ENG_FLUID_SPLAT_COUNT)
        return fail(log, err, err_size, "%s must be an eng_fluid_splat, 0 (raster) or 1 (compute) (got %g)",
                    FIELD("splat"), (double)k->splat);
#undef FIELD
    return true;
}

bool eng_render_check_def(const eng_renderer_def *d, char *err, size_t err_size)
{
    const eng_logger *log = &d->logger;
    if (d->shader_dir && !d->shader_dir[0]) {
        const char *msg = "eng_renderer_def.shader_dir must be NULL (the embedded shaders) or name the shader "
                          "directory (got \"\")";
        eng_log(log, ENG_LOG_ERROR, "%s", msg);
        if (err && err_size > 0) snprintf(err, err_size, "%s", msg);
        return false;
    }
    if (!eng_render_check_rgb(log, err, err_size, "eng_renderer_def.sky_color", d->sky_color, 1.0f)) return false;
    if (!eng_render_check_light(log, err, err_size, "eng_renderer_def.light", &d->light)) return false;
    if (!(d->specular >= 0.0f && d->specular <= 1.0f))
        return fail(log, err, err_size, "%s must be 0..1 (got %g)", "eng_renderer_def.specular", (double)d->specular);
    if (!(d->shininess >= 1.0f && d->shininess <= 1024.0f))
        return fail(log, err, err_size, "%s must be 1..1024 (got %g)", "eng_renderer_def.shininess",
                    (double)d->shininess);
    if (!isfinite(d->ground_height))
        return fail(log, err, err_size, "%s must be finite m (got %g)", "eng_renderer_def.ground_height",
                    (double)d->ground_height);
    if (!(d->ground_size > 0.0f && isfinite(d->ground_size)))
        return fail(log, err, err_size, "%s must be > 0 m (got %g)", "eng_renderer_def.ground_size",
                    (double)d->ground_size);
    if (!(d->ground_cell > 0.0f && isfinite(d->ground_cell)))
        return fail(log, err, err_size, "%s must be > 0 m (got %g)", "eng_renderer_def.ground_cell",
                    (double)d->ground_cell);
    if (!eng_render_check_rgb(log, err, err_size, "eng_renderer_def.ground_color", d->ground_color, 1.0f)) return false;
    if (!(d->fog_start >= 0.0f && isfinite(d->fog_start)))
        return fail(log, err, err_size, "%s must be >= 0 m (got %g)", "eng_renderer_def.fog_start",
                    (double)d->fog_start);
    if (!(d->fog_end > d->fog_start && isfinite(d->fog_end)))
        return fail(log, err, err_size, "%s must be > fog_start (m) (got %g)", "eng_renderer_def.fog_end",
                    (double)d->fog_end);
    if (!eng_render_check_look(log, err, err_size, "eng_renderer_def.fluid", &d->fluid)) return false;
    if (d->shadow_size < 64 || d->shadow_size > 8192)
        return fail(log, err, err_size, "%s must be 64..8192 texels (got %g)", "eng_renderer_def.shadow_size",
                    (double)d->shadow_size);
    return true;
}

bool eng_render_check_style(const eng_logger *log, const eng_particle_style *s)
{
    if (!eng_render_check_rgb(log, NULL, 0, "eng_particle_style.color_low", s->color_low, 1.0f)) return false;
    if (!eng_render_check_rgb(log, NULL, 0, "eng_particle_style.color_mid", s->color_mid, 1.0f)) return false;
    if (!eng_render_check_rgb(log, NULL, 0, "eng_particle_style.color_high", s->color_high, 1.0f)) return false;
    if (!(s->specular >= 0.0f && s->specular <= 1.0f))
        return fail(log, NULL, 0, "%s must be 0..1 (got %g)", "eng_particle_style.specular", (double)s->specular);
    if (!(s->shininess >= 1.0f && s->shininess <= 1024.0f))
        return fail(log, NULL, 0, "%s must be 1..1024 (got %g)", "eng_particle_style.shininess", (double)s->shininess);
    return true;
}


bool eng_fluid_look_check(const eng_fluid_look *look, const char *field, char *err, size_t err_size)
{
    eng_logger quiet = eng_default_logger();
    quiet.min_level = (eng_log_level)(ENG_LOG_ERROR + 1);
    return look && eng_render_check_look(&quiet, err, err_size, field ? field : "eng_fluid_look", look);
}

static const char *const view_names[ENG_FLUID_VIEW_COUNT] = { "shaded", "depth", "normals", "thickness" };

const char *eng_fluid_view_name(eng_fluid_view view)
{
    return (unsigned)view < ENG_FLUID_VIEW_COUNT ? view_names[view] : NULL;
}

bool eng_fluid_view_parse(const char *name, eng_fluid_view *view)
{
    int i = name_index(view_names, ENG_FLUID_VIEW_COUNT, name);
    if (i >= 0) *view = (eng_fluid_view)i;
    return i >= 0;
}

static const char *const splat_names[ENG_FLUID_SPLAT_COUNT] = { "raster", "compute" };

const char *eng_fluid_splat_name(eng_fluid_splat splat)
{
    return (unsigned)splat < ENG_FLUID_SPLAT_COUNT ? splat_names[splat] : NULL;
}

bool eng_fluid_splat_parse(const char *name, eng_fluid_splat *splat)
{
    int i = name_index(splat_names, ENG_FLUID_SPLAT_COUNT, name);
    if (i >= 0) *splat = (eng_fluid_splat)i;
    return i >= 0;
}
