// Keyboard and mouse input, captured from the GLFW callbacks of the context's window:
// per-frame state (keys down, keys pressed this frame, mouse position, motion, buttons,
// scroll) and a queue of events that a host (the Lua layer) drains each frame.
//
// Headless there is no window: the input stays all zero (nothing down, no motion), so
// the same frame code runs. Events can also be injected (eng_input_inject), which is how
// tests and scripted runs drive cameras and callbacks without a window.
//
// Keys and mouse buttons are GLFW codes (GLFW_KEY_W, GLFW_MOUSE_BUTTON_LEFT, ...);
// positions are window pixels from the top-left corner, +y down.
//
// Per frame: eng_input_begin_frame() (clears "pressed", motion and scroll), then
// eng_context_poll() (callbacks fire), then read the state and drain the events.
#ifndef ENG_INPUT_H
#define ENG_INPUT_H

#include <stdbool.h>

#include "engine/gl/context.h"

#define ENG_INPUT_MAX_KEYS 512        ///< GLFW key codes are below this (GLFW_KEY_LAST = 348)
#define ENG_INPUT_MAX_BUTTONS 8       ///< GLFW_MOUSE_BUTTON_1..8
#define ENG_INPUT_QUEUE_CAPACITY 1024 ///< events kept between drains; more are dropped and counted

typedef enum eng_event_type {
    ENG_EVENT_KEY = 1,      ///< key, action, mods
    ENG_EVENT_MOUSE_BUTTON, ///< button, action, mods, x, y
    ENG_EVENT_MOTION,       ///< x, y (position), dx, dy (since the previous motion event)
    ENG_EVENT_SCROLL,       ///< dx, dy in scroll steps (wheel notches; +dy = away from the user)
} eng_event_type;

typedef enum eng_action {
    ENG_RELEASE = 0, ///< = GLFW_RELEASE
    ENG_PRESS = 1,   ///< = GLFW_PRESS
    ENG_REPEAT = 2,  ///< = GLFW_REPEAT (key held, auto-repeat)
} eng_action;

typedef struct eng_event {
    eng_event_type type;
    int key;      ///< GLFW key code (ENG_EVENT_KEY)
    int scancode; ///< platform scancode (ENG_EVENT_KEY)
    int button;   ///< GLFW mouse button (ENG_EVENT_MOUSE_BUTTON)
    int action;   ///< eng_action
    int mods;     ///< GLFW_MOD_* bits
    double x, y;  ///< mouse position in pixels
    double dx, dy;
} eng_event;

typedef struct eng_input eng_input;

/// Creates the input for `ctx` and, when it has a window, installs GLFW callbacks on it
/// (chaining to callbacks installed before). `ctx` may be NULL: a detached, no-op input.
eng_input *eng_input_create(eng_context *ctx);
/// Removes the callbacks (restoring the previous ones) and frees the input.
void eng_input_destroy(eng_input *input);

/// Starts a frame: forgets "pressed this frame", mouse motion and scroll.
void eng_input_begin_frame(eng_input *input);
/// Feeds one event as if GLFW had sent it: state and queue are updated the same way.
/// Out-of-range key or button codes are ignored (they still enter the queue).
void eng_input_inject(eng_input *input, const eng_event *event);

bool eng_input_key_down(const eng_input *input, int key);
/// True when the key went down during the current frame (auto-repeat does not count).
bool eng_input_key_pressed(const eng_input *input, int key);
bool eng_input_mouse_down(const eng_input *input, int button);
bool eng_input_mouse_pressed(const eng_input *input, int button);
/// Mouse position in pixels from the top-left corner.
void eng_input_mouse_position(const eng_input *input, double *x, double *y);
/// Mouse motion in pixels during the current frame.
void eng_input_mouse_delta(const eng_input *input, double *dx, double *dy);
/// Scroll in steps during the current frame.
void eng_input_scroll(const eng_input *input, double *dx, double *dy);

/// Takes the oldest queued event; false when the queue is empty.
bool eng_input_next_event(eng_input *input, eng_event *out);
int eng_input_queued(const eng_input *input);
/// Events lost because the queue was full (since creation).
long eng_input_dropped(const eng_input *input);

#endif
