/* FMI 3.0 model exchange over the plant: the continuous states are x, v and friction.F[1..N]
 * (fmi3_nx), the event indicators the FMI 2.0 ones; events and nominals as in fmi2_me.c
 * (the event update is fmi3UpdateDiscreteStates, fmi3_instance.c). */
#include <math.h>
#include <string.h>

#include "fmi3_glue.h"

static int size_ok(instance_t *c, const char *fn, const void *p, size_t n, size_t expected) {
    if (n != expected) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: size %zu, this FMU has %zu (friction.N = %d)", fn, n, expected,
                fmi3_n(&c->m));
        return 0;
    }
    if (n > 0 && !p) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL array", fn); return 0; }
    return 1;
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3EnterContinuousTimeMode);
    if (!c) return fmi3Error;
    c->m.fsm = ST_CONT;
    return fmi3OK;
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation) {
    instance_t *c = FMU_ENTER(instance, fmi3CompletedIntegratorStep);
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!c) return fmi3Error;
    if (!enterEventMode || !terminateSimulation) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3CompletedIntegratorStep: NULL output argument");
        return fmi3Error;
    }
    fmu_check_stroke(c);
    *enterEventMode = fmi3False;
    *terminateSimulation = fmi3False;
    return fmi3OK;
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
    instance_t *c = FMU_ENTER(instance, fmi3SetTime);
    if (!c) return fmi3Error;
    if (!isfinite(time)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3SetTime: time = %g is not finite", time);
        return fmi3Error;
    }
    c->m.time = time;
    c->m.tau = time - c->m.t0;
    c->m.out_valid = 0;
    return fmi3OK;
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 x[], size_t nx) {
    instance_t *c = FMU_ENTER(instance, fmi3SetContinuousStates);
    char msg[512];
    size_t j;
    if (!c) return fmi3Error;
    if (!size_ok(c, "fmi3SetContinuousStates", x, nx, fmi3_nx(&c->m))) return fmi3Error;
    for (j = 0; j < nx; j++) {
        unsigned vr = MODEL_STATE_VR[fmi3_state_index(&c->m, j)];
        if (!isfinite(x[j])) {
            fmu_log(c, fmi2Error, LOG_ERROR, "fmi3SetContinuousStates: state %s = %g is not finite",
                    MODEL_VARS[MODEL_VR_INDEX[vr]].name, x[j]);
            return fmi3Error;
        }
        if (!params_check_value(vr, x[j], msg, sizeof msg)) {
            fmu_log(c, fmi2Error, LOG_ERROR, "fmi3SetContinuousStates: state %s", msg);
            return fmi3Error;
        }
    }
    for (j = 0; j < nx; j++) c->m.y[fmi3_state_index(&c->m, j)] = x[j];
    c->m.out_valid = 0;
    return fmi3OK;
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t nx) {
    instance_t *c = FMU_ENTER(instance, fmi3GetContinuousStateDerivatives);
    size_t j;
    if (!c) return fmi3Error;
    if (!size_ok(c, "fmi3GetContinuousStateDerivatives", derivatives, nx, fmi3_nx(&c->m))) return fmi3Error;
    if (!fmu_finite_result(c, "fmi3GetContinuousStateDerivatives", NULL, 0)) return fmi3Error;
    fmu_update_outputs(c);
    if (!fmu_finite_result(c, "fmi3GetContinuousStateDerivatives", c->m.dydt, PLANT_NX)) return fmi3Error;
    for (j = 0; j < nx; j++) derivatives[j] = c->m.dydt[fmi3_state_index(&c->m, j)];
    return fmi3OK;
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 z[], size_t nz) {
    instance_t *c = FMU_ENTER(instance, fmi3GetEventIndicators);
    model_t *m;
    if (!c) return fmi3Error;
    if (!size_ok(c, "fmi3GetEventIndicators", z, nz, PLANT_NZ)) return fmi3Error;
    m = &c->m;
    if (!fmu_finite_result(c, "fmi3GetEventIndicators", NULL, 0)) return fmi3Error;
    params_inputs(m->val, &m->in);
    plant_indicators(&m->p, &m->d, m->y, &m->in, z);
    return fmu_finite_result(c, "fmi3GetEventIndicators", z, nz) ? fmi3OK : fmi3Error;
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 x[], size_t nx) {
    instance_t *c = FMU_ENTER(instance, fmi3GetContinuousStates);
    size_t j;
    if (!c) return fmi3Error;
    if (!size_ok(c, "fmi3GetContinuousStates", x, nx, fmi3_nx(&c->m))) return fmi3Error;
    if (!fmu_finite_result(c, "fmi3GetContinuousStates", c->m.y, PLANT_NX)) return fmi3Error;
    for (j = 0; j < nx; j++) x[j] = c->m.y[fmi3_state_index(&c->m, j)];
    return fmi3OK;
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t nx) {
    instance_t *c = FMU_ENTER(instance, fmi3GetNominalsOfContinuousStates);
    size_t j;
    if (!c) return fmi3Error;
    if (!size_ok(c, "fmi3GetNominalsOfContinuousStates", nominals, nx, fmi3_nx(&c->m))) return fmi3Error;
    for (j = 0; j < nx; j++) nominals[j] = MODEL_STATE_NOMINAL(fmi3_state_index(&c->m, j));
    return fmi3OK;
}
