// Framebuffer read-back and PNG / JPEG screenshots. See screenshot.h.
#include "engine/gl/screenshot.h"

#include <epoxy/gl.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <stb/stb_image_write.h>

static bool say(char *err, size_t err_size, const char *msg)
{
    if (err && err_size > 0) snprintf(err, err_size, "%s", msg);
    return false;
}

bool eng_read_pixels(const eng_context *ctx, unsigned char *rgba, int width, int height,
                     char *err, size_t err_size)
{
    int w, h;
    eng_context_size(ctx, &w, &h);
    if (width != w || height != h) {
        char msg[160];
        snprintf(msg, sizeof msg, "eng_read_pixels: width/height must match the framebuffer %dx%d (got %dx%d)",
                 w, h, width, height);
        return say(err, err_size, msg);
    }
    if (!rgba) return say(err, err_size, "eng_read_pixels: rgba must not be NULL");
    while (glGetError() != GL_NO_ERROR) {
    }
    GLint prev_read = 0, prev_pack = 4;
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &prev_read);
    glGetIntegerv(GL_PACK_ALIGNMENT, &prev_pack);
    GLuint fb = eng_context_framebuffer(ctx);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, fb);
    glReadBuffer(fb ? GL_COLOR_ATTACHMENT0 : GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    GLenum e = glGetError();
    glPixelStorei(GL_PACK_ALIGNMENT, prev_pack);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)prev_read);
    if (e != GL_NO_ERROR) {
        char msg[96];
        snprintf(msg, sizeof msg, "eng_read_pixels: glReadPixels failed (GL error 0x%04x)", e);
        return say(err, err_size, msg);
    }
    // GL's rows run bottom-up; images run top-down.
    size_t stride = (size_t)w * 4;
    unsigned char *tmp = malloc(stride);
    if (!tmp) return say(err, err_size, "eng_read_pixels: out of memory");
    for (int y = 0; y < h / 2; y++) {
        unsigned char *a = rgba + (size_t)y * stride;
        unsigned char *b = rgba + (size_t)(h - 1 - y) * stride;
        memcpy(tmp, a, stride);
        memcpy(a, b, stride);
        memcpy(b, tmp, stride);
    }
    free(tmp);
    return true;
}

typedef struct file_sink {
    FILE *f;
    bool failed;
    int error;
} file_sink;

static void sink_write(void *user, void *data, int size)
{
    file_sink *s = user;
    if (s->failed || size <= 0) return;
    if (fwrite(data, 1, (size_t)size, s->f) != (size_t)size) {
        s->failed = true;
        s->error = errno;
    }
}

static bool write_failed(const eng_context *ctx, char *err, size_t err_size, const char *path,
                         const char *reason)
{
    char msg[1200];
    snprintf(msg, sizeof msg, "cannot write screenshot '%s': %s", path, reason);
    // One report: to the caller when it takes the message, else to the log.
    if (!err || err_size == 0) eng_log(eng_context_logger(ctx), ENG_LOG_ERROR, "%s", msg);
    return say(err, err_size, msg);
}

static bool write_image(const eng_context *ctx, const char *path, eng_image_format format, char *err, size_t err_size)
{
    if (!path || !path[0]) return write_failed(ctx, err, err_size, "", "path must be a file name (got an empty path)");
    int w, h;
    eng_context_size(ctx, &w, &h);
    unsigned char *rgba = malloc((size_t)w * (size_t)h * 4);
    if (!rgba) return write_failed(ctx, err, err_size, path, "out of memory");
    char rerr[256];
    if (!eng_read_pixels(ctx, rgba, w, h, rerr, sizeof rerr)) {
        free(rgba);
        return write_failed(ctx, err, err_size, path, rerr);
    }
    // Drop alpha: a window's back buffer may carry any alpha, and PNG viewers honour it.
    unsigned char *rgb = rgba;
    for (size_t i = 0, n = (size_t)w * (size_t)h; i < n; i++) {
        rgb[i * 3 + 0] = rgba[i * 4 + 0];
        rgb[i * 3 + 1] = rgba[i * 4 + 1];
        rgb[i * 3 + 2] = rgba[i * 4 + 2];
    }
    file_sink sink = { fopen(path, "wb"), false, 0 };
    if (!sink.f) {
        int e = errno;
        free(rgba);
        return write_failed(ctx, err, err_size, path, strerror(e));
    }
    int ok = format == ENG_IMAGE_JPEG ? stbi_write_jpg_to_func(sink_write, &sink, w, h, 3, rgb, 95)
                                      : stbi_write_png_to_func(sink_write, &sink, w, h, 3, rgb, w * 3);
    free(rgba);
    int close_err = fclose(sink.f) != 0 ? errno : 0;
    const char *reason = !ok ? (format == ENG_IMAGE_JPEG ? "JPEG encoding failed" : "PNG encoding failed")
                         : sink.failed ? strerror(sink.error)
                         : close_err   ? strerror(close_err)
                                       : NULL;
    if (!reason) return true;
    // No part of an image left behind as if it were one: a plain file this call wrote is
    // removed (a device or a pipe the name leads to is left alone).
    struct stat st;
    char why[512];
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode) && remove(path) == 0) {
        snprintf(why, sizeof why, "%s (the incomplete file was removed)", reason);
        reason = why;
    }
    return write_failed(ctx, err, err_size, path, reason);
}

bool eng_screenshot_write_png(const eng_context *ctx, const char *path, char *err, size_t err_size)
{
    return write_image(ctx, path, ENG_IMAGE_PNG, err, err_size);
}

bool eng_screenshot_write(const eng_context *ctx, const char *path, char *err, size_t err_size)
{
    eng_image_format format = eng_image_format_of(path);
    if (format == ENG_IMAGE_UNKNOWN) {
        char msg[1200];
        snprintf(msg, sizeof msg, "screenshot '%s' must end in " ENG_SCREENSHOT_EXTENSIONS, path ? path : "");
        if (!err || err_size == 0) eng_log(eng_context_logger(ctx), ENG_LOG_ERROR, "%s", msg);
        return say(err, err_size, msg);
    }
    return write_image(ctx, path, format, err, err_size);
}
