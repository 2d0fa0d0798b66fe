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

/* FMI 2.0's view of the continuous states: all of the model's */
static const me_view_t ALL_STATES = {GLUE_NX, NULL, NULL, 0};

fmi2Status fmi2EnterEventMode(fmi2Component comp) {
    return fmu_set_mode(FMU_ENTER(comp, fmi2EnterEventMode), ST_EVENT);
}

fmi2Status fmi2NewDiscreteStates(fmi2Component comp, fmi2EventInfo *info) {
    instance_t *c = FMU_ENTER(comp, fmi2NewDiscreteStates);
    int changed, next_defined;
    if (!c) return fmi2Error;
    if (!info) { fmu_log(c, fmi2Error, LOG_ERROR, "fmi2NewDiscreteStates: eventInfo is NULL"); return fmi2Error; }
    if (fmu_me_event_update(c, "fmi2NewDiscreteStates", &changed, &next_defined, &info->nextEventTime) != fmi2OK)
        return fmi2Error;
    info->newDiscreteStatesNeeded = fmi2False;
    info->terminateSimulation = fmi2False;
    info->nominalsOfContinuousStatesChanged = fmi2False;
    info->valuesOfContinuousStatesChanged = changed ? fmi2True : fmi2False;
    info->nextEventTimeDefined = next_defined ? fmi2True : fmi2False;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component comp) {
    return fmu_set_mode(FMU_ENTER(comp, fmi2EnterContinuousTimeMode), ST_CONT);
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component comp, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation) {
    (void)noSetFMUStatePriorToCurrentPoint;
    if (fmu_me_completed_step(FMU_ENTER(comp, fmi2CompletedIntegratorStep), "fmi2CompletedIntegratorStep",
                              enterEventMode && terminateSimulation) != fmi2OK)
        return fmi2Error;
    *enterEventMode = *terminateSimulation = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component comp, fmi2Real time) {
    return fmu_me_set_time(FMU_ENTER(comp, fmi2SetTime), "fmi2SetTime", time);
}
fmi2Status fmi2SetContinuousStates(fmi2Component comp, const fmi2Real x[], size_t nx) {
    return fmu_me_set_states(FMU_ENTER(comp, fmi2SetContinuousStates), "fmi2SetContinuousStates", &ALL_STATES, x,
                             nx);
}
fmi2Status fmi2GetDerivatives(fmi2Component comp, fmi2Real derivatives[], size_t nx) {
    return fmu_me_get_derivatives(FMU_ENTER(comp, fmi2GetDerivatives), "fmi2GetDerivatives", &ALL_STATES,
                                  derivatives, nx);
}
fmi2Status fmi2GetEventIndicators(fmi2Component comp, fmi2Real z[], size_t nz) {
    return fmu_me_get_indicators(FMU_ENTER(comp, fmi2GetEventIndicators), "fmi2GetEventIndicators", &ALL_STATES, z,
                                 nz);
}
fmi2Status fmi2GetContinuousStates(fmi2Component comp, fmi2Real x[], size_t nx) {
    return fmu_me_get_states(FMU_ENTER(comp, fmi2GetContinuousStates), "fmi2GetContinuousStates", &ALL_STATES, x,
                             nx);
}
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component comp, fmi2Real x_nominal[], size_t nx) {
    return fmu_me_get_nominals(FMU_ENTER(comp, fmi2GetNominalsOfContinuousStates),
                               "fmi2GetNominalsOfContinuousStates", &ALL_STATES, x_nominal, nx);
}

/* ---------------------------------------------------------------- co-simulation */

fmi2Status fmi2DoStep(fmi2Component comp, fmi2Real t, fmi2Real h, fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    instance_t *c = FMU_ENTER(comp, fmi2DoStep);
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!c) return fmi2Error;
    return model_do_step(c, "fmi2DoStep", t, h);
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
