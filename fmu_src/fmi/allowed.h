/* The one table of the call sequence, FMI 2.0 and FMI 3.0: for every function that takes an
 * instance, the interface(s) it belongs to and the states it may be called in (after the
 * Reference FMUs' MASK_fmi2... / MASK_fmi3... defines). FMI 3.0 (fmi3.c) maps its states onto
 * these: StepMode = ST_STEP_COMPLETE, StepDiscarded = ST_STEP_FAILED, plus ST_CONFIG
 * (Configuration Mode); a co-simulation instance also has Event Mode. Every entry point
 * (fmi2.c, fmi3.c) starts with FMU_ENTER(comp, fmiXxx), which checks both against this table;
 * an illegal call logs "<function>: illegal call in state <state>", moves the instance to the
 * Error state and returns NULL (the call answers an error). */
#ifndef ALLOWED_H
#define ALLOWED_H

/* call-sequence states (one bit each) */
enum {
    ST_INSTANTIATED = 1 << 0,
    ST_INIT = 1 << 1,
    ST_EVENT = 1 << 2,
    ST_CONT = 1 << 3,
    ST_STEP_COMPLETE = 1 << 4,
    ST_STEP_FAILED = 1 << 5,
    ST_TERMINATED = 1 << 6,
    ST_ERROR = 1 << 7,
    ST_FATAL = 1 << 8,
    ST_CONFIG = 1 << 9              /* FMI 3.0 only */
};
/* no state check: the function answers every state itself (with fmi2Error, fmi2Discard or a
 * value that is valid in every state) */
#define ST_ANY (~0)
#define ST_AFTER_INIT (ST_EVENT | ST_CONT | ST_STEP_COMPLETE | ST_STEP_FAILED | ST_TERMINATED | ST_ERROR)
#define ST_SETTABLE (ST_INSTANTIATED | ST_INIT | ST_EVENT | ST_CONT | ST_STEP_COMPLETE)
#define ST_ME_OUTPUTS (ST_EVENT | ST_CONT | ST_TERMINATED | ST_ERROR)

/* interfaces: bit (1 << fmi2Type) */
#define FOR_ME 1
#define FOR_CS 2
#define FOR_BOTH (FOR_ME | FOR_CS)

