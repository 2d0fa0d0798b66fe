/* The model interface of the FMI glue (after the Reference FMUs' model.h): what each model
 * provides, at link time, to the version-neutral core (enter.c, lifecycle.c, values.c,
 * snapshot.c, state_format.c, fmi3_view.c) and to the entry points of fmi2.c and fmi3.c. The
 * model's folder (on the include path) holds model_data.h with:
 *   model_t       its data, plain (a saved state is its bytes); the fields the glue uses:
 *                 magic, fsm, time, t0, tau, stop_time, stop_defined, tol, tol_defined, val[],
 *                 params_ok (its parameters compiled), out_valid (0: outputs stale),
 *                 y[] (continuous states), dydt[] (their derivatives)
 *   MODEL_CAPS    what it offers (MODEL_CAN_*), which must agree with its modelDescription.xml:
 *                 an entry point it does not offer answers through fmu_refuse
 *   MODEL_MAGIC, MODEL_TOKEN (GUID / instantiation token), MODEL_ND (discrete-state numbers of
 *                 a saved state), MODEL_STRUCTURAL_VR (the FMI 3.0 arrays' dimension), TOL_MAX
 *                 (the loosest tolerance it integrates with)
 *   its value table under the glue's names: glue_var_t, GLUE_VARS, GLUE_NVARS, GLUE_NVR,
 *                 GLUE_VR_INDEX, GLUE_NX, GLUE_NZ, GLUE_STATE_VR, GLUE_STATE_NOMINAL(j)
 * and, for FMI 3.0, its generated model_vars3.h (gen_fmi3.py). */
#ifndef MODEL_H
#define MODEL_H

#include "fmi3FunctionTypes.h"

#define MODEL_CAN_ME 1              /* model exchange */
#define MODEL_CAN_CS 2              /* co-simulation */
#define MODEL_CAN_STATE 4           /* Get/Set/Serialize FMU state */
#define MODEL_CAN_CONFIG 8          /* structural parameters (FMI 3.0 Configuration Mode) */
#define MODEL_CAN_EARLY_RETURN 16   /* FMI 3.0 co-simulation early return */
#define MODEL_CAN_CLOCKS 32         /* FMI 3.0 clocks (the clock functions below) */
#define OFFERS(cap) ((MODEL_CAPS & (cap)) != 0)

/* life cycle */
/* a freshly instantiated model: every variable at its compiled-in start value, Instantiated */
void model_defaults(model_t *m);
/* the start values of the model's resources (FMI 2.0: a file URI, is_uri = 1; FMI 3.0: a path;
 * NULL: none) into c->m.val and c->start_val; 0 (logged) when they are refused */
int model_load_start_values(instance_t *c, const char *location, int is_uri);
/* every variable back at its start value (Reset) */
void model_reset(instance_t *c);
/* compile the parameters and initialise from the current values (logged as fn's error);
 * exiting: Initialization Mode ends */
fmi2Status model_initialize(instance_t *c, const char *fn, int exiting);

/* values */
/* value v of table row `row` acceptable (the model's rules and ranges; logged as fn's if not) */
int model_check_value(instance_t *c, const char *fn, int row, double v);
/* value v of the continuous state of value reference vr acceptable (its declared range) */
int model_check_state(instance_t *c, const char *fn, unsigned vr, double v);
/* parameters changed after initialisation: recompile; on failure log, restore *backup_val, Error */
fmi2Status model_recompile(instance_t *c, const char *fn, const double *backup_val);
/* values stored that were not parameters: what depends on them is stale */
void model_values_changed(instance_t *c);
/* a get of these value references answered without computing the rest (1: done, *st its
 * answer), 0: the glue reads them from val[] after model_update */
int model_get_direct(instance_t *c, const char *fn, const unsigned vr[], size_t nvr, char type, void *value,
                     fmi2Status *st);
/* val[] up to date for a read of vr[0..nvr) (parameters compiled); 0 when it cannot (logged) */
int model_update(instance_t *c, const char *fn, const unsigned vr[], size_t nvr);

/* events and continuous time */
/* process what is due at tau = time - t0 (slack: how far a time may miss an event); the number
 * of discrete changes, -1 (logged as fn's error) when it cannot; *changed: the continuous
 * states or their right-hand side jumped */
int model_event_update(instance_t *c, const char *fn, double tau, double slack, fmi2Boolean *changed);
/* the next time event (0: none) */
int model_next_event(const model_t *m, double *t);
/* an integrator step completed (model exchange) */
void model_completed_step(instance_t *c);
/* the derivatives of the continuous states into m->dydt (model exchange) */
void model_derivatives(instance_t *c);
/* the event indicators z[GLUE_NZ] */
void model_indicators(instance_t *c, double *z);

/* co-simulation */
/* one step from t of length h (arguments checked here, logged as fn's errors) */
fmi2Status model_do_step(instance_t *c, const char *fn, double t, double h);
/* the first derivatives of outputs (FMI 2.0 GetRealOutputDerivatives' rules) */
fmi2Status model_output_derivatives(instance_t *c, const char *fn, const unsigned vr[], size_t nvr,
                                    const int order[], double value[]);
/* FMI 3.0: a step from t of length h may start (0: refused, logged) */
int model_cs_step_ok(instance_t *c, double t, double h);
/* FMI 3.0: the update of a co-simulation instance's Event Mode (fmi3UpdateDiscreteStates) */
fmi2Status model_cs_event_update(instance_t *c, const char *fn);
/* FMI 3.0: Event Mode left for Step Mode (Error, logged, when the model refuses) */
fmi2Status model_enter_step_mode(instance_t *c);
/* FMI 3.0: the model set back to a snapshot of itself inside a step (early return) */
void model_restored(instance_t *c);

/* FMU states (MODEL_CAN_STATE): the model's part of the saved state (state_format.h) */
size_t model_state_bytes(void);
void model_state_encode(const model_t *m, int type, unsigned char *out);
/* bytes checked (every field) into *out; 0, logged as fn's error, when refused */
int model_state_decode(instance_t *c, const char *fn, const unsigned char *b, size_t len, model_t *out);

/* clocks (MODEL_CAN_CLOCKS; FMI 3.0 types): set, get, interval and shift of the model's clocks;
 * model_clock_refusal: why a fraction, a set interval or a set shift is refused */
fmi2Status model_set_clock(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr,
                           const fmi3Clock v[]);
fmi2Status model_get_clock(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr, fmi3Clock v[]);
fmi2Status model_get_interval(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr,
                              fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[]);
fmi2Status model_get_shift(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr,
                           fmi3Float64 shifts[]);
const char *model_clock_refusal(int set_interval, int set_shift);

#endif
