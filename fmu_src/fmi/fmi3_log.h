/* The logger of an FMI 3.0 instance (fmi3.c): FMI 3.0 has no memory callbacks (calloc/free),
 * and the core logs through an fmi2CallbackLogger: log_adapter hands its messages to the
 * fmi3LogMessageCallback (the text unescaped, the FMI 2.0 function names in the models'
 * messages renamed); componentEnvironment is an fmi3_logger_t (or a struct that starts with
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
    /* the shared glue's messages name its FMI 2.0 functions where FMI 3.0 has others */
    static const char *const RENAMED[][2] = {
        {"fmi2Instantiate", "fmi3Instantiate"}, {"fmi2SetupExperiment", "fmi3EnterInitializationMode"},
        {"fmi2DoStep", "fmi3DoStep"}, {"fmi2GetRealOutputDerivatives", "fmi3GetOutputDerivatives"},
        {"fmi2SetDebugLogging", "fmi3SetDebugLogging"}, {"fmi2NewDiscreteStates", "fmi3UpdateDiscreteStates"},
        {"fmi2EnterInitializationMode", "fmi3EnterInitializationMode"},
        {"fmi2ExitInitializationMode", "fmi3ExitInitializationMode"}, {"fmi2GetReal", "fmi3GetFloat64"},
        {"fmi2SetReal", "fmi3SetFloat64"}, {"fmi2GetInteger", "fmi3GetInt32"}, {"fmi2SetInteger", "fmi3SetInt32"},
        {"fmi2GetBoolean", "fmi3GetBoolean"}, {"fmi2SetBoolean", "fmi3SetBoolean"}};
    const fmi3_logger_t *e = (const fmi3_logger_t *)env;
    char buf[2048];
    size_t i = 0, k;
    (void)name;
    if (!e || !e->log_message || !message) return;
    for (k = 0; k < sizeof RENAMED / sizeof RENAMED[0]; k++) {
        size_t n = strlen(RENAMED[k][0]);
        if (strncmp(message, RENAMED[k][0], n) == 0 && (message[n] == ':' || message[n] == ' ')) {
            size_t m = strlen(RENAMED[k][1]);
            memcpy(buf, RENAMED[k][1], m);
            i = m;
            message += n;
            break;
        }
    }
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
