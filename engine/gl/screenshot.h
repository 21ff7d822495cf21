// Reading back what was drawn: into memory (tests, capture) or into a PNG or JPEG file.
// Reads the framebuffer the scene is drawn into (eng_context_framebuffer): the window's
// back buffer, or the offscreen framebuffer headless. Call after drawing and before
// eng_context_present (after a swap the back buffer's content is undefined).
#ifndef ENG_SCREENSHOT_H
#define ENG_SCREENSHOT_H

#include <ctype.h>
#include <stdbool.h>
#include <stddef.h>
#include <string.h>

#include "engine/gl/context.h"

/// Reads the whole framebuffer into `rgba` (width * height * 4 bytes, 8 bits a channel),
/// rows from the top of the image down. `width`/`height` must equal the context size.
/// Returns false with a message in `err` (may be NULL) on a size mismatch or GL error.
bool eng_read_pixels(const eng_context *ctx, unsigned char *rgba, int width, int height,
                     char *err, size_t err_size);

/// True when `path` ends in `ext` (".png"), in any case. Header-only, so that a program
/// can check an output's name (the runner's command line) without linking GL code.
static inline bool eng_path_has_extension(const char *path, const char *ext)
{
    size_t n = path ? strlen(path) : 0, k = strlen(ext);
    if (n <= k) return false;
    for (size_t i = 0; i < k; i++)
        if (tolower((unsigned char)path[n - k + i]) != tolower((unsigned char)ext[i])) return false;
    return true;
}

typedef enum eng_image_format {
    ENG_IMAGE_UNKNOWN = 0,
    ENG_IMAGE_PNG,  ///< .png: lossless
    ENG_IMAGE_JPEG, ///< .jpg or .jpeg: quality 95
} eng_image_format;

/// The extensions eng_screenshot_write knows, for messages.
#define ENG_SCREENSHOT_EXTENSIONS ".png, .jpg or .jpeg"

/// The format a file name asks for by its extension (any case); ENG_IMAGE_UNKNOWN for
/// anything but .png, .jpg and .jpeg.
static inline eng_image_format eng_image_format_of(const char *path)
{
    if (eng_path_has_extension(path, ".png")) return ENG_IMAGE_PNG;
    if (eng_path_has_extension(path, ".jpg") || eng_path_has_extension(path, ".jpeg")) return ENG_IMAGE_JPEG;
    return ENG_IMAGE_UNKNOWN;
}

/// Writes the framebuffer to a PNG file at `path` (RGB, top row first), whatever its name.
/// Returns false with "cannot write screenshot '<path>': <reason>" in `err` when the file
/// cannot be written; the message goes to the context's log only when `err` is NULL (a
/// caller that takes the message reports it, once).
bool eng_screenshot_write_png(const eng_context *ctx, const char *path, char *err, size_t err_size);

/// As eng_screenshot_write_png, in the format the name asks for (eng_image_format_of):
/// PNG or JPEG. A name with another extension is refused before anything is written:
/// "screenshot '<path>' must end in .png, .jpg or .jpeg".
bool eng_screenshot_write(const eng_context *ctx, const char *path, char *err, size_t err_size);

#endif
