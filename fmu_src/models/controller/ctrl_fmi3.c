/* FMI 3.0 co-simulation glue of the controller FMU over its FMI 2.0 glue (ctrl_fmi2.c, in the
 * same library; only the fmi3 functions are exported, fmu_src/fmi/fmi3.map): the same instance,
 * call sequence and messages (fmi3_log.h renames the functions), calloc/free for memory.
 * Event Mode with a periodic input clock `tick` (interval Ts, the parameter): an instance made
 * with eventModeUsed takes its samples at the ticks only -- at t_k the importer enters Event
 * Mode, activates the clock (fmi3SetClock), sets the inputs of t_k, reads u_k (computed from
 * them: no delay but ctrl.delay's), fmi3UpdateDiscreteStates commits the sample (outputs read
 * after it are the same), and fmi3EnterStepMode returns to the steps, each ending at the latest
 * at the next tick. Without
 * eventModeUsed the instance samples as the FMI 2.0 FMU does (inside fmi3DoStep). No early
 * return, no FMU state, no model exchange; the functions neither FMU provides are in
 * fmu_src/fmi/fmi3_stubs.c. */
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3_log.h"

int ctrl_is_instance(fmi2Component comp);
void *ctrl_environment(fmi2Component comp);
void ctrl_refuse_message(fmi2Component comp, const char *fn, const char *why);
int ctrl_stepping(fmi2Component comp);
double ctrl_sample_period(fmi2Component comp);
int ctrl_tick(fmi2Component comp, const char *fn);
void ctrl_drop_pending(fmi2Component comp);
int ctrl_step_within_tick(fmi2Component comp, double t, double h);

/* the value reference of the input clock `tick` (fmu_src/generators/gen_fmi3.py's CTRL_VR_TICK) */
#define VR_TICK 9u

/* the instance environment of the FMI 2.0 glue underneath: the logger first (fmi3_log.h), then
 * the FMI 3.0 modes it does not know */
typedef struct {
    fmi3_logger_t lg;
    int event_mode_used;
    int in_event;          /* Event Mode (after initialisation with eventModeUsed, or entered) */
    int ticked;            /* the clock set active in this Event Mode, its sample not yet taken */
} ctrl3_env_t;

static ctrl3_env_t *env3(fmi3Instance instance) { return (ctrl3_env_t *)ctrl_environment(instance); }

fmi3Status fmi3_refuse(fmi3Instance instance, const char *fn, const char *why) {
    if (!ctrl_is_instance(instance)) return fmi3Error;
    if (!why) return fmi3OK;
    ctrl_refuse_message(instance, fn, why);
    return fmi3Error;
}

const char *fmi3GetVersion(void) { return fmi3Version; }

