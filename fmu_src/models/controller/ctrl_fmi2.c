/* FMI 2.0 co-simulation glue of the controller FMU: the plant's call-sequence table
 * (allowed.h) and logging (log.h), the value table of ctrl_vars.h, one controller
 * sample per sample instant t_k = t0 + k Ts.
 * Sample convention: u at t_k is the controller's output for the inputs as they stand at t_k (it
 * depends on x_meas directly): fmi2GetReal computes the pending sample from the current inputs,
 * fmi2DoStep commits it and takes every further sample inside the step with the inputs held.
 * Once read in Step Mode, the sample at t_k is fixed: inputs set after the read are the next
 * sample's (FMI's Step Mode: no output of an instant after a set at that instant).  So a master
 * that steps the plant first and the controller second (Gauss-Seidel) reads u_k+1 from
 * x(t_k+1), no delay; a Jacobi master (outputs read after the step, inputs set after) reads
 * at t_k+1 the sample computed from x(t_k): one sample of delay at h = Ts. */
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "fmi2Functions.h"
#include "allowed.h"
#include "log.h"
#include "ctrl_params.h"

#define CTRL_MAGIC 0x46444354u   /* "FDCT" */
/* Work budget of one call (README "The controller FMU"): fmi2DoStep takes at most this many
 * controller samples (h/Ts), a longer step is refused before any sample is taken */
#define CTRL_BUDGET_SAMPLES 1e6
/* the most values an array can hold (fmi2Real, the widest element): a larger nvr is no array */
#define CTRL_MAX_NVR ((size_t)PTRDIFF_MAX / sizeof(fmi2Real))

typedef struct {
    unsigned magic;
    int fsm;
    double time, t0;
    double val[CTRL_NVR];
    ctrl_params_t p;
    int params_ok;
    ctrl_state_t s, pending;      /* committed state; the sample at the current instant */
    int pending_ok;
    int pending_read;             /* the pending sample's outputs were read in Step Mode */
    fmi2CallbackFunctions cb;
    char *name;
    int logging_on;
    unsigned log_mask;
} ctrl_instance_t;

static void ctrl_log(ctrl_instance_t *c, fmi2Status st, unsigned cat, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(FMU_PRINTF_FORMAT, 4, 5)))
#endif
    ;
static void ctrl_log(ctrl_instance_t *c, fmi2Status st, unsigned cat, const char *fmt, ...) {
    va_list ap;
    if (!c) return;
    va_start(ap, fmt);
    log_v(&c->cb, c->name, c->logging_on, c->log_mask, st, cat, fmt, ap);
    va_end(ap);
}

/* the entry check of allowed.h (FMU_ENTER) */
static ctrl_instance_t *fmu_enter(fmi2Component comp, const char *fn, int iface, int mask) {
    ctrl_instance_t *c = (ctrl_instance_t *)comp;
    if (!c || c->magic != CTRL_MAGIC) return NULL;
    if (!(iface & FOR_CS)) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "%s: only for model exchange; this FMU is co-simulation only", fn);
        return NULL;
    }
    if (mask == ST_ANY || (c->fsm & mask)) return c;
    ctrl_log(c, fmi2Error, LOG_ERROR, "%s: illegal call in state %s", fn, fsm_name(c->fsm));
    if (c->fsm != ST_FATAL) c->fsm = ST_ERROR;
    return NULL;
}

static void inputs(const ctrl_instance_t *c, ctrl_in_t *in) {
    in->x_ref = c->val[CVR_x_ref];
    in->v_ref = c->val[CVR_v_ref];
    in->a_ref = c->val[CVR_a_ref];
    in->x_meas = c->val[CVR_x_meas];
}

static void store_outputs(ctrl_instance_t *c, const ctrl_state_t *s) {
    c->val[CVR_u] = s->u;
    c->val[CVR_x_cmd] = s->x_cmd;
    c->val[CVR_u_ff] = s->u_ff;
    c->val[CVR_r_x] = s->r_x;
}

static double sample_time(const ctrl_instance_t *c, long long k) { return c->t0 + (double)k * c->p.Ts; }
/* how far a communication time may miss a sample instant and still be it: 1e-9 of the time
 * elapsed (at least of 1 s), at most Ts/64, as the plant FMU's.  Masters that add h to a double
 * (Ecos: t += h) drift by ~n ulp: 5e-13 s after 25 750 steps of 50 us, more than a fixed
 * 1e-9 Ts = 5e-13 s, which took a sample one macro step early from a stale x_meas */
