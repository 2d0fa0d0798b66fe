/* The FMI 3.0 entry points, every model: each enters through the one table (FMU_ENTER,
 * allowed.h) or answers through the one refusal (fmi3_refuse: fmu_refuse behind the table's
 * fmi3NotProvided) and hands the call to the version-neutral core (instance.h), the FMI 3.0
 * view of the variables (fmi3_view.h) or the model (model.h). An FMI 3.0 instance is the
 * core's, made with calloc/free and a logger that hands the messages to
 * fmi3LogMessageCallback (fmi3_log.h). Co-simulation adds event mode and early return at a
 * discrete change (on_switch): the first one after the step's start is snapshotted (the whole
 * model, right after its event update); with earlyReturnAllowed the step then returns there,
 * the instance set back to the snapshot, so the trajectory is the one the full step computed,
 * cut at the switch; with eventModeUsed the step reports eventHandlingNeeded (the update is
 * already made; in Event Mode the master may set inputs at that instant). No intermediate
 * update (providesIntermediateUpdate is false). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3_view.h"

const char *fmi3GetVersion(void) { return fmi3Version; }

static instance_t *instantiate(fmi3String name, fmi2Type type, fmi3String token, fmi3String resource_path,
                               fmi3Boolean logging_on,
                               fmi3InstanceEnvironment env, fmi3LogMessageCallback log_message,
                               int event_mode_used, int early_return_allowed) {
    fmi3_ext_t *e = (fmi3_ext_t *)calloc(1, sizeof(fmi3_ext_t));
    fmi2CallbackFunctions cb;
    instance_t *c;
    if (!e) return NULL;
    e->log.env = env;
    e->log.log_message = log_message;
    e->event_mode_used = event_mode_used;
    e->early_return_allowed = early_return_allowed;
    cb = fmi3_callbacks(&e->log);
    c = fmu_instantiate("fmi3Instantiate", name, type, token, &cb, logging_on);
    if (!c) { free(e); return NULL; }
    c->fmi3 = 1;
    c->event_mode_used = event_mode_used;
    c->ext = e;
    if (!model_load_start_values(c, resource_path, 0)) {
        fmu_free_instance(c);
        free(e);
        return NULL;
    }
    return c;
}

static void fmi3_on_switch(void *instance);

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
    (void)visible;
    return instantiate(instanceName, fmi2ModelExchange, instantiationToken, resourcePath, loggingOn, instanceEnvironment,
                       logMessage, 0, 0);
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate) {
    instance_t *c;
    (void)visible; (void)requiredIntermediateVariables;
    (void)intermediateUpdate;   /* providesIntermediateUpdate is false: never called */
    c = instantiate(instanceName, fmi2CoSimulation, instantiationToken, resourcePath, loggingOn, instanceEnvironment, logMessage,
                    eventModeUsed != 0, earlyReturnAllowed != 0);
    if (!c) return NULL;
    if (nRequiredIntermediateVariables > 0) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3InstantiateCoSimulation: %zu required intermediate variables: "
                "this FMU provides no intermediate update (providesIntermediateUpdate is false)",
                nRequiredIntermediateVariables);
        free(c->ext);
        c->ext = NULL;
        fmu_free_instance(c);
        return NULL;
    }
    c->on_switch = fmi3_on_switch;
    return c;
}

void fmi3FreeInstance(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3FreeInstance);
    void *e;
    if (!c) return;
    e = c->ext;
    fmu_free_instance(c);
    free(e);
}

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    return (fmi3Status)fmu_set_debug_logging(FMU_ENTER(instance, fmi3SetDebugLogging), "fmi3SetDebugLogging",
                                             loggingOn, nCategories, categories);
}

/* ---------------------------------------------------------------- life cycle */

