// The camera the benchmarks draw from: seiche-render-bench's rippled block and
// seiche-bench --render's dam break are both seen from here, so that their frame times
// compare (a header of static functions: each program includes it once).
#ifndef SEICHE_BENCH_CAMERA_H
#define SEICHE_BENCH_CAMERA_H

#include <stdbool.h>
#include <stddef.h>
#include <string.h>

#include "engine/render/camera.h"

// Fills `cam`; false with the message in `err` if the camera refused its def.
static inline bool bench_camera(eng_camera *cam, char *err, size_t err_size)
{
    eng_camera_def d = eng_default_camera_def();
    const float eye[3] = { 1.3f, 1.25f, 2.7f }, target[3] = { 0.8f, 0.45f, 0.75f };
    memcpy(d.position, eye, sizeof eye);
    memcpy(d.target, target, sizeof target);
    d.fov_y = 50.0f * 3.14159265f / 180.0f;
    return eng_camera_init(cam, &d, err, err_size);
}

#endif
