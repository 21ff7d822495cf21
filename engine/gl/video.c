// Frames to ffmpeg through a pipe, ffmpeg spawned without a shell. See video.h.
#include "engine/gl/video.h"

#include <errno.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "engine/gl/screenshot.h"

extern char **environ;

struct eng_video {
    FILE *pipe;
    pid_t pid;
    int width, height;
    unsigned char *pixels;
    bool existed;       // the file was there before eng_video_open
    struct stat before; // and this is what it was
    char path[1024];
};

bool eng_video_rate(double frame_s, long *num, long *den)
{
    if (!(frame_s >= 1e-6 && frame_s <= 1.0)) return false;
    // The convergents h/k of frame_s's continued fraction, until one equals it (to well
    // below a frame's rounding) or the next would pass 1000000.
    long long h0 = 0, h1 = 1, k0 = 1, k1 = 0;
    double x = frame_s;
    for (int i = 0; i < 64; i++) {
        double a = floor(x);
        if (a > 1e6) break;
        long long h = (long long)a * h1 + h0, k = (long long)a * k1 + k0;
        if (h > 1000000 || k > 1000000) break;
        h0 = h1, h1 = h, k0 = k1, k1 = k;
        if (h > 0 && fabs((double)h / (double)k - frame_s) <= 1e-15 * frame_s) break;
        if (x - a <= 0.0) break;
        x = 1.0 / (x - a);
    }
    if (h1 <= 0) return false; // not reached for frame_s >= 1e-6
    *num = (long)k1;
    *den = (long)h1;
    return true;
}