#define NO_CONFIG "this FMU has no structural parameters"

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3EnterConfigurationMode);
    if (!c) return fmi3Error;
    if (!OFFERS(MODEL_CAN_CONFIG)) return (fmi3Status)fmu_refuse(c, "fmi3EnterConfigurationMode", NO_CONFIG);
    c->m.fsm = ST_CONFIG;
    return fmi3OK;
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3ExitConfigurationMode);
    if (!c) return fmi3Error;
    if (!OFFERS(MODEL_CAN_CONFIG)) return (fmi3Status)fmu_refuse(c, "fmi3ExitConfigurationMode", NO_CONFIG);
    c->m.fsm = ST_INSTANTIATED;
    return fmi3OK;
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    instance_t *c = FMU_ENTER(instance, fmi3EnterInitializationMode);
    fmi2Status st = fmu_setup_experiment(c, "fmi3EnterInitializationMode", toleranceDefined, tolerance, startTime,
                                         stopTimeDefined, stopTime);
    if (st != fmi2OK && st != fmi2Warning) return fmi3Error;
    if (fmu_enter_initialization(c) != fmi2OK) return fmi3Error;
    return (fmi3Status)st;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3ExitInitializationMode);
    if (!c) return fmi3Error;
    /* model exchange and co-simulation with event mode: the initial event update is the master's */
    return (fmi3Status)fmu_exit_initialization(c, "fmi3ExitInitializationMode",
                                               (c->type == fmi2ModelExchange || fmi3_ext(c)->event_mode_used)
                                                   ? ST_EVENT : ST_STEP_COMPLETE);
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3EnterEventMode);
    if (!c) return fmi3Error;
    if (c->m.fsm == ST_EVENT)
        return (fmi3Status)fmu_refuse(c, "fmi3EnterEventMode", "illegal call in Event Mode (already in it)");
    if (c->type == fmi2CoSimulation && !fmi3_ext(c)->event_mode_used) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3EnterEventMode: this co-simulation instance was instantiated with "
                "eventModeUsed = false");
        return fmi3Error;
    }
    c->m.fsm = ST_EVENT;
    return fmi3OK;
}

fmi3Status fmi3Terminate(fmi3Instance instance) {
    return (fmi3Status)fmu_terminate(FMU_ENTER(instance, fmi3Terminate));
}

fmi3Status fmi3Reset(fmi3Instance instance) {
    return (fmi3Status)fmu_reset(FMU_ENTER(instance, fmi3Reset));
}

/* ---------------------------------------------------------------- event mode */

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged, fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime) {
    instance_t *c = FMU_ENTER(instance, fmi3UpdateDiscreteStates);
    int changed = 0, next_defined = 0;
    double next = 0.0;
    if (!c) return fmi3Error;
    if (!discreteStatesNeedUpdate || !terminateSimulation || !nominalsOfContinuousStatesChanged ||
        !valuesOfContinuousStatesChanged || !nextEventTimeDefined || !nextEventTime) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3UpdateDiscreteStates: NULL output argument");
        return fmi3Error;
    }
    if (c->type == fmi2CoSimulation) {
        if (model_cs_event_update(c, "fmi3UpdateDiscreteStates") != fmi2OK) return fmi3Error;
        next_defined = model_next_event(&c->m, &next);
    } else if (fmu_me_event_update(c, "fmi3UpdateDiscreteStates", &changed, &next_defined, &next) != fmi2OK) {
        return fmi3Error;
    }
    *discreteStatesNeedUpdate = fmi3False;
    *terminateSimulation = fmi3False;
    *nominalsOfContinuousStatesChanged = fmi3False;
    *valuesOfContinuousStatesChanged = changed != 0;
    *nextEventTimeDefined = next_defined != 0;
    *nextEventTime = next;
    return fmi3OK;
}

/* ---------------------------------------------------------------- values */

