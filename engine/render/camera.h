// A perspective camera with two controls:
//   ENG_CAMERA_ORBIT  left-drag turns around `target`, scroll zooms (distance to target);
//   ENG_CAMERA_FLY    WASD moves along the view, Q/E down/up (world Y), mouse look while
//                     the right button is held; Shift moves faster.
// The camera is a plain value: set it up with eng_camera_init, move it with
// eng_camera_update each frame, read its matrices. Y is up; angles in radians.
#ifndef ENG_CAMERA_H
#define ENG_CAMERA_H

#include <cglm/cglm.h>
#include <stdbool.h>
#include <stddef.h>

#include "engine/gl/input.h"

typedef enum eng_camera_mode {
    ENG_CAMERA_ORBIT = 0,
    ENG_CAMERA_FLY,
} eng_camera_mode;

typedef struct eng_camera_def {
    eng_camera_mode mode;
    float position[3];    ///< eye in m
    float target[3];      ///< looked-at point in m (the orbit centre); != position
    float fov_y;          ///< vertical field of view, radians, 0.01..3.1
    float near_plane;     ///< m, > 0
    float far_plane;      ///< m, > near_plane
    float move_speed;     ///< fly speed in m/s, >= 0 (x4 with Shift)
    float look_speed;     ///< radians per pixel of mouse motion, >= 0 (fly look and orbit)
    float zoom_step;      ///< fraction of the distance per scroll step, 0..0.9
    float min_distance;   ///< orbit distance limits in m, 0 < min <= max
    float max_distance;
} eng_camera_def;

/// Orbit mode, eye (4, 3, 6) looking at (0, 0.5, 0), fov 60 deg, near 0.05 m, far 500 m,
/// 3 m/s, 0.005 rad/pixel, 10 % zoom per step, distance 0.2..200 m.
eng_camera_def eng_default_camera_def(void);

typedef struct eng_camera {
    eng_camera_mode mode;
    float position[3]; ///< eye, m
    float target[3];   ///< orbit centre, m (in fly mode: a point `distance` ahead)
    float yaw;         ///< radians; 0 looks down -Z, positive turns right (towards +X)
    float pitch;       ///< radians; positive looks up; within +-89 deg
    float distance;    ///< eye to target, m
    float fov_y, near_plane, far_plane;
    float move_speed, look_speed, zoom_step, min_distance, max_distance;
} eng_camera;

/// Sets up `cam` from `def`. False with a message naming the field in `err` (may be NULL)
/// when the def is out of range; `cam` is then left unchanged.
bool eng_camera_init(eng_camera *cam, const eng_camera_def *def, char *err, size_t err_size);
/// Puts the eye at `eye` looking at `target` (which becomes the orbit centre).
void eng_camera_look_at(eng_camera *cam, const float eye[3], const float target[3]);
void eng_camera_set_mode(eng_camera *cam, eng_camera_mode mode);
/// Applies one frame of input; `dt` in s (0..1). `input` may be NULL (no change).
void eng_camera_update(eng_camera *cam, const eng_input *input, float dt);
/// Unit view direction (from the eye towards the target).
void eng_camera_forward(const eng_camera *cam, float out[3]);
/// World -> view (right-handed, the camera looks down -Z of view space).
void eng_camera_view(const eng_camera *cam, mat4 out);
/// View -> clip, OpenGL conventions (depth -1..1); `aspect` = width / height.
void eng_camera_projection(const eng_camera *cam, float aspect, mat4 out);

#endif
