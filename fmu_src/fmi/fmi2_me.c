/* FMI 2.0 model-exchange entry points over the plant. */
#include <math.h>
#include <string.h>

#include "fmi2_instance.h"

static int array_ok(instance_t *c, const char *fn, const void *p, size_t n, size_t expected) {
    if (n != expected) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: size %zu, this FMU has %zu", fn, n, expected);
        return 0;
    }
    if (n > 0 && !p) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL array", fn);
        return 0;
    }
    return 1;
}

fmi2Status fmi2EnterEventMode(fmi2Component comp) {
    instance_t *c = FMU_ENTER(comp, fmi2EnterEventMode);
    if (!c) return fmi2Error;
    c->m.fsm = ST_EVENT;
    return fmi2OK;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component comp, fmi2EventInfo *info) {
    instance_t *c = FMU_ENTER(comp, fmi2NewDiscreteStates);
    fmi2Boolean changed = fmi2False;
    long long k_before;
    int switches;
    if (!c) return fmi2Error;
    if (!info) { fmu_log(c, fmi2Error, LOG_ERROR, "fmi2NewDiscreteStates: eventInfo is NULL"); return fmi2Error; }
    k_before = c->m.d.k;
    switches = fmu_event_update(c, "fmi2NewDiscreteStates", c->m.time - c->m.t0, fmu_ulp_slack(c->m.time), &changed);
    if (switches < 0) return fmi2Error;
    /* the right-hand side is discontinuous at a friction switch and at a current-loop sample
     * (i jumps): report it, so importers that keep integrator history unless told (C fmusim's
     * CVODE) restart there; FMI 2.0 allows false, but only an importer that always resets
     * would then be right */
    if (switches > 0 || c->m.d.k != k_before) changed = fmi2True;
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = changed;
    info->nextEventTimeDefined = c->m.p.current_dynamics ? fmi2True : fmi2False;
    info->nextEventTime = c->m.p.current_dynamics ? fmu_next_sample(&c->m) : 0.0;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component comp) {
    instance_t *c = FMU_ENTER(comp, fmi2EnterContinuousTimeMode);
    if (!c) return fmi2Error;
    c->m.fsm = ST_CONT;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component comp, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation) {
    instance_t *c = FMU_ENTER(comp, fmi2CompletedIntegratorStep);
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!c) return fmi2Error;
    if (!enterEventMode || !terminateSimulation) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2CompletedIntegratorStep: NULL output argument");
        return fmi2Error;
    }
    fmu_check_stroke(c);
    *enterEventMode = fmi2False;
    *terminateSimulation = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component comp, fmi2Real time) {
    instance_t *c = FMU_ENTER(comp, fmi2SetTime);
    if (!c) return fmi2Error;
    if (!isfinite(time)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SetTime: time = %g is not finite", time);
        return fmi2Error;
    }
    c->m.time = time;
    c->m.tau = time - c->m.t0;
    c->m.out_valid = 0;
    return fmi2OK;
}

fmi2Status fmi2SetContinuousStates(fmi2Component comp, const fmi2Real x[], size_t nx) {
    instance_t *c = FMU_ENTER(comp, fmi2SetContinuousStates);
    char msg[512];
    size_t j;
    if (!c) return fmi2Error;
    if (!array_ok(c, "fmi2SetContinuousStates", x, nx, PLANT_NX)) return fmi2Error;
    for (j = 0; j < nx; j++) {
        if (!isfinite(x[j])) {
            fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SetContinuousStates: state %s = %g is not finite",
                    MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].name, x[j]);
            return fmi2Error;
        }
        if (!params_check_value(MODEL_STATE_VR[j], x[j], msg, sizeof msg)) {   /* the XML's min/max */
            fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SetContinuousStates: state %s", msg);
            return fmi2Error;
        }
    }
    memcpy(c->m.y, x, nx * sizeof(double));
    c->m.out_valid = 0;
    return fmi2OK;
}

fmi2Status fmi2GetDerivatives(fmi2Component comp, fmi2Real derivatives[], size_t nx) {
    instance_t *c = FMU_ENTER(comp, fmi2GetDerivatives);
    if (!c) return fmi2Error;
    if (!array_ok(c, "fmi2GetDerivatives", derivatives, nx, PLANT_NX)) return fmi2Error;
    if (!fmu_finite_result(c, "fmi2GetDerivatives", NULL, 0)) return fmi2Error;
    fmu_update_outputs(c);
    if (!fmu_finite_result(c, "fmi2GetDerivatives", c->m.dydt, nx)) return fmi2Error;
    memcpy(derivatives, c->m.dydt, nx * sizeof(double));
    return fmi2OK;
}

fmi2Status fmi2GetEventIndicators(fmi2Component comp, fmi2Real z[], size_t nz) {
    instance_t *c = FMU_ENTER(comp, fmi2GetEventIndicators);
    model_t *m;
    if (!c) return fmi2Error;
    if (!array_ok(c, "fmi2GetEventIndicators", z, nz, PLANT_NZ)) return fmi2Error;
    m = &c->m;
    if (!fmu_finite_result(c, "fmi2GetEventIndicators", NULL, 0)) return fmi2Error;
    params_inputs(m->val, &m->in);
    plant_indicators(&m->p, &m->d, m->y, &m->in, z);
    return fmu_finite_result(c, "fmi2GetEventIndicators", z, nz) ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetContinuousStates(fmi2Component comp, fmi2Real x[], size_t nx) {
    instance_t *c = FMU_ENTER(comp, fmi2GetContinuousStates);
    if (!c) return fmi2Error;
    if (!array_ok(c, "fmi2GetContinuousStates", x, nx, PLANT_NX)) return fmi2Error;
    if (!fmu_finite_result(c, "fmi2GetContinuousStates", c->m.y, nx)) return fmi2Error;
    memcpy(x, c->m.y, nx * sizeof(double));
    return fmi2OK;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component comp, fmi2Real x_nominal[], size_t nx) {
    instance_t *c = FMU_ENTER(comp, fmi2GetNominalsOfContinuousStates);
    size_t j;
    if (!c) return fmi2Error;
    if (!array_ok(c, "fmi2GetNominalsOfContinuousStates", x_nominal, nx, PLANT_NX)) return fmi2Error;
    for (j = 0; j < nx; j++) x_nominal[j] = MODEL_STATE_NOMINAL(j);
    return fmi2OK;
}