static double time_eps(const ctrl_instance_t *c, double t) {
    double tau = fabs(t - c->t0), eps = 1e-9 * (tau > 1.0 ? tau : 1.0);
    return eps < c->p.Ts / 64.0 ? eps : c->p.Ts / 64.0;
}
static int due(const ctrl_instance_t *c, double t) {
    return sample_time(c, c->s.k) <= t + time_eps(c, t);
}

/* the sample at the current instant from the current inputs (not yet committed); 0 when it is
 * not finite (logged as fn's error, the instance in state Error, the outputs those of the last
 * finite sample) */
static int evaluate(ctrl_instance_t *c, const char *fn) {
    ctrl_in_t in;
    char why[160];
    if (c->pending_ok || !due(c, c->time)) return 1;
    inputs(c, &in);
    c->pending = c->s;
    if (!ctrl_sample(&c->p, &c->pending, &in, why, sizeof why)) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "%s: sample %lld at t = %.17g s: %s (x_meas = %g m, x_ref = %g m): the "
                 "controller or its pre-filter diverged (unstable ss.Ac / zpetc.a) or its inputs are out of scale",
                 fn, c->s.k, sample_time(c, c->s.k), why, in.x_meas, in.x_ref);
        c->fsm = ST_ERROR;
        return 0;
    }
    store_outputs(c, &c->pending);
    c->pending_ok = 1;
    c->pending_read = 0;
    return 1;
}

static fmi2Status compile(ctrl_instance_t *c, const char *fn) {
    char msg[512];
    if (!ctrl_compile(c->val, &c->p, msg, sizeof msg)) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "%s: %s", fn, msg);
        return fmi2Error;
    }
    return fmi2OK;
}

static fmi2Status initialize(ctrl_instance_t *c, const char *fn) {
    if (compile(c, fn) != fmi2OK) { c->params_ok = 0; return fmi2Error; }
    c->params_ok = 1;
    ctrl_reset(&c->p, &c->s);
    c->pending_ok = c->pending_read = 0;
    return fmi2OK;
}

static void defaults(ctrl_instance_t *c) {
    memset(c->val, 0, sizeof c->val);
    ctrl_defaults(c->val);
    c->fsm = ST_INSTANTIATED;
    c->time = c->t0 = 0.0;
    c->params_ok = 0;
    c->pending_ok = c->pending_read = 0;
}

/* ---------------------------------------------------------------- life cycle */
const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
    ctrl_instance_t *c;
    size_t len;
    char buf[512];
    (void)fmuResourceLocation;
    (void)visible;
    if (!functions || !functions->allocateMemory || !functions->freeMemory) return NULL;
    buf[0] = 0;
    if (!instanceName || !*instanceName) snprintf(buf, sizeof buf, "fmi2Instantiate: instanceName must be a non-empty string");
    else if (!fmuGUID || strcmp(fmuGUID, CTRL_GUID) != 0)
        snprintf(buf, sizeof buf, "fmi2Instantiate: GUID %s does not match this FMU's %s", fmuGUID ? fmuGUID : "(null)", CTRL_GUID);
    else if (fmuType != fmi2CoSimulation)
        snprintf(buf, sizeof buf, "fmi2Instantiate: fmuType %d: this FMU is co-simulation (1) only", (int)fmuType);
    if (buf[0]) {
        if (functions->logger) log_emit(functions, instanceName ? instanceName : "?", fmi2Error, "logStatusError", buf);
        return NULL;
    }
    c = (ctrl_instance_t *)functions->allocateMemory(1, sizeof(ctrl_instance_t));
    if (!c) return NULL;
    memset(c, 0, sizeof *c);
    len = strlen(instanceName) + 1;
    c->name = (char *)functions->allocateMemory(len, 1);
    if (!c->name) { functions->freeMemory(c); return NULL; }
    memcpy(c->name, instanceName, len);
    c->magic = CTRL_MAGIC;
    c->cb = *functions;
    c->logging_on = loggingOn != 0;
    c->log_mask = LOG_ALL;
    defaults(c);
    return c;
}

