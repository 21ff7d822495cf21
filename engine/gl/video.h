// Recording frames to a video: raw RGBA frames piped into ffmpeg, which is spawned with an
// argument vector (no shell ever sees the path; it is passed as file:PATH so that ffmpeg
// reads no protocol or option into it). Each failure is a message naming the path.
#ifndef ENG_VIDEO_H
#define ENG_VIDEO_H

#include <stdbool.h>
#include <stddef.h>

#include "engine/gl/context.h"
#include "engine/gl/screenshot.h"

typedef struct eng_video eng_video;

/// The extensions a video may end in, for messages: ffmpeg picks the container (and its
/// encoder) from the name, and each of these keeps the exact frame rate.
#define ENG_VIDEO_EXTENSIONS ".mp4, .mkv, .mov, .webm or .avi"

/// True when `path` ends in one of ENG_VIDEO_EXTENSIONS (any case). Header-only: the
/// runner's command line checks it without linking GL code.
static inline bool eng_video_extension_ok(const char *path)
{
    return eng_path_has_extension(path, ".mp4") || eng_path_has_extension(path, ".mkv") ||
           eng_path_has_extension(path, ".mov") || eng_path_has_extension(path, ".webm") ||
           eng_path_has_extension(path, ".avi");
}

/// Opens `path` (created or kept, so an unwritable path fails here) and starts ffmpeg for
/// frames of the context's size, one every `frame_s` seconds: the rate given to ffmpeg is
/// 1/frame_s as a fraction (eng_video_rate). Refused, before ffmpeg starts and with
/// nothing created: a name without one of ENG_VIDEO_EXTENSIONS, an odd width or height
/// (the encoders' yuv420p halves both for colour). NULL with a message in `err`: "--record
/// needs ffmpeg on the PATH ..." when there is none.
eng_video *eng_video_open(const eng_context *ctx, const char *path, double frame_s, char *err, size_t err_size);
/// Reads the current framebuffer and sends it. False with a message when ffmpeg stopped
/// taking frames; the video is then closed and its incomplete file removed (said in the
/// message).
bool eng_video_frame(eng_video *v, const eng_context *ctx, char *err, size_t err_size);
/// Closes the pipe, waits for ffmpeg and frees `v`. False with a message when ffmpeg failed
/// or a write failed; the incomplete file is then removed (said in the message) unless
/// ffmpeg left a file that was there before untouched. NULL is fine.
bool eng_video_close(eng_video *v, char *err, size_t err_size);

/// 1/frame_s frames per second as num/den, each in [1, 1000000]: exact whenever frame_s
/// is a fraction with both parts in that range (0.03 s: 100/3; 1/60 s: 60/1; 0.016 s:
/// 125/2), else the nearest such fraction. False for frame_s outside [0.000001, 1].
bool eng_video_rate(double frame_s, long *num, long *den);

#endif
