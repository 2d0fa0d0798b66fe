/* The plant as a model of the FMI glue (fmu_src/fmi/model.h): its data driven from the value
 * table (params.h), the event update (current-loop samples and friction switches), the
 * recompilation of tuned parameters, the solver's set-up, and what the glue asks of a model
 * to read and set values, step in model exchange and report its next event. The co-simulation
 * step is in plant_step.c, the plant's part of a saved state in plant_snapshot.c. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "instance.h"
#include "plant_model.h"

double plant_next_sample(const model_t *m) { return m->t0 + (double)(m->d.k + 1) * m->p.Ts; }

double plant_time_eps(const model_t *m, double t) {
    double tau = fabs(t - m->t0), eps = 1e-9 * (tau > 1.0 ? tau : 1.0);
    double ulp16 = fmu_ulp_slack(t);
    if (m->params_ok && eps > m->p.Ts / 64.0) eps = m->p.Ts / 64.0;
    return eps > ulp16 ? eps : ulp16;
}

int plant_sample_due(const model_t *m, double tau, double slack) {
    double eps = 1e-9 * (fabs(tau) > 1.0 ? fabs(tau) : 1.0);
    if (eps > m->p.Ts / 64.0) eps = m->p.Ts / 64.0;
    if (eps < slack) eps = slack;
    return m->p.current_dynamics && tau >= (double)(m->d.k + 1) * m->p.Ts - eps;
}


/* m->out at (d, y, in): the outputs alone, val[] untouched (a read of the signals a loop exchanges) */
static inline void plant_update_out(model_t *m) {
    if (m->out_valid >= OUT_OUTPUTS) return;
    params_inputs(m->val, &m->in);
    plant_outputs_memo(&m->p, &m->d, m->y, &m->in, &m->memo, &m->out);
    m->out_valid = OUT_OUTPUTS;
}

void plant_update_values(instance_t *c) {
    model_t *m = &c->m;
    if (m->out_valid >= OUT_VALUES) return;
    plant_update_out(m);
    params_store_outputs(m->val, m->y, &m->out, &m->d);
    m->val[VR_stats_n_steps] = (double)m->solver.n_steps;
    m->val[VR_stats_n_rhs] = (double)m->solver.n_rhs;
    m->out_valid = OUT_VALUES;
}

void plant_update_outputs(instance_t *c) {
    model_t *m = &c->m;
    if (m->out_valid == OUT_ALL) return;
    plant_update_values(c);
    plant_state_derivatives(&m->p, &m->d, m->y, &m->out, &m->memo, m->dydt);
    params_store_derivatives(m->val, m->y, m->dydt);
    m->out_valid = OUT_ALL;
}

static void plant_der_vr_table(unsigned char *is_der) {
    int j;
    memset(is_der, 0, MODEL_NVR);
    for (j = 0; j < MODEL_NX; j++) is_der[MODEL_DER_VR[j]] = 1;
    for (j = 0; j < MODEL_NX; j++) is_der[MODEL_STATE_VR[j]] = 0;   /* a state's value is kept */
}


void plant_check_stroke(instance_t *c) {
    model_t *m = &c->m;
    double x = m->y[PLANT_IX];
    if (x < m->p.x_min || x > m->p.x_max) {
        if (!m->stroke_warned)
            fmu_log(c, fmi2Warning, LOG_WARNING,
                    "x = %.9g m left the stroke [%g, %g] m at t = %.9g s: the maps are evaluated at the "
                    "nearest stroke end until it returns", x, m->p.x_min, m->p.x_max, m->time);
        m->stroke_warned = 1;
    } else {
        m->stroke_warned = 0;
    }
}

int model_event_update(instance_t *c, const char *fn, double tau, double slack, fmi2Boolean *states_changed) {
    model_t *m = &c->m;
    bool changed = false;
    int n = 0, samples = 0;
    double behind = m->p.current_dynamics ? (tau - (double)(m->d.k + 1) * m->p.Ts) / m->p.Ts : 0.0;
    *states_changed = fmi2False;
    if (behind > BUDGET_OVERDUE_SAMPLES) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: t = %.17g s is %.0f current-loop samples past the next one at "
                "%.17g s (Ts = %g s): allowed at most %d per call (the importer must stop at nextEventTime)",
                fn, m->time, floor(behind) + 1.0, plant_next_sample(m), m->p.Ts, BUDGET_OVERDUE_SAMPLES);
        return -1;
    }
    /* indicators of (d, y) alone, positive there: no switch is due whatever the inputs and samples
     * (the current-loop samples are all that is left to do) */
    const int no_switch = m->ind_positive && plant_indicators_of_state(&m->p);
    m->ind_positive = 0;
    params_inputs(m->val, &m->in);
    do {
        int due = plant_sample_due(m, tau, slack);
        if (no_switch) {
            if (due) plant_sample_update(&m->p, &m->d, &m->in);
        } else {
            n += plant_event_update(&m->p, &m->d, m->y, &m->in, due != 0, &m->memo, &changed);
        }
        samples += due;
        if (due && c->logging_on && (c->log_mask & LOG_DEBUG))   /* no argument list per sample */
            fmu_log(c, fmi2OK, LOG_DEBUG, "t = %.9g s: current-loop sample %lld, i = %.9g A", m->time,
                    m->d.k, m->d.i);
    } while (plant_sample_due(m, tau, slack) && samples <= BUDGET_OVERDUE_SAMPLES);
    if (samples > 1)
        fmu_log(c, fmi2Warning, LOG_WARNING, "t = %.9g s: %d current-loop samples were overdue (the importer "
                "stepped past nextEventTime)", m->time, samples);
    if (n > 0)
        fmu_log(c, fmi2OK, LOG_EVENTS, "t = %.9g s: %d friction switch(es), v = %.6g m/s, %d element(s) stuck",
                m->time, n, m->y[PLANT_IV], plant_n_stuck(&m->p, &m->d));
    plant_check_stroke(c);
    m->out_valid = 0;
    /* the right-hand side is discontinuous at a friction switch and at a current-loop sample (i
     * jumps): reported as a change, so importers that keep integrator history unless told (C
     * fmusim's CVODE) restart there */
    *states_changed = (changed || n > 0 || samples > 0) ? fmi2True : fmi2False;
    if (n > 0 && c->on_switch) c->on_switch(c);
    return n;
}

