/* The controller FMU's C test host (see ctrl_host.h).
 * Usage: ctrl_host LIB|- hostile [case]     the hostile cases (all, or one), each printing the
 *                                            FMU's answer: "PASS|FAIL <case>: <answer>"
 *                                            (ctrl_hostile.c, the cases in ctrl_case_*.c)
 *        ctrl_host LIB|- fuzz [calls] [seed] random FMI 2.0 / 3.0 calls and settings (ctrl_fuzz.c)
 *        ctrl_host LIB|- threads [seconds] [threads]   parallel == sequential (ctrl_threads.c)
 * LIB: DriveController.so (the plain build ctrl_host3, linked against DriveController3.so for
 * the FMI 3.0 calls), or - for the sources linked in (ctrl_host_san, ctrl_host_tsan). Ends with
 * "N passed, M failed"; exit 0 only without a failure. */
#include "ctrl_host.h"
#include "ctrl_hostile.h"

#include <stdio.h>
#include <string.h>

fmi_api_t api;

void env3_mark(env3_t *e) {
    e->worst = -1;
    e->n_since_mark = 0;
}

#ifdef CTRL_FMI3
void env3_log(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message) {
    env3_t *e = (env3_t *)env;
    (void)category;
    if (!e) return;
    e->n_msgs++;
    e->n_since_mark++;
    if ((int)status > e->worst) e->worst = (int)status;
    snprintf(e->last, sizeof e->last, "%s", message ? message : "(null)");
    if (e->echo) fprintf(stderr, "[fmi3] status %d: %s\n", (int)status, e->last);
}
#endif

fmi2Component ctrl2_new(host_env_t *env, const char *name) {
    fmi2CallbackFunctions cb = host_callbacks(env);
    /* the callbacks are copied by the FMU (FMI 2.0: valid for the instance's life is enough) */
    return api.Instantiate(name, fmi2CoSimulation, CTRL_GUID, "", &cb, fmi2False, fmi2False);
}

static int row_of(unsigned vr) { return vr < CTRL_NVR ? CTRL_VR_INDEX[vr] : -1; }

fmi2Status ctrl2_set(fmi2Component c, unsigned vr, double value) {
    int row = row_of(vr);
    fmi2ValueReference r = vr;
    if (row >= 0 && CTRL_VARS[row].type == 'I') { fmi2Integer i = (fmi2Integer)value; return api.SetInteger(c, &r, 1, &i); }
    if (row >= 0 && CTRL_VARS[row].type == 'B') { fmi2Boolean b = value != 0.0; return api.SetBoolean(c, &r, 1, &b); }
    return api.SetReal(c, &r, 1, &value);
}

fmi2Status ctrl2_init(fmi2Component c) {
    fmi2Status st = api.SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    if (st > fmi2Warning) return st;
    if ((st = api.EnterInitializationMode(c)) > fmi2Warning) return st;
    return api.ExitInitializationMode(c);
}

int main(int argc, char **argv) {
    char err[512];
    const char *lib = argc > 1 && strcmp(argv[1], "-") != 0 ? argv[1] : NULL;
    int rc;
    if (argc < 3) {
        fprintf(stderr, "usage: ctrl_host LIB|- hostile [case] | fuzz [calls] [seed] | threads [seconds] [threads]\n");
        return 2;
    }
    if (fmi_api_load(&api, lib, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 2; }
    if (strcmp(argv[2], "hostile") == 0) rc = hostile_main(argc - 3, argv + 3);
    else if (strcmp(argv[2], "fuzz") == 0) rc = fuzz_main(argc - 3, argv + 3);
    else if (strcmp(argv[2], "threads") == 0) rc = threads_main(argc - 3, argv + 3);
    else { fprintf(stderr, "unknown mode %s\n", argv[2]); rc = 2; }
    fmi_api_unload(&api);
    return rc;
}
