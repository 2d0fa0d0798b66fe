/* FMI 2.0 get/set of variable values: type and state checks, every value checked before any
 * is stored (a rejected call changes nothing), tunable parameters recompiled. */
#include <limits.h>
#include <math.h>
#include <string.h>

#include "fmi2_instance.h"

/* ---------------------------------------------------------------- get / set */

static int lookup(instance_t *c, const char *fn, fmi2ValueReference vr, char type) {
    int row;
    static const char *const TN[] = {"Real", "Integer", "Boolean"};
    if (vr >= MODEL_NVR || (row = MODEL_VR_INDEX[vr]) < 0) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: unknown value reference %u", fn, (unsigned)vr);
        return -1;
    }
    if (MODEL_VARS[row].type != type) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s (value reference %u) is not of type %s", fn,
                MODEL_VARS[row].name, (unsigned)vr, TN[type == 'R' ? 0 : (type == 'I' ? 1 : 2)]);
        return -1;
    }
    return row;
}

static int args_ok(instance_t *c, const char *fn, const void *vr, size_t nvr, const void *value) {
    if (nvr > 0 && (!vr || !value)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL array with nvr = %zu", fn, nvr);
        return 0;
    }
    return 1;
}

/* Every value asked for is the position, the measured position or the velocity (a controller's
 * read between steps): these are the states themselves (x_measured: x, or x + compliance.dx on
 * the load side), so nothing else need be computed (outputs are computed when read). */
static int states_only(const model_t *m, const fmi2ValueReference vr[], size_t nvr, char type) {
    size_t k;
    if (type != 'R' || m->out_valid || !m->params_ok || nvr == 0) return 0;
    for (k = 0; k < nvr; k++)
        if (vr[k] != VR_x && vr[k] != VR_v && vr[k] != VR_x_measured) return 0;
    return 1;
}

static double state_value(const model_t *m, fmi2ValueReference vr) {
    if (vr == VR_x_measured) return compliance_x_measured(&m->p, m->y);
    return m->y[vr == VR_x ? PLANT_IX : PLANT_IV];
}

/* c: the instance admitted by FMU_ENTER (NULL: the call was refused) */
fmi2Status fmu_get_values(instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                             char type, void *value) {
    size_t k;
    if (!c) return fmi2Error;
    if (!args_ok(c, fn, vr, nvr, value)) return fmi2Error;
    if (c->m.fsm == ST_INIT && !c->m.params_ok) {
        /* initialization mode: compute with the values set so far */
        if (fmu_initialize_plant(c) != fmi2OK) return fmi2Error;
    }
    if (states_only(&c->m, vr, nvr, type)) {
        for (k = 0; k < nvr; k++) {
            double v = state_value(&c->m, vr[k]);
            if (!isfinite(v)) {
                fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s = %g is not finite (the simulation overflowed)", fn,
                        MODEL_VARS[MODEL_VR_INDEX[vr[k]]].name, v);
                return fmi2Error;
            }
            ((fmi2Real *)value)[k] = v;
        }
        return fmi2OK;
    }
    if (c->m.params_ok) {
        /* the derivatives only when one is asked for */
        int der = 0;
        for (k = 0; k < nvr; k++) der |= vr[k] < MODEL_NVR && c->m.is_der[vr[k]];
        if (der) fmu_update_outputs(c);
        else fmu_update_values(c);
    }
    for (k = 0; k < nvr; k++) {
        int row = lookup(c, fn, vr[k], type);
        double v;
        if (row < 0) return fmi2Error;
        v = c->m.val[vr[k]];
        if (!isfinite(v)) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s = %g is not finite (the simulation overflowed)", fn,
                    MODEL_VARS[row].name, v);
            return fmi2Error;
        }
        if (type == 'R') ((fmi2Real *)value)[k] = v;
        else if (type == 'I')   /* counters saturate at INT_MAX instead of wrapping */
            ((fmi2Integer *)value)[k] = v >= (double)INT_MAX ? INT_MAX : (v <= (double)INT_MIN ? INT_MIN : (fmi2Integer)v);
        else ((fmi2Boolean *)value)[k] = v != 0.0 ? fmi2True : fmi2False;
    }
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    return fmu_get_values(FMU_ENTER(c, fmi2GetReal), "fmi2GetReal", vr, nvr, 'R', value);
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
    return fmu_get_values(FMU_ENTER(c, fmi2GetInteger), "fmi2GetInteger", vr, nvr, 'I', value);
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
    return fmu_get_values(FMU_ENTER(c, fmi2GetBoolean), "fmi2GetBoolean", vr, nvr, 'B', value);
}
fmi2Status fmi2GetString(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
    instance_t *c = FMU_ENTER(comp, fmi2GetString);
    (void)vr; (void)value;
    if (!c) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    fmu_log(c, fmi2Error, LOG_ERROR, "fmi2GetString: this FMU has no String variables (value reference %u)",
            vr ? (unsigned)vr[0] : 0u);
    return fmi2Error;
}