eng_video *eng_video_open(const eng_context *ctx, const char *path, double frame_s, char *err, size_t err_size)
{
    int width, height;
    eng_context_size(ctx, &width, &height);
    long rate_num, rate_den;
    if (!path || !eng_video_extension_ok(path)) {
        snprintf(err, err_size, "--record must name a file ending in " ENG_VIDEO_EXTENSIONS
                 " (ffmpeg picks the format from it) (got '%s')", path ? path : "");
        return NULL;
    }
    if (width % 2 || height % 2) {
        snprintf(err, err_size, "--record needs an even width and height for the video encoder (got a %dx%d "
                 "framebuffer; --size takes even numbers)", width, height);
        return NULL;
    }
    if (!eng_video_rate(frame_s, &rate_num, &rate_den)) {
        snprintf(err, err_size, "--record: the frame step must be in [0.000001, 1] s (got %g)", frame_s);
        return NULL;
    }
    eng_video *v = calloc(1, sizeof *v);
    if (!v) {
        snprintf(err, err_size, "--record: out of memory");
        return NULL;
    }
    v->existed = stat(path, &v->before) == 0;
    FILE *probe = fopen(path, "ab"); // creates it if missing, keeps what is there
    if (!probe) {
        snprintf(err, err_size, "--record: cannot write '%s': %s", path, strerror(errno));
        free(v);
        return NULL;
    }
    fclose(probe);
    snprintf(v->path, sizeof v->path, "%s", path);
    v->width = width;
    v->height = height;
    v->pixels = malloc((size_t)v->width * (size_t)v->height * 4);
    char size[32], rate[48], target[1100];
    snprintf(size, sizeof size, "%dx%d", v->width, v->height);
    snprintf(rate, sizeof rate, "%ld/%ld", rate_num, rate_den);
    snprintf(target, sizeof target, "file:%s", path);
    char *const argv[] = { "ffmpeg", "-nostdin", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba",
                           "-s", size, "-r", rate, "-i", "pipe:0", "-vf", "vflip", "-pix_fmt", "yuv420p",
                           target, NULL };
    int fds[2];
    if (!v->pixels || pipe(fds) != 0) {
        snprintf(err, err_size, "--record: cannot make a pipe for ffmpeg: %s", strerror(errno));
        if (!v->existed) remove(path);
        free(v->pixels);
        free(v);
        return NULL;
    }
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_adddup2(&fa, fds[0], 0);
    posix_spawn_file_actions_addclose(&fa, fds[0]);
    posix_spawn_file_actions_addclose(&fa, fds[1]);
    int e = posix_spawnp(&v->pid, "ffmpeg", &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    close(fds[0]);
    if (e == 0) v->pipe = fdopen(fds[1], "w");
    if (e != 0 || !v->pipe) {
        if (e != 0) close(fds[1]);
        if (!v->existed) remove(path);
        if (e == ENOENT) snprintf(err, err_size, "--record needs ffmpeg on the PATH (apt-get install ffmpeg)");
        else snprintf(err, err_size, "--record: cannot start ffmpeg: %s", strerror(e ? e : errno));
        if (e == 0) {
            close(fds[1]);
            waitpid(v->pid, NULL, 0);
        }
        free(v->pixels);
        free(v);
        return NULL;
    }
    return v;
}

// After a failed recording: removes what ffmpeg left at the path (a 0-byte or truncated
// file is no video), unless it is not a regular file or is a file that was there before
// and ffmpeg never touched. Appends what happened to the message in `err`.
static void discard(const eng_video *v, char *err, size_t err_size)
{
    struct stat now;
    const char *what;
    if (stat(v->path, &now) != 0 || !S_ISREG(now.st_mode)) what = "";
    else if (v->existed && now.st_ino == v->before.st_ino && now.st_size == v->before.st_size &&
             now.st_mtim.tv_sec == v->before.st_mtim.tv_sec && now.st_mtim.tv_nsec == v->before.st_mtim.tv_nsec)
        what = "; the file that was there is left as it was";
    else what = remove(v->path) == 0 ? "; removed the incomplete file" : "; could not remove the incomplete file";
    size_t n = err ? strlen(err) : 0;
    if (err && n < err_size) snprintf(err + n, err_size - n, "%s", what);
}

// Ends ffmpeg: closes the pipe, waits for it and frees `v`. `failure` is what went wrong
// before (NULL: nothing); the message in `err` says it, or the failure found here, with
// ffmpeg's exit status (its own messages are above on stderr) and what became of the file.
static bool finish(eng_video *v, const char *failure, char *err, size_t err_size)
{
    int close_error = fclose(v->pipe) != 0 ? errno : 0;
    int ws = 0;
    while (waitpid(v->pid, &ws, 0) < 0 && errno == EINTR) {}
    bool ffmpeg_ok = WIFEXITED(ws) && WEXITSTATUS(ws) == 0;
    char how[48];
    snprintf(how, sizeof how, "%s %d", WIFEXITED(ws) ? "exit status" : "signal",
             WIFEXITED(ws) ? WEXITSTATUS(ws) : WTERMSIG(ws));
    char why[400] = "";
    if (failure) snprintf(why, sizeof why, "%s", failure);
    else if (close_error) snprintf(why, sizeof why, "ffmpeg stopped taking frames: %s", strerror(close_error));
    else if (!ffmpeg_ok) snprintf(why, sizeof why, "ffmpeg failed");
    bool ok = !why[0];
    if (!ok && err && err_size > 0) {
        snprintf(err, err_size, "--record: %s writing '%s' (ffmpeg: %s)", why, v->path, how);
        discard(v, err, err_size);
    } else if (!ok) {
        discard(v, NULL, 0);
    }
    free(v->pixels);
    free(v);
    return ok;
}

bool eng_video_frame(eng_video *v, const eng_context *ctx, char *err, size_t err_size)
{
    char msg[256];
    if (!eng_read_pixels(ctx, v->pixels, v->width, v->height, msg, sizeof msg)) {
        char why[300];
        snprintf(why, sizeof why, "reading the frame back failed (%s)", msg);
        return finish(v, why, err, err_size);
    }
    size_t n = (size_t)v->width * (size_t)v->height;
    if (fwrite(v->pixels, 4, n, v->pipe) != n) {
        char why[300];
        snprintf(why, sizeof why, "ffmpeg stopped taking frames (%s)", strerror(errno));
        finish(v, why, err, err_size);
        return false;
    }
    return true;
}

bool eng_video_close(eng_video *v, char *err, size_t err_size)
{
    if (!v) return true;
    return finish(v, NULL, err, err_size);
}