fmi2Status model_recompile(instance_t *c, const char *fn, const double *backup_val) {
    model_t *m = &c->m;
    char msg[512];
    (void)fn;
    plant_params_t old = m->p;
    /* refused: values and compiled parameters back, the caches untouched (nothing changes) */
    if (!params_compile(m->val, &m->p, msg, sizeof msg)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s", msg);
        if (backup_val) memcpy(m->val, backup_val, sizeof m->val);
        m->p = old;
        return fmi2Error;
    }
    plant_memo_reset(&m->memo);
    m->carry.valid = 0;
    m->ind_positive = 0;
    m->fast_ok = fast_path_ok(&m->p);
    plant_retune(&old, &m->p, &m->d, m->y);
    m->params_ok = 1;
    m->out_valid = 0;
    m->solver_restart = 1;
    return fmi2OK;
}

void model_defaults(model_t *m) {
    int j;
    memset(m, 0, sizeof *m);
    m->magic = MODEL_MAGIC;
    m->size = (unsigned)sizeof(model_t);
    m->fsm = ST_INSTANTIATED;
    plant_der_vr_table(m->is_der);
    for (j = 0; j < PLANT_NX; j++) {
        m->y_lo[j] = MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].min;
        m->y_hi[j] = MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].max;
    }
    params_defaults(m->val);
    m->tol = m->val[VR_solver_tol];
}

/* ---------------------------------------------------------------- life cycle */

void plant_solver_setup(model_t *m) {
    double atol[PLANT_NX];
    int j;
    plant_memo_reset(&m->memo);   /* called after every compile of the parameters but model_recompile's */
    m->carry.valid = 0;
    m->ind_positive = 0;
    m->fast_ok = fast_path_ok(&m->p);
    for (j = 0; j < PLANT_NX; j++) {
        atol[j] = m->tol * MODEL_STATE_NOMINAL(j);   /* XML nominals */
        m->inv_atol[j] = 1.0 / atol[j];
    }
    /* x, v and the forces of the N elements in use: the slots past N stay 0 (their derivative is 0);
     * the error norm still counts the PLANT_NX_BASE states, so the steps are those of a 12-state
     * run. With compliance every state is integrated (its two come after the elements) and counted. */
    if (m->p.compliance) {
        dp45_init(&m->solver, PLANT_NX, PLANT_NZ, m->tol, atol, m->p.Ts);
        m->solver.n_norm = PLANT_NX;
    } else {
        dp45_init(&m->solver, 2 + m->p.N, PLANT_NZ, m->tol, atol, m->p.Ts);
        m->solver.n_norm = PLANT_NX_BASE;
    }
    /* every accepted step is checked against the states' declared ranges (plant_step.c) */
    m->solver.bounded = 1;
    for (j = 0; j < m->solver.n; j++) {
        m->solver.y_lo[j] = MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].min;
        m->solver.y_hi[j] = MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].max;
    }
}

/* compile parameters and initialise the plant from the current values */
fmi2Status model_initialize(instance_t *c, const char *fn, int exiting) {
    model_t *m = &c->m;
    char msg[512];
    (void)fn; (void)exiting;   /* the parameters' messages name the variable; every initialisation compiles */
    if (!params_compile(m->val, &m->p, msg, sizeof msg)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s", msg);
        m->params_ok = 0;
        return fmi2Error;
    }
    m->params_ok = 1;
    params_states(m->val, m->y);
    params_inputs(m->val, &m->in);
    plant_init(&m->p, &m->d, m->y, &m->in);
    if (!m->tol_defined) m->tol = m->val[VR_solver_tol];
    plant_solver_setup(m);
    m->solver_restart = 1;
    m->out_valid = 0;
    plant_check_stroke(c);
    return fmi2OK;
}

/* ---------------------------------------------------------------- what the glue asks (model.h) */

