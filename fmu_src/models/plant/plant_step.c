/* The plant's co-simulation step (model.h's model_do_step, every FMI version): a step
 * integrates the plant interval by interval between current-loop samples: by the per-sample scheme (fast_path.h) where fast_path_ok()
 * allows it and its step passes, else with the event-locating Dormand-Prince 5(4) solver
 * (solver_dp45.c), stopping at every current-loop sample and every friction switch inside the
 * step. A sample that falls on the end of a communication step is taken at the start of the
 * next one, after the master has set that instant's inputs. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fast_path.h"
#include "plant_model.h"

/* the interval of h from the current state by the per-sample scheme (fast_path.h) when solver.fast
 * is on: 1 when taken (m->y advanced), 0 when the adaptive solver must take it. fresh: an event
 * update has just been made. */
static int fast_interval(model_t *m, double h, int fresh) {
    fast_tol_t tol;
    tol.rtol = m->solver.rtol;
    tol.atol = m->solver.atol;
    tol.inv_atol = m->inv_atol;
    tol.n_norm = m->solver.n_norm;
    if (!fast_step(&m->p, &m->d, &m->in, h, &tol, fresh, m->y, &m->solver.n_rhs, &m->carry, &m->memo)) return 0;
    m->ind_positive = 1;   /* fast_step tests the indicators at the end (fast_path.h) */
    m->solver.n_steps++;
    dp45_restart(&m->solver);
    return 1;
}

static void rhs(void *ctx, double t, const double *y, double *dydt) {
    model_t *m = (model_t *)ctx;
    (void)t;
    plant_derivatives_memo(&m->p, &m->d, y, &m->in, &m->memo, dydt);
}

static void indicators(void *ctx, double t, const double *y, double *z) {
    const model_t *m = (const model_t *)ctx;
    (void)t;
    plant_indicators(&m->p, &m->d, y, &m->in, z);
}

/* a step from t (the time reached so far) of size h > 0, not past the stop time (logs if not) */
static int step_args_ok(instance_t *c, const char *fn, double t, double h, double eps) {
    const model_t *m = &c->m;
    if (!isfinite(t) || !isfinite(h) || h <= 0.0) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: currentCommunicationPoint = %g, "
                "communicationStepSize = %g: allowed finite values with communicationStepSize > 0", fn, t, h);
        return 0;
    }
    if (m->p.current_dynamics && fmu_ulp_slack(t + h) > m->p.Ts / 8.0) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: at t = %.17g s a double resolves only %g s, too coarse for "
                "the current-loop samples of Ts = %g s (allowed: 16 ulp(t) <= Ts/8, a start time nearer 0)", fn,
                t + h, fmu_ulp_slack(t + h) / 16.0, m->p.Ts);
        return 0;
    }
    if (fabs(t - m->time) > eps) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: currentCommunicationPoint = %.17g differs from the "
                "FMU's time %.17g (allowed: the time reached by the previous step)", fn, t, m->time);
        return 0;
    }
    if (m->stop_defined && t + h > m->stop_time + eps) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: step to %.17g passes the stopTime %.17g given to %s", fn,
                t + h, m->stop_time, c->fmi3 ? "fmi3EnterInitializationMode" : "fmi2SetupExperiment");
        return 0;
    }
    return 1;
}

/* the work one step of length h may take (model_data.h) */
typedef struct { double steps, events, start_attempts; long long n_events; } budget_t;

static void budget_start(const model_t *m, double h, budget_t *b) {
    double extra_steps = BUDGET_STEPS_RATE * h, extra_events = BUDGET_EVENTS_RATE * h;
    b->steps = BUDGET_STEPS_BASE + BUDGET_STEPS_PER_SAMPLE * h / m->p.Ts +
               (extra_steps < BUDGET_STEPS_EXTRA ? extra_steps : BUDGET_STEPS_EXTRA);
    b->events = BUDGET_EVENTS_BASE + (extra_events < BUDGET_EVENTS_EXTRA ? extra_events : BUDGET_EVENTS_EXTRA);
    b->start_attempts = (double)(m->solver.n_steps + m->solver.n_rejected);
    b->n_events = 0;
}

