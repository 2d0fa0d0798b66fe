/* Get/set of variable values by value reference, every version (FMI 3.0's arrays are expanded
 * to these in fmi3_view.c): type and state checks, every value checked by the model before any
 * is stored (a rejected call changes nothing), tunable parameters recompiled by the model. */
#include <limits.h>
#include <math.h>
#include <string.h>

#include "instance.h"

/* ---------------------------------------------------------------- get / set */

static int lookup(instance_t *c, const char *fn, fmi2ValueReference vr, char type) {
    int row;
    static const char *const TN[] = {"Real", "Integer", "Boolean"};
    if (vr >= GLUE_NVR || (row = GLUE_VR_INDEX[vr]) < 0) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: unknown value reference %u", fn, (unsigned)vr);
        return -1;
    }
    if (GLUE_VARS[row].type != type) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s (value reference %u) is not of type %s", fn,
                GLUE_VARS[row].name, (unsigned)vr, TN[type == 'R' ? 0 : (type == 'I' ? 1 : 2)]);
        return -1;
    }
    return row;
}

/* the value arrays of a get/set: not NULL when nvr > 0, nvr no more than an array can hold */
static int args_ok(instance_t *c, const char *fn, const void *vr, size_t nvr, const void *value) {
    if (nvr > 0 && (!vr || !value)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL array with nvr = %zu", fn, nvr);
        return 0;
    }
    if (nvr > FMU_MAX_VALUES) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: nvr = %zu: allowed at most %zu (no array holds more values)", fn, nvr,
                FMU_MAX_VALUES);
        return 0;
    }
    return 1;
}

/* c: the instance admitted by FMU_ENTER (NULL: the call was refused) */
fmi2Status fmu_get_values(instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                             char type, void *value) {
    size_t k;
    if (!c) return fmi2Error;
    if (!args_ok(c, fn, vr, nvr, value)) return fmi2Error;
    if (c->m.fsm == ST_INIT && !c->m.params_ok) {
        /* initialization mode: compute with the values set so far */
        if (model_initialize(c, fn, 0) != fmi2OK) return fmi2Error;
    }
    {
        fmi2Status st;
        if (model_get_direct(c, fn, vr, nvr, type, value, &st)) return st;
    }
    if (c->m.params_ok && !model_update(c, fn, vr, nvr)) return fmi2Error;
    for (k = 0; k < nvr; k++) {
        int row = lookup(c, fn, vr[k], type);
        double v;
        if (row < 0) return fmi2Error;
        v = c->m.val[vr[k]];
        if (!isfinite(v)) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s = %g is not finite (the simulation overflowed)", fn,
                    GLUE_VARS[row].name, v);
            return fmi2Error;
        }
        if (type == 'R') ((fmi2Real *)value)[k] = v;
        else if (type == 'I')   /* counters saturate at INT_MAX instead of wrapping */
            ((fmi2Integer *)value)[k] = v >= (double)INT_MAX ? INT_MAX : (v <= (double)INT_MIN ? INT_MIN : (fmi2Integer)v);
        else ((fmi2Boolean *)value)[k] = v != 0.0 ? fmi2True : fmi2False;
    }
    return fmi2OK;
}

/* a get/set of String values: this glue's models have none */
fmi2Status fmu_no_strings(instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr) {
    if (!c) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    fmu_log(c, fmi2Error, LOG_ERROR, "%s: this FMU has no String variables (value reference %u)", fn,
            vr ? (unsigned)vr[0] : 0u);
    return fmi2Error;
}

/* May variable `row` be set in the current state? */
static int settable(instance_t *c, const char *fn, int row) {
    const glue_var_t *v = &GLUE_VARS[row];
    int st = c->m.fsm;
    if (v->causality == 'i') {
        if (st & SET_INPUT) return 1;
    } else if (v->causality == 'p') {
        if (st & (v->variability == 't' ? SET_TUNABLE : SET_FIXED)) return 1;
    } else if (v->has_start && (v->variability == 'c')) {
        if (st & SET_EXACT_STATE) return 1;
    }
    fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s (causality %s, variability %s) cannot be set in this state%s", fn,
            v->name, v->causality == 'p' ? "parameter" : (v->causality == 'i' ? "input" :
            (v->causality == 'o' ? "output" : "local")),
            v->variability == 'f' ? "fixed" : (v->variability == 't' ? "tunable" :
            (v->variability == 'd' ? "discrete" : "continuous")),
            v->causality == 'p' && v->variability == 'f' ? " (fixed parameters only before initialization ends)" : "");
    return 0;
}

fmi2Status fmu_set_values(instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                             char type, const void *value) {
    model_t *m;
    size_t k;
    int param_changed = 0;
    if (!c) return fmi2Error;
    m = &c->m;
    if (!args_ok(c, fn, vr, nvr, value)) return fmi2Error;
    /* validate everything first, so a rejected call changes nothing */
    for (k = 0; k < nvr; k++) {
        int row = lookup(c, fn, vr[k], type);
        double v;
        if (row < 0 || !settable(c, fn, row)) return fmi2Error;
        if (type == 'R') v = ((const fmi2Real *)value)[k];
        else if (type == 'I') v = (double)((const fmi2Integer *)value)[k];
        else {
            fmi2Boolean b = ((const fmi2Boolean *)value)[k];
            if (b != fmi2True && b != fmi2False) {
                fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s = %d is not a Boolean: allowed 0 or 1", fn,
                        GLUE_VARS[row].name, (int)b);
                return fmi2Error;
            }
            v = b ? 1.0 : 0.0;
        }
        if (!model_check_value(c, fn, row, v)) return fmi2Error;
        if (GLUE_VARS[row].causality == 'p' && (m->fsm & (ST_EVENT | ST_STEP_COMPLETE))) param_changed = 1;
    }
    if (param_changed) {
        double *save = (double *)c->cb.allocateMemory(GLUE_NVR, sizeof(double));
        fmi2Status st;
        if (!save) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: out of memory", fn); return fmi2Error; }
        memcpy(save, m->val, sizeof m->val);
        for (k = 0; k < nvr; k++)
            m->val[vr[k]] = type == 'R' ? ((const fmi2Real *)value)[k]
                          : type == 'I' ? (double)((const fmi2Integer *)value)[k]
                                        : (((const fmi2Boolean *)value)[k] ? 1.0 : 0.0);
        st = model_recompile(c, fn, save);
        c->cb.freeMemory(save);
        return st;
    }
    for (k = 0; k < nvr; k++) {
        m->val[vr[k]] = type == 'R' ? ((const fmi2Real *)value)[k]
                      : type == 'I' ? (double)((const fmi2Integer *)value)[k]
                                    : (((const fmi2Boolean *)value)[k] ? 1.0 : 0.0);
    }
    model_values_changed(c);
    return fmi2OK;
}