fmi3Status fmi3GetFloat64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 v[], size_t nv) {
    return fmi3_get_values(FMU_ENTER(i, fmi3GetFloat64), "fmi3GetFloat64", vr, nvr, 'R', v, nv);
}
fmi3Status fmi3GetInt32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Int32 v[], size_t nv) {
    return fmi3_get_values(FMU_ENTER(i, fmi3GetInt32), "fmi3GetInt32", vr, nvr, 'I', v, nv);
}
fmi3Status fmi3GetBoolean(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Boolean v[], size_t nv) {
    return fmi3_get_values(FMU_ENTER(i, fmi3GetBoolean), "fmi3GetBoolean", vr, nvr, 'B', v, nv);
}
fmi3Status fmi3SetFloat64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Float64 v[], size_t nv) {
    return fmi3_set_values(FMU_ENTER(i, fmi3SetFloat64), "fmi3SetFloat64", vr, nvr, 'R', v, nv);
}
fmi3Status fmi3SetInt32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Int32 v[], size_t nv) {
    return fmi3_set_values(FMU_ENTER(i, fmi3SetInt32), "fmi3SetInt32", vr, nvr, 'I', v, nv);
}
fmi3Status fmi3SetBoolean(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Boolean v[], size_t nv) {
    return fmi3_set_values(FMU_ENTER(i, fmi3SetBoolean), "fmi3SetBoolean", vr, nvr, 'B', v, nv);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates) {
    instance_t *c = FMU_ENTER(instance, fmi3GetNumberOfContinuousStates);
    if (!c) return fmi3Error;
    if (!OFFERS(MODEL_CAN_ME))
        return (fmi3Status)fmu_refuse(c, "fmi3GetNumberOfContinuousStates", "this FMU is co-simulation only");
    if (!nContinuousStates) { fmu_log(c, fmi2Error, LOG_ERROR, "fmi3GetNumberOfContinuousStates: NULL argument"); return fmi3Error; }
    *nContinuousStates = fmi3_nx(&c->m);
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators) {
    instance_t *c = FMU_ENTER(instance, fmi3GetNumberOfEventIndicators);
    if (!c) return fmi3Error;
    if (!OFFERS(MODEL_CAN_ME))
        return (fmi3Status)fmu_refuse(c, "fmi3GetNumberOfEventIndicators", "this FMU is co-simulation only");
    if (!nEventIndicators) { fmu_log(c, fmi2Error, LOG_ERROR, "fmi3GetNumberOfEventIndicators: NULL argument"); return fmi3Error; }
    *nEventIndicators = GLUE_NZ;
    return fmi3OK;
}

/* ---------------------------------------------------------------- FMU state */

#define NO_STATE "canGetAndSetFMUState is false"
fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    instance_t *c = FMU_ENTER(instance, fmi3GetFMUState);
    return (fmi3Status)(c && !OFFERS(MODEL_CAN_STATE) ? fmu_refuse(c, "fmi3GetFMUState", NO_STATE)
                                                      : fmu_state_get(c, "fmi3GetFMUState", FMUState));
}
fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState) {
    instance_t *c = FMU_ENTER(instance, fmi3SetFMUState);
    return (fmi3Status)(c && !OFFERS(MODEL_CAN_STATE) ? fmu_refuse(c, "fmi3SetFMUState", NO_STATE)
                                                      : fmu_state_set(c, "fmi3SetFMUState", FMUState));
}
fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    instance_t *c = FMU_ENTER(instance, fmi3FreeFMUState);
    return (fmi3Status)(c && !OFFERS(MODEL_CAN_STATE) ? fmu_refuse(c, "fmi3FreeFMUState", NO_STATE)
                                                      : fmu_state_free(c, "fmi3FreeFMUState", FMUState));
}
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size) {
    instance_t *c = FMU_ENTER(instance, fmi3SerializedFMUStateSize);
    return (fmi3Status)(c && !OFFERS(MODEL_CAN_STATE) ? fmu_refuse(c, "fmi3SerializedFMUStateSize", NO_STATE)
                                                      : fmu_state_size(c, "fmi3SerializedFMUStateSize", FMUState, size));
}
fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[], size_t size) {
    instance_t *c = FMU_ENTER(instance, fmi3SerializeFMUState);
    return (fmi3Status)(c && !OFFERS(MODEL_CAN_STATE)
                            ? fmu_refuse(c, "fmi3SerializeFMUState", NO_STATE)
                            : fmu_state_serialize(c, "fmi3SerializeFMUState", FMUState, serializedState, size));
}
fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState) {
    instance_t *c = FMU_ENTER(instance, fmi3DeserializeFMUState);
    return (fmi3Status)(c && !OFFERS(MODEL_CAN_STATE)
                            ? fmu_refuse(c, "fmi3DeserializeFMUState", NO_STATE)
                            : fmu_state_deserialize(c, "fmi3DeserializeFMUState", serializedState, size, FMUState));
}