/*       function                              interface  states */
/* life cycle */
#define ALLOW_fmi2FreeInstance                 FOR_BOTH, ST_ANY
#define ALLOW_fmi2SetDebugLogging              FOR_BOTH, ST_ANY
#define ALLOW_fmi2SetupExperiment              FOR_BOTH, ST_INSTANTIATED
#define ALLOW_fmi2EnterInitializationMode      FOR_BOTH, ST_INSTANTIATED
#define ALLOW_fmi2ExitInitializationMode       FOR_BOTH, ST_INIT
#define ALLOW_fmi2Terminate                    FOR_BOTH, (ST_EVENT | ST_CONT | ST_STEP_COMPLETE | ST_STEP_FAILED)
#define ALLOW_fmi2Reset                        FOR_BOTH, (~ST_FATAL)
/* values */
#define ALLOW_fmi2GetReal                      FOR_BOTH, (ST_INIT | ST_AFTER_INIT)
#define ALLOW_fmi2GetInteger                   FOR_BOTH, (ST_INIT | ST_AFTER_INIT)
#define ALLOW_fmi2GetBoolean                   FOR_BOTH, (ST_INIT | ST_AFTER_INIT)
#define ALLOW_fmi2GetString                    FOR_BOTH, ST_ANY
#define ALLOW_fmi2SetReal                      FOR_BOTH, ST_SETTABLE
#define ALLOW_fmi2SetInteger                   FOR_BOTH, ST_SETTABLE
#define ALLOW_fmi2SetBoolean                   FOR_BOTH, ST_SETTABLE
#define ALLOW_fmi2SetString                    FOR_BOTH, ST_ANY
/* FMU state */
#define ALLOW_fmi2GetFMUstate                  FOR_BOTH, (~(ST_FATAL | ST_ERROR))
#define ALLOW_fmi2SetFMUstate                  FOR_BOTH, (~ST_FATAL)
#define ALLOW_fmi2FreeFMUstate                 FOR_BOTH, ST_ANY
#define ALLOW_fmi2SerializedFMUstateSize       FOR_BOTH, ST_ANY
#define ALLOW_fmi2SerializeFMUstate            FOR_BOTH, ST_ANY
#define ALLOW_fmi2DeSerializeFMUstate          FOR_BOTH, ST_ANY
#define ALLOW_fmi2GetDirectionalDerivative     FOR_BOTH, ST_ANY
/* model exchange */
#define ALLOW_fmi2EnterEventMode               FOR_ME, (ST_EVENT | ST_CONT)
#define ALLOW_fmi2NewDiscreteStates            FOR_ME, ST_EVENT
#define ALLOW_fmi2EnterContinuousTimeMode      FOR_ME, ST_EVENT
#define ALLOW_fmi2CompletedIntegratorStep      FOR_ME, ST_CONT
#define ALLOW_fmi2SetTime                      FOR_ME, (ST_EVENT | ST_CONT)
#define ALLOW_fmi2SetContinuousStates          FOR_ME, ST_CONT
#define ALLOW_fmi2GetDerivatives               FOR_ME, ST_ME_OUTPUTS
#define ALLOW_fmi2GetEventIndicators           FOR_ME, ST_ME_OUTPUTS
#define ALLOW_fmi2GetContinuousStates          FOR_ME, ST_ME_OUTPUTS
#define ALLOW_fmi2GetNominalsOfContinuousStates FOR_ME, (ST_INSTANTIATED | ST_ME_OUTPUTS)
/* co-simulation (the functions that always answer fmi2Error or fmi2Discard take every state) */
#define ALLOW_fmi2DoStep                       FOR_CS, ST_STEP_COMPLETE
#define ALLOW_fmi2CancelStep                   FOR_BOTH, ST_ANY
#define ALLOW_fmi2SetRealInputDerivatives      FOR_BOTH, ST_ANY
#define ALLOW_fmi2GetRealOutputDerivatives     FOR_CS, (ST_STEP_COMPLETE | ST_STEP_FAILED | ST_TERMINATED)
#define ALLOW_fmi2GetStatus                    FOR_BOTH, ST_ANY
#define ALLOW_fmi2GetRealStatus                FOR_BOTH, ST_ANY
#define ALLOW_fmi2GetIntegerStatus             FOR_BOTH, ST_ANY
#define ALLOW_fmi2GetBooleanStatus             FOR_BOTH, ST_ANY
#define ALLOW_fmi2GetStringStatus              FOR_BOTH, ST_ANY

