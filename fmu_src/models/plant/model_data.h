/* The plant's data behind the FMI glue (fmu_src/fmi/model.h): the model_t every instance holds,
 * its sizes and capabilities, and the plant's own work budgets and tolerance bound. */
#ifndef MODEL_DATA_H
#define MODEL_DATA_H

#include "fast_path.h"
#include "params.h"
#include "plant.h"
#include "solver_dp45.h"

/* what the plant offers (model.h's MODEL_CAN_*): both interfaces, FMU states, Configuration
 * Mode for its structural parameter friction.N, early return; no clocks */
#define MODEL_CAPS (MODEL_CAN_ME | MODEL_CAN_CS | MODEL_CAN_STATE | MODEL_CAN_CONFIG | MODEL_CAN_EARLY_RETURN)
#define MODEL_TOKEN MODEL_GUID      /* the GUID (FMI 2.0), the instantiation token (FMI 3.0) */
/* the value table (model_vars.h) under the glue's names */
typedef model_var_t glue_var_t;
#define GLUE_VARS MODEL_VARS
#define GLUE_NVARS MODEL_NVARS
#define GLUE_NVR MODEL_NVR
#define GLUE_VR_INDEX MODEL_VR_INDEX
#define GLUE_NX MODEL_NX
#define GLUE_NZ MODEL_NZ
#define GLUE_STATE_VR MODEL_STATE_VR
#define GLUE_STATE_NOMINAL(j) MODEL_STATE_NOMINAL(j)
#define MODEL_ND PLANT_ND           /* discrete-state numbers of a saved state */
#define MODEL_HAS_ARRAYS 1          /* FMI 3.0 arrays of the dimension of MODEL_STRUCTURAL_VR */
#define MODEL_STRUCTURAL_VR VR_friction_N   /* the structural parameter: the arrays' dimension (FMI 3.0) */

#define MODEL_MAGIC 0x46445256u   /* "FDRV": marks instances and FMU states */
/* The loosest relative tolerance of the co-simulation integrator (solver.tol's declared max; an
 * experiment tolerance above it is tightened to it): up to 1e-2 the error of the DP45 follows the
 * tolerance (max |dv| / max |v| = 1.1 to 1.2 tol at the stiffest declared settings, m = 1e-3 kg with
 * friction.k = 1e9 N/m); above it the controller accepts steps whose error is of the order of the
 * state (0.05: 4 %, 0.1: 16 %, 0.5: 300 %, 0.99: v = 3.7e298 m/s). */
#define TOL_MAX 1e-2

/* The model: plain data, no pointers (a saved FMU state holds only its state part, see
 * plant_snapshot.c). The fields up to tol are those model.h asks of every model. */
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
    int out_valid;                  /* 0, OUT_OUTPUTS, OUT_VALUES or OUT_ALL (plant_model.c) */
    plant_out_t out;
    double dydt[PLANT_NX];
    int stroke_warned;
    dp45_t solver;
    int solver_restart;
    plant_memo_t memo;              /* the maps at the last position evaluated (valid = 0 after a compile) */
    fast_carry_t carry;             /* the per-sample scheme's last derivative (valid = 0 after a compile) */
    int fast_ok;                    /* fast_path_ok(&p), renewed with every compile of p */
    int ind_positive;               /* the per-sample scheme's last step found every event indicator > 0
                                       at (d, y), and nothing has changed them since (plant_step.c) */
    double y_lo[PLANT_NX], y_hi[PLANT_NX];   /* the states' declared min/max (modelDescription.xml) */
    double inv_atol[PLANT_NX];               /* 1 / the solver's atol (plant_solver_setup) */
    unsigned char is_der[MODEL_NVR];         /* 1: the value reference is a derivative's only */
} model_t;
#define OUT_OUTPUTS 1               /* out holds the outputs at (d, y, in) */
#define OUT_VALUES 2                /* ... and val[] the states, outputs and statistics */
#define OUT_ALL 3                   /* ... and the derivatives (m->dydt too) */

/* Work budget of one call (README "Co-simulation"): a step of length h may take
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

#endif
