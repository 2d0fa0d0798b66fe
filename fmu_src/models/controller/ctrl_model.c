/* The controller as a model of the FMI glue (fmu_src/fmi/model.h): one controller sample per
 * sample instant t_k = t0 + k Ts, from the value table of ctrl_vars.h.
 * Sample convention: u at t_k is the controller's output for the inputs as they stand at t_k (it
 * depends on x_meas directly): a read computes the pending sample from the current inputs, the
 * step commits it and takes every further sample inside the step with the inputs held.
 * Once read in Step Mode, the sample at t_k is fixed: inputs set after the read are the next
 * sample's (FMI's Step Mode: no output of an instant after a set at that instant).  So a master
 * that steps the plant first and the controller second (Gauss-Seidel) reads u_k+1 from
 * x(t_k+1), no delay; a Jacobi master (outputs read after the step, inputs set after) reads
 * at t_k+1 the sample computed from x(t_k): one sample of delay at h = Ts. With the input clock
 * (FMI 3.0, eventModeUsed) the samples are taken at the ticks only (ctrl_clock.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "instance.h"
#include "ctrl_model.h"
#include "ctrl_params.h"

const unsigned CTRL_NO_STATE[1] = {0u};

static void inputs(const model_t *m, ctrl_in_t *in) {
    in->x_ref = m->val[CVR_x_ref];
    in->v_ref = m->val[CVR_v_ref];
    in->a_ref = m->val[CVR_a_ref];
    in->x_meas = m->val[CVR_x_meas];
}

static void store_outputs(model_t *m, const ctrl_state_t *s) {
    m->val[CVR_u] = s->u;
    m->val[CVR_x_cmd] = s->x_cmd;
    m->val[CVR_u_ff] = s->u_ff;
    m->val[CVR_r_x] = s->r_x;
}

double ctrl_sample_time(const model_t *m, long long k) { return m->t0 + (double)k * m->p.Ts; }

/* how far a communication time may miss a sample instant and still be it: 1e-9 of the time
 * elapsed (at least of 1 s), at most Ts/64, as the plant's.  Masters that add h to a double
 * (Ecos: t += h) drift by ~n ulp: 5e-13 s after 25 750 steps of 50 us, more than a fixed
 * 1e-9 Ts = 5e-13 s, which took a sample one macro step early from a stale x_meas */
double ctrl_time_eps(const model_t *m, double t) {
    double tau = fabs(t - m->t0), eps = 1e-9 * (tau > 1.0 ? tau : 1.0);
    return eps < m->p.Ts / 64.0 ? eps : m->p.Ts / 64.0;
}
static int due(const model_t *m, double t) { return ctrl_sample_time(m, m->s.k) <= t + ctrl_time_eps(m, t); }

int ctrl_evaluate(instance_t *c, const char *fn) {
    model_t *m = &c->m;
    ctrl_in_t in;
    char why[160];
    if (m->pending_ok || !due(m, m->time)) return 1;
    inputs(m, &in);
    m->pending = m->s;
    if (!ctrl_sample(&m->p, &m->pending, &in, why, sizeof why)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: sample %lld at t = %.17g s: %s (x_meas = %g m, x_ref = %g m): the "
                "controller or its pre-filter diverged (unstable ss.Ac / zpetc.a) or its inputs are out of scale",
                fn, m->s.k, ctrl_sample_time(m, m->s.k), why, in.x_meas, in.x_ref);
        m->fsm = ST_ERROR;
        return 0;
    }
    store_outputs(m, &m->pending);
    m->pending_ok = 1;
    m->pending_read = 0;
    return 1;
}

void ctrl_commit(model_t *m) {
    m->s = m->pending;
    m->pending_ok = m->pending_read = 0;
}

static fmi2Status compile(instance_t *c, const char *fn) {
    char msg[512];
    if (ctrl_compile(c->m.val, &c->m.p, msg, sizeof msg)) return fmi2OK;
    fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s", fn, msg);
    return fmi2Error;
}

/* ---------------------------------------------------------------- what the glue asks (model.h) */

void model_defaults(model_t *m) {
    memset(m, 0, sizeof *m);
    m->magic = MODEL_MAGIC;
    ctrl_defaults(m->val);
    m->fsm = ST_INSTANTIATED;
    m->tol = 1e-6;
}

int model_load_start_values(instance_t *c, const char *location, int is_uri) {
    (void)location; (void)is_uri;   /* the controller has no resources */
    memcpy(c->start_val, c->m.val, sizeof c->start_val);
    return 1;
}

void model_reset(instance_t *c) {
    model_defaults(&c->m);
    memcpy(c->m.val, c->start_val, sizeof c->start_val);
}

fmi2Status model_initialize(instance_t *c, const char *fn, int exiting) {
    model_t *m = &c->m;
    if (!exiting || !m->params_ok) {
        if (compile(c, fn) != fmi2OK) { m->params_ok = 0; return fmi2Error; }
        m->params_ok = 1;
        ctrl_reset(&m->p, &m->s);
        m->pending_ok = m->pending_read = 0;
    }
    if (exiting) m->pending_read = m->pending_ok;   /* a first sample read in Initialization Mode is fixed */
    return fmi2OK;
}

int model_check_value(instance_t *c, const char *fn, int row, double v) {
    const ctrl_var_t *mv = &CTRL_VARS[row];
    char msg[512];
    if (!ctrl_check_value(mv->vr, v, msg, sizeof msg)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s", fn, msg);
        return 0;
    }
    if (v < mv->min || v > mv->max) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s = %.17g is out of range: allowed [%.17g, %.17g] %s", fn,
                mv->name, v, mv->min, mv->max, mv->unit);
        return 0;
    }
    return 1;
}

