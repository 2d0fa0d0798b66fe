/* FMI 2.0 glue common to model exchange and co-simulation: life cycle, the one call-sequence
 * check (its table is fmi2_allowed.h), logging, and the plant driven from the value table
 * (params.h). Get/set are in fmi2_values.c, FMU state snapshots in fmi2_state.c. */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "fmi2_instance.h"
#include "start_values.h"

static void log_early(const fmi2CallbackFunctions *cb, const char *name, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(FMU_PRINTF_FORMAT, 3, 4)))
#endif
    ;
static void log_early(const fmi2CallbackFunctions *cb, const char *name, const char *fmt, ...) {
    char buf[1024];
    va_list ap;
    if (!cb->logger) return;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    fmi2_log_emit(cb, name, fmi2Error, "logStatusError", buf);
}

void fmu_log(instance_t *c, fmi2Status st, unsigned cat, const char *fmt, ...) {
    va_list ap;
    if (!c) return;
    /* errors and warnings are always reported; event traces only when asked for */
    va_start(ap, fmt);
    fmi2_log_v(&c->cb, c->name, c->logging_on, c->log_mask, st, cat, fmt, ap);
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
            c->fmi3 ? fmi3_state_name(c->m.fsm) : fmi2_state_name(c->m.fsm));
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

double fmu_next_sample(const model_t *m) { return m->t0 + (double)(m->d.k + 1) * m->p.Ts; }

double fmu_time_eps(const model_t *m, double t) {
    double tau = fabs(t - m->t0), eps = 1e-9 * (tau > 1.0 ? tau : 1.0);
    double ulp16 = fmu_ulp_slack(t);
    if (m->params_ok && eps > m->p.Ts / 64.0) eps = m->p.Ts / 64.0;
    return eps > ulp16 ? eps : ulp16;
}

int fmu_sample_due(const model_t *m, double tau, double slack) {
    double eps = 1e-9 * (fabs(tau) > 1.0 ? fabs(tau) : 1.0);
    if (eps > m->p.Ts / 64.0) eps = m->p.Ts / 64.0;
    if (eps < slack) eps = slack;
    return m->p.current_dynamics && tau >= (double)(m->d.k + 1) * m->p.Ts - eps;
}

double fmu_ulp_slack(double t) {
    /* nextafter(|t|, +inf) - |t| from the bits: the next double up is the one whose pattern is
     * one more (+inf and NaN stay as they are, the difference is then NaN as nextafter's) */
    double a = fabs(t), b;
    uint64_t u;
    memcpy(&u, &a, sizeof u);
    if (u < 0x7FF0000000000000ull) u++;
    memcpy(&b, &u, sizeof b);
    return 16.0 * (b - a);
}

void fmu_update_values(instance_t *c) {
    model_t *m = &c->m;
    if (m->out_valid) return;
    params_inputs(m->val, &m->in);
    plant_outputs_memo(&m->p, &m->d, m->y, &m->in, &m->memo, &m->out);
    params_store_outputs(m->val, m->y, &m->out, &m->d);
    m->val[VR_stats_n_steps] = (double)m->solver.n_steps;
    m->val[VR_stats_n_rhs] = (double)m->solver.n_rhs;
    m->out_valid = OUT_VALUES;
}

void fmu_update_outputs(instance_t *c) {
    model_t *m = &c->m;
    if (m->out_valid == OUT_ALL) return;
    fmu_update_values(c);
    plant_state_derivatives(&m->p, &m->d, m->y, &m->out, &m->memo, m->dydt);
    params_store_derivatives(m->val, m->y, m->dydt);
    m->out_valid = OUT_ALL;
}

void fmu_der_vr_table(unsigned char *is_der) {
    int j;
    memset(is_der, 0, MODEL_NVR);
    for (j = 0; j < MODEL_NX; j++) is_der[MODEL_DER_VR[j]] = 1;
    for (j = 0; j < MODEL_NX; j++) is_der[MODEL_STATE_VR[j]] = 0;   /* a state's value is kept */
}

