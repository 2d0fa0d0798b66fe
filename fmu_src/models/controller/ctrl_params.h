/* The controller's value table (ctrl_vars.h) and its compilation into ctrl_params_t. */
#ifndef CTRL_PARAMS_H
#define CTRL_PARAMS_H

#include <stdbool.h>
#include <stddef.h>

#include "controller.h"
#include "ctrl_vars.h"
#include "params.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

void ctrl_defaults(double *val);
const char *ctrl_var_name(unsigned vr);
/* a value reference of the imported plant.* parameters */
int ctrl_is_plant_vr(unsigned vr);
/* one value alone: finite, and for plant.* the plant's own rule (params.c) */
bool ctrl_check_value(unsigned vr, double value, char *msg, size_t msglen);
/* every rule of the combination; false with a message naming variable, value and range */
bool ctrl_compile(const double *val, ctrl_params_t *p, char *msg, size_t msglen);

#endif
