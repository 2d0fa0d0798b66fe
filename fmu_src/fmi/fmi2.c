/* The FMI 2.0 entry points, every model: each enters through the one table (FMU_ENTER,
 * allowed.h) and hands the call to the version-neutral core (instance.h) or to the model
 * (model.h); what the model does not offer (MODEL_CAPS) answers through fmu_refuse. */
#include <math.h>
#include <string.h>

#include "instance.h"

/* ---------------------------------------------------------------- life cycle */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn) {
    instance_t *c;
    (void)visible;
    c = fmu_instantiate("fmi2Instantiate", instanceName, fmuType, fmuGUID, functions, loggingOn);
    if (c && !model_load_start_values(c, fmuResourceLocation, 1)) {
        fmu_free_instance(c);
        return NULL;
    }
    return c;
}

void fmi2FreeInstance(fmi2Component comp) { fmu_free_instance(FMU_ENTER(comp, fmi2FreeInstance)); }

fmi2Status fmi2SetDebugLogging(fmi2Component comp, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    return fmu_set_debug_logging(FMU_ENTER(comp, fmi2SetDebugLogging), "fmi2SetDebugLogging", loggingOn,
                                 nCategories, categories);
}

fmi2Status fmi2SetupExperiment(fmi2Component comp, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    return fmu_setup_experiment(FMU_ENTER(comp, fmi2SetupExperiment), "fmi2SetupExperiment", toleranceDefined,
                                tolerance, startTime, stopTimeDefined, stopTime);
}

fmi2Status fmi2EnterInitializationMode(fmi2Component comp) {
    return fmu_enter_initialization(FMU_ENTER(comp, fmi2EnterInitializationMode));
}

fmi2Status fmi2ExitInitializationMode(fmi2Component comp) {
    instance_t *c = FMU_ENTER(comp, fmi2ExitInitializationMode);
    if (!c) return fmi2Error;
    return fmu_exit_initialization(c, "fmi2ExitInitializationMode",
                                   c->type == fmi2ModelExchange ? ST_EVENT : ST_STEP_COMPLETE);
}

fmi2Status fmi2Terminate(fmi2Component comp) { return fmu_terminate(FMU_ENTER(comp, fmi2Terminate)); }
fmi2Status fmi2Reset(fmi2Component comp) { return fmu_reset(FMU_ENTER(comp, fmi2Reset)); }

/* ---------------------------------------------------------------- values */

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]) {
    return fmu_get_values(FMU_ENTER(c, fmi2GetReal), "fmi2GetReal", vr, nvr, 'R', value);
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]) {
    return fmu_get_values(FMU_ENTER(c, fmi2GetInteger), "fmi2GetInteger", vr, nvr, 'I', value);
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]) {
    return fmu_get_values(FMU_ENTER(c, fmi2GetBoolean), "fmi2GetBoolean", vr, nvr, 'B', value);
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[]) {
    (void)value;
    return fmu_no_strings(FMU_ENTER(c, fmi2GetString), "fmi2GetString", vr, nvr);
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]) {
    return fmu_set_values(FMU_ENTER(c, fmi2SetReal), "fmi2SetReal", vr, nvr, 'R', value);
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]) {
    return fmu_set_values(FMU_ENTER(c, fmi2SetInteger), "fmi2SetInteger", vr, nvr, 'I', value);
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]) {
    return fmu_set_values(FMU_ENTER(c, fmi2SetBoolean), "fmi2SetBoolean", vr, nvr, 'B', value);
}
fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[]) {
    (void)value;
    return fmu_no_strings(FMU_ENTER(c, fmi2SetString), "fmi2SetString", vr, nvr);
}

/* ---------------------------------------------------------------- FMU state */

