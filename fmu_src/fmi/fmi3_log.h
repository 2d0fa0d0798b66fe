/* The logger of an FMI 3.0 instance (fmi3.c): FMI 3.0 has no memory callbacks (calloc/free),
 * and the core logs through an fmi2CallbackLogger: log_adapter hands its messages (each naming
 * the FMI 3.0 function called) to the fmi3LogMessageCallback, the text unescaped;
 * componentEnvironment is an fmi3_logger_t (or a struct that starts with
 * one). fmi3_refuse: the answer of a function no model offers (fmi3_stubs.c), in fmi3.c. */
#ifndef FMI3_LOG_H
#define FMI3_LOG_H

#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "fmi3Functions.h"

typedef struct {
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log_message;
} fmi3_logger_t;

static inline void *fmi3_mem_alloc(size_t n, size_t size) { return calloc(n, size); }
static inline void fmi3_mem_free(void *p) { free(p); }

static inline void fmi3_log_adapter(fmi2ComponentEnvironment env, fmi2String name, fmi2Status st,
                                    fmi2String category, fmi2String message, ...) {
    const fmi3_logger_t *e = (const fmi3_logger_t *)env;
    char buf[2048];
    size_t i = 0;
    (void)name;
    if (!e || !e->log_message || !message) return;
    for (; *message && i + 1 < sizeof buf; message++) {
        if (message[0] == '%' && message[1] == '%') message++;
        buf[i++] = *message;
    }
    buf[i] = 0;
    e->log_message(e->env, (fmi3Status)st, category, buf);
}

/* the FMI 2.0 callbacks of an FMI 3.0 instance whose logger is *lg */
static inline fmi2CallbackFunctions fmi3_callbacks(fmi3_logger_t *lg) {
    fmi2CallbackFunctions cb;
    memset(&cb, 0, sizeof cb);
    cb.logger = fmi3_log_adapter;
    cb.allocateMemory = fmi3_mem_alloc;
    cb.freeMemory = fmi3_mem_free;
    cb.componentEnvironment = lg;
    return cb;
}

/* why == NULL: fmi3OK for a live instance (a call with nothing to do), else logs "<fn>: not
 * provided (<why>)" and answers fmi3Error; fmi3Error for anything that is not an instance */
fmi3Status fmi3_refuse(fmi3Instance instance, const char *fn, const char *why);

#endif
