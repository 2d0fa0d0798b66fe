/* FMI 2.0 co-simulation entry points: fmi2DoStep integrates the plant with the event-locating
 * Dormand-Prince 5(4) solver (solver_dp45.c), stopping at every current-loop sample and every
 * friction switch inside the step. A sample that falls on the end of a communication step is
 * taken at the start of the next one, after the master has set that instant's inputs. */
#include <math.h>
#include <string.h>

#include "fmi2_instance.h"

static void rhs(void *ctx, double t, const double *y, double *dydt) {
    const model_t *m = (const model_t *)ctx;
    (void)t;
    plant_derivatives(&m->p, &m->d, y, &m->in, dydt);
}

static void indicators(void *ctx, double t, const double *y, double *z) {
    const model_t *m = (const model_t *)ctx;
    (void)t;
    plant_indicators(&m->p, &m->d, y, &m->in, z);
}

/* a step from t (the time reached so far) of size h > 0, not past the stop time (logs if not) */
static int step_args_ok(instance_t *c, double t, double h, double eps) {
    const model_t *m = &c->m;
    if (!isfinite(t) || !isfinite(h) || h <= 0.0) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2DoStep: currentCommunicationPoint = %g, "
                "communicationStepSize = %g: allowed finite values with communicationStepSize > 0", t, h);
        return 0;
    }
    if (fabs(t - m->time) > eps) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2DoStep: currentCommunicationPoint = %.17g differs from the "
                "FMU's time %.17g (allowed: the time reached by the previous step)", t, m->time);
        return 0;
    }
    if (m->stop_defined && t + h > m->stop_time + eps) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2DoStep: step to %.17g passes the stopTime %.17g given to "
                "fmi2SetupExperiment", t + h, m->stop_time);
        return 0;
    }
    return 1;
}

fmi2Status fmi2DoStep(fmi2Component comp, fmi2Real t, fmi2Real h, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    instance_t *c = FMU_ENTER(comp, fmi2DoStep);
    model_t *m;
    double t_end, eps, t_target;
    int roots[PLANT_NZ], guard = 0;
    fmi2Boolean changed;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!c) return fmi2Error;
    m = &c->m;
    eps = 1e-9 * (fabs(t) > 1.0 ? fabs(t) : 1.0);
    if (!step_args_ok(c, t, h, eps)) return fmi2Error;
    t_end = t + h;
    m->time = t;
    params_inputs(m->val, &m->in);
    /* what is due now, with the inputs the master has just set */
    if (fmu_sample_due(m) || m->solver_restart) {
        fmu_event_update(c, &changed);
        dp45_restart(&m->solver);
        m->solver_restart = 0;
    }
    while (m->time < t_end) {
        int r;
        t_target = t_end;
        if (m->p.current_dynamics) {
            double ns = fmu_next_sample(m);
            if (ns < t_end - eps) t_target = ns;
        }
        r = dp45_advance(&m->solver, m, rhs, indicators, &m->time, t_target, m->y, roots);
        if (r == DP45_ERROR || ++guard > 10000000) {
            fmu_log(c, fmi2Error, LOG_ERROR, "fmi2DoStep: the integrator failed at t = %.17g s (x = %g m, "
                    "v = %g m/s): step size below its minimum or a non-finite state", m->time,
                    m->y[PLANT_IX], m->y[PLANT_IV]);
            m->fsm = ST_ERROR;
            m->out_valid = 0;
            return fmi2Error;
        }
        if (r == DP45_ROOT || (m->time < t_end && fmu_sample_due(m))) {
            fmu_event_update(c, &changed);
            dp45_restart(&m->solver);
        }
    }
    m->time = t_end;
    fmu_check_stroke(c);
    m->out_valid = 0;
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component comp) {
    instance_t *c = FMU_ENTER(comp, fmi2CancelStep);
    if (!c) return fmi2Error;
    fmu_log(c, fmi2Error, LOG_ERROR, "fmi2CancelStep: fmi2DoStep never returns fmi2Pending, nothing to cancel");
    return fmi2Error;
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    instance_t *c = FMU_ENTER(comp, fmi2SetRealInputDerivatives);
    (void)vr; (void)order; (void)value;
    if (!c) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SetRealInputDerivatives: inputs are held constant over a step "
            "(canInterpolateInputs is false)");
    return fmi2Error;
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    instance_t *c = FMU_ENTER(comp, fmi2GetRealOutputDerivatives);
    size_t k;
    if (!c) return fmi2Error;
    if (nvr > 0 && (!vr || !order || !value)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2GetRealOutputDerivatives: NULL array with nvr = %zu", nvr);
        return fmi2Error;
    }
    fmu_update_outputs(c);
    for (k = 0; k < nvr; k++) {
        if (order[k] != 1) {
            fmu_log(c, fmi2Error, LOG_ERROR, "fmi2GetRealOutputDerivatives: order %d, allowed 1 "
                    "(maxOutputDerivativeOrder)", (int)order[k]);
            return fmi2Error;
        }
        if (vr[k] == VR_x) value[k] = c->m.y[PLANT_IV];
        else if (vr[k] == VR_v) value[k] = c->m.out.a;
        else if (vr[k] == VR_i && c->m.p.current_dynamics) value[k] = 0.0;   /* held between samples */
        else {
            fmu_log(c, fmi2Error, LOG_ERROR, "fmi2GetRealOutputDerivatives: value reference %u: derivatives "
                    "are provided for x, v and (with current_dynamics) i", (unsigned)vr[k]);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

static fmi2Status no_status(instance_t *c, const char *fn) {
    if (!c) return fmi2Error;
    fmu_log(c, fmi2Discard, LOG_ERROR, "%s: no asynchronous step status (fmi2DoStep never returns "
            "fmi2Pending)", fn);
    return fmi2Discard;
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)s; (void)value;
    return no_status(FMU_ENTER(c, fmi2GetStatus), "fmi2GetStatus");
}
fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    instance_t *ci = FMU_ENTER(c, fmi2GetRealStatus);
    if (ci && s == fmi2LastSuccessfulTime && value) { *value = ci->m.time; return fmi2OK; }
    return no_status(ci, "fmi2GetRealStatus");
}
fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    (void)s; (void)value;
    return no_status(FMU_ENTER(c, fmi2GetIntegerStatus), "fmi2GetIntegerStatus");
}
fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    instance_t *ci = FMU_ENTER(c, fmi2GetBooleanStatus);
    if (ci && s == fmi2Terminated && value) { *value = fmi2False; return fmi2OK; }
    return no_status(ci, "fmi2GetBooleanStatus");
}
fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    (void)s; (void)value;
    return no_status(FMU_ENTER(c, fmi2GetStringStatus), "fmi2GetStringStatus");
}