void fmi2FreeInstance(fmi2Component comp) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2FreeInstance);
    fmi2CallbackFreeMemory fr;
    if (!c) return;
    fr = c->cb.freeMemory;
    c->magic = 0;
    fr(c->name);
    fr(c);
}

fmi2Status fmi2SetDebugLogging(fmi2Component comp, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2SetDebugLogging);
    long long bad;
    if (!c) return fmi2Error;
    c->logging_on = loggingOn != 0;
    if (nCategories > 0 && !categories) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "fmi2SetDebugLogging: categories is NULL with nCategories = %zu",
                 nCategories);
        return fmi2Error;
    }
    if ((bad = log_categories(nCategories, categories, &c->log_mask)) >= 0) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "fmi2SetDebugLogging: unknown log category \"%s\" (known: "
                 "logEvents, logStatusWarning, logStatusError)", categories[bad] ? categories[bad] : "(null)");
        return fmi2Error;
    }
    return fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component comp, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2SetupExperiment);
    (void)toleranceDefined; (void)tolerance;
    if (!c) return fmi2Error;
    if (!isfinite(startTime) || (stopTimeDefined && !(stopTime >= startTime))) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "fmi2SetupExperiment: startTime = %g, stopTime = %g: allowed finite "
                 "startTime, stopTime >= startTime", startTime, stopTime);
        return fmi2Error;
    }
    c->time = c->t0 = startTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component comp) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2EnterInitializationMode);
    if (!c) return fmi2Error;
    c->fsm = ST_INIT;
    c->params_ok = 0;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component comp) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2ExitInitializationMode);
    if (!c) return fmi2Error;
    if (!c->params_ok && initialize(c, "fmi2ExitInitializationMode") != fmi2OK) { c->fsm = ST_ERROR; return fmi2Error; }
    c->pending_read = c->pending_ok;   /* a first sample read in Initialization Mode is fixed */
    c->fsm = ST_STEP_COMPLETE;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component comp) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2Terminate);
    if (!c) return fmi2Error;
    c->fsm = ST_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component comp) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2Reset);
    if (!c) return fmi2Error;
    defaults(c);
    return fmi2OK;
}

/* ---------------------------------------------------------------- get / set */
static int lookup(ctrl_instance_t *c, const char *fn, fmi2ValueReference vr, char type) {
    int row;
    static const char *const TN[] = {"Real", "Integer", "Boolean"};
    if (vr >= CTRL_NVR || (row = CTRL_VR_INDEX[vr]) < 0) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "%s: unknown value reference %u", fn, (unsigned)vr);
        return -1;
    }
    if (CTRL_VARS[row].type != type) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "%s: %s (value reference %u) is not of type %s", fn,
                 CTRL_VARS[row].name, (unsigned)vr, TN[type == 'R' ? 0 : (type == 'I' ? 1 : 2)]);
        return -1;
    }
    return row;
}

/* the value arrays of a get/set: not NULL when nvr > 0, nvr no more than an array can hold */
static int arrays_ok(ctrl_instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                     const void *value) {
    if (nvr > 0 && (!vr || !value)) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "%s: NULL array with nvr = %zu", fn, nvr);
        return 0;
    }
    if (nvr > CTRL_MAX_NVR) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "%s: nvr = %zu: allowed at most %zu (no array holds more values)", fn,
                 nvr, CTRL_MAX_NVR);
        return 0;
    }
    return 1;
}

