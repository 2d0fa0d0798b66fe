/* Logging shared by the FMUs' glue (plant and controller): the text goes to the importer's
 * logger as a printf format with every '%' doubled, so importers that cannot read variadic
 * arguments (ctypes, JNI) still get the whole message. */
#ifndef FMI2_LOG_H
#define FMI2_LOG_H

#include "fmi2Functions.h"

static inline void fmi2_log_emit(const fmi2CallbackFunctions *cb, const char *name, fmi2Status st,
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

#endif
