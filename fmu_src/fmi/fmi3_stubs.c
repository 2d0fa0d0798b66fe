/* The FMI 3.0 functions no model of the glue provides (the clock functions are in fmi3.c,
 * answered by the model's clocks or refused), in both FMI 3.0 libraries: each answers through
 * fmi3_refuse (fmi3.c), fmi3Error with a message naming the function (fmi3OK for a get/set of
 * nothing). */
#include "fmi3_log.h"

#define NO_TYPE "this FMU has variables of types Float64, Int32 and Boolean only"

fmi3Status fmi3GetFloat32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Float32 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3GetFloat32", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3SetFloat32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Float32 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3SetFloat32", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3GetInt8(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Int8 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3GetInt8", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3SetInt8(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Int8 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3SetInt8", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3GetUInt8(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3UInt8 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3GetUInt8", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3SetUInt8(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3UInt8 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3SetUInt8", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3GetInt16(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Int16 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3GetInt16", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3SetInt16(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Int16 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3SetInt16", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3GetUInt16(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3UInt16 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3GetUInt16", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3SetUInt16(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3UInt16 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3SetUInt16", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3GetUInt32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3UInt32 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3GetUInt32", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3SetUInt32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3UInt32 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3SetUInt32", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3GetInt64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Int64 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3GetInt64", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3SetInt64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Int64 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3SetInt64", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3GetUInt64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3UInt64 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3GetUInt64", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3SetUInt64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3UInt64 v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3SetUInt64", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3GetString(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3String v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3GetString", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3SetString(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3String v[], size_t nv) {
    (void)vr; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3SetString", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3GetBinary(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, size_t sizes[],
                         fmi3Binary v[], size_t nv) {
    (void)vr; (void)sizes; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3GetBinary", nvr ? NO_TYPE : NULL);
}
fmi3Status fmi3SetBinary(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const size_t sizes[],
                         const fmi3Binary v[], size_t nv) {
    (void)vr; (void)sizes; (void)v; (void)nv;
    return fmi3_refuse(i, "fmi3SetBinary", nvr ? NO_TYPE : NULL);
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed; (void)sensitivity;
    (void)nSensitivity;
    return fmi3_refuse(instance, "fmi3GetDirectionalDerivative", "providesDirectionalDerivative is false");
}
fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                    size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity) {
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed; (void)sensitivity;
    (void)nSensitivity;
    return fmi3_refuse(instance, "fmi3GetAdjointDerivative", "providesAdjointDerivatives is false");
}
fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
                                               size_t *nDependencies) {
    (void)valueReference; (void)nDependencies;
    return fmi3_refuse(instance, "fmi3GetNumberOfVariableDependencies", "the model description lists none");
}
fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies) {
    (void)dependent; (void)elementIndicesOfDependent; (void)independents; (void)elementIndicesOfIndependents;
    (void)dependencyKinds; (void)nDependencies;
    return fmi3_refuse(instance, "fmi3GetVariableDependencies", "the model description lists none");
}
fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
    return fmi3_refuse(instance, "fmi3EvaluateDiscreteStates", "providesEvaluateDiscreteStates is false");
}
fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime) {
    (void)clockReference; (void)activationTime;
    return fmi3_refuse(instance, "fmi3ActivateModelPartition", "no scheduled execution");
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                               fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage,
                                               fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption) {
    (void)instanceName; (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn;
    (void)clockUpdate; (void)lockPreemption; (void)unlockPreemption;
    if (logMessage)
        logMessage(instanceEnvironment, fmi3Error, "logStatusError",
                   "fmi3InstantiateScheduledExecution: this FMU has no scheduled execution");
    return NULL;
}