/* the answer of the functions no model of this glue offers (fmi3_stubs.c): "<fn>: not
 * provided (<why>)", Error; OK for a call with nothing to do (why NULL) */
fmi3Status fmi3_refuse(fmi3Instance instance, const char *fn, const char *why) {
    instance_t *c = FMU_ENTER(instance, fmi3NotProvided);
    if (!c || !why) return c ? fmi3OK : fmi3Error;
    fmu_log(c, fmi2Error, LOG_ERROR, "%s: not provided (%s)", fn, why);
    return fmi3Error;
}

/* ---------------------------------------------------------------- model exchange */

/* FMI 3.0's view of the continuous states: those of the arrays' current dimension */
static me_view_t view3(const instance_t *c) {
    me_view_t v;
    v.n = c ? fmi3_nx(&c->m) : 0;
    v.index = fmi3_state_index;
    v.dim_name = fmi3_structural_name();
    v.dim = c ? fmi3_n(&c->m) : 0;
    return v;
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
    return (fmi3Status)fmu_set_mode(FMU_ENTER(instance, fmi3EnterContinuousTimeMode), ST_CONT);
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation) {
    instance_t *c = FMU_ENTER(instance, fmi3CompletedIntegratorStep);
    (void)noSetFMUStatePriorToCurrentPoint;
    if (fmu_me_completed_step(c, "fmi3CompletedIntegratorStep", enterEventMode && terminateSimulation) != fmi2OK)
        return fmi3Error;
    *enterEventMode = *terminateSimulation = fmi3False;
    return fmi3OK;
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
    return (fmi3Status)fmu_me_set_time(FMU_ENTER(instance, fmi3SetTime), "fmi3SetTime", time);
}
fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 x[], size_t nx) {
    instance_t *c = FMU_ENTER(instance, fmi3SetContinuousStates);
    me_view_t v = view3(c);
    return (fmi3Status)fmu_me_set_states(c, "fmi3SetContinuousStates", &v, x, nx);
}
fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t nx) {
    instance_t *c = FMU_ENTER(instance, fmi3GetContinuousStateDerivatives);
    me_view_t v = view3(c);
    return (fmi3Status)fmu_me_get_derivatives(c, "fmi3GetContinuousStateDerivatives", &v, derivatives, nx);
}
fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 z[], size_t nz) {
    instance_t *c = FMU_ENTER(instance, fmi3GetEventIndicators);
    me_view_t v = view3(c);
    return (fmi3Status)fmu_me_get_indicators(c, "fmi3GetEventIndicators", &v, z, nz);
}
fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 x[], size_t nx) {
    instance_t *c = FMU_ENTER(instance, fmi3GetContinuousStates);
    me_view_t v = view3(c);
    return (fmi3Status)fmu_me_get_states(c, "fmi3GetContinuousStates", &v, x, nx);
}
fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t nx) {
    instance_t *c = FMU_ENTER(instance, fmi3GetNominalsOfContinuousStates);
    me_view_t v = view3(c);
    return (fmi3Status)fmu_me_get_nominals(c, "fmi3GetNominalsOfContinuousStates", &v, nominals, nx);
}

