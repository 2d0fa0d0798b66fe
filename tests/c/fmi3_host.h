/* Shared by the FMI 3.0 host's files (fmi3_host.c: instantiation, Configuration Mode, ME and CS
 * loops, main; fmi3_host_robust.c: FMU state, limits, wrong states, many instances). */
#ifndef FMI3_HOST_H
#define FMI3_HOST_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "fmi_host.h"
#include "model_vars.h"
#include "model_vars3.h"


#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define VR3_friction_F 12u   /* the array friction.F (its element 1's value reference) */
#define VR3_friction_k 176u
#define VR3_friction_nu 175u
#define NZ MODEL_NZ
#define NX_MAX MODEL_NX
#define T_CS 1.0             /* the co-simulation's length, s */
#define H_CS 1e-3            /* its communication step, s */
#define N_CS 1000
#define U_AMP 1.5            /* V */
#define U_FREQ 2.0           /* Hz */

typedef struct {
    long n_msgs;
    int worst;
    char last[1024];
} env3_t;

typedef struct {
    long early_returns, events, dosteps;
    double x[N_CS + 1];
} cs_run_t;

extern long n_checks;
extern int leave_states;          /* --leave-states: many instances, their FMU states left to fmi3FreeInstance */

void fail(const char *what, const char *detail);
void check(int ok, const char *what, const env3_t *env);
#define CHECK(cond, what, env) check((cond) != 0, what, env)
double u_of(double t);
fmi3Instance me_new(env3_t *env, const char *name);
fmi3Instance cs_new(env3_t *env, const char *name, int event_mode, int early);
int configure(fmi3Instance c, int n);
int initialise(fmi3Instance c, double u0);
void cs_steps(fmi3Instance c, env3_t *env, int event_mode, cs_run_t *r, int k0, int k1);
fmi3Instance cs_open(env3_t *env, int event_mode, int early, cs_run_t *r);
void part_state(void);
void part_state_structure(void);
void part_limits(void);
void part_wrong_states(void);
void part_many(void);

#endif
