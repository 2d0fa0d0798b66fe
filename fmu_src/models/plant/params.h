/* The FMU's variables by value reference (the table generated from modelDescription.xml) and
 * the plant's structs: start values, the checks of single values and of their combination, the
 * compilation into plant_params_t with the effect switches applied, and the transfer of inputs,
 * states and outputs between the value table and the plant. Knows nothing of the FMI calls. */
#ifndef PARAMS_H
#define PARAMS_H

#include <stdbool.h>
#include <stddef.h>

#include "model_vars.h"
#include "plant.h"

/* every variable at its start value */
void params_defaults(double *val);
/* Check one value alone (called on fmi2Set*); true if acceptable, else a message naming the
 * variable, its value and the allowed range in msg. */
bool params_check_value(unsigned vr, double value, char *msg, size_t msglen);
/* Compile the values (indexed by value reference) into p. On error, returns false and writes a
 * message naming the variable, its value and the allowed range into msg. */
bool params_compile(const double *val, plant_params_t *p, char *msg, size_t msglen);
/* The parameter behind the fastest rate the solver must resolve (1/Ts, friction.C / (p_min F_c), the
 * frequency sqrt(k_j / m) of a stuck element, sigma2 / m, the cogging stiffness
 * sqrt(|a_j| 2 pi / (lambda_j m))), written as "name = value (rate R 1/s with m = M kg)". */
void params_fastest_rate(const double *val, const plant_params_t *p, char *buf, size_t n);
/* why continuous state j (PLANT_I*) has the value it has, from the outputs o at (y, in): the
 * forces accelerating the slide (x, v), the element's stiffness (friction.F[j]), the load's
 * spring (compliance); for the message of a state leaving its declared range */
void params_state_cause(const plant_params_t *p, const double *y, const plant_in_t *in, const plant_out_t *o,
                        int j, char *buf, size_t n);
/* the inputs and the continuous states (start values) from the value table */
void params_inputs(const double *val, plant_in_t *in);
void params_states(const double *val, double *y);
/* states, outputs and the plant's event statistics into the value table */
void params_store_outputs(double *val, const double *y, const plant_out_t *o, const plant_disc_t *d);
/* the states' derivatives into the value table (a variable that is both a state and another's
 * derivative keeps the state's value, which is the same) */
void params_store_derivatives(double *val, const double *y, const double *dydt);

#endif