static fmi2Status get_values(ctrl_instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                             char type, void *value) {
    size_t k;
    if (!c || !arrays_ok(c, fn, vr, nvr, value)) return fmi2Error;
    if (c->fsm == ST_INIT && !c->params_ok && initialize(c, fn) != fmi2OK) return fmi2Error;
    if (c->params_ok && (c->fsm & (ST_INIT | ST_STEP_COMPLETE)) && !evaluate(c, fn)) return fmi2Error;
    if (c->pending_ok && (c->fsm & ST_STEP_COMPLETE)) c->pending_read = 1;
    for (k = 0; k < nvr; k++) {
        int row = lookup(c, fn, vr[k], type);
        double v;
        if (row < 0) return fmi2Error;
        v = c->val[vr[k]];
        if (!isfinite(v)) {   /* every value stored is finite: this guards the rule, it never fires */
            ctrl_log(c, fmi2Error, LOG_ERROR, "%s: %s = %g is not finite", fn, CTRL_VARS[row].name, v);
            return fmi2Error;
        }
        if (type == 'R') ((fmi2Real *)value)[k] = v;
        else if (type == 'I') ((fmi2Integer *)value)[k] = (fmi2Integer)v;
        else ((fmi2Boolean *)value)[k] = v != 0.0 ? fmi2True : fmi2False;
    }
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    return get_values(FMU_ENTER(c, fmi2GetReal), "fmi2GetReal", vr, nvr, 'R', value);
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
    return get_values(FMU_ENTER(c, fmi2GetInteger), "fmi2GetInteger", vr, nvr, 'I', value);
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
    return get_values(FMU_ENTER(c, fmi2GetBoolean), "fmi2GetBoolean", vr, nvr, 'B', value);
}
fmi2Status fmi2GetString(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2GetString);
    (void)vr; (void)value;
    if (!c) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    ctrl_log(c, fmi2Error, LOG_ERROR, "fmi2GetString: this FMU has no String variables");
    return fmi2Error;
}

static int settable(ctrl_instance_t *c, const char *fn, int row) {
    const ctrl_var_t *v = &CTRL_VARS[row];
    if (v->causality == 'i' && (c->fsm & SET_INPUT)) return 1;
    if (v->causality == 'p' && (c->fsm & (v->variability == 't' ? SET_TUNABLE : SET_FIXED))) return 1;
    ctrl_log(c, fmi2Error, LOG_ERROR, "%s: %s (causality %s, variability %s) cannot be set in this state", fn,
             v->name, v->causality == 'p' ? "parameter" : (v->causality == 'i' ? "input" : "output"),
             v->variability == 'f' ? "fixed" : (v->variability == 't' ? "tunable" : "discrete/continuous"));
    return 0;
}

static double as_double(char type, const void *value, size_t k) {
    return type == 'R' ? ((const fmi2Real *)value)[k]
         : type == 'I' ? (double)((const fmi2Integer *)value)[k]
                       : (((const fmi2Boolean *)value)[k] ? 1.0 : 0.0);
}

static fmi2Status set_values(ctrl_instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                             char type, const void *value) {
    size_t k;
    int param_changed = 0;
    char msg[512];
    if (!c || !arrays_ok(c, fn, vr, nvr, value)) return fmi2Error;
    for (k = 0; k < nvr; k++) {   /* every value checked before any is stored */
        int row = lookup(c, fn, vr[k], type);
        const ctrl_var_t *mv;
        double v;
        if (row < 0 || !settable(c, fn, row)) return fmi2Error;
        mv = &CTRL_VARS[row];
        if (type == 'B') {
            fmi2Boolean b = ((const fmi2Boolean *)value)[k];
            if (b != fmi2True && b != fmi2False) {
                ctrl_log(c, fmi2Error, LOG_ERROR, "%s: %s = %d is not a Boolean: allowed 0 or 1", fn, mv->name, (int)b);
                return fmi2Error;
            }
        }
        v = as_double(type, value, k);
        if (!ctrl_check_value(vr[k], v, msg, sizeof msg)) {
            ctrl_log(c, fmi2Error, LOG_ERROR, "%s: %s", fn, msg);
            return fmi2Error;
        }
        if (v < mv->min || v > mv->max) {
            ctrl_log(c, fmi2Error, LOG_ERROR, "%s: %s = %.17g is out of range: allowed [%.17g, %.17g] %s", fn,
                     mv->name, v, mv->min, mv->max, mv->unit);
            return fmi2Error;
        }
        if (mv->causality == 'p' && (c->fsm & ST_STEP_COMPLETE)) param_changed = 1;
    }
    if (param_changed) {   /* a tunable parameter between steps: recompile, keep the state */
        ctrl_params_t old = c->p;
        double save[CTRL_NVR];
        memcpy(save, c->val, sizeof save);
        for (k = 0; k < nvr; k++) c->val[vr[k]] = as_double(type, value, k);
        if (compile(c, fn) != fmi2OK) {
            memcpy(c->val, save, sizeof save);
            c->p = old;
            return fmi2Error;
        }
        c->pending_ok = c->pending_read = 0;
        return fmi2OK;
    }
    for (k = 0; k < nvr; k++) c->val[vr[k]] = as_double(type, value, k);
    if (c->fsm & ST_INIT) c->params_ok = 0;
    if (!c->pending_read) c->pending_ok = 0;   /* a sample read in Step Mode keeps its inputs */
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    return set_values(FMU_ENTER(c, fmi2SetReal), "fmi2SetReal", vr, nvr, 'R', value);
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
    return set_values(FMU_ENTER(c, fmi2SetInteger), "fmi2SetInteger", vr, nvr, 'I', value);
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
    return set_values(FMU_ENTER(c, fmi2SetBoolean), "fmi2SetBoolean", vr, nvr, 'B', value);
}
fmi2Status fmi2SetString(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2SetString);
    (void)vr; (void)value;
    if (!c) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    ctrl_log(c, fmi2Error, LOG_ERROR, "fmi2SetString: this FMU has no String variables");
    return fmi2Error;
}