int model_check_state(instance_t *c, const char *fn, unsigned vr, double v) {
    (void)c; (void)fn; (void)vr; (void)v;
    return 0;   /* no continuous states: never called */
}

/* a tunable parameter between steps: recompile, keep the state */
fmi2Status model_recompile(instance_t *c, const char *fn, const double *backup_val) {
    ctrl_params_t old = c->m.p;
    if (compile(c, fn) != fmi2OK) {
        memcpy(c->m.val, backup_val, sizeof c->m.val);
        c->m.p = old;
        return fmi2Error;
    }
    c->m.pending_ok = c->m.pending_read = 0;
    return fmi2OK;
}

void model_values_changed(instance_t *c) {
    if (c->m.fsm & ST_INIT) c->m.params_ok = 0;
    if (!c->m.pending_read) c->m.pending_ok = 0;   /* a sample read in Step Mode keeps its inputs */
}

int model_get_direct(instance_t *c, const char *fn, const unsigned vr[], size_t nvr, char type, void *value,
                     fmi2Status *st) {
    (void)c; (void)fn; (void)vr; (void)nvr; (void)type; (void)value; (void)st;
    return 0;
}

/* the pending sample computed for a read (Initialization, Step and Event Mode) */
int model_update(instance_t *c, const char *fn, const unsigned vr[], size_t nvr) {
    model_t *m = &c->m;
    (void)vr; (void)nvr;
    if ((m->fsm & (ST_INIT | ST_STEP_COMPLETE | ST_EVENT)) && !ctrl_evaluate(c, fn)) return 0;
    if (m->pending_ok && (m->fsm & (ST_STEP_COMPLETE | ST_EVENT))) m->pending_read = 1;
    return 1;
}

int model_event_update(instance_t *c, const char *fn, double tau, double slack, fmi2Boolean *changed) {
    (void)c; (void)fn; (void)tau; (void)slack;
    *changed = fmi2False;
    return 0;
}

int model_next_event(const model_t *m, double *t) {
    (void)m;
    *t = 0.0;   /* the next event is the importer's next tick */
    return 0;
}

void model_completed_step(instance_t *c) { (void)c; }
void model_derivatives(instance_t *c) { (void)c; }
void model_indicators(instance_t *c, double *z) { (void)c; (void)z; }
void model_restored(instance_t *c) { (void)c; }

fmi2Status model_output_derivatives(instance_t *c, const char *fn, const unsigned vr[], size_t nvr,
                                    const int order[], double value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    return fmu_refuse(c, fn, "maxOutputDerivativeOrder is 0");
}

size_t model_state_bytes(void) { return 0; }
void model_state_encode(const model_t *m, int type, unsigned char *out) { (void)m; (void)type; (void)out; }
int model_state_decode(instance_t *c, const char *fn, const unsigned char *b, size_t len, model_t *out) {
    (void)b; (void)len; (void)out;
    fmu_log(c, fmi2Error, LOG_ERROR, "%s: canGetAndSetFMUstate is false", fn);
    return 0;
}

/* ---------------------------------------------------------------- co-simulation */

/* a step from t of length h: every sample instant inside [t, t + h) taken with the inputs held */
fmi2Status model_do_step(instance_t *c, const char *fn, double t, double h) {
    model_t *m = &c->m;
    double samples, taken = 0.0;
    if (!isfinite(h) || !(h > 0.0) || !isfinite(t) || !isfinite(t + h) ||
        fabs(t - m->time) > 1e-9 * (fabs(t) > 1.0 ? fabs(t) : 1.0)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: currentCommunicationPoint = %.17g, communicationStepSize = %.17g: "
                "allowed the FMU's time %.17g and a finite communicationStepSize > 0", fn, t, h, m->time);
        return fmi2Error;
    }
    /* the sample instants must be times a double tells apart (as the plant's: 16 ulp <= Ts/8) */
    if (fmu_ulp_slack(t + h) > m->p.Ts / 8.0) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: at t = %.17g s a double resolves only %g s, too coarse for the "
                "controller samples of Ts = %g s (allowed: 16 ulp(t) <= Ts/8, a start time nearer 0)", fn, t + h,
                fmu_ulp_slack(t + h) / 16.0, m->p.Ts);
        return fmi2Error;
    }
    /* the samples this step takes, counted before the first: a refused step changes nothing */
    samples = ceil((t + h - ctrl_sample_time(m, m->s.k)) / m->p.Ts);
    if (samples > CTRL_BUDGET_SAMPLES) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: communicationStepSize = %.17g s spans %.0f samples of Ts = %g s: "
                "allowed at most %.0f samples per call (budget), communicationStepSize <= %g s at this Ts", fn,
                h, samples, m->p.Ts, CTRL_BUDGET_SAMPLES, CTRL_BUDGET_SAMPLES * m->p.Ts);
        return fmi2Error;
    }
    while (ctrl_sample_time(m, m->s.k) < t + h - ctrl_time_eps(m, t + h)) {
        m->time = fmax(m->time, ctrl_sample_time(m, m->s.k));
        if (!ctrl_evaluate(c, fn)) return fmi2Error;
        ctrl_commit(m);
        if (++taken > CTRL_BUDGET_SAMPLES + 2.0) {   /* the count above bounds this loop; kept as its guard */
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: more than %.0f samples in one step (budget)", fn,
                    CTRL_BUDGET_SAMPLES);
            m->fsm = ST_ERROR;
            return fmi2Error;
        }
    }
    m->time = t + h;
    return fmi2OK;
}
