/* The plant's functions shared by its files behind the glue (plant_model.c, plant_step.c,
 * plant_snapshot.c, start_values.c); what the glue itself calls is declared in fmi/model.h. */
#ifndef PLANT_MODEL_H
#define PLANT_MODEL_H

#include "instance.h"

/* startTime + (k + 1) Ts: the next sample, from its index */
double plant_next_sample(const model_t *m);
/* how close the master's time must be to the FMU's at t: 1e-9 max(1, |t - t0|) (at most Ts/64),
 * and at least fmu_ulp_slack(t) */
double plant_time_eps(const model_t *m, double t);
/* the sample k + 1 is due at tau = time - startTime: tau >= (k + 1) Ts - eps, eps =
 * 1e-9 max(1, |tau|) (at most Ts/64) or slack if larger (fmu_ulp_slack(time) when tau comes
 * from an importer's time, 0 when it is the co-simulation's own exact tau) */
int plant_sample_due(const model_t *m, double tau, double slack);
/* outputs and derivatives up to date */
void plant_update_outputs(instance_t *c);
/* the same without the derivatives (what a read of no derivative needs) */
void plant_update_values(instance_t *c);
/* the stroke warning (once per excursion) */
void plant_check_stroke(instance_t *c);
/* the solver configured from m->tol, the XML nominals and m->p.Ts (statistics reset) */
void plant_solver_setup(model_t *m);

#endif
