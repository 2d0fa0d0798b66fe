/* FMI 3.0 life cycle: instantiation over the shared instance (fmi2Instantiate with calloc/free
 * and a logger that hands the messages to fmi3LogMessageCallback, fmi3_log.h), Configuration Mode for the
 * structural parameter friction.N, initialization, event mode, termination, reset. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3_glue.h"
#include "start_values.h"

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
    c = (instance_t *)fmi2Instantiate(name, type, token, NULL, &cb, fmi2False, logging_on ? fmi2True : fmi2False);
    if (!c) { free(e); return NULL; }
    c->fmi3 = 1;
    c->event_mode_used = event_mode_used;
    c->ext = e;
    if (!fmu_start_values_load(c, resource_path, 0)) {
        fmi2FreeInstance(c);
        free(e);
        return NULL;
    }
    return c;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
    (void)visible;
    return instantiate(instanceName, fmi2ModelExchange, instantiationToken, resourcePath, loggingOn, instanceEnvironment,
                       logMessage, 0, 0);
}

void fmi3_on_switch(void *instance);   /* fmi3_cs.c */

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
        fmi2FreeInstance(c);
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
    fmi2FreeInstance(c);
    free(e);
}

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    instance_t *c = FMU_ENTER(instance, fmi3SetDebugLogging);
    if (!c) return fmi3Error;
    return (fmi3Status)fmi2SetDebugLogging(c, loggingOn ? fmi2True : fmi2False, nCategories, categories);
}

/* ---------------------------------------------------------------- states of the FMI 3.0 view */

int fmi3_n(const model_t *m) { return (int)m->val[VR_friction_N]; }

/* is FMI 2.0 state j an element past friction.N of an array of dimension N? */
static int state_unused(const model_t *m, int j) {
    int r, p, n = fmi3_n(m);
    for (r = 0; r < MODEL3_NVARS; r++) {
        if (MODEL3_VARS[r].kind != 1) continue;
        for (p = 0; p < MODEL3_VARS[r].count; p++)
            if (MODEL3_ELEMS[MODEL3_VARS[r].first + p] == MODEL_STATE_VR[j]) return p >= n;
    }
    return 0;
}

size_t fmi3_nx(const model_t *m) {
    size_t n = 0;
    int j;
    for (j = 0; j < MODEL_NX; j++) n += !state_unused(m, j);
    return n;
}

int fmi3_state_index(const model_t *m, size_t j) {
    int k;
    for (k = 0; k < MODEL_NX; k++)
        if (!state_unused(m, k) && j-- == 0) return k;
    return -1;
}

/* ---------------------------------------------------------------- life cycle */

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3EnterConfigurationMode);
    if (!c) return fmi3Error;
    c->m.fsm = ST_CONFIG;
    return fmi3OK;
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3ExitConfigurationMode);
    if (!c) return fmi3Error;
    c->m.fsm = ST_INSTANTIATED;
    return fmi3OK;
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    instance_t *c = FMU_ENTER(instance, fmi3EnterInitializationMode);
    if (!c) return fmi3Error;
    fmi2Status st = fmi2SetupExperiment(c, toleranceDefined, tolerance, startTime, stopTimeDefined, stopTime);
    if (st != fmi2OK && st != fmi2Warning) return fmi3Error;
    if (fmi2EnterInitializationMode(c) != fmi2OK) return fmi3Error;
    return (fmi3Status)st;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3ExitInitializationMode);
    if (!c) return fmi3Error;
    if (fmu_initialize_plant(c) != fmi2OK) { c->m.fsm = ST_ERROR; return fmi3Error; }
    /* model exchange and co-simulation with event mode: the initial event update is the master's */
    c->m.fsm = (c->type == fmi2ModelExchange || fmi3_ext(c)->event_mode_used) ? ST_EVENT : ST_STEP_COMPLETE;
    return fmi3OK;
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3EnterEventMode);
    if (!c) return fmi3Error;
    if (c->type == fmi2CoSimulation && !fmi3_ext(c)->event_mode_used) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3EnterEventMode: this co-simulation instance was instantiated with "
                "eventModeUsed = false");
        return fmi3Error;
    }
    c->m.fsm = ST_EVENT;
    return fmi3OK;
}

fmi3Status fmi3Terminate(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3Terminate);
    if (!c) return fmi3Error;
    c->m.fsm = ST_TERMINATED;
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance instance) {
    instance_t *c = FMU_ENTER(instance, fmi3Reset);
    if (!c) return fmi3Error;
    fmu_instance_defaults(c);
    return fmi3OK;
}

/* ---------------------------------------------------------------- event mode */

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged, fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime) {
    instance_t *c = FMU_ENTER(instance, fmi3UpdateDiscreteStates);
    fmi2Boolean changed = fmi2False;
    long long k_before;
    int switches;
    if (!c) return fmi3Error;
    if (!discreteStatesNeedUpdate || !terminateSimulation || !nominalsOfContinuousStatesChanged ||
        !valuesOfContinuousStatesChanged || !nextEventTimeDefined || !nextEventTime) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi3UpdateDiscreteStates: NULL output argument");
        return fmi3Error;
    }
    if (c->type == fmi2CoSimulation) {
        /* co-simulation: the switch that ended the step was updated inside it; what the inputs
         * set in Event Mode cause and a sample due now are taken at the start of the next
         * fmi3DoStep, with the inputs then set (fmi2DoStep's convention, so event mode and early
         * return do not change the trajectory) */
        c->m.solver_restart = 1;
    } else {
        k_before = c->m.d.k;
        switches = fmu_event_update(c, "fmi3UpdateDiscreteStates", c->m.time - c->m.t0,
                                    fmu_ulp_slack(c->m.time), &changed);
        if (switches < 0) return fmi3Error;
        /* as fmi2NewDiscreteStates: the right-hand side jumps at a switch and at a sample */
        if (switches > 0 || c->m.d.k != k_before) changed = fmi2True;
    }
    *discreteStatesNeedUpdate = fmi3False;
    *terminateSimulation = fmi3False;
    *nominalsOfContinuousStatesChanged = fmi3False;
    *valuesOfContinuousStatesChanged = changed ? fmi3True : fmi3False;
    *nextEventTimeDefined = c->m.p.current_dynamics ? fmi3True : fmi3False;
    *nextEventTime = c->m.p.current_dynamics ? fmu_next_sample(&c->m) : 0.0;
    return fmi3OK;
}
