// Perspective camera with orbit and fly controls. See camera.h.
#include "engine/render/camera.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#define MAX_PITCH 1.5533430f // 89 degrees

eng_camera_def eng_default_camera_def(void)
{
    eng_camera_def d;
    memset(&d, 0, sizeof d);
    d.mode = ENG_CAMERA_ORBIT;
    d.position[0] = 4.0f, d.position[1] = 3.0f, d.position[2] = 6.0f;
    d.target[0] = 0.0f, d.target[1] = 0.5f, d.target[2] = 0.0f;
    d.fov_y = 1.0471976f; // 60 degrees
    d.near_plane = 0.05f;
    d.far_plane = 500.0f;
    d.move_speed = 3.0f;
    d.look_speed = 0.005f;
    d.zoom_step = 0.1f;
    d.min_distance = 0.2f;
    d.max_distance = 200.0f;
    return d;
}

static bool bad(char *err, size_t err_size, const char *field, const char *rule, double got)
{
    if (err && err_size > 0) snprintf(err, err_size, "eng_camera_def.%s must be %s (got %g)", field, rule, got);
    return false;
}

static float clampf(float v, float lo, float hi) { return v < lo ? lo : v > hi ? hi : v; }

void eng_camera_forward(const eng_camera *cam, float out[3])
{
    float cp = cosf(cam->pitch);
    out[0] = cp * sinf(cam->yaw);
    out[1] = sinf(cam->pitch);
    out[2] = -cp * cosf(cam->yaw);
}

// Eye from target, angles and distance (orbit).
static void place_eye(eng_camera *cam)
{
    float f[3];
    eng_camera_forward(cam, f);
    for (int k = 0; k < 3; k++) cam->position[k] = cam->target[k] - f[k] * cam->distance;
}

// Target from eye, angles and distance (fly).
static void place_target(eng_camera *cam)
{
    float f[3];
    eng_camera_forward(cam, f);
    for (int k = 0; k < 3; k++) cam->target[k] = cam->position[k] + f[k] * cam->distance;
}

bool eng_camera_init(eng_camera *cam, const eng_camera_def *def, char *err, size_t err_size)
{
    if (def->mode != ENG_CAMERA_ORBIT && def->mode != ENG_CAMERA_FLY)
        return bad(err, err_size, "mode", "ENG_CAMERA_ORBIT or ENG_CAMERA_FLY", (double)def->mode);
    for (int k = 0; k < 3; k++) {
        if (!isfinite(def->position[k])) return bad(err, err_size, "position", "finite (m)", (double)def->position[k]);
        if (!isfinite(def->target[k])) return bad(err, err_size, "target", "finite (m)", (double)def->target[k]);
    }
    float d = sqrtf(glm_vec3_distance2((float *)def->position, (float *)def->target));
    if (!(d > 1e-6f)) return bad(err, err_size, "target", "a point other than position (distance > 0 m)", (double)d);
    if (!(def->fov_y >= 0.01f && def->fov_y <= 3.1f))
        return bad(err, err_size, "fov_y", "0.01..3.1 radians", (double)def->fov_y);
    if (!(def->near_plane > 0.0f && isfinite(def->near_plane)))
        return bad(err, err_size, "near_plane", "> 0 m", (double)def->near_plane);
    if (!(def->far_plane > def->near_plane && isfinite(def->far_plane)))
        return bad(err, err_size, "far_plane", "> near_plane (m)", (double)def->far_plane);
    if (!(def->move_speed >= 0.0f && isfinite(def->move_speed)))
        return bad(err, err_size, "move_speed", ">= 0 m/s", (double)def->move_speed);
    if (!(def->look_speed >= 0.0f && isfinite(def->look_speed)))
        return bad(err, err_size, "look_speed", ">= 0 radians per pixel", (double)def->look_speed);
    if (!(def->zoom_step >= 0.0f && def->zoom_step <= 0.9f))
        return bad(err, err_size, "zoom_step", "0..0.9", (double)def->zoom_step);
    if (!(def->min_distance > 0.0f && isfinite(def->min_distance)))
        return bad(err, err_size, "min_distance", "> 0 m", (double)def->min_distance);
    if (!(def->max_distance >= def->min_distance && isfinite(def->max_distance)))
        return bad(err, err_size, "max_distance", ">= min_distance (m)", (double)def->max_distance);
    memset(cam, 0, sizeof *cam);
    cam->mode = def->mode;
    cam->fov_y = def->fov_y;
    cam->near_plane = def->near_plane;
    cam->far_plane = def->far_plane;
    cam->move_speed = def->move_speed;
    cam->look_speed = def->look_speed;
    cam->zoom_step = def->zoom_step;
    cam->min_distance = def->min_distance;
    cam->max_distance = def->max_distance;
    eng_camera_look_at(cam, def->position, def->target);
    if (err && err_size > 0) err[0] = 0;
    return true;
}

