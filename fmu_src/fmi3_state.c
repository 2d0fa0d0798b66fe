/* FMI 3.0 FMU state: the FMI 2.0 glue's snapshots (fmi2_state.c) in the same versioned,
 * CRC-checked format (fmi2_state_format.h; the instantiation token is the FMI 2.0 GUID, so a
 * state serialised by one version loads into an instance of the other of the same interface).
 * Partial derivatives, variable dependencies and clocks are not provided. */
#include "fmi3_glue.h"

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    return (fmi3Status)fmu_state_get(FMU_ENTER(instance, fmi3GetFMUState), "fmi3GetFMUState", FMUState);
}
fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState) {
    return (fmi3Status)fmu_state_set(FMU_ENTER(instance, fmi3SetFMUState), "fmi3SetFMUState", FMUState);
}
fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    return (fmi3Status)fmu_state_free(FMU_ENTER(instance, fmi3FreeFMUState), "fmi3FreeFMUState", FMUState);
}
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size) {
    return (fmi3Status)fmu_state_size(FMU_ENTER(instance, fmi3SerializedFMUStateSize), "fmi3SerializedFMUStateSize",
                                      FMUState, size);
}
fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[], size_t size) {
    return (fmi3Status)fmu_state_serialize(FMU_ENTER(instance, fmi3SerializeFMUState), "fmi3SerializeFMUState",
                                           FMUState, serializedState, size);
}
fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState) {
    return (fmi3Status)fmu_state_deserialize(FMU_ENTER(instance, fmi3DeserializeFMUState), "fmi3DeserializeFMUState",
                                             serializedState, size, FMUState);
}

static fmi3Status not_provided(fmi3Instance instance, const char *fn, const char *why) {
    instance_t *c = FMU_ENTER(instance, fmi3NotProvided);
    if (!c) return fmi3Error;
    fmu_log(c, fmi2Error, LOG_ERROR, "%s: not provided (%s)", fn, why);
    return fmi3Error;
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed; (void)sensitivity;
    (void)nSensitivity;
    return not_provided(instance, "fmi3GetDirectionalDerivative", "providesDirectionalDerivative is false");
}
fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                    size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed; (void)sensitivity;
    (void)nSensitivity;
    return not_provided(instance, "fmi3GetAdjointDerivative", "providesAdjointDerivatives is false");
}
fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
                                               size_t *nDependencies) {
    (void)valueReference; (void)nDependencies;
    return not_provided(instance, "fmi3GetNumberOfVariableDependencies", "the model description lists none");
}
fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies) {
    (void)dependent; (void)elementIndicesOfDependent; (void)independents; (void)elementIndicesOfIndependents;
    (void)dependencyKinds; (void)nDependencies;
    return not_provided(instance, "fmi3GetVariableDependencies", "the model description lists none");
}

/* clocks: none */
fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3Float64 a[], fmi3IntervalQualifier b[]) {
    (void)vr; (void)n; (void)a; (void)b;
    return not_provided(instance, "fmi3GetIntervalDecimal", "this FMU has no clocks");
}
fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3UInt64 a[], fmi3UInt64 b[], fmi3IntervalQualifier q[]) {
    (void)vr; (void)n; (void)a; (void)b; (void)q;
    return not_provided(instance, "fmi3GetIntervalFraction", "this FMU has no clocks");
}
fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3Float64 a[]) {
    (void)vr; (void)n; (void)a;
    return not_provided(instance, "fmi3GetShiftDecimal", "this FMU has no clocks");
}
fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3UInt64 a[], fmi3UInt64 b[]) {
    (void)vr; (void)n; (void)a; (void)b;
    return not_provided(instance, "fmi3GetShiftFraction", "this FMU has no clocks");
}
fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3Float64 a[]) {
    (void)vr; (void)n; (void)a;
    return not_provided(instance, "fmi3SetIntervalDecimal", "this FMU has no clocks");
}
fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 a[], const fmi3UInt64 b[]) {
    (void)vr; (void)n; (void)a; (void)b;
    return not_provided(instance, "fmi3SetIntervalFraction", "this FMU has no clocks");
}
fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3Float64 a[]) {
    (void)vr; (void)n; (void)a;
    return not_provided(instance, "fmi3SetShiftDecimal", "this FMU has no clocks");
}
fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 a[], const fmi3UInt64 b[]) {
    (void)vr; (void)n; (void)a; (void)b;
    return not_provided(instance, "fmi3SetShiftFraction", "this FMU has no clocks");
}
