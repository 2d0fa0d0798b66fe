/* The glue's lowest layer: logging through the importer's callback, the one entry check of
 * every FMI call against the table of allowed.h, the one refusal of what a model does not
 * offer, and two checks of numbers every model's answers go through. */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <string.h>

#include "instance.h"

void fmu_log(instance_t *c, fmi2Status st, unsigned cat, const char *fmt, ...) {
    va_list ap;
    if (!c) return;
    /* errors and warnings are always reported; event traces only when asked for */
    va_start(ap, fmt);
    log_v(&c->cb, c->name, c->logging_on, c->log_mask, st, cat, fmt, ap);
    va_end(ap);
}

static instance_t *as_instance(fmi2Component comp) {
    instance_t *c = (instance_t *)comp;
    return (c && c->m.magic == MODEL_MAGIC) ? c : NULL;
}

/* the state check: logs and moves to Error (unless Fatal) when the state is not in mask */
static int state_allowed(instance_t *c, const char *fn, int mask) {
    if (mask == ST_ANY || (c->m.fsm & mask)) return 1;
    fmu_log(c, fmi2Error, LOG_ERROR, "%s: illegal call in state %s", fn,
            c->fmi3 ? fsm_name3(c->m.fsm) : fsm_name(c->m.fsm));
    if (c->m.fsm != ST_FATAL) c->m.fsm = ST_ERROR;
    return 0;
}

instance_t *fmu_enter(fmi2Component comp, const char *fn, int iface, int mask) {
    instance_t *c = as_instance(comp);
    if (!c) return NULL;
    if (!(iface & (1 << c->type))) {
        int me = iface == FOR_ME;
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: only for %s; this instance is %s", fn,
                me ? "model exchange" : "co-simulation", me ? "co-simulation" : "model exchange");
        return NULL;
    }
    return state_allowed(c, fn, mask) ? c : NULL;
}

fmi2Status fmu_refuse(instance_t *c, const char *fn, const char *why) {
    if (!c) return fmi2Error;
    if (!why) return fmi2OK;
    fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s", fn, why);
    return fmi2Error;
}

double fmu_ulp_slack(double t) {
    /* nextafter(|t|, +inf) - |t| from the bits: the next double up is the one whose pattern is
     * one more (+inf and NaN stay as they are, the difference is then NaN as nextafter's) */
    union { double d; uint64_t u; } bits;   /* the double's pattern (C99 TC3 6.5.2.3) */
    double a;
    bits.d = fabs(t);
    a = bits.d;
    if (bits.u < 0x7FF0000000000000ull) bits.u++;
    return 16.0 * (bits.d - a);
}

int fmu_finite_result(instance_t *c, const char *fn, const double *x, size_t n) {
    size_t j;
    if (!c->m.params_ok) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: the model is not initialized (no successful %s)", fn,
                c->fmi3 ? "fmi3ExitInitializationMode" : "fmi2ExitInitializationMode");
        return 0;
    }
    for (j = 0; j < n; j++) {
        if (!isfinite(x[j])) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: element %zu = %g is not finite (the simulation overflowed)",
                    fn, j, x[j]);
            return 0;
        }
    }
    return 1;
}
