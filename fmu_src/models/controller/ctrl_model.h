/* The controller's functions shared by its files behind the glue (ctrl_model.c, ctrl_clock.c);
 * what the glue itself calls is declared in fmi/model.h. */
#ifndef CTRL_MODEL_H
#define CTRL_MODEL_H

#include "instance.h"

/* t0 + k Ts: sample instant k */
double ctrl_sample_time(const model_t *m, long long k);
/* how far a time may miss a sample instant and still be it */
double ctrl_time_eps(const model_t *m, double t);
/* the sample at the current instant from the current inputs (not yet committed); 0 when it is
 * not finite (logged as fn's error, the instance in state Error, the outputs those of the last
 * finite sample) */
int ctrl_evaluate(instance_t *c, const char *fn);
/* the pending sample committed: the state moves to the next sample */
void ctrl_commit(model_t *m);

#endif