/* ---------------------------------------------------------------- co-simulation */

static void fmi3_on_switch(void *instance) {
    instance_t *c = (instance_t *)instance;
    fmi3_ext_t *e = fmi3_ext(c);
    if (!e || !e->armed || !(c->m.time > e->step_t0)) return;
    e->n_switches++;
    if (!e->taken) {
        e->snap = c->m;
        e->taken = 1;
    }
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3EnterStepMode);
    if (!c) return fmi3Error;
    if (model_enter_step_mode(c) != fmi2OK) return fmi3Error;
    c->m.fsm = ST_STEP_COMPLETE;
    return fmi3OK;
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint, fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint, fmi3Boolean *eventHandlingNeeded,
                      fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
    instance_t *c = FMU_ENTER(instance, fmi3DoStep);
    fmi3_ext_t *e;
    fmi2Status st;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!c) return fmi3Error;
    if (!eventHandlingNeeded || !terminateSimulation || !earlyReturn || !lastSuccessfulTime) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3DoStep: NULL output argument");
        return fmi3Error;
    }
    e = fmi3_ext(c);
    *eventHandlingNeeded = *terminateSimulation = *earlyReturn = fmi3False;
    *lastSuccessfulTime = c->m.time;
    if (c->m.fsm == ST_EVENT)
        return (fmi3Status)fmu_refuse(c, "fmi3DoStep", "illegal call in Event Mode (fmi3EnterStepMode first)");
    if (!model_cs_step_ok(c, currentCommunicationPoint, communicationStepSize)) return fmi3Error;
    e->armed = e->event_mode_used || e->early_return_allowed;
    e->taken = 0;
    e->n_switches = 0;
    e->step_t0 = currentCommunicationPoint;
    st = model_do_step(c, "fmi3DoStep", currentCommunicationPoint, communicationStepSize);
    e->armed = 0;
    if (st != fmi2OK) { *lastSuccessfulTime = c->m.time; return (fmi3Status)st; }
    /* a switch on the step's end is no early return: the step ends there anyway */
    if (e->taken && e->early_return_allowed && e->snap.time < c->m.time) {
        c->m = e->snap;
        model_restored(c);
        *earlyReturn = fmi3True;
    }
    *eventHandlingNeeded = e->event_mode_used && e->taken;
    *lastSuccessfulTime = c->m.time;
    return fmi3OK;
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[],
                                    size_t nValues) {
    instance_t *c = FMU_ENTER(instance, fmi3GetOutputDerivatives);
    if (!c) return fmi3Error;
    if (nValues != nValueReferences) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3GetOutputDerivatives: nValues = %zu, allowed %zu (scalar outputs "
                "x, v and i)", nValues, nValueReferences);
        return fmi3Error;
    }
    return (fmi3Status)model_output_derivatives(c, "fmi3GetOutputDerivatives", valueReferences, nValueReferences,
                                                orders, values);
}

/* ---------------------------------------------------------------- clocks */

/* the clock functions: the model's (MODEL_CAN_CLOCKS), else "no clocks" */
#if (MODEL_CAPS) & MODEL_CAN_CLOCKS
#define CLOCKS(call, fn, n) ((fmi3Status)(call))
#define CLOCK_REFUSAL(fn, n, set_interval, set_shift) \
    ((fmi3Status)fmu_refuse(c, fn, (n) ? model_clock_refusal(set_interval, set_shift) : NULL))
#else
#define CLOCKS(call, fn, n) ((fmi3Status)fmu_refuse(c, fn, (n) ? NO_CLOCKS : NULL))
#define CLOCK_REFUSAL(fn, n, set_interval, set_shift) ((fmi3Status)fmu_refuse(c, fn, NO_CLOCKS))
#endif
#define NO_CLOCKS "not provided (this FMU has no clocks)"