static void early_error(fmi3InstanceEnvironment env, fmi3LogMessageCallback log, const char *text) {
    if (log) log(env, fmi3Error, "logStatusError", text);
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate) {
    ctrl3_env_t *lg;
    fmi2CallbackFunctions cb;
    fmi2Component c;
    (void)resourcePath; (void)visible; (void)earlyReturnAllowed;   /* never returns early */
    (void)requiredIntermediateVariables; (void)intermediateUpdate;
    if (nRequiredIntermediateVariables > 0) {
        early_error(instanceEnvironment, logMessage, "fmi3InstantiateCoSimulation: required intermediate variables "
                    "given; this FMU provides no intermediate update");
        return NULL;
    }
    if (!(lg = (ctrl3_env_t *)calloc(1, sizeof *lg))) return NULL;
    lg->lg.env = instanceEnvironment;
    lg->lg.log_message = logMessage;
    lg->event_mode_used = eventModeUsed != fmi3False;
    cb = fmi3_callbacks(&lg->lg);
    c = fmi2Instantiate(instanceName, fmi2CoSimulation, instantiationToken, NULL, &cb, fmi2False,
                        loggingOn ? fmi2True : fmi2False);
    if (!c) free(lg);
    return c;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
    (void)instanceName; (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn;
    early_error(instanceEnvironment, logMessage, "fmi3InstantiateModelExchange: this FMU is co-simulation only");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance instance) {
    void *lg;
    if (!ctrl_is_instance(instance)) return;
    lg = ctrl_environment(instance);
    fmi2FreeInstance(instance);
    free(lg);
}

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    return (fmi3Status)fmi2SetDebugLogging(instance, loggingOn ? fmi2True : fmi2False, nCategories, categories);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    if (fmi2SetupExperiment(instance, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime) != fmi2OK)
        return fmi3Error;
    return (fmi3Status)fmi2EnterInitializationMode(instance);
}
/* with eventModeUsed the instance leaves Initialization Mode into Event Mode (FMI 3.0) */
fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    fmi3Status st = (fmi3Status)fmi2ExitInitializationMode(instance);
    if (st == fmi3OK && env3(instance)->event_mode_used) env3(instance)->in_event = 1;
    return st;
}
fmi3Status fmi3Terminate(fmi3Instance instance) {
    fmi3Status st = (fmi3Status)fmi2Terminate(instance);
    if (st == fmi3OK) env3(instance)->in_event = env3(instance)->ticked = 0;
    return st;
}
fmi3Status fmi3Reset(fmi3Instance instance) {
    fmi3Status st = (fmi3Status)fmi2Reset(instance);
    if (st == fmi3OK) env3(instance)->in_event = env3(instance)->ticked = 0;
    return st;
}

/* ---------------------------------------------------------------- values: scalars only */

/* the arguments of a get/set of scalars: nValues = nValueReferences, no NULL array with
 * nValueReferences > 0, no more values than an array of the widest element (fmi3Float64) holds
 * (so that the Boolean conversion buffer's size cannot wrap) */
static int scalars(fmi3Instance instance, const char *fn, const fmi3ValueReference vr[], size_t nvr,
                   const void *v, size_t nv) {
    char why[160];
    if (nvr != nv)
        snprintf(why, sizeof why, "nValues = %zu must equal nValueReferences = %zu (this FMU has no arrays)", nv, nvr);
    else if (nvr > 0 && (!vr || !v))
        snprintf(why, sizeof why, "NULL array with nValueReferences = %zu", nvr);
    else if (nvr > (size_t)PTRDIFF_MAX / sizeof(fmi3Float64))
        snprintf(why, sizeof why, "nValueReferences = %zu: allowed at most %zu (no array holds more values)", nvr,
                 (size_t)PTRDIFF_MAX / sizeof(fmi3Float64));
    else
        return 1;
    ctrl_refuse_message(instance, fn, why);
    return 0;
}

/* value reference 0 is the independent variable `time` of the FMI 3.0 description (the FMI 2.0
 * controller has no such variable): served from the instance's time, the rest by fmi2GetReal */
