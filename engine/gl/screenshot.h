// Reading back what was drawn: into memory (tests, capture) or into a PNG file.
// Reads the framebuffer the scene is drawn into (eng_context_framebuffer): the window's
// back buffer, or the offscreen framebuffer headless. Call after drawing and before
// eng_context_present (after a swap the back buffer's content is undefined).
#ifndef ENG_SCREENSHOT_H
#define ENG_SCREENSHOT_H

#include <stdbool.h>
#include <stddef.h>

#include "engine/gl/context.h"

/// Reads the whole framebuffer into `rgba` (width * height * 4 bytes, 8 bits a channel),
/// rows from the top of the image down. `width`/`height` must equal the context size.
/// Returns false with a message in `err` (may be NULL) on a size mismatch or GL error.
bool eng_read_pixels(const eng_context *ctx, unsigned char *rgba, int width, int height,
                     char *err, size_t err_size);

/// Writes the framebuffer to a PNG file at `path` (RGB, top row first). Returns false with
/// "cannot write screenshot '<path>': <reason>" in `err` (may be NULL) and in the
/// context's log when the file cannot be written.
bool eng_screenshot_write_png(const eng_context *ctx, const char *path, char *err, size_t err_size);

#endif
