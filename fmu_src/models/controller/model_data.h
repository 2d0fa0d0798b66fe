/* The controller's data behind the FMI glue (fmu_src/fmi/model.h): the model_t every instance
 * holds, its value table under the glue's names, and what it offers: co-simulation with an
 * input clock (FMI 3.0), no model exchange, no FMU state, no structural parameter. */
#ifndef MODEL_DATA_H
#define MODEL_DATA_H

#include <math.h>

#include "controller.h"
#include "ctrl_vars.h"

#define MODEL_CAPS (MODEL_CAN_CS | MODEL_CAN_CLOCKS)
#define MODEL_TOKEN CTRL_GUID
#define MODEL_MAGIC 0x46444354u   /* "FDCT" */
#define MODEL_ND 0
#define MODEL_HAS_ARRAYS 0          /* FMI 3.0 arrays of the dimension of MODEL_STRUCTURAL_VR */
#define MODEL_STRUCTURAL_VR 0xFFFFFFFEu   /* none: no arrays (no value reference) */
#define TOL_MAX HUGE_VAL          /* no integrator: any tolerance > 0 */
/* the value table (ctrl_vars.h) under the glue's names; no continuous states, no indicators */
typedef ctrl_var_t glue_var_t;
#define GLUE_VARS CTRL_VARS
#define GLUE_NVARS CTRL_NVARS
#define GLUE_NVR CTRL_NVR
#define GLUE_VR_INDEX CTRL_VR_INDEX
#define GLUE_NX 0
#define GLUE_NZ 0
#define GLUE_STATE_VR CTRL_NO_STATE
#define GLUE_STATE_NOMINAL(j) 1.0
extern const unsigned CTRL_NO_STATE[1];
/* Work budget of one call (README "The controller FMU"): a step takes at most this many
 * controller samples (h/Ts), a longer step is refused before any sample is taken */
#define CTRL_BUDGET_SAMPLES 1e6

/* The model: plain data. The fields up to dydt are those model.h asks of every model. */
typedef struct {
    unsigned magic;
    int fsm;
    double time, t0, tau, stop_time, tol;
    int stop_defined, tol_defined;
    double val[CTRL_NVR];
    int params_ok;
    int out_valid;                /* unused: outputs are stored with every sample */
    double y[1], dydt[1];         /* no continuous states */
    ctrl_params_t p;
    ctrl_state_t s, pending;      /* committed state; the sample at the current instant */
    int pending_ok;
    int pending_read;             /* the pending sample's outputs were read in Step Mode */
    int ticked;                   /* the input clock set active in this Event Mode, its sample not yet taken */
} model_t;

#endif