fmi3Status fmi3GetFloat64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 v[], size_t nv) {
    size_t k, j;
    if (!scalars(i, "fmi3GetFloat64", vr, nvr, v, nv)) return fmi3Error;
    for (k = 0; k < nvr && vr[k] != 0; k++) {}
    if (k == nvr) return (fmi3Status)fmi2GetReal(i, vr, nvr, v);
    for (k = 0; k < nvr; k = j) {
        fmi2Status st;
        if (vr[k] == 0) {
            st = fmi2GetRealStatus(i, fmi2LastSuccessfulTime, &v[k]);
            j = k + 1;
        } else {
            for (j = k; j < nvr && vr[j] != 0; j++) {}
            st = fmi2GetReal(i, vr + k, j - k, v + k);
        }
        if (st != fmi2OK) return (fmi3Status)st;
    }
    return fmi3OK;
}
fmi3Status fmi3SetFloat64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Float64 v[], size_t nv) {
    return scalars(i, "fmi3SetFloat64", vr, nvr, v, nv) ? (fmi3Status)fmi2SetReal(i, vr, nvr, v) : fmi3Error;
}
fmi3Status fmi3GetInt32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Int32 v[], size_t nv) {
    return scalars(i, "fmi3GetInt32", vr, nvr, v, nv) ? (fmi3Status)fmi2GetInteger(i, vr, nvr, v) : fmi3Error;
}
fmi3Status fmi3SetInt32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Int32 v[], size_t nv) {
    return scalars(i, "fmi3SetInt32", vr, nvr, v, nv) ? (fmi3Status)fmi2SetInteger(i, vr, nvr, v) : fmi3Error;
}
/* the FMI 2.0 Booleans of n FMI 3.0 ones (n checked by scalars: n + 1 cannot wrap) */
static fmi2Boolean *bool_buffer(fmi3Instance i, const char *fn, size_t n) {
    fmi2Boolean *b = (fmi2Boolean *)calloc(n + 1, sizeof *b);
    char why[96];
    if (b) return b;
    snprintf(why, sizeof why, "no memory for %zu Boolean values", n);
    ctrl_refuse_message(i, fn, why);
    return NULL;
}

fmi3Status fmi3GetBoolean(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Boolean v[], size_t nv) {
    fmi2Boolean *b;
    fmi3Status st;
    size_t k;
    if (!scalars(i, "fmi3GetBoolean", vr, nvr, v, nv)) return fmi3Error;
    if (!(b = bool_buffer(i, "fmi3GetBoolean", nvr))) return fmi3Error;
    st = (fmi3Status)fmi2GetBoolean(i, vr, nvr, b);
    if (st == fmi3OK)
        for (k = 0; k < nvr; k++) v[k] = b[k] != fmi2False;
    free(b);
    return st;
}
fmi3Status fmi3SetBoolean(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Boolean v[], size_t nv) {
    fmi2Boolean *b;
    fmi3Status st;
    size_t k;
    if (!scalars(i, "fmi3SetBoolean", vr, nvr, v, nv)) return fmi3Error;
    if (!(b = bool_buffer(i, "fmi3SetBoolean", nvr))) return fmi3Error;
    for (k = 0; k < nvr; k++) b[k] = v[k] ? fmi2True : fmi2False;
    st = (fmi3Status)fmi2SetBoolean(i, vr, nvr, b);
    free(b);
    return st;
}

/* ---------------------------------------------------------------- co-simulation */

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint, fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint, fmi3Boolean *eventHandlingNeeded,
                      fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
    fmi3Status st;
    if (!eventHandlingNeeded || !terminateSimulation || !earlyReturn || !lastSuccessfulTime) {
        ctrl_refuse_message(instance, "fmi3DoStep", "NULL output argument");
        return fmi3Error;
    }
    *eventHandlingNeeded = *terminateSimulation = *earlyReturn = fmi3False;
    *lastSuccessfulTime = currentCommunicationPoint;
    if (env3(instance) && env3(instance)->in_event) {
        ctrl_refuse_message(instance, "fmi3DoStep", "illegal call in Event Mode (fmi3EnterStepMode first)");
        return fmi3Error;
    }
    if (env3(instance) && env3(instance)->event_mode_used &&
        !ctrl_step_within_tick(instance, currentCommunicationPoint, communicationStepSize))
        return fmi3Error;
    st = (fmi3Status)fmi2DoStep(instance, currentCommunicationPoint, communicationStepSize,
                                noSetFMUStatePriorToCurrentPoint ? fmi2True : fmi2False);
    *lastSuccessfulTime = st == fmi3OK ? currentCommunicationPoint + communicationStepSize : currentCommunicationPoint;
    return st;
}

/* ---------------------------------------------------------------- Event Mode and the input clock */

