/* A C master for the closed loop as two FMUs: controller FMU (DriveController) + plant FMU,
 * macro step Ts, Gauss-Seidel with the plant first (python/feeddrive/harness/two_fmus.py):
 * step the plant over [t_k, t_k+1] holding u_k, read x(t_k+1), set it as the controller's
 * x_meas, step the controller over [t_k, t_k+1], read u_k+1, set it on the plant.  No input
 * is set and read back at one instant in Step Mode; the harness's run with ctrl.delay.
 * Usage: two_fmus PLANT.so CONTROLLER.so PARAMS N X0 OUT [repetitions]
 *   PARAMS: one controller start value a line, "<value reference> <R|I|B> <value>"
 *   (written by feeddrive.bench_c.run_two_fmus); the plant keeps its defaults (the paper's).
 *   OUT: x(t_k), k = 0..N, of the last repetition, one a line ("%.17g").
 * Prints one JSON object: {"wall_s_best": ..., "wall_s_median": ..., "samples": N}. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi_host.h"
#include "model_vars.h"
#include "controller/ctrl_vars.h"   /* build/gen/controller: the controller FMU's table */

#define CHECK(call, what) do { if ((call) > fmi2Warning) { \
    fprintf(stderr, "%s failed: %s\n", what, env.last); return -1; } } while (0)

typedef struct { unsigned vr; char type; double value; } start_t;

static int cmp_double(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static int read_params(const char *path, start_t **out, long *n) {
    FILE *f = fopen(path, "r");
    long cap = 64;
    start_t s;
    if (!f) { fprintf(stderr, "%s: cannot open\n", path); return -1; }
    *out = (start_t *)malloc(sizeof(start_t) * (size_t)cap);
    *n = 0;
    while (fscanf(f, "%u %c %lg", &s.vr, &s.type, &s.value) == 3) {
        if (*n == cap) { cap *= 2; *out = (start_t *)realloc(*out, sizeof(start_t) * (size_t)cap); }
        (*out)[(*n)++] = s;
    }
    fclose(f);
    return 0;
}

static int set_start(const fmi_api_t *api, fmi2Component c, const start_t *s) {
    const fmi2ValueReference vr = s->vr;
    if (s->type == 'R') return api->SetReal(c, &vr, 1, &s->value);
    if (s->type == 'I') { fmi2Integer v = (fmi2Integer)s->value; return api->SetInteger(c, &vr, 1, &v); }
    { fmi2Boolean v = s->value != 0.0; return api->SetBoolean(c, &vr, 1, &v); }
}

/* one run; x[0..n] filled; returns the wall time or -1 */
static double run(const fmi_api_t *plant, const fmi_api_t *ctrl, const start_t *starts, long ns,
                  long n, double x0, double *x) {
    host_env_t env;
    fmi2CallbackFunctions cb;
    fmi2Component pc, cc;
    const fmi2ValueReference vx = VR_x, vv = VR_v, vu = VR_u, vxm = CVR_x_meas, vcu = CVR_u;
    const double Ts = 5e-4, zero = 0.0;
    double u, w0, w;
    long j, k;
    memset(&env, 0, sizeof env);
    cb = host_callbacks(&env);
    w0 = host_now();
    cc = ctrl->Instantiate("controller", fmi2CoSimulation, CTRL_GUID, "",
                           &cb, fmi2False, fmi2False);
    pc = plant->Instantiate("plant", fmi2CoSimulation, MODEL_GUID, "", &cb, fmi2False, fmi2False);
    if (!cc || !pc) { fprintf(stderr, "instantiate failed: %s\n", env.last); return -1; }
    CHECK(ctrl->SetupExperiment(cc, fmi2False, 0.0, 0.0, fmi2False, 0.0), "controller setup");
    for (j = 0; j < ns; j++) CHECK(set_start(ctrl, cc, &starts[j]), "controller start value");
    CHECK(ctrl->SetReal(cc, &vxm, 1, &x0), "controller x_meas");
    CHECK(ctrl->EnterInitializationMode(cc), "controller init");
    CHECK(ctrl->ExitInitializationMode(cc), "controller init");
    CHECK(ctrl->GetReal(cc, &vcu, 1, &u), "controller u");
    CHECK(plant->SetupExperiment(pc, fmi2False, 0.0, 0.0, fmi2False, 0.0), "plant setup");
    CHECK(plant->SetReal(pc, &vx, 1, &x0), "plant x");
    CHECK(plant->SetReal(pc, &vv, 1, &zero), "plant v");
    CHECK(plant->SetReal(pc, &vu, 1, &u), "plant u");
    CHECK(plant->EnterInitializationMode(pc), "plant init");
    CHECK(plant->ExitInitializationMode(pc), "plant init");
    CHECK(plant->GetReal(pc, &vx, 1, &x[0]), "plant x");
    for (k = 0; k < n; k++) {
        double t = (double)k * Ts;
        if (k > 0) CHECK(plant->SetReal(pc, &vu, 1, &u), "plant u");
        CHECK(plant->DoStep(pc, t, Ts, fmi2True), "plant doStep");
        CHECK(plant->GetReal(pc, &vx, 1, &x[k + 1]), "plant x");
        CHECK(ctrl->SetReal(cc, &vxm, 1, &x[k + 1]), "controller x_meas");
        CHECK(ctrl->DoStep(cc, t, Ts, fmi2True), "controller doStep");
        CHECK(ctrl->GetReal(cc, &vcu, 1, &u), "controller u");
    }
    w = host_now() - w0;
    ctrl->FreeInstance(cc);
    plant->FreeInstance(pc);
    return w;
}

int main(int argc, char **argv) {
    fmi_api_t plant, ctrl;
    char err[512];
    start_t *starts;
    long ns, n, j;
    int reps, r;
    double x0, *x, *walls;
    FILE *f;
    if (argc < 7) {
        fprintf(stderr, "usage: two_fmus PLANT.so CONTROLLER.so PARAMS N X0 OUT [repetitions]\n");
        return 2;
    }
    if (fmi_api_load(&plant, argv[1], err, sizeof err) != 0 || fmi_api_load(&ctrl, argv[2], err, sizeof err) != 0) {
        fprintf(stderr, "%s\n", err);
        return 2;
    }
    if (read_params(argv[3], &starts, &ns) != 0) return 2;
    n = atol(argv[4]);
    x0 = atof(argv[5]);
    reps = argc > 7 ? atoi(argv[7]) : 5;
    if (n < 1 || reps < 1) { fprintf(stderr, "N and repetitions must be >= 1\n"); return 2; }
    x = (double *)malloc(sizeof(double) * (size_t)(n + 1));
    walls = (double *)malloc(sizeof(double) * (size_t)reps);
    for (r = 0; r < reps; r++)
        if ((walls[r] = run(&plant, &ctrl, starts, ns, n, x0, x)) < 0) return 1;
    qsort(walls, (size_t)reps, sizeof(double), cmp_double);
    f = fopen(argv[6], "w");
    if (!f) { fprintf(stderr, "%s: cannot write\n", argv[6]); return 2; }
    for (j = 0; j <= n; j++) fprintf(f, "%.17g\n", x[j]);
    fclose(f);
    printf("{\"wall_s_best\": %.9g, \"wall_s_median\": %.9g, \"samples\": %ld}\n", walls[0],
           walls[reps / 2], n);
    free(x);
    free(walls);
    free(starts);
    fmi_api_unload(&plant);
    fmi_api_unload(&ctrl);
    return 0;
}
