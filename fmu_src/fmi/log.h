/* Logging of the FMI glue, every model and version: categories, the filter (event
 * traces only when logging is on and logEvents selected; per-sample traces only when logDebug
 * is named in fmi2SetDebugLogging -- not part of "all categories", so a system run with
 * logging on is not drowned by 2 000 lines per second; warnings and errors always), the
 * fmi2SetDebugLogging category list, and the text handed to the importer's logger as a printf
 * format with every '%' doubled, so importers that cannot read variadic arguments (ctypes,
 * JNI) still get the whole message. */
#ifndef LOG_H
#define LOG_H

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "fmi2Functions.h"

#define LOG_EVENTS 1u
#define LOG_WARNING 2u
#define LOG_ERROR 4u
#define LOG_DEBUG 8u
#define LOG_ALL (LOG_EVENTS | LOG_WARNING | LOG_ERROR)   /* logDebug only when named */

/* the printf archetype the logging functions' formats are checked against: on Windows (MinGW)
 * the C99 one of MinGW's own printf family (built with __USE_MINGW_ANSI_STDIO, so %zu and %lld
 * mean what they mean on Linux), elsewhere the C library's */
#if defined(__MINGW32__)
#define FMU_PRINTF_FORMAT __MINGW_PRINTF_FORMAT
#else
#define FMU_PRINTF_FORMAT printf
#endif

static inline void log_emit(const fmi2CallbackFunctions *cb, const char *name, fmi2Status st,
                                 const char *cat, const char *text) {
    char esc[2048];
    size_t i = 0;
    for (; *text && i + 2 < sizeof esc; text++) {
        if (*text == '%') esc[i++] = '%';
        esc[i++] = *text;
    }
    esc[i] = 0;
    cb->logger(cb->componentEnvironment, name, st, cat, esc);
}

/* format and emit a message of category cat (LOG_*) unless the filter drops it */
static inline void log_v(const fmi2CallbackFunctions *cb, const char *name, int logging_on,
                              unsigned mask, fmi2Status st, unsigned cat, const char *fmt, va_list ap) {
    char buf[1024];
    const char *cname = cat == LOG_EVENTS ? "logEvents" : cat == LOG_DEBUG ? "logDebug"
                        : (cat == LOG_WARNING ? "logStatusWarning" : "logStatusError");
    if (!cb->logger) return;
    if ((cat == LOG_EVENTS || cat == LOG_DEBUG) && !(logging_on && (mask & cat))) return;
    vsnprintf(buf, sizeof buf, fmt, ap);
    log_emit(cb, name ? name : "?", st, cname, buf);
}

/* the mask of SetDebugLogging's categories (none: all); -1 when every name is known,
 * else the index of the first unknown one */
static inline long long log_categories(size_t n, const fmi2String categories[], unsigned *mask) {
    size_t k;
    if (n == 0) { *mask = LOG_ALL; return -1; }
    *mask = LOG_WARNING | LOG_ERROR;
    for (k = 0; k < n; k++) {
        if (categories[k] && strcmp(categories[k], "logEvents") == 0) *mask |= LOG_EVENTS;
        else if (categories[k] && strcmp(categories[k], "logDebug") == 0) *mask |= LOG_DEBUG;
        else if (!categories[k] || (strcmp(categories[k], "logStatusWarning") != 0 &&
                                    strcmp(categories[k], "logStatusError") != 0))
            return (long long)k;
    }
    return -1;
}

#endif
