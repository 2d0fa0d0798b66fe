/* Start values of parameters from the FMU's resources: resources/start_values.txt (written by
 * `feeddrive fmu` when it packs an identified machine as its own FMU) replaces the compiled-in
 * start values of the parameters it names; without the file the FMU starts from its XML's
 * start values as built. One line per parameter, "name value" (the FMI 2.0 name; a decimal
 * number with '.' whatever the locale, an integer, or true/false), '#' starts a comment line. */
#ifndef START_VALUES_H
#define START_VALUES_H

#include "instance.h"

#define START_VALUES_FILE "start_values.txt"

/* Read the file in the resource folder `location` (FMI 2.0: a file URI, is_uri = 1; FMI 3.0: a
 * native path, is_uri = 0; NULL or no file: nothing changes) into c->m.val and keep the values
 * for fmi2Reset (c->start_val). Returns 0, with a message naming the file, the line, the
 * parameter, its value and the allowed range logged, when a line is malformed, names no
 * parameter of this FMU, or a value (or their combination) is out of range. */
int model_load_start_values(instance_t *c, const char *location, int is_uri);
/* every variable at its start value: the compiled-in ones and those of the resource file */
void model_reset(instance_t *c);

#endif
