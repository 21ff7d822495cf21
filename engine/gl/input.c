// Input from GLFW callbacks, or nothing headless. See input.h.
#include "engine/gl/input.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <stdlib.h>
#include <string.h>

struct eng_input {
    GLFWwindow *window;
    void *prev_user;
    GLFWkeyfun prev_key;
    GLFWmousebuttonfun prev_button;
    GLFWcursorposfun prev_cursor;
    GLFWscrollfun prev_scroll;

    unsigned char down[ENG_INPUT_MAX_KEYS];
    unsigned char pressed[ENG_INPUT_MAX_KEYS];
    unsigned char button_down[ENG_INPUT_MAX_BUTTONS];
    unsigned char button_pressed[ENG_INPUT_MAX_BUTTONS];
    double x, y, dx, dy, scroll_x, scroll_y;
    bool have_position;

    eng_event queue[ENG_INPUT_QUEUE_CAPACITY];
    int head, count;
    long dropped;
};

static void enqueue(eng_input *in, const eng_event *e)
{
    if (in->count == ENG_INPUT_QUEUE_CAPACITY) {
        in->dropped++;
        return;
    }
    in->queue[(in->head + in->count) % ENG_INPUT_QUEUE_CAPACITY] = *e;
    in->count++;
}

void eng_input_inject(eng_input *in, const eng_event *e)
{
    eng_event ev = *e;
    switch (e->type) {
    case ENG_EVENT_KEY:
        if (e->key >= 0 && e->key < ENG_INPUT_MAX_KEYS) {
            if (e->action == ENG_PRESS) {
                in->down[e->key] = 1;
                in->pressed[e->key] = 1;
            } else if (e->action == ENG_RELEASE) {
                in->down[e->key] = 0;
            }
        }
        break;
    case ENG_EVENT_MOUSE_BUTTON:
        if (e->button >= 0 && e->button < ENG_INPUT_MAX_BUTTONS) {
            if (e->action == ENG_PRESS) {
                in->button_down[e->button] = 1;
                in->button_pressed[e->button] = 1;
            } else if (e->action == ENG_RELEASE) {
                in->button_down[e->button] = 0;
            }
        }
        ev.x = in->x;
        ev.y = in->y;
        break;
    case ENG_EVENT_MOTION:
        // The first position only sets the origin: no jump from (0, 0).
        ev.dx = in->have_position ? e->x - in->x : 0.0;
        ev.dy = in->have_position ? e->y - in->y : 0.0;
        in->dx += ev.dx;
        in->dy += ev.dy;
        in->x = e->x;
        in->y = e->y;
        in->have_position = true;
        break;
    case ENG_EVENT_SCROLL:
        in->scroll_x += e->dx;
        in->scroll_y += e->dy;
        break;
    }
    enqueue(in, &ev);
}

static eng_input *from(GLFWwindow *w) { return glfwGetWindowUserPointer(w); }

// While our callback runs, the window's user pointer is ours; the previous owner's
// callback expects its own pointer, so it is swapped in around the call.
#define CHAIN(in, w, call)                                                                 \
    do {                                                                                   \
        glfwSetWindowUserPointer((w), (in)->prev_user);                                    \
        call;                                                                              \
        glfwSetWindowUserPointer((w), (in));                                               \
    } while (0)

static void on_key(GLFWwindow *w, int key, int scancode, int action, int mods)
{
    eng_input *in = from(w);
    eng_event e = { .type = ENG_EVENT_KEY, .key = key, .scancode = scancode, .action = action, .mods = mods };
    eng_input_inject(in, &e);
    if (in->prev_key) CHAIN(in, w, in->prev_key(w, key, scancode, action, mods));
}

static void on_button(GLFWwindow *w, int button, int action, int mods)
{
    eng_input *in = from(w);
    eng_event e = { .type = ENG_EVENT_MOUSE_BUTTON, .button = button, .action = action, .mods = mods };
    eng_input_inject(in, &e);
    if (in->prev_button) CHAIN(in, w, in->prev_button(w, button, action, mods));
}