#define NO_STATE "not provided (canGetAndSetFMUstate is false)"
fmi2Status fmi2GetFMUstate(fmi2Component comp, fmi2FMUstate *state) {
    instance_t *c = FMU_ENTER(comp, fmi2GetFMUstate);
    return c && !OFFERS(MODEL_CAN_STATE) ? fmu_refuse(c, "fmi2GetFMUstate", NO_STATE)
                                         : fmu_state_get(c, "fmi2GetFMUstate", state);
}
fmi2Status fmi2SetFMUstate(fmi2Component comp, fmi2FMUstate state) {
    instance_t *c = FMU_ENTER(comp, fmi2SetFMUstate);
    return c && !OFFERS(MODEL_CAN_STATE) ? fmu_refuse(c, "fmi2SetFMUstate", NO_STATE)
                                         : fmu_state_set(c, "fmi2SetFMUstate", state);
}
fmi2Status fmi2FreeFMUstate(fmi2Component comp, fmi2FMUstate *state) {
    instance_t *c = FMU_ENTER(comp, fmi2FreeFMUstate);
    return c && !OFFERS(MODEL_CAN_STATE) ? fmu_refuse(c, "fmi2FreeFMUstate", NO_STATE)
                                         : fmu_state_free(c, "fmi2FreeFMUstate", state);
}
fmi2Status fmi2SerializedFMUstateSize(fmi2Component comp, fmi2FMUstate state, size_t *size) {
    instance_t *c = FMU_ENTER(comp, fmi2SerializedFMUstateSize);
    return c && !OFFERS(MODEL_CAN_STATE) ? fmu_refuse(c, "fmi2SerializedFMUstateSize", NO_STATE)
                                         : fmu_state_size(c, "fmi2SerializedFMUstateSize", state, size);
}
fmi2Status fmi2SerializeFMUstate(fmi2Component comp, fmi2FMUstate state, fmi2Byte serializedState[], size_t size) {
    instance_t *c = FMU_ENTER(comp, fmi2SerializeFMUstate);
    return c && !OFFERS(MODEL_CAN_STATE) ? fmu_refuse(c, "fmi2SerializeFMUstate", NO_STATE)
        : fmu_state_serialize(c, "fmi2SerializeFMUstate", state, (unsigned char *)serializedState, size);
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component comp, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *state) {
    instance_t *c = FMU_ENTER(comp, fmi2DeSerializeFMUstate);
    return c && !OFFERS(MODEL_CAN_STATE) ? fmu_refuse(c, "fmi2DeSerializeFMUstate", NO_STATE)
        : fmu_state_deserialize(c, "fmi2DeSerializeFMUstate", (const unsigned char *)serializedState, size, state);
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component comp, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[]) {
    instance_t *c = FMU_ENTER(comp, fmi2GetDirectionalDerivative);
    (void)vUnknown_ref; (void)nUnknown; (void)vKnown_ref; (void)nKnown; (void)dvKnown; (void)dvUnknown;
    return fmu_refuse(c, "fmi2GetDirectionalDerivative", "not provided (providesDirectionalDerivative is false)");
}

/* ---------------------------------------------------------------- model exchange */

static int array_ok(instance_t *c, const char *fn, const void *p, size_t n, size_t expected) {
    if (n != expected) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: size %zu, this FMU has %zu", fn, n, expected);
        return 0;
    }
    if (n > 0 && !p) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL array", fn);
        return 0;
    }
    return 1;
}

fmi2Status fmi2EnterEventMode(fmi2Component comp) {
    instance_t *c = FMU_ENTER(comp, fmi2EnterEventMode);
    if (!c) return fmi2Error;
    c->m.fsm = ST_EVENT;
    return fmi2OK;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component comp, fmi2EventInfo *info) {
    instance_t *c = FMU_ENTER(comp, fmi2NewDiscreteStates);
    fmi2Boolean changed = fmi2False;
    int switches;
    if (!c) return fmi2Error;
    if (!info) { fmu_log(c, fmi2Error, LOG_ERROR, "fmi2NewDiscreteStates: eventInfo is NULL"); return fmi2Error; }
    switches = model_event_update(c, "fmi2NewDiscreteStates", c->m.time - c->m.t0, fmu_ulp_slack(c->m.time),
                                  &changed);
    if (switches < 0) return fmi2Error;
    /* FMI 2.0 allows valuesOfContinuousStatesChanged false at a jump of the right-hand side, but
     * only an importer that always resets would then be right: the model reports it */
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = changed;
    info->nextEventTimeDefined = model_next_event(&c->m, &info->nextEventTime) ? fmi2True : fmi2False;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component comp) {
    instance_t *c = FMU_ENTER(comp, fmi2EnterContinuousTimeMode);
    if (!c) return fmi2Error;
    c->m.fsm = ST_CONT;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component comp, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation) {
    instance_t *c = FMU_ENTER(comp, fmi2CompletedIntegratorStep);
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!c) return fmi2Error;
    if (!enterEventMode || !terminateSimulation) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2CompletedIntegratorStep: NULL output argument");
        return fmi2Error;
    }
    model_completed_step(c);
    *enterEventMode = fmi2False;
    *terminateSimulation = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component comp, fmi2Real time) {
    instance_t *c = FMU_ENTER(comp, fmi2SetTime);
    if (!c) return fmi2Error;
    if (!isfinite(time)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SetTime: time = %g is not finite", time);
        return fmi2Error;
    }
    c->m.time = time;
    c->m.tau = time - c->m.t0;
    c->m.out_valid = 0;
    return fmi2OK;
}