/* params_check_value binds every variable to the physics' ranges and the min/max of
 * modelDescription.xml; solver.tol must in addition be > 0 (its declared min 0 is open). */
int model_check_value(instance_t *c, const char *fn, int row, double v) {
    char msg[512];
    /* an input (set every sample) has no rule beyond its declared min/max (params.c's range_of):
     * a finite value inside them passes without the rule tables; anything else gets the message */
    if (MODEL_VARS[row].causality == 'i' && v >= MODEL_VARS[row].min && v <= MODEL_VARS[row].max && isfinite(v))
        return 1;
    if (!params_check_value(MODEL_VARS[row].vr, v, msg, sizeof msg)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s", fn, msg);
        return 0;
    }
    if (MODEL_VARS[row].vr == VR_solver_tol && !(v > 0.0 && v <= TOL_MAX)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: solver.tol = %.17g is out of range: allowed (0, %g] (the loosest "
                "tolerance at which the integrator's error follows it)", fn, v, TOL_MAX);
        return 0;
    }
    return 1;
}

int model_check_state(instance_t *c, const char *fn, unsigned vr, double v) {
    char msg[512];
    if (params_check_value(vr, v, msg, sizeof msg)) return 1;   /* the XML's min/max */
    fmu_log(c, fmi2Error, LOG_ERROR, "%s: state %s", fn, msg);
    return 0;
}

void model_values_changed(instance_t *c) {
    model_t *m = &c->m;
    if (m->fsm & ST_INIT) m->params_ok = 0;
    m->out_valid = 0;
    if (m->fsm & (ST_EVENT | ST_CONT | ST_STEP_COMPLETE)) {
        params_inputs(m->val, &m->in);
        m->solver_restart = 1;
    }
}

/* Every value asked for is a signal a control loop reads every sample: a state itself (x, v,
 * x_measured: x, or x + compliance.dx on the load side) or an output of plant_out_t, from m->out
 * computed once (plant_update_out) without storing the value table. Any other value reference:
 * 0 (what was written to value[] is then overwritten by the glue's general read). */
int model_get_direct(instance_t *c, const char *fn, const unsigned vr[], size_t nvr, char type, void *value,
                     fmi2Status *st) {
    model_t *m = &c->m;
    const plant_out_t *o = &m->out;
    size_t k;
    if (type != 'R' || !m->params_ok || nvr == 0) return 0;
    for (k = 0; k < nvr; k++) {
        double v;
        switch (vr[k]) {
        case VR_x: v = m->y[PLANT_IX]; break;
        case VR_v: v = m->y[PLANT_IV]; break;
        case VR_x_measured: v = compliance_x_measured(&m->p, m->y); break;
        case VR_i: plant_update_out(m); v = o->i; break;
        case VR_F_motor: plant_update_out(m); v = o->F_motor; break;
        case VR_F_cogging: plant_update_out(m); v = o->F_cg; break;
        case VR_F_friction: plant_update_out(m); v = o->F_fric; break;
        case VR_K_f: plant_update_out(m); v = o->K_f; break;
        default: return 0;
        }
        if (!isfinite(v)) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s = %g is not finite (the simulation overflowed)", fn,
                    MODEL_VARS[MODEL_VR_INDEX[vr[k]]].name, v);
            *st = fmi2Error;
            return 1;
        }
        ((double *)value)[k] = v;
    }
    *st = fmi2OK;
    return 1;
}

/* the derivatives only when one is asked for */
int model_update(instance_t *c, const char *fn, const unsigned vr[], size_t nvr) {
    int der = 0;
    size_t k;
    (void)fn;
    for (k = 0; k < nvr; k++) der |= vr[k] < MODEL_NVR && c->m.is_der[vr[k]];
    if (der) plant_update_outputs(c);
    else plant_update_values(c);
    return 1;
}

int model_next_event(const model_t *m, double *t) {
    *t = m->p.current_dynamics ? plant_next_sample(m) : 0.0;
    return m->p.current_dynamics;
}

void model_completed_step(instance_t *c) { plant_check_stroke(c); }

void model_derivatives(instance_t *c) { plant_update_outputs(c); }

void model_indicators(instance_t *c, double *z) {
    model_t *m = &c->m;
    params_inputs(m->val, &m->in);
    plant_indicators(&m->p, &m->d, m->y, &m->in, z);
}

int model_cs_step_ok(instance_t *c, double t, double h) {
    (void)c; (void)t; (void)h;
    return 1;
}

/* co-simulation: the switch that ended the step was updated inside it; what the inputs set in
 * Event Mode cause and a sample due now are taken at the start of the next step, with the
 * inputs then set (fmi2DoStep's convention, so event mode and early return do not change the
 * trajectory) */
fmi2Status model_cs_event_update(instance_t *c, const char *fn) {
    (void)fn;
    c->m.solver_restart = 1;
    return fmi2OK;
}

fmi2Status model_enter_step_mode(instance_t *c) {
    (void)c;
    return fmi2OK;
}

/* the step's integrator restarted after the switch, so does the next */
void model_restored(instance_t *c) {
    c->m.solver_restart = 1;
    c->m.out_valid = 0;
}
