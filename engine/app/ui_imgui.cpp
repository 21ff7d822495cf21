// The runner's UI on Dear ImGui (GLFW + OpenGL 3 backends). See ui.h.
//
// ImGui keeps its current context in a process-wide pointer, and its GLFW callbacks (which
// fire inside glfwPollEvents) use whatever context is current then. So this shim makes its
// context current when it is created and leaves it so, and makes it current again at every
// call: one eng_ui per process (the runner has one window).
#include "engine/app/ui.h"

#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <new>

struct eng_ui {
    ImGuiContext *ctx;
    GLFWwindow *window;
};

namespace {

struct current {
    explicit current(const eng_ui *ui) { ImGui::SetCurrentContext(ui->ctx); }
};

void stat_row(const char *label, const char *fmt, double v)
{
    ImGui::TextUnformatted(label);
    ImGui::SameLine(110.0f);
    ImGui::Text(fmt, v);
}

void panel(eng_ui_frame *f)
{
    ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.82f);
    char title[128];
    std::snprintf(title, sizeof title, "%s###seiche_panel", f->title && *f->title ? f->title : "seiche");
    if (!ImGui::Begin(title, &f->show_panel, ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::End();
        return;
    }
    if (ImGui::Button(f->paused ? "Run (space)" : "Pause (space)")) f->toggle_pause = true;
    ImGui::SameLine();
    if (ImGui::Button("Step (n)")) f->step = true;
    ImGui::SameLine();
    if (ImGui::Button("Reset (r)")) f->reset = true;
    ImGui::SameLine();
    if (ImGui::Button("Reload (F5)")) f->reload = true;

    ImGui::Separator();
    ImGui::Text("frame %llu   t = %.2f s%s", (unsigned long long)f->frame, f->time, f->paused ? "   (paused)" : "");
    ImGui::Text("particles %u / %u   bodies %u", f->particles, f->capacity, f->bodies);
    stat_row("rho_avg", "%.1f kg/m^3", f->rho_avg);
    ImGui::SameLine();
    if (f->rho0 > 0) ImGui::Text("(%+.2f %%)", 100.0 * (f->rho_avg / f->rho0 - 1.0));
    stat_row("rho_max", "%.1f kg/m^3", f->rho_max);
    ImGui::SameLine();
    if (f->rho0 > 0) ImGui::Text("(%+.2f %%)", 100.0 * (f->rho_max / f->rho0 - 1.0));
    stat_row("rho0", "%.1f kg/m^3", f->rho0);
    stat_row("GPU step", "%.2f ms", f->step_ms);
    stat_row("frames/s", "%.1f", f->fps);
    ImGui::Text("solver %d iterations x %d substeps", f->iterations, f->substeps);
    ImGui::Text("compression %.3f %% (mean)   worst %+.2f %% over rho0", 100.0 * f->compression, 100.0 * f->worst_over);
    if (f->stage_count > 0 && ImGui::CollapsingHeader("GPU ms per stage", ImGuiTreeNodeFlags_DefaultOpen)) {
        for (int i = 0; i < f->stage_count; i++)
            if (f->stage_ms[i] > 0.0) stat_row(f->stage_names[i], "%.3f", f->stage_ms[i]);
    }

    if (f->param_count > 0 && ImGui::CollapsingHeader("Fluid parameters")) {
        ImGui::PushItemWidth(120.0f);
        for (int i = 0; i < f->param_count; i++) {
            eng_ui_param *p = &f->params[i];
            char label[96];
            std::snprintf(label, sizeof label, "%s%s%s%s", p->name, p->unit && *p->unit ? " (" : "",
                          p->unit && *p->unit ? p->unit : "", p->unit && *p->unit ? ")" : "");
            ImGui::BeginDisabled(p->read_only);
            if (p->is_int) {
                int v = (int)std::lround(p->value);
                if (ImGui::SliderInt(label, &v, (int)p->min, (int)p->max, "%d", ImGuiSliderFlags_AlwaysClamp)) {
                    p->value = v;
                    p->changed = true;
                }
            } else {
                float v = (float)p->value;
                bool log = p->min > 0 && p->max / p->min > 100.0;
                if (ImGui::SliderFloat(label, &v, (float)p->min, (float)p->max, "%.4g",
                                       ImGuiSliderFlags_AlwaysClamp | (log ? ImGuiSliderFlags_Logarithmic : 0))) {
                    p->value = v;
                    p->changed = true;
                }
            }
            ImGui::EndDisabled();
            if (p->description && ImGui::IsItemHovered(ImGuiHoveredFlags_AllowWhenDisabled))
                ImGui::SetTooltip("%s", p->description);
        }
        ImGui::PopItemWidth();
    }
    if (f->renderer) ImGui::TextDisabled("%s", f->renderer);
    ImGui::TextDisabled("F1 panel  c camera  Esc quit");
    ImGui::End();
}

void error_box(eng_ui_frame *f)
{
    ImGuiIO &io = ImGui::GetIO();
    float w = io.DisplaySize.x * 0.9f;
    ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x * 0.05f, io.DisplaySize.y - 10.0f), ImGuiCond_Always, ImVec2(0, 1));
    ImGui::SetNextWindowSizeConstraints(ImVec2(w, 0), ImVec2(w, io.DisplaySize.y * 0.6f));
    ImGui::SetNextWindowBgAlpha(0.9f);
    ImGui::PushStyleColor(ImGuiCol_WindowBg, ImVec4(0.22f, 0.03f, 0.03f, 0.92f));
    ImGui::PushStyleColor(ImGuiCol_TitleBg, ImVec4(0.55f, 0.08f, 0.08f, 1.0f));
    ImGui::PushStyleColor(ImGuiCol_TitleBgActive, ImVec4(0.65f, 0.10f, 0.10f, 1.0f));
    bool open = true;
    if (ImGui::Begin("Script error (fix the file and save it, or press F5)###seiche_error",
                     &open, ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_AlwaysAutoResize)) {
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.86f, 0.82f, 1.0f));
        ImGui::PushTextWrapPos(w - 20.0f);
        ImGui::TextUnformatted(f->error);
        ImGui::PopTextWrapPos();
        ImGui::PopStyleColor();
    }
    ImGui::End();
    ImGui::PopStyleColor(3);
    if (!open) f->dismiss_error = true;
}

} // namespace

