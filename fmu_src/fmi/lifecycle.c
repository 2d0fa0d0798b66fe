/* The life cycle of an instance, every version: instantiation (with the model's start values),
 * freeing (with the FMU states it still holds), the logging categories, the experiment's times
 * and tolerance, Initialization Mode, termination and reset. fn names the calling function in
 * messages. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "instance.h"

static void log_early(const fmi2CallbackFunctions *cb, const char *name, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(FMU_PRINTF_FORMAT, 3, 4)))
#endif
    ;
static void log_early(const fmi2CallbackFunctions *cb, const char *name, const char *fmt, ...) {
    char buf[1024];
    va_list ap;
    if (!cb->logger) return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    log_emit(cb, name, fmi2Error, "logStatusError", buf);
}

/* the arguments of an instantiation: 0 (logged through the callbacks) when refused */
static int instantiate_ok(const char *fn, const char *name, fmi2Type type, const char *token,
                          const fmi2CallbackFunctions *functions) {
    if (!functions || !functions->allocateMemory || !functions->freeMemory) return 0;
    if (!name || !*name) {
        log_early(functions, "?", "%s: instanceName must be a non-empty string", fn);
        return 0;
    }
    if (!token || strcmp(token, MODEL_TOKEN) != 0) {
        log_early(functions, name, "%s: GUID %s does not match this FMU's %s", fn, token ? token : "(null)",
                  MODEL_TOKEN);
        return 0;
    }
    if (type != fmi2ModelExchange && type != fmi2CoSimulation) {
        log_early(functions, name, "%s: fmuType %d is neither fmi2ModelExchange (0) nor fmi2CoSimulation (1)", fn,
                  (int)type);
        return 0;
    }
    if (!OFFERS(type == fmi2ModelExchange ? MODEL_CAN_ME : MODEL_CAN_CS)) {
        log_early(functions, name, "%s: fmuType %d: this FMU is %s only", fn, (int)type,
                  type == fmi2ModelExchange ? "co-simulation (1)" : "model exchange (0)");
        return 0;
    }
    return 1;
}

instance_t *fmu_instantiate(const char *fn, const char *name, fmi2Type type, const char *token,
                            const fmi2CallbackFunctions *functions, int logging_on) {
    instance_t *c;
    size_t len;
    if (!instantiate_ok(fn, name, type, token, functions)) return NULL;
    c = (instance_t *)functions->allocateMemory(1, sizeof(instance_t));
    if (!c) return NULL;
    memset(c, 0, sizeof *c);
    len = strlen(name) + 1;
    c->name = (char *)functions->allocateMemory(len, 1);
    if (!c->name) { functions->freeMemory(c); return NULL; }
    memcpy(c->name, name, len);
    c->cb = *functions;
    c->type = type;
    c->logging_on = logging_on != 0;
    c->log_mask = LOG_ALL;
    model_defaults(&c->m);
    return c;
}

void fmu_free_instance(instance_t *c) {
    fmi2CallbackFreeMemory fr;
    if (!c) return;
    fr = c->cb.freeMemory;
    fmu_states_free_all(c);
    c->m.magic = 0;
    fr(c->name);
    fr(c);
}

fmi2Status fmu_set_debug_logging(instance_t *c, const char *fn, int logging_on, size_t n,
                                 const fmi2String categories[]) {
    long long bad;
    if (!c) return fmi2Error;
    c->logging_on = logging_on != 0;
    if (n == 0) { c->log_mask = LOG_ALL; return fmi2OK; }
    if (!categories) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: categories is NULL with nCategories = %zu", fn, n);
        return fmi2Error;
    }
    if ((bad = log_categories(n, categories, &c->log_mask)) >= 0) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: unknown log category \"%s\" (known: logEvents, logStatusWarning, "
                "logStatusError, logDebug)", fn, categories[bad] ? categories[bad] : "(null)");
        return fmi2Error;
    }
    return fmi2OK;
}

fmi2Status fmu_setup_experiment(instance_t *c, const char *fn, int tol_defined, double tol, double start,
                                int stop_defined, double stop) {
    if (!c) return fmi2Error;
    if (!isfinite(start) || (stop_defined && (!isfinite(stop) || stop < start)) ||
        (tol_defined && (!isfinite(tol) || tol <= 0.0))) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: startTime = %g, stopTime = %g, tolerance = %g: allowed finite "
                "startTime, stopTime >= startTime, tolerance > 0", fn, start, stop, tol);
        return fmi2Error;
    }
    c->m.time = c->m.t0 = start;
    c->m.tau = 0.0;
    c->m.stop_defined = stop_defined != 0;
    c->m.stop_time = stop;
    c->m.tol_defined = tol_defined != 0;
    if (tol_defined) c->m.tol = tol < TOL_MAX ? tol : TOL_MAX;
    if (tol_defined && tol > TOL_MAX) {
        /* FMI: the FMU may integrate with a smaller tolerance than the importer's */
        fmu_log(c, fmi2Warning, LOG_WARNING, "%s: tolerance = %g is looser than %g, the loosest at which the "
                "integrator's error follows its tolerance: integrating with %g", fn, tol, TOL_MAX, TOL_MAX);
        return fmi2Warning;
    }
    return fmi2OK;
}

fmi2Status fmu_enter_initialization(instance_t *c) {
    if (!c) return fmi2Error;
    c->m.fsm = ST_INIT;
    c->m.out_valid = 0;
    c->m.params_ok = 0;
    return fmi2OK;
}

fmi2Status fmu_exit_initialization(instance_t *c, const char *fn, int next) {
    if (!c) return fmi2Error;
    if (model_initialize(c, fn, 1) != fmi2OK) { c->m.fsm = ST_ERROR; return fmi2Error; }
    c->m.fsm = next;
    return fmi2OK;
}

fmi2Status fmu_set_mode(instance_t *c, int fsm) {
    if (!c) return fmi2Error;
    c->m.fsm = fsm;
    return fmi2OK;
}

fmi2Status fmu_terminate(instance_t *c) {
    if (!c) return fmi2Error;
    c->m.fsm = ST_TERMINATED;
    return fmi2OK;
}

fmi2Status fmu_reset(instance_t *c) {
    if (!c) return fmi2Error;
    model_reset(c);
    return fmi2OK;
}
