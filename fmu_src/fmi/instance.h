/* The FMI glue's instance, version-neutral: the model's data (model_t of the model's
 * model_data.h, see model.h), the importer's callbacks, logging, the FMI 3.0 modes of an
 * FMI 3.0 instance and the FMU states it holds; the one entry check (allowed.h) and logging. */
#ifndef INSTANCE_H
#define INSTANCE_H

#include <stddef.h>
#include <stdint.h>

#include "fmi2Functions.h"
#include "allowed.h"
#include "log.h"
#include "model_data.h"

typedef struct {
    model_t m;
    fmi2CallbackFunctions cb;
    char *name;
    fmi2Type type;
    int logging_on;
    unsigned log_mask;              /* LOG_* bits (log.h) */
    /* an FMI 3.0 instance (fmi3.c; 0 for FMI 2.0): its data, and the hook that the model's event
     * update calls after a discrete change inside a step (NULL: none) */
    int fmi3;
    int event_mode_used;            /* an FMI 3.0 co-simulation instance made with eventModeUsed */
    void *ext;
    void (*on_switch)(void *instance);
    /* the FMU states this instance's Get/DeserializeFMUState allocated and no FreeFMUState has
     * freed yet (snapshot.c): FreeInstance frees them ("frees all the allocated memory") */
    void *states;
    /* every variable's start value: the compiled-in ones and those of the model's resources;
     * Reset goes back to them */
    double start_val[GLUE_NVR];
} instance_t;

/* enter.c: logging, the entry check, the one refusal */
void fmu_log(instance_t *c, fmi2Status st, unsigned cat, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(FMU_PRINTF_FORMAT, 4, 5)))
#endif
    ;
/* entry of every FMI call (through FMU_ENTER): the instance when comp is one, the call belongs to
 * its interface (a FOR_* set) and its state is one of `mask`, else NULL (with a logged message) */
instance_t *fmu_enter(fmi2Component comp, const char *fn, int iface, int mask);
/* the one refusal of a call the model does not offer or does not take now (c admitted by
 * FMU_ENTER, NULL: refused): why == NULL: OK (a call with nothing to do), else logs
 * "<fn>: <why>" and answers Error (the instance's state unchanged) */
fmi2Status fmu_refuse(instance_t *c, const char *fn, const char *why);
/* 16 units in the last place of t: the rounding of a time an importer computed */
double fmu_ulp_slack(double t);
/* a result array about to be returned: the model is initialized and every x[j] is finite (logs if not) */
int fmu_finite_result(instance_t *c, const char *fn, const double *x, size_t n);

/* the most values an array can hold (double, the widest element): a larger count is no array */
#define FMU_MAX_VALUES ((size_t)PTRDIFF_MAX / sizeof(double))

/* lifecycle.c: the life cycle of every version (fn names the calling function in messages) */
instance_t *fmu_instantiate(const char *fn, const char *name, fmi2Type type, const char *token,
                            const fmi2CallbackFunctions *functions, int logging_on);
void fmu_free_instance(instance_t *c);
fmi2Status fmu_set_debug_logging(instance_t *c, const char *fn, int logging_on, size_t n,
                                 const fmi2String categories[]);
fmi2Status fmu_setup_experiment(instance_t *c, const char *fn, int tol_defined, double tol, double start,
                                int stop_defined, double stop);
fmi2Status fmu_enter_initialization(instance_t *c);
/* Initialization Mode left into state `next` (the model initialised first) */
fmi2Status fmu_exit_initialization(instance_t *c, const char *fn, int next);
/* the instance in call-sequence state fsm (a mode entered) */
fmi2Status fmu_set_mode(instance_t *c, int fsm);
fmi2Status fmu_terminate(instance_t *c);
fmi2Status fmu_reset(instance_t *c);

/* values.c: get/set by value reference, type 'R', 'I' (int) or 'B' (fmi2Boolean); every value
 * checked before any is stored (a rejected set changes nothing) */
fmi2Status fmu_get_values(instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                          char type, void *value);
fmi2Status fmu_set_values(instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                          char type, const void *value);
/* a get/set of a type the model has no variables of */
fmi2Status fmu_no_strings(instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr);

/* continuous.c: model exchange, every version, over a view of the continuous states: n of
 * them, index(m, j) the model's state j of the view (NULL: j itself), dim_name and dim the
 * arrays' dimension named in size messages (NULL: none) */
typedef struct {
    size_t n;
    int (*index)(const model_t *m, size_t j);
    const char *dim_name;
    int dim;
} me_view_t;
fmi2Status fmu_me_set_time(instance_t *c, const char *fn, double time);
fmi2Status fmu_me_completed_step(instance_t *c, const char *fn, int outputs_given);
fmi2Status fmu_me_set_states(instance_t *c, const char *fn, const me_view_t *v, const double x[], size_t nx);
fmi2Status fmu_me_get_states(instance_t *c, const char *fn, const me_view_t *v, double x[], size_t nx);
fmi2Status fmu_me_get_derivatives(instance_t *c, const char *fn, const me_view_t *v, double dx[], size_t nx);
fmi2Status fmu_me_get_nominals(instance_t *c, const char *fn, const me_view_t *v, double x[], size_t nx);
fmi2Status fmu_me_get_indicators(instance_t *c, const char *fn, const me_view_t *v, double z[], size_t nz);
fmi2Status fmu_me_event_update(instance_t *c, const char *fn, int *changed, int *next_defined, double *next);

/* snapshot.c: FMU state objects, their bytes those of the model's state format (model.h) */
void fmu_states_free_all(instance_t *c);
fmi2Status fmu_state_get(instance_t *c, const char *fn, void **state);
fmi2Status fmu_state_set(instance_t *c, const char *fn, void *state);
fmi2Status fmu_state_free(instance_t *c, const char *fn, void **state);
fmi2Status fmu_state_size(instance_t *c, const char *fn, void *state, size_t *size);
fmi2Status fmu_state_serialize(instance_t *c, const char *fn, void *state, unsigned char *out, size_t size);
fmi2Status fmu_state_deserialize(instance_t *c, const char *fn, const unsigned char *b, size_t size, void **state);

#include "model.h"

#endif