int fmu_finite_result(instance_t *c, const char *fn, const double *x, size_t n) {
    size_t j;
    if (!c->m.params_ok) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: the model is not initialized (no successful "
                "fmi2ExitInitializationMode)", fn);
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

void fmu_check_stroke(instance_t *c) {
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

int fmu_event_update(instance_t *c, const char *fn, double tau, double slack, fmi2Boolean *states_changed) {
    model_t *m = &c->m;
    bool changed = false;
    int n = 0, samples = 0;
    double behind = m->p.current_dynamics ? (tau - (double)(m->d.k + 1) * m->p.Ts) / m->p.Ts : 0.0;
    *states_changed = fmi2False;
    if (behind > BUDGET_OVERDUE_SAMPLES) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: t = %.17g s is %.0f current-loop samples past the next one at "
                "%.17g s (Ts = %g s): allowed at most %d per call (the importer must stop at nextEventTime)",
                fn, m->time, floor(behind) + 1.0, fmu_next_sample(m), m->p.Ts, BUDGET_OVERDUE_SAMPLES);
        return -1;
    }
    /* indicators of (d, y) alone, positive there: no switch is due whatever the inputs and samples
     * (the current-loop samples are all that is left to do) */
    const int no_switch = m->ind_positive && plant_indicators_of_state(&m->p);
    m->ind_positive = 0;
    params_inputs(m->val, &m->in);
    do {
        int due = fmu_sample_due(m, tau, slack);
        if (no_switch) {
            if (due) plant_sample_update(&m->p, &m->d, &m->in);
        } else {
            n += plant_event_update(&m->p, &m->d, m->y, &m->in, due != 0, &m->memo, &changed);
        }
        samples += due;
        if (due && c->logging_on && (c->log_mask & LOG_DEBUG))   /* no argument list per sample */
            fmu_log(c, fmi2OK, LOG_DEBUG, "t = %.9g s: current-loop sample %lld, i = %.9g A", m->time,
                    m->d.k, m->d.i);
    } while (fmu_sample_due(m, tau, slack) && samples <= BUDGET_OVERDUE_SAMPLES);
    if (samples > 1)
        fmu_log(c, fmi2Warning, LOG_WARNING, "t = %.9g s: %d current-loop samples were overdue (the importer "
                "stepped past nextEventTime)", m->time, samples);
    if (n > 0)
        fmu_log(c, fmi2OK, LOG_EVENTS, "t = %.9g s: %d friction switch(es), v = %.6g m/s, %d element(s) stuck",
                m->time, n, m->y[PLANT_IV], plant_n_stuck(&m->p, &m->d));
    fmu_check_stroke(c);
    m->out_valid = 0;
    *states_changed = changed ? fmi2True : fmi2False;
    if (n > 0 && c->on_switch) c->on_switch(c);
    return n;
}

fmi2Status fmu_recompile(instance_t *c, const double *backup_val) {
    model_t *m = &c->m;
    char msg[512];
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

void fmu_model_defaults(model_t *m) {
    int j;
    memset(m, 0, sizeof *m);
    m->magic = MODEL_MAGIC;
    m->size = (unsigned)sizeof(model_t);
    m->fsm = ST_INSTANTIATED;
    fmu_der_vr_table(m->is_der);
    for (j = 0; j < PLANT_NX; j++) {
        m->y_lo[j] = MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].min;
        m->y_hi[j] = MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].max;
    }
    params_defaults(m->val);
    m->tol = m->val[VR_solver_tol];
}

/* ---------------------------------------------------------------- life cycle */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
    instance_t *c;
    size_t len;
    (void)visible;
    if (!functions || !functions->allocateMemory || !functions->freeMemory) return NULL;
    if (!instanceName || !*instanceName) {
        log_early(functions, "?", "fmi2Instantiate: instanceName must be a non-empty string");
        return NULL;
    }
    if (!fmuGUID || strcmp(fmuGUID, MODEL_GUID) != 0) {
        log_early(functions, instanceName, "fmi2Instantiate: GUID %s does not match this FMU's %s",
                  fmuGUID ? fmuGUID : "(null)", MODEL_GUID);
        return NULL;
    }
    if (fmuType != fmi2ModelExchange && fmuType != fmi2CoSimulation) {
        log_early(functions, instanceName, "fmi2Instantiate: fmuType %d is neither fmi2ModelExchange (0) "
                  "nor fmi2CoSimulation (1)", (int)fmuType);
        return NULL;
    }
    c = (instance_t *)functions->allocateMemory(1, sizeof(instance_t));
    if (!c) return NULL;
    memset(c, 0, sizeof *c);
    len = strlen(instanceName) + 1;
    c->name = (char *)functions->allocateMemory(len, 1);
    if (!c->name) { functions->freeMemory(c); return NULL; }
    memcpy(c->name, instanceName, len);
    c->cb = *functions;
    c->type = fmuType;
    c->logging_on = loggingOn != 0;
    c->log_mask = LOG_ALL;
    fmu_model_defaults(&c->m);
    if (!fmu_start_values_load(c, fmuResourceLocation, 1)) {
        functions->freeMemory(c->name);
        functions->freeMemory(c);
        return NULL;
    }
    return c;
}