/* the instance's FMI 3.0 modes, NULL (fn's error logged) when it was not made with eventModeUsed */
static ctrl3_env_t *clocked(fmi3Instance i, const char *fn) {
    ctrl3_env_t *e = env3(i);
    if (!e) return NULL;
    if (e->event_mode_used) return e;
    ctrl_refuse_message(i, fn, "the instance was made with eventModeUsed = false: it samples inside fmi3DoStep");
    return NULL;
}

fmi3Status fmi3EnterEventMode(fmi3Instance i) {
    ctrl3_env_t *e = clocked(i, "fmi3EnterEventMode");
    if (!e) return fmi3Error;
    if (e->in_event) return fmi3_refuse(i, "fmi3EnterEventMode", "illegal call in Event Mode (already in it)");
    if (!ctrl_stepping(i)) return fmi3_refuse(i, "fmi3EnterEventMode", "allowed in Step Mode only");
    e->in_event = 1;
    e->ticked = 0;
    return fmi3OK;
}

fmi3Status fmi3EnterStepMode(fmi3Instance i) {
    ctrl3_env_t *e = clocked(i, "fmi3EnterStepMode");
    if (!e) return fmi3Error;
    if (!e->in_event) return fmi3_refuse(i, "fmi3EnterStepMode", "allowed in Event Mode only");
    if (e->ticked)
        return fmi3_refuse(i, "fmi3EnterStepMode", "the clock tick was set active and its sample not taken: "
                                                  "fmi3UpdateDiscreteStates first");
    e->in_event = 0;
    return fmi3OK;
}

/* one input clock, `tick` (value reference VR_TICK): the arrays checked, every reference it */
static int clock_refs(fmi3Instance i, const char *fn, const fmi3ValueReference vr[], size_t nvr, const void *v) {
    char why[160];
    size_t k;
    if (nvr > 0 && (!vr || !v)) {
        snprintf(why, sizeof why, "NULL array with nValueReferences = %zu", nvr);
        ctrl_refuse_message(i, fn, why);
        return 0;
    }
    for (k = 0; k < nvr; k++)
        if (vr[k] != VR_TICK) {
            snprintf(why, sizeof why, "value reference %u is no clock: the one clock is tick (value reference %u)",
                     (unsigned)vr[k], VR_TICK);
            ctrl_refuse_message(i, fn, why);
            return 0;
        }
    return 1;
}

fmi3Status fmi3SetClock(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Clock v[]) {
    ctrl3_env_t *e = env3(i);
    size_t k;
    if (!e) return fmi3Error;
    if (!clock_refs(i, "fmi3SetClock", vr, nvr, v)) return fmi3Error;
    if (nvr == 0) return fmi3OK;
    if (!clocked(i, "fmi3SetClock")) return fmi3Error;
    if (!e->in_event) return fmi3_refuse(i, "fmi3SetClock", "tick can be set in Event Mode only (fmi3EnterEventMode "
                                                             "at the tick's instant first)");
    for (k = 0; k < nvr; k++) e->ticked = v[k] != fmi3ClockInactive;
    if (e->ticked) ctrl_drop_pending(i);
    return fmi3OK;
}

fmi3Status fmi3GetClock(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Clock v[]) {
    if (!env3(i) || !clock_refs(i, "fmi3GetClock", vr, nvr, v)) return fmi3Error;
    return fmi3_refuse(i, "fmi3GetClock", nvr ? "tick is an input clock: the importer sets it (fmi3SetClock)" : NULL);
}

