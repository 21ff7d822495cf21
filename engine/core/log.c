#include "engine/core/log.h"

#include <stdarg.h>
#include <stdio.h>

eng_logger eng_default_logger(void)
{
    eng_logger l = { NULL, NULL, ENG_LOG_INFO };
    return l;
}

const char *eng_log_level_name(eng_log_level level)
{
    switch (level) {
    case ENG_LOG_DEBUG: return "debug";
    case ENG_LOG_INFO: return "info";
    case ENG_LOG_WARN: return "warning";
    case ENG_LOG_ERROR: return "error";
    }
    return "?";
}

void eng_log(const eng_logger *log, eng_log_level level, const char *fmt, ...)
{
    if (log && level < log->min_level) return;
    char buf[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    if (log && log->fn) log->fn(log->user, level, buf);
    else fprintf(stderr, "seiche: %s: %s\n", eng_log_level_name(level), buf);
}

bool eng_fail(char *err, size_t err_size, const char *fmt, ...)
{
    if (err && err_size) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err, err_size, fmt, ap);
        va_end(ap);
    }
    return false;
}
