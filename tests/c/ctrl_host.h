/* Shared by the controller FMU's C test host (DriveController, FMI 2.0 and 3.0):
 * ctrl_host.c (main), ctrl_hostile.c with ctrl_case_*.c (the hostile cases, ctrl_hostile.h),
 * ctrl_fuzz.c (random calls, random settings), ctrl_threads.c (instances in parallel threads).
 * Built with the controller's sources linked in (-DFMI_STATIC, CTRL_FMI3: the FMI 3.0 glue too)
 * under AddressSanitizer + UBSan or ThreadSanitizer, or as the shipped libraries:
 * DriveController.so through dlopen, and (ctrl_host3, CTRL_FMI3) DriveController3.so linked for
 * the FMI 3.0 calls. The FMI 2.0 calls go through fmi_host.h's table and only ever to FMI 2.0
 * instances. */
#ifndef CTRL_HOST_H
#define CTRL_HOST_H

#include <stddef.h>

#include "fmi_host.h"
#include "ctrl_vars.h"
#ifdef CTRL_FMI3
#include "fmi3Functions.h"
#endif

extern fmi_api_t api;

/* what one FMI 3.0 instance logged (its instanceEnvironment) */
typedef struct {
    long n_msgs, n_since_mark;
    int worst;
    int echo;
    char last[1024];
} env3_t;

void env3_mark(env3_t *e);
#ifdef CTRL_FMI3
void env3_log(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message);
#endif

/* a fresh FMI 2.0 instance with the start values, NULL (logged) if it cannot be made */
fmi2Component ctrl2_new(host_env_t *env, const char *name);
/* set one Real / Integer / Boolean by value reference; the status */
fmi2Status ctrl2_set(fmi2Component c, unsigned vr, double value);
/* setup (t0 = 0), enter and exit initialization mode; the worst status */
fmi2Status ctrl2_init(fmi2Component c);

int fuzz_main(int argc, char **argv);
int threads_main(int argc, char **argv);

#endif
