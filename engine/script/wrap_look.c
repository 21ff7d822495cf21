// Binds what the player sees besides the scene: seiche.text (HUD text this frame) and
// seiche.colour (tinting the water in a box; emitters take a `colour` field in
// wrap_emitter.c). The tint lives on the GPU with each particle (fluid/pbf.h, "tints").
#include "engine/script/script_internal.h"

#include <stdlib.h>
#include <string.h>

// ---- seiche.text -------------------------------------------------------------------------

/// Window coordinates accepted, pixels (a 16k display at most).
#define TEXT_MAX_COORD 16384.0

int eng_script_texts(const eng_script *s, const eng_script_text **out)
{
    if (out) *out = s ? s->texts : NULL;
    return s ? s->text_count : 0;
}

void eng_script_begin_frame(eng_script *s)
{
    if (s) s->text_count = 0;
}

// seiche.text(x, y, string [, {size =, colour =}])
static int l_text(lua_State *L)
{
    eng_script *s = scr_get_script(L);
    const char *fn = "seiche.text";
    if (!s->loaded)
        scr_raise(L, "%s: call it from a callback (on_step, on_key, a timer, ...): text is drawn in the frame of the call, "
                  "and the main chunk runs before the first frame", fn);
    double x = scr_arg_number(L, 1, fn, "x", 0.0, TEXT_MAX_COORD, 0, "pixels from the left");
    double y = scr_arg_number(L, 2, fn, "y", 0.0, TEXT_MAX_COORD, 0, "pixels from the top");
    char got[64];
    if (lua_type(L, 3) != LUA_TSTRING && lua_type(L, 3) != LUA_TNUMBER)
        scr_raise(L, "%s: argument #3 'text' must be a string (got %s)", fn, scr_describe(L, 3, got, sizeof got));
    size_t len = 0;
    const char *str = lua_tolstring(L, 3, &len);
    if (len > ENG_SCRIPT_TEXT_BYTES)
        scr_raise(L, "%s: argument #3 'text' must be at most %d bytes (got %zu bytes)", fn, ENG_SCRIPT_TEXT_BYTES, len);
    if (strlen(str) != len) scr_raise(L, "%s: argument #3 'text' must not hold a zero byte", fn);
    eng_script_text t = { .x = (float)x, .y = (float)y, .size = 20.0f, .colour = { 1, 1, 1, 1 } };
    if (!lua_isnoneornil(L, 4)) {
        scr_check_table_arg(L, 4, fn, "size, colour");
        static const char *const known[] = { "size", "colour", "color", NULL };
        scr_check_fields(L, 4, fn, known);
        double v;
        if (scr_opt_number(L, 4, fn, "size", 4.0, 256.0, 0, "pixels", &v)) t.size = (float)v;
        const char *colour = scr_colour_field(L, 4, fn);
        if (colour) {
            lua_getfield(L, 4, colour);
            int n = lua_istable(L, -1) ? (int)lua_rawlen(L, -1) : 0;
            if (n != 3 && n != 4)
                scr_raise(L, "%s: field '%s' must be a colour {r, g, b} or {r, g, b, a} (alpha), each a number in [0, 1] "
                          "(got %s)", fn, colour, lua_istable(L, -1) ? (n ? "a table of another length" : "an empty table or named fields")
                                                                 : scr_describe(L, -1, got, sizeof got));
            lua_pop(L, 1);
            scr_opt_vec(L, 4, fn, colour, n, 0.0, 1.0, 0, "", t.colour);
        }
    }
    memcpy(t.text, str, len + 1);
    if (s->text_count >= ENG_SCRIPT_MAX_TEXTS)
        scr_raise(L, "%s: at most %d texts in one frame (this is call %d)", fn, ENG_SCRIPT_MAX_TEXTS, s->text_count + 1);
    if (!s->texts) {
        size_t bytes = ENG_SCRIPT_MAX_TEXTS * sizeof *s->texts;
        scr_charge(L, s, fn, bytes);
        s->texts = malloc(bytes);
        if (!s->texts) {
            scr_uncharge(s, bytes);
            scr_raise(L, "%s: out of memory", fn);
        }
    }
    s->texts[s->text_count++] = t;
    return 0;
}

// ---- seiche.colour -----------------------------------------------------------------------

// seiche.colour{min =, max =, colour = {r, g, b} | false}: tints the particles in the box
// now (queued like every edit: applied before the next step, to the particles there then).
static int tint_box(lua_State *L, const char *fn)
{
    eng_script *s = scr_get_script(L);
    scr_check_table_arg(L, 1, fn, "min = {x, y, z}, max = {x, y, z}, colour = {r, g, b} or false");
    static const char *const known[] = { "min", "max", "colour", "color", NULL };
    scr_check_fields(L, 1, fn, known);
    float mn[3], mx[3], rgb[3] = { 0, 0, 0 };
    scr_read_box(L, 1, fn, mn, mx);
    bool tinted = false;
    const char *colour = scr_colour_field(L, 1, fn);
    if (!colour || !scr_opt_tint(L, 1, fn, colour, &tinted, rgb))
        scr_raise(L, "%s: field 'colour' is required: a colour {r, g, b} with each in [0, 1], or false for none (got nil)",
                  fn);
    command *c = scr_push_command(L, s, CMD_TINT, fn);
    memcpy(c->u.block.min, mn, sizeof mn);
    memcpy(c->u.block.max, mx, sizeof mx);
    c->tinted = tinted;
    memcpy(c->tint, rgb, sizeof rgb);
    return 0;
}

// seiche.colour and seiche.color: one function, two spellings (as its field).
static int l_colour(lua_State *L) { return tint_box(L, "seiche.colour"); }
static int l_color(lua_State *L) { return tint_box(L, "seiche.color"); }

static const luaL_Reg functions[] = {
    { "text", l_text },
    { "colour", l_colour },
    { "color", l_color },
    { NULL, NULL },
};

void scr_open_look(scr_api *api)
{
    scr_api_functions(api, functions);
}
