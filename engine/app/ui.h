// The runner's on-screen UI, a C shim over Dear ImGui (engine/ui_imgui.cpp): a parameter
// panel (fluid parameters as sliders, pause / step / reset / reload buttons, density
// statistics) and the script's error message. Window mode only: headless there is no UI.
//
//     eng_ui *ui = eng_ui_create(eng_context_window(ctx), err, sizeof err);
//     each frame, after drawing the scene and before presenting:
//         eng_ui_frame f = { ... };  eng_ui_draw(ui, &f);  then act on f's outputs
//     eng_ui_destroy(ui);             // before eng_input_destroy (callbacks chain)
//
// The UI installs its GLFW callbacks on top of those already installed (eng_input's) and
// chains to them, so create it after eng_input_create and destroy it before.
#ifndef ENG_UI_H
#define ENG_UI_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

struct GLFWwindow;
typedef struct eng_ui eng_ui;

/// One slider of the parameter panel.
typedef struct eng_ui_param {
    const char *name;        ///< "iterations"
    const char *unit;        ///< "m", "" when dimensionless
    const char *description; ///< shown as a tooltip
    double min, max;         ///< slider range
    double value;            ///< in: current value; out: the new one when `changed`
    bool is_int;
    bool read_only;          ///< shown, not editable
    bool changed;            ///< out
} eng_ui_param;

/// A line of the script's HUD (seiche.text), drawn over everything, panel or not.
typedef struct eng_ui_text {
    float x, y;              ///< pixels of the window from its top-left corner
    float size;              ///< pixels, the font's height
    float colour[4];         ///< rgba, 0..1
    const char *text;        ///< UTF-8
} eng_ui_text;

/// What one frame of the UI shows (in) and what the user did (out).
typedef struct eng_ui_frame {
    const char *title;       ///< scene name
    const char *renderer;    ///< GL renderer string
    uint64_t frame;
    double time;             ///< s
    uint32_t particles, capacity;
    uint32_t bodies;
    double rho0, rho_avg, rho_max; ///< kg/m^3
    double step_ms;          ///< GPU ms per step
    double fps;              ///< frames drawn per wall-clock second (0: not measured yet)
    int iterations, substeps;
    double compression;      ///< mean compression error of the last step, fraction
    double worst_over;       ///< highest rho_max / rho0 - 1 so far in this run, fraction
    const double *stage_ms;  ///< GPU ms of each stage in the last step (stage_count of them)
    const char *const *stage_names;
    int stage_count;
    bool paused;
    bool show_panel;         ///< in/out: the panel is shown (F1 toggles it in the app)
    const char *error;       ///< NULL or "": none; else shown in red until dismissed
    eng_ui_param *params;
    int param_count;
    const eng_ui_text *texts; ///< the script's HUD of this frame (drawn on the foreground draw list)
    int text_count;
    int width, height;       ///< framebuffer pixels (read without a window; a window has its own)
    // out
    bool toggle_pause, step, reset, reload, dismiss_error;
} eng_ui_frame;

/// NULL (with a message in err) when ImGui cannot start. With window NULL (headless), the
/// UI draws only the script's HUD text (for screenshots and videos): no panel, no error
/// box, no input.
eng_ui *eng_ui_create(struct GLFWwindow *window, char *err, size_t err_size);
void eng_ui_destroy(eng_ui *ui);

/// True when the pointer is over the UI (or dragging a widget): the app should not give
/// the mouse to the camera or the script. False for NULL.
bool eng_ui_wants_mouse(const eng_ui *ui);
/// True when a widget takes keyboard input (a text field). False for NULL.
bool eng_ui_wants_keyboard(const eng_ui *ui);

/// Builds and draws the UI into the current framebuffer (the window's).
void eng_ui_draw(eng_ui *ui, eng_ui_frame *frame);

#ifdef __cplusplus
}
#endif
#endif