/* step attempts left in this call (at least 1, at most what a long long fits) */
static long long budget_left(const model_t *m, const budget_t *b) {
    double left = b->steps - ((double)(m->solver.n_steps + m->solver.n_rejected) - b->start_attempts);
    return left < 1.0 ? 1 : (left > 1e15 ? (long long)1e15 : (long long)left);
}

/* the integrator failed or a budget ran out: the message, state Error */
static fmi2Status step_failed(instance_t *c, const char *fn, const budget_t *b, double h) {
    model_t *m = &c->m;
    char why[320];
    double used = (double)(m->solver.n_steps + m->solver.n_rejected) - b->start_attempts;
    params_fastest_rate(m->val, &m->p, why, sizeof why);
    if (b->n_events > b->events)
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: more than %.0f state events in a step of %g s (budget "
                "%g + %g/s): the friction switches chatter at t = %.17g s (x = %g m, v = %g m/s); fastest rate: %s", fn,
                b->events, h, BUDGET_EVENTS_BASE, BUDGET_EVENTS_RATE, m->time, m->y[PLANT_IX], m->y[PLANT_IV], why);
    else if (used >= b->steps)
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: more than %.0f integrator steps in a step of %g s (budget "
                "%g + %g per Ts + %g/s): the problem is too stiff at t = %.17g s; stiffest: %s", fn, b->steps, h,
                BUDGET_STEPS_BASE, BUDGET_STEPS_PER_SAMPLE, BUDGET_STEPS_RATE, m->time, why);
    else
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: the integrator failed at t = %.17g s (x = %g m, "
                "v = %g m/s): step size below its minimum or a non-finite state", fn, m->time,
                m->y[PLANT_IX], m->y[PLANT_IV]);
    m->fsm = ST_ERROR;
    m->out_valid = 0;
    return fmi2Error;
}

/* every continuous state inside the min/max of modelDescription.xml (a NaN is outside); else the
 * message names the state, its value, the range and the cause, and the step fails. The states
 * the integrators move are the solver's n (x, v, the forces of the N elements in use, the
 * compliance's two when it is on); the others keep the values checked when they were set. */
static int states_in_range(instance_t *c, const char *fn) {
    model_t *m = &c->m;
    char cause[320], vb[40];
    int j, in = 1;
    /* without a branch per state (a NaN compares false); the loop below only for the message */
    for (j = 0; j < m->solver.n; j++) in &= (m->y[j] >= m->y_lo[j]) & (m->y[j] <= m->y_hi[j]);
    if (in) return 1;
    for (j = 0; j < PLANT_NX; j++) {
        const model_var_t *v;
        if (m->y[j] >= m->y_lo[j] && m->y[j] <= m->y_hi[j]) continue;
        v = &MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]];
        snprintf(vb, sizeof vb, "%.9g", m->y[j]);
        m->out_valid = 0;
        plant_update_outputs(c);
        params_state_cause(&m->p, m->y, &m->in, &m->out, j, cause, sizeof cause);
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s = %s %s left its declared range [%g, %g] %s at t = %.17g s: %s", fn,
                v->name, vb, v->unit, v->min, v->max, v->unit, m->time,
                cause);
        m->fsm = ST_ERROR;
        m->out_valid = 0;
        return 0;
    }
    return 1;
}

/* integrate from tau (= time - t0, exact for t0 = 0) to tau_end, stopping at every sample
 * (keyed to its index: tau_k = k Ts) and every friction switch; every continuous state is checked
 * against its declared range after every accepted integrator step and where each interval ends
 * (sample, switch, step end) */
