/* A minimal FMI 2.0 host for the C test drivers: the FMU's entry points as a table of
 * function pointers (dlopen-ed from the built .so, or, with -DFMI_STATIC, the FMU's sources
 * linked into the test binary, e.g. for sanitizer builds), callbacks that capture what the
 * FMU logs, and a counting allocator. Thread-safe: no mutable global state except atomic
 * counters. */
#ifndef FMI_HOST_H
#define FMI_HOST_H

#include <stddef.h>
#include <stdint.h>

#include "fmi2Functions.h"

typedef struct {
    void *dl;   /* dlopen handle, NULL when linked statically */
    fmi2GetTypesPlatformTYPE *GetTypesPlatform;
    fmi2GetVersionTYPE *GetVersion;
    fmi2SetDebugLoggingTYPE *SetDebugLogging;
    fmi2InstantiateTYPE *Instantiate;
    fmi2FreeInstanceTYPE *FreeInstance;
    fmi2SetupExperimentTYPE *SetupExperiment;
    fmi2EnterInitializationModeTYPE *EnterInitializationMode;
    fmi2ExitInitializationModeTYPE *ExitInitializationMode;
    fmi2TerminateTYPE *Terminate;
    fmi2ResetTYPE *Reset;
    fmi2GetRealTYPE *GetReal;
    fmi2GetIntegerTYPE *GetInteger;
    fmi2GetBooleanTYPE *GetBoolean;
    fmi2GetStringTYPE *GetString;
    fmi2SetRealTYPE *SetReal;
    fmi2SetIntegerTYPE *SetInteger;
    fmi2SetBooleanTYPE *SetBoolean;
    fmi2SetStringTYPE *SetString;
    fmi2GetFMUstateTYPE *GetFMUstate;
    fmi2SetFMUstateTYPE *SetFMUstate;
    fmi2FreeFMUstateTYPE *FreeFMUstate;
    fmi2SerializedFMUstateSizeTYPE *SerializedFMUstateSize;
    fmi2SerializeFMUstateTYPE *SerializeFMUstate;
    fmi2DeSerializeFMUstateTYPE *DeSerializeFMUstate;
    fmi2GetDirectionalDerivativeTYPE *GetDirectionalDerivative;
    /* model exchange */
    fmi2EnterEventModeTYPE *EnterEventMode;
    fmi2NewDiscreteStatesTYPE *NewDiscreteStates;
    fmi2EnterContinuousTimeModeTYPE *EnterContinuousTimeMode;
    fmi2CompletedIntegratorStepTYPE *CompletedIntegratorStep;
    fmi2SetTimeTYPE *SetTime;
    fmi2SetContinuousStatesTYPE *SetContinuousStates;
    fmi2GetDerivativesTYPE *GetDerivatives;
    fmi2GetEventIndicatorsTYPE *GetEventIndicators;
    fmi2GetContinuousStatesTYPE *GetContinuousStates;
    fmi2GetNominalsOfContinuousStatesTYPE *GetNominalsOfContinuousStates;
    /* co-simulation */
    fmi2SetRealInputDerivativesTYPE *SetRealInputDerivatives;
    fmi2GetRealOutputDerivativesTYPE *GetRealOutputDerivatives;
    fmi2DoStepTYPE *DoStep;
    fmi2CancelStepTYPE *CancelStep;
    fmi2GetStatusTYPE *GetStatus;
    fmi2GetRealStatusTYPE *GetRealStatus;
    fmi2GetIntegerStatusTYPE *GetIntegerStatus;
    fmi2GetBooleanStatusTYPE *GetBooleanStatus;
    fmi2GetStringStatusTYPE *GetStringStatus;
} fmi_api_t;

/* Fill api from the shared library at so_path (NULL: the statically linked FMU, which needs
 * -DFMI_STATIC). Returns 0, or -1 with a reason in err. */
int fmi_api_load(fmi_api_t *api, const char *so_path, char *err, size_t errlen);
void fmi_api_unload(fmi_api_t *api);

/* What the FMU logged through one set of callbacks (one per instance / thread). */
typedef struct {
    long n_msgs;                /* messages received */
    int worst;                  /* highest status seen in a message since the last host_env_mark */
    long n_since_mark;
    int echo;                   /* print every message to stderr */
    char last[1024];            /* text of the last message */
} host_env_t;

void host_env_mark(host_env_t *env);    /* start of one call: clear worst/n_since_mark */
fmi2CallbackFunctions host_callbacks(host_env_t *env);

/* counting allocator used by host_callbacks (atomic, across threads) */
long host_live_allocations(void);
long host_total_allocations(void);
long host_peak_bytes(void);   /* most bytes held through the callbacks at once */

/* seconds from a monotonic clock */
double host_now(void);

/* CRC-32 (IEEE 802.3, reflected) of n bytes: the checksum the FMU's state format keeps over
   its payload, recomputed by the hosts that forge states to reach the checks behind it */
static inline uint32_t host_crc32(const unsigned char *b, size_t n) {
    uint32_t crc = 0xFFFFFFFFu;
    size_t i;
    int k;
    for (i = 0; i < n; i++) {
        crc ^= b[i];
        for (k = 0; k < 8; k++) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

#endif