void eng_camera_look_at(eng_camera *cam, const float eye[3], const float target[3])
{
    float dir[3] = { target[0] - eye[0], target[1] - eye[1], target[2] - eye[2] };
    float d = sqrtf(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    if (!(d > 1e-6f)) return; // no direction: keep the current one
    memcpy(cam->position, eye, sizeof cam->position);
    memcpy(cam->target, target, sizeof cam->target);
    cam->distance = d;
    cam->pitch = clampf(asinf(clampf(dir[1] / d, -1.0f, 1.0f)), -MAX_PITCH, MAX_PITCH);
    cam->yaw = atan2f(dir[0], -dir[2]);
    if (fabsf(dir[1] / d) > sinf(MAX_PITCH)) place_eye(cam); // straight up/down: tilt slightly
}

void eng_camera_set_mode(eng_camera *cam, eng_camera_mode mode) { cam->mode = mode; }

void eng_camera_update(eng_camera *cam, const eng_input *in, float dt)
{
    if (!in) return;
    dt = clampf(isfinite(dt) ? dt : 0.0f, 0.0f, 1.0f);
    double mdx, mdy, sx, sy;
    eng_input_mouse_delta(in, &mdx, &mdy);
    eng_input_scroll(in, &sx, &sy);
    if (cam->mode == ENG_CAMERA_ORBIT) {
        if (eng_input_mouse_down(in, GLFW_MOUSE_BUTTON_LEFT)) {
            // The scene turns with the hand: dragging right swings the eye left around the
            // target, dragging down lifts the eye (looking more steeply down).
            cam->yaw += (float)mdx * cam->look_speed;
            cam->pitch = clampf(cam->pitch - (float)mdy * cam->look_speed, -MAX_PITCH, MAX_PITCH);
        }
        if (sy != 0.0) {
            // Each step away from the user (+y) brings the eye closer by zoom_step.
            cam->distance *= powf(1.0f - cam->zoom_step, (float)sy);
            cam->distance = clampf(cam->distance, cam->min_distance, cam->max_distance);
        }
        place_eye(cam);
        return;
    }
    // Fly.
    if (eng_input_mouse_down(in, GLFW_MOUSE_BUTTON_RIGHT)) {
        cam->yaw += (float)mdx * cam->look_speed;
        cam->pitch = clampf(cam->pitch - (float)mdy * cam->look_speed, -MAX_PITCH, MAX_PITCH);
    }
    float f[3], right[3], up[3] = { 0.0f, 1.0f, 0.0f };
    eng_camera_forward(cam, f);
    right[0] = cosf(cam->yaw), right[1] = 0.0f, right[2] = sinf(cam->yaw);
    float move[3] = { 0.0f, 0.0f, 0.0f };
    float axis_f = (float)eng_input_key_down(in, GLFW_KEY_W) - (float)eng_input_key_down(in, GLFW_KEY_S);
    float axis_r = (float)eng_input_key_down(in, GLFW_KEY_D) - (float)eng_input_key_down(in, GLFW_KEY_A);
    float axis_u = (float)eng_input_key_down(in, GLFW_KEY_E) - (float)eng_input_key_down(in, GLFW_KEY_Q);
    for (int k = 0; k < 3; k++) move[k] = f[k] * axis_f + right[k] * axis_r + up[k] * axis_u;
    float len = sqrtf(move[0] * move[0] + move[1] * move[1] + move[2] * move[2]);
    if (len > 0.0f) {
        float speed = cam->move_speed;
        if (eng_input_key_down(in, GLFW_KEY_LEFT_SHIFT) || eng_input_key_down(in, GLFW_KEY_RIGHT_SHIFT)) speed *= 4.0f;
        for (int k = 0; k < 3; k++) cam->position[k] += move[k] / len * speed * dt;
    }
    place_target(cam);
}

void eng_camera_view(const eng_camera *cam, mat4 out)
{
    float f[3], center[3];
    eng_camera_forward(cam, f);
    for (int k = 0; k < 3; k++) center[k] = cam->position[k] + f[k];
    glm_lookat((float *)cam->position, center, (vec3){ 0.0f, 1.0f, 0.0f }, out);
}

void eng_camera_projection(const eng_camera *cam, float aspect, mat4 out)
{
    glm_perspective(cam->fov_y, aspect > 0.0f ? aspect : 1.0f, cam->near_plane, cam->far_plane, out);
}
