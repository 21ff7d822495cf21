// Engine logger: levels, stderr by default, replaceable by a host. No global state:
// a logger lives in the engine context (or wherever the host keeps it).
#ifndef ENG_LOG_H
#define ENG_LOG_H

#include <stdbool.h>
#include <stddef.h>

typedef enum eng_log_level {
    ENG_LOG_DEBUG = 0,
    ENG_LOG_INFO,
    ENG_LOG_WARN,
    ENG_LOG_ERROR,
} eng_log_level;

typedef void eng_log_fn(void *user, eng_log_level level, const char *message);

typedef struct eng_logger {
    eng_log_fn *fn;          ///< NULL: write to stderr
    void *user;
    eng_log_level min_level; ///< messages below this level are dropped
} eng_logger;

/// A logger that writes INFO and above to stderr.
eng_logger eng_default_logger(void);

void eng_log(const eng_logger *log, eng_log_level level, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

const char *eng_log_level_name(eng_log_level level);

/// Formats a message into the caller's error buffer (nothing when err is NULL or err_size 0)
/// and returns false: `return eng_fail(err, err_size, "mesh %s: ...", path);`.
bool eng_fail(char *err, size_t err_size, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

#endif