extern "C" {

eng_ui *eng_ui_create(GLFWwindow *window, char *err, size_t err_size)
{
    eng_ui *ui = new (std::nothrow) eng_ui();
    if (!ui) {
        if (err && err_size) std::snprintf(err, err_size, "eng_ui_create: out of memory");
        return nullptr;
    }
    ui->ctx = ImGui::CreateContext();
    ui->window = window;
    ImGui::SetCurrentContext(ui->ctx);
    ImGuiIO &io = ImGui::GetIO();
    io.IniFilename = nullptr; // no imgui.ini next to the user's files
    io.LogFilename = nullptr;
    ImGui::StyleColorsDark();
    ImGui::GetStyle().WindowRounding = 4.0f;
    bool ok = (!window || ImGui_ImplGlfw_InitForOpenGL(window, true)) && ImGui_ImplOpenGL3_Init("#version 330 core");
    if (!ok) {
        if (err && err_size)
            std::snprintf(err, err_size, "eng_ui_create: the ImGui %s backends failed to start",
                          window ? "GLFW/OpenGL3" : "OpenGL3");
        eng_ui_destroy(ui);
        return nullptr;
    }
    return ui;
}

void eng_ui_destroy(eng_ui *ui)
{
    if (!ui) return;
    {
        current c(ui);
        if (ImGui::GetIO().BackendRendererUserData) ImGui_ImplOpenGL3_Shutdown();
        if (ImGui::GetIO().BackendPlatformUserData) ImGui_ImplGlfw_Shutdown();
    }
    ImGui::DestroyContext(ui->ctx); // also clears the current context
    delete ui;
}

bool eng_ui_wants_mouse(const eng_ui *ui)
{
    if (!ui) return false;
    current c(ui);
    return ImGui::GetIO().WantCaptureMouse;
}

bool eng_ui_wants_keyboard(const eng_ui *ui)
{
    if (!ui) return false;
    current c(ui);
    return ImGui::GetIO().WantCaptureKeyboard;
}

void eng_ui_draw(eng_ui *ui, eng_ui_frame *f)
{
    f->toggle_pause = f->step = f->reset = f->reload = f->dismiss_error = false;
    for (int i = 0; i < f->param_count; i++) f->params[i].changed = false;
    if (!ui) return;
    current c(ui);
    ImGui_ImplOpenGL3_NewFrame();
    if (ui->window) {
        ImGui_ImplGlfw_NewFrame();
    } else {
        // Headless: no platform backend; the frame's size and a nominal time step.
        ImGuiIO &io = ImGui::GetIO();
        io.DisplaySize = ImVec2((float)(f->width > 0 ? f->width : 1), (float)(f->height > 0 ? f->height : 1));
        io.DisplayFramebufferScale = ImVec2(1.0f, 1.0f);
        io.DeltaTime = 1.0f / 60.0f;
    }
    ImGui::NewFrame();
    if (ui->window && f->show_panel) panel(f);
    if (ui->window && f->error && *f->error) error_box(f);
    ImDrawList *fg = ImGui::GetForegroundDrawList();
    for (int i = 0; i < f->text_count; i++) {
        const eng_ui_text *t = &f->texts[i];
        ImU32 col = ImGui::GetColorU32(ImVec4(t->colour[0], t->colour[1], t->colour[2], t->colour[3]));
        fg->AddText(ImGui::GetFont(), t->size, ImVec2(t->x, t->y), col, t->text);
    }
    ImGui::Render();
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
}

} // extern "C"