fmi2Status fmi2SetContinuousStates(fmi2Component comp, const fmi2Real x[], size_t nx) {
    instance_t *c = FMU_ENTER(comp, fmi2SetContinuousStates);
    size_t j;
    if (!c) return fmi2Error;
    if (!array_ok(c, "fmi2SetContinuousStates", x, nx, GLUE_NX)) return fmi2Error;
    for (j = 0; j < nx; j++) {
        if (!isfinite(x[j])) {
            fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SetContinuousStates: state %s = %g is not finite",
                    GLUE_VARS[GLUE_VR_INDEX[GLUE_STATE_VR[j]]].name, x[j]);
            return fmi2Error;
        }
        if (!model_check_state(c, "fmi2SetContinuousStates", GLUE_STATE_VR[j], x[j])) return fmi2Error;
    }
    memcpy(c->m.y, x, nx * sizeof(double));
    c->m.out_valid = 0;
    return fmi2OK;
}

fmi2Status fmi2GetDerivatives(fmi2Component comp, fmi2Real derivatives[], size_t nx) {
    instance_t *c = FMU_ENTER(comp, fmi2GetDerivatives);
    if (!c) return fmi2Error;
    if (!array_ok(c, "fmi2GetDerivatives", derivatives, nx, GLUE_NX)) return fmi2Error;
    if (!fmu_finite_result(c, "fmi2GetDerivatives", NULL, 0)) return fmi2Error;
    model_derivatives(c);
    if (!fmu_finite_result(c, "fmi2GetDerivatives", c->m.dydt, nx)) return fmi2Error;
    memcpy(derivatives, c->m.dydt, nx * sizeof(double));
    return fmi2OK;
}

fmi2Status fmi2GetEventIndicators(fmi2Component comp, fmi2Real z[], size_t nz) {
    instance_t *c = FMU_ENTER(comp, fmi2GetEventIndicators);
    if (!c) return fmi2Error;
    if (!array_ok(c, "fmi2GetEventIndicators", z, nz, GLUE_NZ)) return fmi2Error;
    if (!fmu_finite_result(c, "fmi2GetEventIndicators", NULL, 0)) return fmi2Error;
    model_indicators(c, z);
    return fmu_finite_result(c, "fmi2GetEventIndicators", z, nz) ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetContinuousStates(fmi2Component comp, fmi2Real x[], size_t nx) {
    instance_t *c = FMU_ENTER(comp, fmi2GetContinuousStates);
    if (!c) return fmi2Error;
    if (!array_ok(c, "fmi2GetContinuousStates", x, nx, GLUE_NX)) return fmi2Error;
    if (!fmu_finite_result(c, "fmi2GetContinuousStates", c->m.y, nx)) return fmi2Error;
    memcpy(x, c->m.y, nx * sizeof(double));
    return fmi2OK;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component comp, fmi2Real x_nominal[], size_t nx) {
    instance_t *c = FMU_ENTER(comp, fmi2GetNominalsOfContinuousStates);
    size_t j;
    if (!c) return fmi2Error;
    if (!array_ok(c, "fmi2GetNominalsOfContinuousStates", x_nominal, nx, GLUE_NX)) return fmi2Error;
    for (j = 0; j < nx; j++) x_nominal[j] = GLUE_STATE_NOMINAL(j);
    return fmi2OK;
}

/* ---------------------------------------------------------------- co-simulation */

fmi2Status fmi2DoStep(fmi2Component comp, fmi2Real t, fmi2Real h, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    instance_t *c = FMU_ENTER(comp, fmi2DoStep);
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!c) return fmi2Error;
    return model_do_step(c, t, h);
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
    return model_output_derivatives(FMU_ENTER(comp, fmi2GetRealOutputDerivatives), "fmi2GetRealOutputDerivatives",
                                    vr, nvr, order, value);
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
