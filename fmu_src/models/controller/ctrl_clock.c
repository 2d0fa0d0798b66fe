/* The controller's input clock `tick` (FMI 3.0; value reference 9, interval Ts, the parameter)
 * behind the glue's clock functions (fmu_src/fmi/fmi3.c, model.h): an instance made with
 * eventModeUsed takes its samples at the ticks only -- at t_k the importer enters Event Mode,
 * activates the clock (fmi3SetClock), sets the inputs of t_k, reads u_k (computed from them: no
 * delay but ctrl.delay's), fmi3UpdateDiscreteStates commits the sample (outputs read after it
 * are the same), and fmi3EnterStepMode returns to the steps, each ending at the latest at the
 * next tick. Without eventModeUsed the instance samples inside the step. */
#include <math.h>
#include <stddef.h>

#include "ctrl_model.h"
#include "fmi3_view.h"

/* the value reference of the input clock `tick` (fmu_src/generators/gen_fmi3.py's CTRL_VR_TICK) */
#define VR_TICK 9u

/* the instance was made with eventModeUsed (else fn's error logged) */
static int clocked(instance_t *c, const char *fn) {
    if (c->event_mode_used) return 1;
    fmu_log(c, fmi2Error, LOG_ERROR, "%s: the instance was made with eventModeUsed = false: it samples inside "
            "fmi3DoStep", fn);
    return 0;
}

/* one input clock, `tick`: the arrays checked, every reference it */
static int clock_refs(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr, const void *v) {
    size_t k;
    if (nvr > 0 && (!vr || !v)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL array with nValueReferences = %zu", fn, nvr);
        return 0;
    }
    for (k = 0; k < nvr; k++)
        if (vr[k] != VR_TICK) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: value reference %u is no clock: the one clock is tick (value "
                    "reference %u)", fn, (unsigned)vr[k], VR_TICK);
            return 0;
        }
    return 1;
}

/* the tick set active: a sample computed before (an output read before the tick) is dropped;
 * the tick's sample comes from the inputs set at the tick */
fmi2Status model_set_clock(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr,
                           const fmi3Clock v[]) {
    size_t k;
    if (!clock_refs(c, fn, vr, nvr, v)) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    if (!clocked(c, fn)) return fmi2Error;
    if (c->m.fsm != ST_EVENT)
        return fmu_refuse(c, fn, "tick can be set in Event Mode only (fmi3EnterEventMode at the tick's instant first)");
    for (k = 0; k < nvr; k++) c->m.ticked = v[k] != fmi3ClockInactive;
    if (c->m.ticked) c->m.pending_ok = c->m.pending_read = 0;
    return fmi2OK;
}

fmi2Status model_get_clock(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr, fmi3Clock v[]) {
    if (!clock_refs(c, fn, vr, nvr, v)) return fmi2Error;
    return fmu_refuse(c, fn, nvr ? "tick is an input clock: the importer sets it (fmi3SetClock)" : NULL);
}

/* the clock's interval: Ts as set (intervalVariability fixed: known from Initialization Mode on) */
fmi2Status model_get_interval(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr,
                              fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[]) {
    size_t k;
    if (!clock_refs(c, fn, vr, nvr, intervals)) return fmi2Error;
    if (nvr > 0 && !qualifiers) return fmu_refuse(c, fn, "NULL array qualifiers");
    for (k = 0; k < nvr; k++) {
        intervals[k] = c->m.val[CVR_Ts];
        qualifiers[k] = fmi3IntervalChanged;
    }
    return fmi2OK;
}

fmi2Status model_get_shift(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr,
                           fmi3Float64 shifts[]) {
    size_t k;
    if (!clock_refs(c, fn, vr, nvr, shifts)) return fmi2Error;
    for (k = 0; k < nvr; k++) shifts[k] = 0.0;
    return fmi2OK;
}

/* why the clock's fraction, interval or shift cannot be set or read as a fraction */
const char *model_clock_refusal(int set_interval, int set_shift) {
    if (set_interval) return "the interval of tick is the parameter Ts (intervalVariability fixed)";
    if (set_shift) return "the shift of tick is 0";
    return "tick has no fraction (supportsFraction is false)";
}

/* ---------------------------------------------------------------- Event Mode */

/* a step of a clocked instance ends at the latest at the next sample instant, whose tick the
 * importer gives in Event Mode: 0, logged, when [t, t + h) holds a sample instant not ticked */
int model_cs_step_ok(instance_t *c, double t, double h) {
    model_t *m = &c->m;
    double tk;
    if (!c->event_mode_used || !m->params_ok || !isfinite(t) || !isfinite(h)) return 1;   /* the step answers */
    tk = ctrl_sample_time(m, m->s.k);
    if (tk < t + h - ctrl_time_eps(m, t + h)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3DoStep: currentCommunicationPoint = %.17g, communicationStepSize = "
                "%.17g: the step passes the clock tick at t = %.17g s (sample %lld) without it; allowed a step "
                "that ends at or before the next tick, the tick given in Event Mode", t, h, tk, m->s.k);
        return 0;
    }
    return 1;
}

fmi2Status model_enter_step_mode(instance_t *c) {
    if (!c->m.ticked) return fmi2OK;
    return fmu_refuse(c, "fmi3EnterStepMode", "the clock tick was set active and its sample not taken: "
                      "fmi3UpdateDiscreteStates first");
}

/* at a tick (the clock set active): the sample of this instant -- the one an output read at the
 * tick computed, else one from the inputs as they stand -- committed (the outputs are its
 * outputs until the next tick); the rest of an Event Mode (no tick) changes nothing. Refused,
 * logged as fn's error, when the instant is no sample instant or the sample is not finite. */
fmi2Status model_cs_event_update(instance_t *c, const char *fn) {
    model_t *m = &c->m;
    double tk;
    if (!m->ticked) return fmi2OK;
    if (!m->params_ok) return fmi2Error;
    tk = ctrl_sample_time(m, m->s.k);
    if (fabs(tk - m->time) > ctrl_time_eps(m, m->time)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: clock tick at t = %.17g s: the next sample instant is t = %.17g s "
                "(t0 + %lld Ts, Ts = %g s): the clock ticks at the sample instants only", fn, m->time, tk, m->s.k,
                m->p.Ts);
        return fmi2Error;
    }
    if (!ctrl_evaluate(c, fn)) return fmi2Error;
    ctrl_commit(m);
    m->ticked = 0;
    return fmi2OK;
}