/* ---------------------------------------------------------------- co-simulation */
fmi2Status fmi2DoStep(fmi2Component comp, fmi2Real t, fmi2Real h, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2DoStep);
    double samples, taken = 0.0;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!c) return fmi2Error;
    if (!isfinite(h) || !(h > 0.0) || !isfinite(t) || !isfinite(t + h) ||
        fabs(t - c->time) > 1e-9 * (fabs(t) > 1.0 ? fabs(t) : 1.0)) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "fmi2DoStep: currentCommunicationPoint = %.17g, communicationStepSize = "
                 "%.17g: allowed the FMU's time %.17g and a finite communicationStepSize > 0", t, h, c->time);
        return fmi2Error;
    }
    /* the sample instants must be times a double tells apart (as the plant's: 16 ulp <= Ts/8) */
    if (16.0 * (nextafter(fabs(t + h), HUGE_VAL) - fabs(t + h)) > c->p.Ts / 8.0) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "fmi2DoStep: at t = %.17g s a double resolves only %g s, too coarse for "
                 "the controller samples of Ts = %g s (allowed: 16 ulp(t) <= Ts/8, a start time nearer 0)", t + h,
                 nextafter(fabs(t + h), HUGE_VAL) - fabs(t + h), c->p.Ts);
        return fmi2Error;
    }
    /* the samples this step takes, counted before the first: a refused step changes nothing */
    samples = ceil((t + h - sample_time(c, c->s.k)) / c->p.Ts);
    if (samples > CTRL_BUDGET_SAMPLES) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "fmi2DoStep: communicationStepSize = %.17g s spans %.0f samples of Ts = "
                 "%g s: allowed at most %.0f samples per call (budget), communicationStepSize <= %g s at this Ts",
                 h, samples, c->p.Ts, CTRL_BUDGET_SAMPLES, CTRL_BUDGET_SAMPLES * c->p.Ts);
        return fmi2Error;
    }
    while (sample_time(c, c->s.k) < t + h - time_eps(c, t + h)) {
        c->time = fmax(c->time, sample_time(c, c->s.k));
        if (!evaluate(c, "fmi2DoStep")) return fmi2Error;
        c->s = c->pending;
        c->pending_ok = c->pending_read = 0;
        if (++taken > CTRL_BUDGET_SAMPLES + 2.0) {   /* the count above bounds this loop; kept as its guard */
            ctrl_log(c, fmi2Error, LOG_ERROR, "fmi2DoStep: more than %.0f samples in one step (budget)",
                     CTRL_BUDGET_SAMPLES);
            c->fsm = ST_ERROR;
            return fmi2Error;
        }
    }
    c->time = t + h;
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component comp) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2CancelStep);
    if (!c) return fmi2Error;
    ctrl_log(c, fmi2Error, LOG_ERROR, "fmi2CancelStep: fmi2DoStep never runs asynchronously here");
    return fmi2Error;
}

fmi2Status fmi2GetRealStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Real *value) {
    ctrl_instance_t *c = FMU_ENTER(comp, fmi2GetRealStatus);
    if (!c) return fmi2Error;
    if (s == fmi2LastSuccessfulTime && value) { *value = c->time; return fmi2OK; }
    ctrl_log(c, fmi2Error, LOG_ERROR, "fmi2GetRealStatus: only fmi2LastSuccessfulTime is known");
    return fmi2Error;
}

