// Binds interaction: timers (seiche.after, every, timer methods), keys and mouse (key_down,
// mouse_down, mouse_position), screen_ray, screen_point, ray_cast, and injected input (inject_*).
#include "engine/script/script_internal.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

// ---- timers -----------------------------------------------------------------------------

static int new_timer(lua_State *L, const char *fn, bool repeat)
{
    eng_script *s = scr_get_script(L);
    double d = scr_arg_number(L, 1, fn, repeat ? "period" : "delay", repeat ? 0 : 0, 1e9, repeat ? OPEN_LO : 0, "s");
    // As the runner's callbacks (script.c, call_callback): a function, or a value with __call.
    char got[64];
    bool callable = lua_isfunction(L, 2);
    if (!callable && luaL_getmetafield(L, 2, "__call") != LUA_TNIL) {
        lua_pop(L, 1);
        callable = true;
    }
    if (!callable)
        scr_raise(L, "%s: argument #2 'callback' must be a function or a table with a __call metamethod (got %s)", fn,
                  scr_describe(L, 2, got, sizeof got));
    scr_timer_reserve(L, s);
    uint32_t slot = scr_obj_new(L, s, OBJ_TIMER);
    obj *o = &s->objs[slot];
    o->u.timer.fn = LUA_NOREF; // until luaL_ref (which may run out of memory) gives one
    lua_pushvalue(L, 2);
    o->u.timer.fn = luaL_ref(L, LUA_REGISTRYINDEX);
    o->u.timer.due = s->host.time + d;
    o->u.timer.period = repeat ? d : 0.0;
    o->state = OBJ_LIVE; // timers are the script's own: nothing to queue
    scr_timer_schedule(s, slot);
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

// ---- keys and mouse ---------------------------------------------------------------------

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

// ---- rays and the screen -----------------------------------------------------------------

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

// ---- injected input ----------------------------------------------------------------------

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
    // A reset or reload asked for while the scene loads would load it again, and again: the
    // frame counter would restart for ever and --frames never end the run.
    if (!s->loaded && action == ENG_PRESS && (code == GLFW_KEY_R || code == GLFW_KEY_F5))
        scr_raise(L, "%s: a %s (\"%s\") cannot be asked for while the scene loads (in the main chunk, on_start or "
                  "on_reload): inject it from on_step or a timer", fn, code == GLFW_KEY_R ? "reset" : "reload",
                  code == GLFW_KEY_R ? "r" : "f5");
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

static const luaL_Reg functions[] = {
    { "after", l_after }, { "every", l_every }, { "key_down", l_key_down }, { "mouse_down", l_mouse_down },
    { "mouse_position", l_mouse_position }, { "screen_ray", l_screen_ray }, { "screen_point", l_screen_point },
    { "ray_cast", l_ray_cast }, { "inject_key", l_inject_key }, { "inject_mouse", l_inject_mouse },
    { "inject_motion", l_inject_motion }, { "inject_scroll", l_inject_scroll }, { NULL, NULL },
};

static const luaL_Reg timer_methods[] = {
    { "cancel", m_timer_cancel }, { "remaining", m_timer_remaining }, { "is_valid", scr_is_valid }, { NULL, NULL },
};

void scr_open_interact(scr_api *api)
{
    scr_api_functions(api, functions);
    scr_api_methods(api, OBJ_TIMER, timer_methods);
}
