/* FMI 3.0 FMU state: the FMI 2.0 glue's snapshots (fmi2_state.c) in the same versioned,
 * CRC-checked format (fmi2_state_format.h; the instantiation token is the FMI 2.0 GUID, so a
 * state serialised by one version loads into an instance of the other of the same interface).
 * fmi3_refuse answers the functions not provided (fmi3_stubs.c). */
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

fmi3Status fmi3_refuse(fmi3Instance instance, const char *fn, const char *why) {
    instance_t *c = FMU_ENTER(instance, fmi3NotProvided);
    if (!c) return fmi3Error;
    if (!why) return fmi3OK;
    fmu_log(c, fmi2Error, LOG_ERROR, "%s: not provided (%s)", fn, why);
    return fmi3Error;
}
