/* FMI glue shared by model exchange and co-simulation: the instance, its call-sequence state
 * machine, logging and the value table. Knows nothing of friction. */
#ifndef FMI2_INSTANCE_H
#define FMI2_INSTANCE_H

#include "fast_path.h"
#include "fmi2Functions.h"
#include "fmi2_allowed.h"
#include "fmi2_log.h"
#include "params.h"
#include "plant.h"
#include "solver_dp45.h"

#define MODEL_MAGIC 0x46445256u   /* "FDRV": marks instances and FMU states */
/* The loosest relative tolerance of the co-simulation integrator (solver.tol's declared max; an
 * experiment tolerance above it is tightened to it): up to 1e-2 the error of the DP45 follows the
 * tolerance (max |dv| / max |v| = 1.1 to 1.2 tol at the stiffest declared settings, m = 1e-3 kg with
 * friction.k = 1e9 N/m); above it the controller accepts steps whose error is of the order of the
 * state (0.05: 4 %, 0.1: 16 %, 0.5: 300 %, 0.99: v = 3.7e298 m/s). */
#define TOL_MAX 1e-2

/* The model: plain data, no pointers (a saved FMU state holds only its state part, see
 * fmi2_state_format.h). */
typedef struct {
    unsigned magic, size;
    int fsm;
    double time, t0, stop_time;
    double tau;                     /* co-simulation: the time since t0 as the integrator holds it (time is
                                       t0 + tau rounded); a step starting at time continues from it */
    int stop_defined, tol_defined;
    double tol;
    double val[MODEL_NVR];          /* every variable by value reference */
    double y[PLANT_NX];             /* continuous states */
    plant_params_t p;
    plant_disc_t d;
    plant_in_t in;
    int params_ok;                  /* p compiled from val */
    int out_valid;                  /* 0, OUT_VALUES or OUT_ALL (fmu_update_values / fmu_update_outputs) */
    plant_out_t out;
    double dydt[PLANT_NX];
    int stroke_warned;
    dp45_t solver;
    int solver_restart;
    plant_memo_t memo;              /* the maps at the last position evaluated (valid = 0 after a compile) */
    fast_carry_t carry;             /* the per-sample scheme's last derivative (valid = 0 after a compile) */
    int fast_ok;                    /* fast_path_ok(&p), renewed with every compile of p */
    int ind_positive;               /* the per-sample scheme's last step found every event indicator > 0
                                       at (d, y), and nothing has changed them since (fmi2_cs.c) */
    double y_lo[PLANT_NX], y_hi[PLANT_NX];   /* the states' declared min/max (modelDescription.xml) */
    unsigned char is_der[MODEL_NVR];         /* 1: the value reference is a derivative's only */
} model_t;
#define OUT_VALUES 1                /* val[] holds the states, outputs and statistics */
#define OUT_ALL 2                   /* ... and the derivatives (m->dydt too) */

typedef struct {
    model_t m;
    fmi2CallbackFunctions cb;
    char *name;
    fmi2Type type;
    int logging_on;
    unsigned log_mask;              /* bit 0 events, 1 warnings, 2 errors */
    /* an FMI 3.0 instance (fmi3_*.c; 0 for FMI 2.0): its glue's data, and the hook that
     * fmu_event_update calls after a friction switch (NULL: none) */
    int fmi3;
    int event_mode_used;            /* an FMI 3.0 co-simulation instance made with eventModeUsed */
    void *ext;
    void (*on_switch)(void *instance);
    /* the FMU states this instance's Get/DeserializeFMUState allocated and no FreeFMUState has
     * freed yet (fmi2_state.c): fmi2FreeInstance frees them ("frees all the allocated memory") */
    void *states;
    /* every variable's start value: the compiled-in ones and those of the resource file
     * (start_values.h); fmi2Reset goes back to them */
    double start_val[MODEL_NVR];
} instance_t;

/* free the FMU states still held by c (fmi2FreeInstance) */
void fmu_states_free_all(instance_t *c);

void fmu_log(instance_t *c, fmi2Status st, unsigned cat, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(FMU_PRINTF_FORMAT, 4, 5)))
#endif
    ;
/* entry of every FMI call (through FMU_ENTER): the instance when comp is one, the call belongs to
 * its interface (a FOR_* set) and its state is one of `mask`, else NULL (with a logged message) */
