// Recording frames to a video: raw RGBA frames piped into ffmpeg, which is spawned with an
// argument vector (no shell ever sees the path; it is passed as file:PATH so that ffmpeg
// reads no protocol or option into it). Each failure is a message naming the path.
#ifndef ENG_VIDEO_H
#define ENG_VIDEO_H

#include <stdbool.h>
#include <stddef.h>

#include "engine/gl/context.h"

typedef struct eng_video eng_video;

/// Opens `path` (created or kept, so an unwritable path fails here) and starts ffmpeg for
/// frames of the context's size at `fps` frames per second. NULL with a message in `err`:
/// "--record needs ffmpeg on the PATH ..." when there is none.
eng_video *eng_video_open(const eng_context *ctx, const char *path, int fps, char *err, size_t err_size);
/// Reads the current framebuffer and sends it. False with a message when ffmpeg stopped
/// taking frames (the video is then closed).
bool eng_video_frame(eng_video *v, const eng_context *ctx, char *err, size_t err_size);
/// Closes the pipe, waits for ffmpeg and frees `v`. False with a message when ffmpeg failed
/// or a write failed. NULL is fine.
bool eng_video_close(eng_video *v, char *err, size_t err_size);

#endif