/* the clock's interval: Ts as set (intervalVariability fixed: known from Initialization Mode on) */
fmi3Status fmi3GetIntervalDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 intervals[],
                                  fmi3IntervalQualifier qualifiers[]) {
    size_t k;
    if (!env3(i) || !clock_refs(i, "fmi3GetIntervalDecimal", vr, nvr, intervals)) return fmi3Error;
    if (nvr > 0 && !qualifiers) return fmi3_refuse(i, "fmi3GetIntervalDecimal", "NULL array qualifiers");
    for (k = 0; k < nvr; k++) {
        intervals[k] = ctrl_sample_period(i);
        qualifiers[k] = fmi3IntervalChanged;
    }
    return fmi3OK;
}
fmi3Status fmi3GetShiftDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 shifts[]) {
    size_t k;
    if (!env3(i) || !clock_refs(i, "fmi3GetShiftDecimal", vr, nvr, shifts)) return fmi3Error;
    for (k = 0; k < nvr; k++) shifts[k] = 0.0;
    return fmi3OK;
}
#define NO_FRACTION "tick has no fraction (supportsFraction is false)"
#define NO_SET_INTERVAL "the interval of tick is the parameter Ts (intervalVariability fixed)"
fmi3Status fmi3GetIntervalFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n, fmi3UInt64 a[],
                                   fmi3UInt64 b[], fmi3IntervalQualifier q[]) {
    (void)vr; (void)a; (void)b; (void)q;
    return fmi3_refuse(i, "fmi3GetIntervalFraction", n ? NO_FRACTION : NULL);
}
fmi3Status fmi3GetShiftFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n, fmi3UInt64 a[], fmi3UInt64 b[]) {
    (void)vr; (void)a; (void)b;
    return fmi3_refuse(i, "fmi3GetShiftFraction", n ? NO_FRACTION : NULL);
}
fmi3Status fmi3SetIntervalDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t n, const fmi3Float64 a[]) {
    (void)vr; (void)a;
    return fmi3_refuse(i, "fmi3SetIntervalDecimal", n ? NO_SET_INTERVAL : NULL);
}
fmi3Status fmi3SetIntervalFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 a[],
                                   const fmi3UInt64 b[]) {
    (void)vr; (void)a; (void)b;
    return fmi3_refuse(i, "fmi3SetIntervalFraction", n ? NO_SET_INTERVAL : NULL);
}
fmi3Status fmi3SetShiftDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t n, const fmi3Float64 a[]) {
    (void)vr; (void)a;
    return fmi3_refuse(i, "fmi3SetShiftDecimal", n ? "the shift of tick is 0" : NULL);
}
fmi3Status fmi3SetShiftFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 a[],
                                const fmi3UInt64 b[]) {
    (void)vr; (void)a; (void)b;
    return fmi3_refuse(i, "fmi3SetShiftFraction", n ? NO_FRACTION : NULL);
}

/* at a tick (the clock set active): the sample of this instant; the rest of an Event Mode
 * (no tick) changes nothing. No discrete state needs a further update; the next event is the
 * importer's next tick. */
fmi3Status fmi3UpdateDiscreteStates(fmi3Instance i, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsChanged,
                                    fmi3Boolean *valuesChanged, fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime) {
    ctrl3_env_t *e = clocked(i, "fmi3UpdateDiscreteStates");
    if (!e) return fmi3Error;
    if (!e->in_event) return fmi3_refuse(i, "fmi3UpdateDiscreteStates", "allowed in Event Mode only");
    if (!discreteStatesNeedUpdate || !terminateSimulation || !nominalsChanged || !valuesChanged ||
        !nextEventTimeDefined || !nextEventTime)
        return fmi3_refuse(i, "fmi3UpdateDiscreteStates", "NULL output argument");
    *discreteStatesNeedUpdate = *terminateSimulation = *nominalsChanged = *valuesChanged = fmi3False;
    *nextEventTimeDefined = fmi3False;
    *nextEventTime = 0.0;
    if (e->ticked && !ctrl_tick(i, "fmi3UpdateDiscreteStates")) return fmi3Error;
    e->ticked = 0;
    return fmi3OK;
}

/* ---------------------------------------------------------------- not offered (as in FMI 2.0) */