instance_t *fmu_enter(fmi2Component comp, const char *fn, int iface, int mask);
/* outputs and derivatives up to date */
void fmu_update_outputs(instance_t *c);
/* the same without the derivatives (what a read of no derivative needs) */
void fmu_update_values(instance_t *c);
/* is_der[vr] (MODEL_NVR entries): 1 for the value references of derivatives that are not states */
void fmu_der_vr_table(unsigned char *is_der);
/* Work budget of one call (README "Co-simulation"): fmi2DoStep of length h may take
 *   BUDGET_STEPS_BASE + BUDGET_STEPS_PER_SAMPLE h/Ts + min(BUDGET_STEPS_RATE h, BUDGET_STEPS_EXTRA)
 * integrator step attempts and BUDGET_EVENTS_BASE + min(BUDGET_EVENTS_RATE h, BUDGET_EVENTS_EXTRA)
 * state events; an event update catches up at most BUDGET_OVERDUE_SAMPLES current-loop samples. */
#define BUDGET_STEPS_BASE 10000.0
#define BUDGET_STEPS_PER_SAMPLE 2.0
#define BUDGET_STEPS_RATE 2e5          /* per simulated second */
#define BUDGET_STEPS_EXTRA 2e6
#define BUDGET_EVENTS_BASE 1000.0
#define BUDGET_EVENTS_RATE 2e4         /* per simulated second */
#define BUDGET_EVENTS_EXTRA 1e5
#define BUDGET_OVERDUE_SAMPLES 1000

/* process what is due at tau = time - startTime: a current-loop sample, then the plant's switches;
 * -1 (logged as fn's error) when more than BUDGET_OVERDUE_SAMPLES samples are overdue */
int fmu_event_update(instance_t *c, const char *fn, double tau, double slack, fmi2Boolean *states_changed);
/* startTime + (k + 1) Ts: the next sample, from its index */
double fmu_next_sample(const model_t *m);
/* how close the master's time must be to the FMU's at t: 1e-9 max(1, |t - t0|) (at most Ts/64),
 * and at least fmu_ulp_slack(t) */
double fmu_time_eps(const model_t *m, double t);
/* 16 units in the last place of t: the rounding of a time an importer computed */
double fmu_ulp_slack(double t);
/* the sample k + 1 is due at tau = time - startTime: tau >= (k + 1) Ts - eps, eps =
 * 1e-9 max(1, |tau|) (at most Ts/64) or slack if larger (fmu_ulp_slack(time) when tau comes
 * from an importer's time, 0 when it is the co-simulation's own exact tau) */
int fmu_sample_due(const model_t *m, double tau, double slack);
void fmu_check_stroke(instance_t *c);
/* a result array about to be returned: the model is initialized and every x[j] is finite (logs if not) */
int fmu_finite_result(instance_t *c, const char *fn, const double *x, size_t n);
/* a freshly instantiated model: every variable at its start value, state Instantiated */
void fmu_model_defaults(model_t *m);
/* the solver configured from m->tol, the XML nominals and m->p.Ts (statistics reset) */
void fmu_solver_setup(model_t *m);
/* compile parameters and initialise the plant from the current values (logs on error) */
fmi2Status fmu_initialize_plant(instance_t *c);
/* recompile parameters after a change; on failure logs, restores *backup and returns fmi2Error */
fmi2Status fmu_recompile(instance_t *c, const double *backup_val);

/* Shared by the FMI 2.0 and FMI 3.0 entry points (c: the instance admitted by FMU_ENTER, NULL:
 * refused; fn names the calling function in messages). */
/* get/set by (FMI 2.0) value reference, type 'R', 'I' (int) or 'B' (fmi2Boolean) (fmi2_values.c) */
fmi2Status fmu_get_values(instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                          char type, void *value);
fmi2Status fmu_set_values(instance_t *c, const char *fn, const fmi2ValueReference vr[], size_t nvr,
                          char type, const void *value);
/* one co-simulation step from t of length h (fmi2_cs.c) */
fmi2Status fmu_cs_do_step(instance_t *c, double t, double h);
/* FMU state snapshots (fmi2_state.c) in the serialised format of fmi2_state_format.h */
fmi2Status fmu_state_get(instance_t *c, const char *fn, void **state);
fmi2Status fmu_state_set(instance_t *c, const char *fn, void *state);
fmi2Status fmu_state_free(instance_t *c, const char *fn, void **state);
fmi2Status fmu_state_size(instance_t *c, const char *fn, void *state, size_t *size);
fmi2Status fmu_state_serialize(instance_t *c, const char *fn, void *state, unsigned char *out, size_t size);
fmi2Status fmu_state_deserialize(instance_t *c, const char *fn, const unsigned char *b, size_t size, void **state);

#endif
