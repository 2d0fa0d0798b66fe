/* FMI glue shared by model exchange and co-simulation: the instance, its call-sequence state
 * machine, logging and the value table. Knows nothing of friction. */
#ifndef FMI2_INSTANCE_H
#define FMI2_INSTANCE_H

#include "fmi2Functions.h"
#include "fmi2_allowed.h"
#include "fmi2_log.h"
#include "params.h"
#include "plant.h"
#include "solver_dp45.h"

#define MODEL_MAGIC 0x46445256u   /* "FDRV": marks instances and FMU states */

/* Everything an FMU state snapshot holds: plain data, no pointers. */
typedef struct {
    unsigned magic, size;
    int fsm;
    double time, t0, stop_time;
    int stop_defined, tol_defined;
    double tol;
    double val[MODEL_NVR];          /* every variable by value reference */
    double y[PLANT_NX];             /* continuous states */
    plant_params_t p;
    plant_disc_t d;
    plant_in_t in;
    int params_ok;                  /* p compiled from val */
    int out_valid;
    plant_out_t out;
    double dydt[PLANT_NX];
    int stroke_warned;
    dp45_t solver;
    int solver_restart;
} model_t;

typedef struct {
    model_t m;
    fmi2CallbackFunctions cb;
    char *name;
    fmi2Type type;
    int logging_on;
    unsigned log_mask;              /* bit 0 events, 1 warnings, 2 errors */
} instance_t;

void fmu_log(instance_t *c, fmi2Status st, unsigned cat, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;
/* entry of every FMI call (through FMU_ENTER): the instance when comp is one, the call belongs to
 * its interface (a FOR_* set) and its state is one of `mask`, else NULL (with a logged message) */
instance_t *fmu_enter(fmi2Component comp, const char *fn, int iface, int mask);
/* outputs and derivatives up to date */
void fmu_update_outputs(instance_t *c);
/* process what is due at the current time: a current-loop sample, then the plant's switches */
int fmu_event_update(instance_t *c, fmi2Boolean *states_changed);
double fmu_next_sample(const model_t *m);
int fmu_sample_due(const model_t *m);
void fmu_check_stroke(instance_t *c);
/* compile parameters and initialise the plant from the current values (logs on error) */
fmi2Status fmu_initialize_plant(instance_t *c);
/* recompile parameters after a change; on failure logs, restores *backup and returns fmi2Error */
fmi2Status fmu_recompile(instance_t *c, const double *backup_val);

#endif