void fmi2FreeInstance(fmi2Component comp) {
    instance_t *c = FMU_ENTER(comp, fmi2FreeInstance);
    fmi2CallbackFreeMemory fr;
    if (!c) return;
    fr = c->cb.freeMemory;
    fmu_states_free_all(c);
    c->m.magic = 0;
    fr(c->name);
    fr(c);
}

fmi2Status fmi2SetDebugLogging(fmi2Component comp, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    instance_t *c = FMU_ENTER(comp, fmi2SetDebugLogging);
    long long bad;
    if (!c) return fmi2Error;
    c->logging_on = loggingOn != 0;
    if (nCategories == 0) { c->log_mask = LOG_ALL; return fmi2OK; }
    if (!categories) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SetDebugLogging: categories is NULL with nCategories = %zu",
                nCategories);
        return fmi2Error;
    }
    if ((bad = fmi2_log_mask(nCategories, categories, &c->log_mask)) >= 0) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SetDebugLogging: unknown log category \"%s\" (known: "
                "logEvents, logStatusWarning, logStatusError, logDebug)", categories[bad] ? categories[bad] : "(null)");
        return fmi2Error;
    }
    return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component comp, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    instance_t *c = FMU_ENTER(comp, fmi2SetupExperiment);
    if (!c) return fmi2Error;
    if (!isfinite(startTime) || (stopTimeDefined && (!isfinite(stopTime) || stopTime < startTime)) ||
        (toleranceDefined && (!isfinite(tolerance) || tolerance <= 0.0))) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SetupExperiment: startTime = %g, stopTime = %g, tolerance = %g: "
                "allowed finite startTime, stopTime >= startTime, tolerance > 0",
                startTime, stopTime, tolerance);
        return fmi2Error;
    }
    c->m.time = c->m.t0 = startTime;
    c->m.tau = 0.0;
    c->m.stop_defined = stopTimeDefined != 0;
    c->m.stop_time = stopTime;
    c->m.tol_defined = toleranceDefined != 0;
    if (toleranceDefined) c->m.tol = tolerance < TOL_MAX ? tolerance : TOL_MAX;
    if (toleranceDefined && tolerance > TOL_MAX) {
        /* FMI: the FMU may integrate with a smaller tolerance than the importer's */
        fmu_log(c, fmi2Warning, LOG_WARNING, "%s: tolerance = %g is looser than %g, the loosest at which the "
                "integrator's error follows its tolerance: integrating with %g",
                c->fmi3 ? "fmi3EnterInitializationMode" : "fmi2SetupExperiment", tolerance, TOL_MAX, TOL_MAX);
        return fmi2Warning;
    }
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component comp) {
    instance_t *c = FMU_ENTER(comp, fmi2EnterInitializationMode);
    if (!c) return fmi2Error;
    c->m.fsm = ST_INIT;
    c->m.out_valid = 0;
    c->m.params_ok = 0;
    return fmi2OK;
}

void fmu_solver_setup(model_t *m) {
    double atol[PLANT_NX];
    int j;
    plant_memo_reset(&m->memo);   /* called after every compile of the parameters but fmu_recompile's */
    m->carry.valid = 0;
    m->ind_positive = 0;
    m->fast_ok = fast_path_ok(&m->p);
    for (j = 0; j < PLANT_NX; j++) atol[j] = m->tol * MODEL_STATE_NOMINAL(j);   /* XML nominals */
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
    /* every accepted step is checked against the states' declared ranges (fmi2_cs.c) */
    m->solver.bounded = 1;
    for (j = 0; j < m->solver.n; j++) {
        m->solver.y_lo[j] = MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].min;
        m->solver.y_hi[j] = MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].max;
    }
}

/* compile parameters and initialise the plant from the current values */
fmi2Status fmu_initialize_plant(instance_t *c) {
    model_t *m = &c->m;
    char msg[512];
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
    fmu_solver_setup(m);
    m->solver_restart = 1;
    m->out_valid = 0;
    fmu_check_stroke(c);
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component comp) {
    instance_t *c = FMU_ENTER(comp, fmi2ExitInitializationMode);
    if (!c) return fmi2Error;
    if (fmu_initialize_plant(c) != fmi2OK) { c->m.fsm = ST_ERROR; return fmi2Error; }
    c->m.fsm = c->type == fmi2ModelExchange ? ST_EVENT : ST_STEP_COMPLETE;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component comp) {
    instance_t *c = FMU_ENTER(comp, fmi2Terminate);
    if (!c) return fmi2Error;
    c->m.fsm = ST_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component comp) {
    instance_t *c = FMU_ENTER(comp, fmi2Reset);
    if (!c) return fmi2Error;
    fmu_instance_defaults(c);
    return fmi2OK;
}