static fmi2Status integrate(instance_t *c, const char *fn, double tau, double tau_end, double h, double eps,
                            int fresh) {
    model_t *m = &c->m;
    int roots[PLANT_NZ], fast = m->val[VR_solver_fast] != 0.0 && m->fast_ok;
    fmi2Boolean changed;
    budget_t b;
    budget_start(m, h, &b);
    while (tau < tau_end) {
        double tau_target = tau_end;
        int r;
        if (m->p.current_dynamics) {
            double ns = (double)(m->d.k + 1) * m->p.Ts;
            if (ns < tau_end - eps) tau_target = ns;
        }
        if (fast && fast_interval(m, tau_target - tau, fresh)) {
            tau = tau_target;
            m->time = m->t0 + tau;
            m->tau = tau;
            fresh = 0;
            if (!states_in_range(c, fn)) return fmi2Error;
            if (tau < tau_end && plant_sample_due(m, tau, 0.0)) {
                if (model_event_update(c, fn, tau, 0.0, &changed) < 0) return step_failed(c, fn, &b, h);
                fresh = 1;
            }
            continue;
        }
        fresh = 0;
        m->ind_positive = 0;
        m->solver.max_steps = budget_left(m, &b);
        r = dp45_advance(&m->solver, m, rhs, indicators, &tau, tau_target, m->y, roots);
        m->time = m->t0 + tau;
        m->tau = tau;
        if (r == DP45_ROOT && ++b.n_events > b.events) r = DP45_ERROR;
        if (r == DP45_ERROR) return step_failed(c, fn, &b, h);
        if (!states_in_range(c, fn)) return fmi2Error;   /* also after DP45_BOUND, which leaves one outside */
        if (r == DP45_ROOT || (tau < tau_end && plant_sample_due(m, tau, 0.0))) {
            if (model_event_update(c, fn, tau, 0.0, &changed) < 0) return step_failed(c, fn, &b, h);
            dp45_restart(&m->solver);
            fresh = 1;
        }
    }
    return fmi2OK;
}

/* fmi2DoStep's work, and fmi3DoStep's (fmi3.c adds event mode and early return) */
fmi2Status model_do_step(instance_t *c, const char *fn, double t, double h) {
    model_t *m = &c->m;
    double t_end, eps, tau;
    fmi2Boolean changed;
    int fresh = 0;
    eps = plant_time_eps(m, t);
    if (!step_args_ok(c, fn, t, h, eps)) return fmi2Error;
    t_end = t + h;
    /* from the time reached (an early return's end, FMI 3.0, is t0 + tau rounded: the step goes on
     * from tau itself, as the step that did not return would have) */
    tau = t == m->time ? m->tau : t - m->t0;
    m->time = t;
    m->tau = tau;
    params_inputs(m->val, &m->in);
    /* what is due now, with the inputs the master has just set */
    if (plant_sample_due(m, tau, 0.0) || m->solver_restart) {
        if (model_event_update(c, fn, tau, 0.0, &changed) < 0) { m->fsm = ST_ERROR; return fmi2Error; }
        dp45_restart(&m->solver);
        m->solver_restart = 0;
        fresh = 1;
    }
    if (integrate(c, fn, tau, t_end - m->t0, h, eps, fresh) != fmi2OK) return fmi2Error;
    m->time = t_end;
    m->tau = t_end - m->t0;
    plant_check_stroke(c);
    m->out_valid = 0;
    return fmi2OK;
}

fmi2Status model_output_derivatives(instance_t *c, const char *fn, const unsigned vr[], size_t nvr,
                                    const int order[], double value[]) {
    size_t k;
    if (!c) return fmi2Error;
    if (nvr > 0 && (!vr || !order || !value)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL array with nvr = %zu", fn, nvr);
        return fmi2Error;
    }
    if (!fmu_finite_result(c, fn, NULL, 0)) return fmi2Error;
    plant_update_outputs(c);
    for (k = 0; k < nvr; k++) {
        if (order[k] != 1) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: order %d, allowed 1 (maxOutputDerivativeOrder)", fn,
                    (int)order[k]);
            return fmi2Error;
        }
        if (vr[k] == VR_x) value[k] = c->m.y[PLANT_IV];
        else if (vr[k] == VR_x_measured) value[k] = compliance_v_measured(&c->m.p, c->m.y);
        else if (vr[k] == VR_v) value[k] = c->m.out.a;
        else if (vr[k] == VR_i && c->m.p.current_dynamics) value[k] = 0.0;   /* held between samples */
        else {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: value reference %u: derivatives are provided for x, "
                    "x_measured, v and (with current_dynamics) i", fn, (unsigned)vr[k]);
            return fmi2Error;
        }
        if (!fmu_finite_result(c, fn, &value[k], 1)) return fmi2Error;
    }
    return fmi2OK;
}