/* May variable `row` be set in the current state? */
static int settable(instance_t *c, const char *fn, int row) {
    const model_var_t *v = &MODEL_VARS[row];
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

/* params_check_value binds every variable to the physics' ranges and the min/max of
 * modelDescription.xml; solver.tol must in addition be > 0 (its declared min 0 is open). */
static int declared_range_ok(instance_t *c, const char *fn, int row, double v) {
    const model_var_t *mv = &MODEL_VARS[row];
    if (mv->vr == VR_solver_tol && !(v > 0.0 && v <= TOL_MAX)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: solver.tol = %.17g is out of range: allowed (0, %g] (the loosest "
                "tolerance at which the integrator's error follows it)", fn, v, TOL_MAX);
        return 0;
    }
    return 1;
}

fmi2Status fmu_set_values(instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                             char type, const void *value) {
    model_t *m;
    size_t k;
    int param_changed = 0;
    char msg[512];
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
                        MODEL_VARS[row].name, (int)b);
                return fmi2Error;
            }
            v = b ? 1.0 : 0.0;
        }
        if (!params_check_value(vr[k], v, msg, sizeof msg)) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s", fn, msg);
            return fmi2Error;
        }
        if (!declared_range_ok(c, fn, row, v)) return fmi2Error;
        if (MODEL_VARS[row].causality == 'p' && (m->fsm & (ST_EVENT | ST_STEP_COMPLETE))) param_changed = 1;
    }
    if (param_changed) {
        double *save = (double *)c->cb.allocateMemory(MODEL_NVR, sizeof(double));
        fmi2Status st;
        if (!save) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: out of memory", fn); return fmi2Error; }
        memcpy(save, m->val, sizeof m->val);
        for (k = 0; k < nvr; k++)
            m->val[vr[k]] = type == 'R' ? ((const fmi2Real *)value)[k]
                          : type == 'I' ? (double)((const fmi2Integer *)value)[k]
                                        : (((const fmi2Boolean *)value)[k] ? 1.0 : 0.0);
        st = fmu_recompile(c, save);
        c->cb.freeMemory(save);
        return st;
    }
    for (k = 0; k < nvr; k++) {
        m->val[vr[k]] = type == 'R' ? ((const fmi2Real *)value)[k]
                      : type == 'I' ? (double)((const fmi2Integer *)value)[k]
                                    : (((const fmi2Boolean *)value)[k] ? 1.0 : 0.0);
    }
    if (m->fsm & ST_INIT) m->params_ok = 0;
    m->out_valid = 0;
    if (m->fsm & (ST_EVENT | ST_CONT | ST_STEP_COMPLETE)) {
        params_inputs(m->val, &m->in);
        m->solver_restart = 1;
    }
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    return fmu_set_values(FMU_ENTER(c, fmi2SetReal), "fmi2SetReal", vr, nvr, 'R', value);
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
    return fmu_set_values(FMU_ENTER(c, fmi2SetInteger), "fmi2SetInteger", vr, nvr, 'I', value);
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
    return fmu_set_values(FMU_ENTER(c, fmi2SetBoolean), "fmi2SetBoolean", vr, nvr, 'B', value);
}
fmi2Status fmi2SetString(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
    instance_t *c = FMU_ENTER(comp, fmi2SetString);
    (void)value;
    if (!c) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SetString: this FMU has no String variables (value reference %u)",
            vr ? (unsigned)vr[0] : 0u);
    return fmi2Error;
}