static void on_cursor(GLFWwindow *w, double x, double y)
{
    eng_input *in = from(w);
    eng_event e = { .type = ENG_EVENT_MOTION, .x = x, .y = y };
    eng_input_inject(in, &e);
    if (in->prev_cursor) CHAIN(in, w, in->prev_cursor(w, x, y));
}

static void on_scroll(GLFWwindow *w, double dx, double dy)
{
    eng_input *in = from(w);
    eng_event e = { .type = ENG_EVENT_SCROLL, .dx = dx, .dy = dy };
    eng_input_inject(in, &e);
    if (in->prev_scroll) CHAIN(in, w, in->prev_scroll(w, dx, dy));
}

eng_input *eng_input_create(eng_context *ctx)
{
    eng_input *in = calloc(1, sizeof *in);
    if (!in) return NULL;
    in->window = ctx ? eng_context_window(ctx) : NULL;
    if (in->window) {
        in->prev_user = glfwGetWindowUserPointer(in->window);
        glfwSetWindowUserPointer(in->window, in);
        in->prev_key = glfwSetKeyCallback(in->window, on_key);
        in->prev_button = glfwSetMouseButtonCallback(in->window, on_button);
        in->prev_cursor = glfwSetCursorPosCallback(in->window, on_cursor);
        in->prev_scroll = glfwSetScrollCallback(in->window, on_scroll);
        double x, y;
        glfwGetCursorPos(in->window, &x, &y);
        in->x = x;
        in->y = y;
        in->have_position = true;
    }
    return in;
}

void eng_input_destroy(eng_input *in)
{
    if (!in) return;
    if (in->window) {
        glfwSetKeyCallback(in->window, in->prev_key);
        glfwSetMouseButtonCallback(in->window, in->prev_button);
        glfwSetCursorPosCallback(in->window, in->prev_cursor);
        glfwSetScrollCallback(in->window, in->prev_scroll);
        glfwSetWindowUserPointer(in->window, in->prev_user);
    }
    free(in);
}

void eng_input_begin_frame(eng_input *in)
{
    memset(in->pressed, 0, sizeof in->pressed);
    memset(in->button_pressed, 0, sizeof in->button_pressed);
    in->dx = in->dy = 0.0;
    in->scroll_x = in->scroll_y = 0.0;
}

bool eng_input_key_down(const eng_input *in, int key)
{
    return key >= 0 && key < ENG_INPUT_MAX_KEYS && in->down[key];
}

bool eng_input_key_pressed(const eng_input *in, int key)
{
    return key >= 0 && key < ENG_INPUT_MAX_KEYS && in->pressed[key];
}

bool eng_input_mouse_down(const eng_input *in, int button)
{
    return button >= 0 && button < ENG_INPUT_MAX_BUTTONS && in->button_down[button];
}

bool eng_input_mouse_pressed(const eng_input *in, int button)
{
    return button >= 0 && button < ENG_INPUT_MAX_BUTTONS && in->button_pressed[button];
}

void eng_input_mouse_position(const eng_input *in, double *x, double *y)
{
    *x = in->x;
    *y = in->y;
}

void eng_input_mouse_delta(const eng_input *in, double *dx, double *dy)
{
    *dx = in->dx;
    *dy = in->dy;
}

void eng_input_scroll(const eng_input *in, double *dx, double *dy)
{
    *dx = in->scroll_x;
    *dy = in->scroll_y;
}

bool eng_input_next_event(eng_input *in, eng_event *out)
{
    if (in->count == 0) return false;
    *out = in->queue[in->head];
    in->head = (in->head + 1) % ENG_INPUT_QUEUE_CAPACITY;
    in->count--;
    return true;
}

int eng_input_queued(const eng_input *in) { return in->count; }
long eng_input_dropped(const eng_input *in) { return in->dropped; }
