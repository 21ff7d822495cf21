// Frames to ffmpeg through a pipe, ffmpeg spawned without a shell. See video.h.
#include "engine/gl/video.h"

#include <errno.h>
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
    char path[1024];
};

eng_video *eng_video_open(const eng_context *ctx, const char *path, int fps, char *err, size_t err_size)
{
    struct stat before;
    bool existed = stat(path, &before) == 0;
    FILE *probe = fopen(path, "ab"); // creates it if missing, keeps what is there
    if (!probe) {
        snprintf(err, err_size, "--record: cannot write '%s': %s", path, strerror(errno));
        return NULL;
    }
    fclose(probe);
    eng_video *v = calloc(1, sizeof *v);
    if (!v) {
        snprintf(err, err_size, "--record: out of memory");
        return NULL;
    }
    snprintf(v->path, sizeof v->path, "%s", path);
    eng_context_size(ctx, &v->width, &v->height);
    v->pixels = malloc((size_t)v->width * (size_t)v->height * 4);
    char size[32], rate[16], target[1100];
    snprintf(size, sizeof size, "%dx%d", v->width, v->height);
    snprintf(rate, sizeof rate, "%d", fps > 0 ? fps : 60);
    snprintf(target, sizeof target, "file:%s", path);
    char *const argv[] = { "ffmpeg", "-nostdin", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba",
                           "-s", size, "-r", rate, "-i", "pipe:0", "-vf", "vflip", "-pix_fmt", "yuv420p",
                           target, NULL };
    int fds[2];
    if (!v->pixels || pipe(fds) != 0) {
        snprintf(err, err_size, "--record: cannot make a pipe for ffmpeg: %s", strerror(errno));
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
        if (!existed) remove(path);
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

bool eng_video_frame(eng_video *v, const eng_context *ctx, char *err, size_t err_size)
{
    char msg[256];
    if (!eng_read_pixels(ctx, v->pixels, v->width, v->height, msg, sizeof msg)) {
        snprintf(err, err_size, "--record: %s", msg);
        eng_video_close(v, NULL, 0);
        return false;
    }
    size_t n = (size_t)v->width * (size_t)v->height;
    if (fwrite(v->pixels, 4, n, v->pipe) != n) {
        snprintf(err, err_size, "--record: ffmpeg stopped taking frames for '%s': %s", v->path, strerror(errno));
        eng_video_close(v, NULL, 0);
        return false;
    }
    return true;
}

bool eng_video_close(eng_video *v, char *err, size_t err_size)
{
    if (!v) return true;
    bool ok = true;
    if (fclose(v->pipe) != 0) {
        if (err) snprintf(err, err_size, "--record: ffmpeg stopped taking frames: %s", strerror(errno));
        ok = false;
    }
    int ws = 0;
    while (waitpid(v->pid, &ws, 0) < 0 && errno == EINTR) {}
    if (ok && !(WIFEXITED(ws) && WEXITSTATUS(ws) == 0)) {
        if (err)
            snprintf(err, err_size, "--record: ffmpeg failed (%s %d) writing '%s'", WIFEXITED(ws) ? "exit status" : "signal",
                     WIFEXITED(ws) ? WEXITSTATUS(ws) : WTERMSIG(ws), v->path);
        ok = false;
    }
    free(v->pixels);
    free(v);
    return ok;
}
