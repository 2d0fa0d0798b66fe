/* Controller FMU instances in parallel threads give results bit-identical to the same runs one
 * at a time. Each instance closes its own loop (PID, internal sinusoid of amplitude 10..45 mm,
 * so cross-talk between instances would show) around a rigid mass driven by K u (m = 13 kg,
 * K = 78.7 N/V: the paper's drive at DC), one fmi2DoStep of Ts = 0.5 ms per sample.
 * Part of ctrl_host (mode "threads [seconds] [threads]"). */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ctrl_host.h"

#define MAX_THREADS 64
#define TS 5e-4
#define MASS 13.0
#define K_F 78.7

typedef struct {
    int id;
    long n;
    double *out;   /* u, r_x, x per sample */
    double max_err;
    int status;
} job_t;

static void *run(void *arg) {
    job_t *j = (job_t *)arg;
    host_env_t env;
    fmi2Component c;
    fmi2ValueReference out_vr[2] = {CVR_u, CVR_r_x}, in_vr = CVR_x_meas;
    double x = 0.15 - (0.010 + 0.005 * j->id), v = 0.0, y[2];
    char name[32];
    long k;
    memset(&env, 0, sizeof env);
    snprintf(name, sizeof name, "thread%d", j->id);
    j->status = -1;
    j->max_err = 0.0;
    if (!(c = ctrl2_new(&env, name))) return NULL;
    if (ctrl2_set(c, CVR_ref_source, 1) > fmi2Warning || ctrl2_set(c, CVR_ref_amplitude, 0.010 + 0.005 * j->id) ||
        ctrl2_set(c, CVR_ref_period, 0.5) || ctrl2_set(c, CVR_ref_duration, 1e3) || ctrl2_set(c, CVR_x_meas, x) ||
        ctrl2_init(c) > fmi2Warning) {
        api.FreeInstance(c);
        return NULL;
    }
    for (k = 0; k < j->n; k++) {
        if (api.SetReal(c, &in_vr, 1, &x) > fmi2Warning || api.GetReal(c, out_vr, 2, y) > fmi2Warning ||
            api.DoStep(c, (double)k * TS, TS, fmi2True) > fmi2Warning) {
            api.FreeInstance(c);
            return NULL;
        }
        j->out[3 * k] = y[0];
        j->out[3 * k + 1] = y[1];
        j->out[3 * k + 2] = x;
        if (k > j->n / 2 && fabs(x - y[1]) > j->max_err) j->max_err = fabs(x - y[1]);
        v += TS * K_F * y[0] / MASS;   /* semi-implicit Euler over one sample */
        x += TS * v;
    }
    api.FreeInstance(c);
    j->status = 0;
    return NULL;
}

int threads_main(int argc, char **argv) {
    double seconds = argc > 0 ? atof(argv[0]) : 1.0;
    int nt = argc > 1 ? atoi(argv[1]) : 8, i, n_pass = 0, n_fail = 0;
    long n = (long)(seconds / TS + 0.5);
    job_t seq[MAX_THREADS], par[MAX_THREADS];
    pthread_t th[MAX_THREADS];
    if (nt < 1 || nt > MAX_THREADS) nt = 8;
    for (i = 0; i < nt; i++) {
        seq[i].id = par[i].id = i;
        seq[i].n = par[i].n = n;
        seq[i].out = (double *)calloc((size_t)(3 * n), sizeof(double));
        par[i].out = (double *)calloc((size_t)(3 * n), sizeof(double));
    }
    for (i = 0; i < nt; i++) run(&seq[i]);
    for (i = 0; i < nt; i++) pthread_create(&th[i], NULL, run, &par[i]);
    for (i = 0; i < nt; i++) pthread_join(th[i], NULL);
    for (i = 0; i < nt; i++) {
        int same = seq[i].status == 0 && par[i].status == 0 &&
                   memcmp(seq[i].out, par[i].out, sizeof(double) * (size_t)(3 * n)) == 0;
        double umax = 0.0;
        long k;
        for (k = 0; k < n; k++) umax = fmax(umax, fabs(seq[i].out[3 * k]));
        printf("%s instance %d: %ld samples, max |u| = %.4f V, max |x - r_x| (2nd half) = %.3g m, parallel %s "
               "sequential\n", same ? "PASS" : "FAIL", i, n, umax, seq[i].max_err, same ? "==" : "!=");
        if (same) n_pass++; else n_fail++;
        free(seq[i].out);
        free(par[i].out);
    }
    if (host_live_allocations() != 0) { printf("FAIL %ld callback allocations left\n", host_live_allocations()); n_fail++; }
    printf("%d passed, %d failed\n", n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
}