#define NO_STATE "canGetAndSetFMUState is false"
#define NO_ME "this FMU is co-simulation only"
fmi3Status fmi3EnterConfigurationMode(fmi3Instance i) {
    return fmi3_refuse(i, "fmi3EnterConfigurationMode", "this FMU has no structural parameters");
}
fmi3Status fmi3ExitConfigurationMode(fmi3Instance i) {
    return fmi3_refuse(i, "fmi3ExitConfigurationMode", "this FMU has no structural parameters");
}
fmi3Status fmi3GetOutputDerivatives(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Int32 o[],
                                    fmi3Float64 v[], size_t nv) {
    (void)vr; (void)nvr; (void)o; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3GetOutputDerivatives", "maxOutputDerivativeOrder is 0");
}
fmi3Status fmi3GetFMUState(fmi3Instance i, fmi3FMUState *s) { (void)s; return fmi3_refuse(i, "fmi3GetFMUState", NO_STATE); }
fmi3Status fmi3SetFMUState(fmi3Instance i, fmi3FMUState s) { (void)s; return fmi3_refuse(i, "fmi3SetFMUState", NO_STATE); }
fmi3Status fmi3FreeFMUState(fmi3Instance i, fmi3FMUState *s) { (void)s; return fmi3_refuse(i, "fmi3FreeFMUState", NO_STATE); }
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance i, fmi3FMUState s, size_t *n) {
    (void)s; (void)n;
    return fmi3_refuse(i, "fmi3SerializedFMUStateSize", NO_STATE);
}
fmi3Status fmi3SerializeFMUState(fmi3Instance i, fmi3FMUState s, fmi3Byte b[], size_t n) {
    (void)s; (void)b; (void)n;
    return fmi3_refuse(i, "fmi3SerializeFMUState", NO_STATE);
}
fmi3Status fmi3DeserializeFMUState(fmi3Instance i, const fmi3Byte b[], size_t n, fmi3FMUState *s) {
    (void)b; (void)n; (void)s;
    return fmi3_refuse(i, "fmi3DeserializeFMUState", NO_STATE);
}
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance i) { return fmi3_refuse(i, "fmi3EnterContinuousTimeMode", NO_ME); }
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance i, fmi3Boolean n, fmi3Boolean *e, fmi3Boolean *t) {
    (void)n; (void)e; (void)t;
    return fmi3_refuse(i, "fmi3CompletedIntegratorStep", NO_ME);
}
fmi3Status fmi3SetTime(fmi3Instance i, fmi3Float64 t) { (void)t; return fmi3_refuse(i, "fmi3SetTime", NO_ME); }
fmi3Status fmi3SetContinuousStates(fmi3Instance i, const fmi3Float64 x[], size_t n) {
    (void)x; (void)n;
    return fmi3_refuse(i, "fmi3SetContinuousStates", NO_ME);
}
fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance i, fmi3Float64 d[], size_t n) {
    (void)d; (void)n;
    return fmi3_refuse(i, "fmi3GetContinuousStateDerivatives", NO_ME);
}
fmi3Status fmi3GetEventIndicators(fmi3Instance i, fmi3Float64 z[], size_t n) {
    (void)z; (void)n;
    return fmi3_refuse(i, "fmi3GetEventIndicators", NO_ME);
}
fmi3Status fmi3GetContinuousStates(fmi3Instance i, fmi3Float64 x[], size_t n) {
    (void)x; (void)n;
    return fmi3_refuse(i, "fmi3GetContinuousStates", NO_ME);
}
fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance i, fmi3Float64 x[], size_t n) {
    (void)x; (void)n;
    return fmi3_refuse(i, "fmi3GetNominalsOfContinuousStates", NO_ME);
}
fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance i, size_t *n) {
    (void)n;
    return fmi3_refuse(i, "fmi3GetNumberOfEventIndicators", NO_ME);
}
fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance i, size_t *n) {
    (void)n;
    return fmi3_refuse(i, "fmi3GetNumberOfContinuousStates", NO_ME);
}