/* FMI 3.0 (fmi3.c) */
#define ST_GETTABLE3 (ST_INSTANTIATED | ST_CONFIG | ST_INIT | ST_AFTER_INIT)
/* life cycle */
#define ALLOW_fmi3FreeInstance                 FOR_BOTH, ST_ANY
#define ALLOW_fmi3SetDebugLogging              FOR_BOTH, ST_ANY
#define ALLOW_fmi3EnterConfigurationMode       FOR_BOTH, ST_INSTANTIATED
#define ALLOW_fmi3ExitConfigurationMode        FOR_BOTH, ST_CONFIG
#define ALLOW_fmi3EnterInitializationMode      FOR_BOTH, ST_INSTANTIATED
#define ALLOW_fmi3ExitInitializationMode       FOR_BOTH, ST_INIT
/* (Event Mode: refused by the function itself, the state kept) */
#define ALLOW_fmi3EnterEventMode               FOR_BOTH, (ST_CONT | ST_STEP_COMPLETE | ST_EVENT)
#define ALLOW_fmi3UpdateDiscreteStates         FOR_BOTH, ST_EVENT
#define ALLOW_fmi3Terminate                    FOR_BOTH, (ST_EVENT | ST_CONT | ST_STEP_COMPLETE | ST_STEP_FAILED)
#define ALLOW_fmi3Reset                        FOR_BOTH, (~ST_FATAL)
/* values */
#define ALLOW_fmi3GetFloat64                   FOR_BOTH, ST_GETTABLE3
#define ALLOW_fmi3GetInt32                     FOR_BOTH, ST_GETTABLE3
#define ALLOW_fmi3GetBoolean                   FOR_BOTH, ST_GETTABLE3
#define ALLOW_fmi3SetFloat64                   FOR_BOTH, (ST_SETTABLE | ST_CONFIG)
#define ALLOW_fmi3SetInt32                     FOR_BOTH, (ST_SETTABLE | ST_CONFIG)
#define ALLOW_fmi3SetBoolean                   FOR_BOTH, (ST_SETTABLE | ST_CONFIG)
#define ALLOW_fmi3OtherType                    FOR_BOTH, ST_ANY   /* types this FMU has none of */
#define ALLOW_fmi3GetNumberOfContinuousStates  FOR_BOTH, ST_ANY
#define ALLOW_fmi3GetNumberOfEventIndicators   FOR_BOTH, ST_ANY
/* FMU state */
#define ALLOW_fmi3GetFMUState                  FOR_BOTH, (~(ST_FATAL | ST_ERROR | ST_CONFIG))
#define ALLOW_fmi3SetFMUState                  FOR_BOTH, (~(ST_FATAL | ST_CONFIG))
#define ALLOW_fmi3FreeFMUState                 FOR_BOTH, ST_ANY
#define ALLOW_fmi3SerializedFMUStateSize       FOR_BOTH, ST_ANY
#define ALLOW_fmi3SerializeFMUState            FOR_BOTH, ST_ANY
#define ALLOW_fmi3DeserializeFMUState          FOR_BOTH, ST_ANY
#define ALLOW_fmi3NotProvided                  FOR_BOTH, ST_ANY   /* derivatives, dependencies */
#define ALLOW_fmi3Clocks                       FOR_BOTH, ST_ANY   /* the clock functions (the model checks the state) */
/* model exchange */
#define ALLOW_fmi3EnterContinuousTimeMode      FOR_ME, ST_EVENT
#define ALLOW_fmi3CompletedIntegratorStep      FOR_ME, ST_CONT
#define ALLOW_fmi3SetTime                      FOR_ME, (ST_EVENT | ST_CONT)
#define ALLOW_fmi3SetContinuousStates          FOR_ME, ST_CONT
#define ALLOW_fmi3GetContinuousStateDerivatives FOR_ME, ST_ME_OUTPUTS
#define ALLOW_fmi3GetEventIndicators           FOR_ME, ST_ME_OUTPUTS
#define ALLOW_fmi3GetContinuousStates          FOR_ME, ST_ME_OUTPUTS
#define ALLOW_fmi3GetNominalsOfContinuousStates FOR_ME, (ST_INSTANTIATED | ST_ME_OUTPUTS)
/* co-simulation */
#define ALLOW_fmi3EnterStepMode                FOR_CS, ST_EVENT
/* (Event Mode: refused by the function itself, the state kept) */
#define ALLOW_fmi3DoStep                       FOR_CS, (ST_STEP_COMPLETE | ST_EVENT)
#define ALLOW_fmi3GetOutputDerivatives         FOR_CS, (ST_STEP_COMPLETE | ST_STEP_FAILED | ST_TERMINATED)

/* which variables fmi2Set{Real,Integer,Boolean} may set in which states (FMI 2.0, Table 3) */
#define SET_INPUT ST_SETTABLE
#define SET_FIXED (ST_INSTANTIATED | ST_INIT)                          /* fixed parameters */
#define SET_TUNABLE (ST_INSTANTIATED | ST_INIT | ST_EVENT | ST_STEP_COMPLETE)
#define SET_EXACT_STATE (ST_INSTANTIATED | ST_INIT)                    /* states with initial="exact" */

/* the name of the (single-bit) state fsm in FMI 2.0's words, for "<function>: illegal call in
 * state <state>" */
static inline const char *fsm_name(int fsm) {
    static const char *const NAMES[] = {"Instantiated", "InitializationMode", "EventMode",
                                        "ContinuousTimeMode", "StepComplete", "StepFailed",
                                        "Terminated", "Error", "Fatal", "ConfigurationMode"};
    int k = 0;
    while (k < 9 && !(fsm & (1 << k))) k++;
    return NAMES[k];
}

/* the same in FMI 3.0's words: Step Mode and Step Discarded for the co-simulation states */
static inline const char *fsm_name3(int fsm) {
    return fsm == ST_STEP_COMPLETE ? "StepMode" : fsm == ST_STEP_FAILED ? "StepDiscarded" : fsm_name(fsm);
}

/* the instance behind comp when function F may be called on it now, else NULL (logged) */
#define FMU_ENTER(comp, F) fmu_enter((comp), #F, ALLOW_##F)

#endif
