/* FMI 2.0 entry points the controller FMU does not offer (a co-simulation FMU without FMU
 * states, directional derivatives, input derivatives or model exchange): each checks the call
 * like every entry point (the instance, the state machine of allowed.h) and refuses it
 * with a logged message, so an importer learns why instead of meeting a missing symbol. */
#include <stddef.h>

#include "fmi2Functions.h"
#include "allowed.h"

/* the state check of allowed.h and the refusal's message (ctrl_fmi2.c) */
fmi2Status ctrl_refuse(fmi2Component comp, const char *fn, int iface, int mask);
#define REFUSE(F) ctrl_refuse(comp, #F, ALLOW_##F)

fmi2Status fmi2SetRealInputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    return REFUSE(fmi2SetRealInputDerivatives);
}
fmi2Status fmi2GetRealOutputDerivatives(fmi2Component comp, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    (void)vr; (void)nvr; (void)order; (void)value;
    return REFUSE(fmi2GetRealOutputDerivatives);
}
fmi2Status fmi2GetStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Status *value) {
    (void)s; (void)value;
    return REFUSE(fmi2GetStatus);
}
fmi2Status fmi2GetIntegerStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Integer *value) {
    (void)s; (void)value;
    return REFUSE(fmi2GetIntegerStatus);
}
fmi2Status fmi2GetBooleanStatus(fmi2Component comp, const fmi2StatusKind s, fmi2Boolean *value) {
    (void)s; (void)value;
    return REFUSE(fmi2GetBooleanStatus);
}
fmi2Status fmi2GetStringStatus(fmi2Component comp, const fmi2StatusKind s, fmi2String *value) {
    (void)s; (void)value;
    return REFUSE(fmi2GetStringStatus);
}

/* FMU states and directional derivatives: not offered (canGetAndSetFMUstate is false) */
fmi2Status fmi2GetFMUstate(fmi2Component comp, fmi2FMUstate *st) { (void)st; return REFUSE(fmi2GetFMUstate); }
fmi2Status fmi2SetFMUstate(fmi2Component comp, fmi2FMUstate st) { (void)st; return REFUSE(fmi2SetFMUstate); }
fmi2Status fmi2FreeFMUstate(fmi2Component comp, fmi2FMUstate *st) { (void)st; return REFUSE(fmi2FreeFMUstate); }
fmi2Status fmi2SerializedFMUstateSize(fmi2Component comp, fmi2FMUstate st, size_t *size) {
    (void)st; (void)size;
    return REFUSE(fmi2SerializedFMUstateSize);
}
fmi2Status fmi2SerializeFMUstate(fmi2Component comp, fmi2FMUstate st, fmi2Byte b[], size_t size) {
    (void)st; (void)b; (void)size;
    return REFUSE(fmi2SerializeFMUstate);
}
fmi2Status fmi2DeSerializeFMUstate(fmi2Component comp, const fmi2Byte b[], size_t size, fmi2FMUstate *st) {
    (void)b; (void)size; (void)st;
    return REFUSE(fmi2DeSerializeFMUstate);
}
fmi2Status fmi2GetDirectionalDerivative(fmi2Component comp, const fmi2ValueReference u[], size_t nu,
                                        const fmi2ValueReference z[], size_t nz, const fmi2Real dv[], fmi2Real dz[]) {
    (void)u; (void)nu; (void)z; (void)nz; (void)dv; (void)dz;
    return REFUSE(fmi2GetDirectionalDerivative);
}

/* model exchange: not offered */
fmi2Status fmi2EnterEventMode(fmi2Component comp) { return REFUSE(fmi2EnterEventMode); }
fmi2Status fmi2NewDiscreteStates(fmi2Component comp, fmi2EventInfo *e) { (void)e; return REFUSE(fmi2NewDiscreteStates); }
fmi2Status fmi2EnterContinuousTimeMode(fmi2Component comp) { return REFUSE(fmi2EnterContinuousTimeMode); }
fmi2Status fmi2CompletedIntegratorStep(fmi2Component comp, fmi2Boolean n, fmi2Boolean *e, fmi2Boolean *t) {
    (void)n; (void)e; (void)t;
    return REFUSE(fmi2CompletedIntegratorStep);
}
fmi2Status fmi2SetTime(fmi2Component comp, fmi2Real t) { (void)t; return REFUSE(fmi2SetTime); }
fmi2Status fmi2SetContinuousStates(fmi2Component comp, const fmi2Real x[], size_t n) {
    (void)x; (void)n;
    return REFUSE(fmi2SetContinuousStates);
}
fmi2Status fmi2GetDerivatives(fmi2Component comp, fmi2Real d[], size_t n) { (void)d; (void)n; return REFUSE(fmi2GetDerivatives); }
fmi2Status fmi2GetEventIndicators(fmi2Component comp, fmi2Real z[], size_t n) {
    (void)z; (void)n;
    return REFUSE(fmi2GetEventIndicators);
}
fmi2Status fmi2GetContinuousStates(fmi2Component comp, fmi2Real x[], size_t n) {
    (void)x; (void)n;
    return REFUSE(fmi2GetContinuousStates);
}
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component comp, fmi2Real x[], size_t n) {
    (void)x; (void)n;
    return REFUSE(fmi2GetNominalsOfContinuousStates);
}