fmi3Status fmi3GetClock(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Clock v[]) {
    instance_t *c = FMU_ENTER(i, fmi3Clocks);
    (void)vr; (void)v;
    return c ? CLOCKS(model_get_clock(c, "fmi3GetClock", vr, nvr, v), "fmi3GetClock", nvr) : fmi3Error;
}
fmi3Status fmi3SetClock(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Clock v[]) {
    instance_t *c = FMU_ENTER(i, fmi3Clocks);
    (void)vr; (void)v;
    return c ? CLOCKS(model_set_clock(c, "fmi3SetClock", vr, nvr, v), "fmi3SetClock", nvr) : fmi3Error;
}
fmi3Status fmi3GetIntervalDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t n, fmi3Float64 a[],
                                  fmi3IntervalQualifier q[]) {
    instance_t *c = FMU_ENTER(i, fmi3Clocks);
    (void)vr; (void)n; (void)a; (void)q;
    return c ? CLOCKS(model_get_interval(c, "fmi3GetIntervalDecimal", vr, n, a, q), "fmi3GetIntervalDecimal", 1)
             : fmi3Error;
}
fmi3Status fmi3GetShiftDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t n, fmi3Float64 a[]) {
    instance_t *c = FMU_ENTER(i, fmi3Clocks);
    (void)vr; (void)n; (void)a;
    return c ? CLOCKS(model_get_shift(c, "fmi3GetShiftDecimal", vr, n, a), "fmi3GetShiftDecimal", 1) : fmi3Error;
}
fmi3Status fmi3GetIntervalFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n, fmi3UInt64 a[],
                                   fmi3UInt64 b[], fmi3IntervalQualifier q[]) {
    instance_t *c = FMU_ENTER(i, fmi3Clocks);
    (void)vr; (void)n; (void)a; (void)b; (void)q;
    return c ? CLOCK_REFUSAL("fmi3GetIntervalFraction", n, 0, 0) : fmi3Error;
}
fmi3Status fmi3GetShiftFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n, fmi3UInt64 a[], fmi3UInt64 b[]) {
    instance_t *c = FMU_ENTER(i, fmi3Clocks);
    (void)vr; (void)n; (void)a; (void)b;
    return c ? CLOCK_REFUSAL("fmi3GetShiftFraction", n, 0, 0) : fmi3Error;
}
fmi3Status fmi3SetIntervalDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t n, const fmi3Float64 a[]) {
    instance_t *c = FMU_ENTER(i, fmi3Clocks);
    (void)vr; (void)n; (void)a;
    return c ? CLOCK_REFUSAL("fmi3SetIntervalDecimal", n, 1, 0) : fmi3Error;
}
fmi3Status fmi3SetIntervalFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 a[],
                                   const fmi3UInt64 b[]) {
    instance_t *c = FMU_ENTER(i, fmi3Clocks);
    (void)vr; (void)n; (void)a; (void)b;
    return c ? CLOCK_REFUSAL("fmi3SetIntervalFraction", n, 1, 0) : fmi3Error;
}
fmi3Status fmi3SetShiftDecimal(fmi3Instance i, const fmi3ValueReference vr[], size_t n, const fmi3Float64 a[]) {
    instance_t *c = FMU_ENTER(i, fmi3Clocks);
    (void)vr; (void)n; (void)a;
    return c ? CLOCK_REFUSAL("fmi3SetShiftDecimal", n, 0, 1) : fmi3Error;
}
fmi3Status fmi3SetShiftFraction(fmi3Instance i, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 a[],
                                const fmi3UInt64 b[]) {
    instance_t *c = FMU_ENTER(i, fmi3Clocks);
    (void)vr; (void)n; (void)a; (void)b;
    return c ? CLOCK_REFUSAL("fmi3SetShiftFraction", n, 0, 0) : fmi3Error;
}