fmi2Status ctrl_refuse(fmi2Component comp, const char *fn, int iface, int mask) {
    ctrl_instance_t *c = fmu_enter(comp, fn, iface, mask);
    if (c) ctrl_log(c, fmi2Error, LOG_ERROR, "%s: not supported by this FMU", fn);
    return fmi2Error;
}

/* ---------------------------------------------------------------- for the FMI 3.0 glue (ctrl_fmi3.c) */
int ctrl_is_instance(fmi2Component comp) {
    const ctrl_instance_t *c = (const ctrl_instance_t *)comp;
    return c && c->magic == CTRL_MAGIC;
}
void *ctrl_environment(fmi2Component comp) {
    return ctrl_is_instance(comp) ? ((ctrl_instance_t *)comp)->cb.componentEnvironment : NULL;
}
void ctrl_refuse_message(fmi2Component comp, const char *fn, const char *why) {
    if (ctrl_is_instance(comp)) ctrl_log((ctrl_instance_t *)comp, fmi2Error, LOG_ERROR, "%s: %s", fn, why);
}

/* ---------------------------------------------------------------- for the clocked FMI 3.0 glue */
/* Step Mode after initialisation (the FMI 3.0 glue's Event Mode keeps this state underneath) */
int ctrl_stepping(fmi2Component comp) {
    return ctrl_is_instance(comp) && ((ctrl_instance_t *)comp)->fsm == ST_STEP_COMPLETE;
}
/* the sample time as set (the clock's interval, before and after initialisation) */
double ctrl_sample_period(fmi2Component comp) {
    return ctrl_is_instance(comp) ? ((ctrl_instance_t *)comp)->val[CVR_Ts] : 0.0;
}

/* The input clock set active: a sample computed before (an output read before the tick) is
 * dropped; the tick's sample comes from the inputs set at the tick. */
void ctrl_drop_pending(fmi2Component comp) {
    if (ctrl_is_instance(comp)) ((ctrl_instance_t *)comp)->pending_ok = ((ctrl_instance_t *)comp)->pending_read = 0;
}

/* A tick of the input clock at the instance's time: the sample due at this instant -- the one
 * an output read at the tick computed, else one from the inputs as they stand -- committed (the
 * outputs are its outputs until the next tick). 0, logged as fn's error, when the instant is no
 * sample instant or the sample is not finite. */
int ctrl_tick(fmi2Component comp, const char *fn) {
    ctrl_instance_t *c = (ctrl_instance_t *)comp;
    double tk;
    if (!ctrl_stepping(comp) || !c->params_ok) return 0;
    tk = sample_time(c, c->s.k);
    if (fabs(tk - c->time) > time_eps(c, c->time)) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "%s: clock tick at t = %.17g s: the next sample instant is t = %.17g s "
                 "(t0 + %lld Ts, Ts = %g s): the clock ticks at the sample instants only", fn, c->time, tk, c->s.k,
                 c->p.Ts);
        return 0;
    }
    if (!evaluate(c, fn)) return 0;
    c->s = c->pending;
    c->pending_ok = c->pending_read = 0;
    return 1;
}

/* A step of a clocked instance ends at the latest at the next sample instant, whose tick the
 * importer gives in Event Mode: 0, logged, when [t, t + h) holds a sample instant not ticked. */
int ctrl_step_within_tick(fmi2Component comp, double t, double h) {
    ctrl_instance_t *c = (ctrl_instance_t *)comp;
    double tk;
    if (!ctrl_stepping(comp) || !c->params_ok || !isfinite(t) || !isfinite(h)) return 1;   /* fmi2DoStep answers */
    tk = sample_time(c, c->s.k);
    if (tk < t + h - time_eps(c, t + h)) {
        ctrl_log(c, fmi2Error, LOG_ERROR, "fmi3DoStep: currentCommunicationPoint = %.17g, communicationStepSize = "
                 "%.17g: the step passes the clock tick at t = %.17g s (sample %lld) without it; allowed a step "
                 "that ends at or before the next tick, the tick given in Event Mode", t, h, tk, c->s.k);
        return 0;
    }
    return 1;
}
