/* Limits of accepted values and of the work per call:
 *   ranges    every parameter and input with a declared min/max, set at and just beyond both ends
 *             (one at a time, the rest at their defaults): beyond is refused with a message; at the
 *             end the set is accepted or refused with a message, and an accepted value runs 0.1 s
 *             at u = +10 V with every answer fmi2OK, finite and inside its declared range, or
 *             fmi2Error with a message;
 *   budget    friction.C = 1e9: a 1 s step is refused within the budget naming friction.C; a 100 s
 *             step at rest with the current loop ideal succeeds; an ME fmi2SetTime jump of 1e7 s is
 *             refused by fmi2NewDiscreteStates naming Ts; Ts = 1e-6 s runs a 0.5 ms step;
 *   time      startTime 1.7e9 s and 1e10 s: 4000 current-loop samples in 2 s and the same sampled
 *             currents, bit for bit, as startTime 0 (x follows the master's rounded communication
 *             points: within 1 mm after the 2 s of stick-slip); a step starting Ts/2 off is refused;
 *             startTime 1e11 s (time resolution 1.5e-5 s, over Ts/8 in 16 ulp) is refused;
 *   sequence  fmi2GetDerivatives after a failed fmi2EnterEventMode from Instantiated is not fmi2OK;
 *   counters  Integer statistics past 2^31 read INT_MAX (a state with n_steps = 3e9).
 * Usage: limits [LinearMotorFeedDrive.so|-]. Prints JSON lines of figures, FAIL lines and
 * "N passed, M failed". */
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi_host.h"
#include "model_vars.h"

static fmi_api_t api;
static long n_pass, n_fail;
static fmi2ValueReference real_vr[MODEL_NVARS];
static size_t n_real;

static void check(int ok, const char *what, const char *detail) {
    if (ok) { n_pass++; return; }
    n_fail++;
    if (n_fail <= 30) printf("FAIL %s: %s\n", what, detail);
}

typedef struct { host_env_t env; fmi2CallbackFunctions cb; fmi2Component c; } inst_t;

static int inst_new(inst_t *I, fmi2Type type) {
    memset(&I->env, 0, sizeof I->env);
    I->cb = host_callbacks(&I->env);
    I->c = api.Instantiate("limits", type, MODEL_GUID, "", &I->cb, fmi2False, fmi2False);
    return I->c != NULL;
}
static int set1(inst_t *I, unsigned vr, double v) {
    const model_var_t *mv = &MODEL_VARS[MODEL_VR_INDEX[vr]];
    fmi2ValueReference r = vr;
    host_env_mark(&I->env);
    if (mv->type == 'I') { fmi2Integer i = (fmi2Integer)v; return api.SetInteger(I->c, &r, 1, &i); }
    return api.SetReal(I->c, &r, 1, &v);
}
static int init(inst_t *I, double t0) {
    host_env_mark(&I->env);
    if (api.SetupExperiment(I->c, fmi2True, 1e-6, t0, fmi2False, 0.0) != fmi2OK) return fmi2Error;
    if (api.EnterInitializationMode(I->c) != fmi2OK) return fmi2Error;
    return api.ExitInitializationMode(I->c);
}
static double get1(inst_t *I, unsigned vr) {
    fmi2ValueReference r = vr;
    double v = NAN;
    api.GetReal(I->c, &r, 1, &v);
    return v;
}
static double get1i(inst_t *I, unsigned vr) {
    fmi2ValueReference r = vr;
    fmi2Integer v = 0;
    return api.GetInteger(I->c, &r, 1, &v) == fmi2OK ? (double)v : NAN;
}
/* every Real: fmi2OK, finite and inside its declared [min, max] (the states x, v, friction.F[j],
 * compliance.dx, compliance.dv, and every parameter and input), or refused with a message */
static int reals_clean(inst_t *I) {
    double v[MODEL_NVARS];
    size_t j;
    host_env_mark(&I->env);
    if (api.GetReal(I->c, real_vr, n_real, v) > fmi2Warning) return I->env.n_since_mark > 0;
    for (j = 0; j < n_real; j++) {
        const model_var_t *mv = &MODEL_VARS[MODEL_VR_INDEX[real_vr[j]]];
        if (!isfinite(v[j]) || v[j] < mv->min || v[j] > mv->max) return 0;
    }
    return 1;
}

/* ------------------------------------------------------------------ ranges */

typedef struct { long params, values, refused_beyond, at_end_accepted, at_end_refused, runs_clean, runs_error; } rtally_t;

/* one value of one variable: 0.1 s at u = 10 V after it was accepted */
static void try_value(unsigned vr, double v, int beyond, rtally_t *t) {
    inst_t I;
    char detail[1400];
    const model_var_t *mv = &MODEL_VARS[MODEL_VR_INDEX[vr]];
    int k, st;
    double tt = 0.0;
    t->values++;
    if (!inst_new(&I, fmi2CoSimulation)) { check(0, "instantiate", ""); return; }
    st = set1(&I, vr, v);
    snprintf(detail, sizeof detail, "%s = %.17g: status %d, %ld messages (%s)", mv->name, v, st, I.env.n_since_mark,
             I.env.last);
    if (beyond) { check(st == fmi2Error && I.env.n_since_mark > 0, "beyond the range refused", detail); t->refused_beyond++; }
    else if (st != fmi2OK) { check(I.env.n_since_mark > 0, "refused at the end with a message", detail); t->at_end_refused++; }
    if (st == fmi2OK && !beyond) {
        if (vr != VR_u) set1(&I, VR_u, 10.0);
        if (init(&I, 0.0) != fmi2OK) { check(I.env.n_since_mark > 0, "init refused with a message", detail); t->at_end_refused++; }
        else {
            t->at_end_accepted++;
            for (k = 0; k < 200; k++, tt += 5e-4) {
                host_env_mark(&I.env);
                if (api.DoStep(I.c, tt, 5e-4, fmi2True) > fmi2Warning) {
                    snprintf(detail, sizeof detail, "%s = %.17g: fmi2DoStep error without a message", mv->name, v);
                    check(I.env.n_since_mark > 0, "step error with a message", detail);
                    t->runs_error++;
                    break;
                }
                snprintf(detail, sizeof detail, "%s = %.17g: a non-finite or out-of-range value with fmi2OK at t = %g",
                         mv->name, v, tt);
                if (!reals_clean(&I)) { check(0, "outputs finite and in their declared ranges", detail); break; }
            }
            if (k == 200) t->runs_clean++;
        }
    }
    api.FreeInstance(I.c);
}

static void ranges(void) {
    rtally_t t;
    int j;
    memset(&t, 0, sizeof t);
    for (j = 0; j < MODEL_NVARS; j++) {
        const model_var_t *mv = &MODEL_VARS[j];
        double step_lo, step_hi;
        if ((mv->causality != 'p' && mv->causality != 'i') || mv->type == 'B') continue;
        if (!isfinite(mv->min) && !isfinite(mv->max)) continue;
        t.params++;
        step_lo = mv->type == 'I' ? 1.0 : 1e-6 * (fabs(mv->min) > 1.0 ? fabs(mv->min) : 1.0);
        step_hi = mv->type == 'I' ? 1.0 : 1e-6 * (fabs(mv->max) > 1.0 ? fabs(mv->max) : 1.0);
        if (isfinite(mv->min)) { try_value(mv->vr, mv->min, 0, &t); try_value(mv->vr, mv->min - step_lo, 1, &t); }
        if (isfinite(mv->max)) { try_value(mv->vr, mv->max, 0, &t); try_value(mv->vr, mv->max + step_hi, 1, &t); }
    }
    printf("{\"ranges\": {\"variables\": %ld, \"values\": %ld, \"beyond_refused\": %ld, \"at_end_accepted\": %ld, "
           "\"at_end_refused\": %ld, \"runs_clean\": %ld, \"runs_refused_with_message\": %ld}}\n", t.params, t.values,
           t.refused_beyond, t.at_end_accepted, t.at_end_refused, t.runs_clean, t.runs_error);
}

/* ------------------------------------------------------------------ budget */

static void budget(void) {
    inst_t I;
    fmi2EventInfo ei;
    char detail[1400];
    double w, t;
    int st, k;
    /* friction.C = 1e9 while slipping: refused, naming friction.C, in bounded time */
    inst_new(&I, fmi2CoSimulation);
    set1(&I, VR_friction_C, 1e9);
    set1(&I, VR_u, 1.0);
    init(&I, 0.0);
    w = host_now();
    host_env_mark(&I.env);
    st = api.DoStep(I.c, 0.0, 1.0, fmi2True);
    w = host_now() - w;
    snprintf(detail, sizeof detail, "status %d after %.2f s: %s", st, w, I.env.last);
    check(st == fmi2Error && strstr(I.env.last, "friction.C = 1000000000") != NULL, "friction.C = 1e9 named", detail);
    printf("{\"budget_friction_C_1e9\": {\"status\": %d, \"wall_s\": %.3f, \"message\": \"%.200s\"}}\n", st, w, I.env.last);
    api.FreeInstance(I.c);
    /* a 100 s step at rest, current loop ideal (h <= Ts: 2e5 steps) */
    inst_new(&I, fmi2CoSimulation);
    { fmi2ValueReference r = VR_effects_current_dynamics; fmi2Boolean f = fmi2False; api.SetBoolean(I.c, &r, 1, &f); }
    init(&I, 0.0);
    w = host_now();
    host_env_mark(&I.env);
    st = api.DoStep(I.c, 0.0, 100.0, fmi2True);
    w = host_now() - w;
    snprintf(detail, sizeof detail, "status %d: %s", st, I.env.last);
    check(st == fmi2OK && reals_clean(&I), "100 s step at rest", detail);
    printf("{\"long_step_at_rest\": {\"h_s\": 100, \"status\": %d, \"steps\": %.0f, \"wall_s\": %.3f}}\n", st,
           get1i(&I, VR_stats_n_steps), w);
    api.FreeInstance(I.c);
    /* Ts = 1e-6 s: a 0.5 ms step takes its 500 samples */
    inst_new(&I, fmi2CoSimulation);
    set1(&I, VR_Ts, 1e-6);
    init(&I, 0.0);
    host_env_mark(&I.env);
    st = api.DoStep(I.c, 0.0, 5e-4, fmi2True);
    snprintf(detail, sizeof detail, "status %d, %ld messages, samples %g: %s", st, I.env.n_since_mark,
             get1i(&I, VR_stats_n_time_events), I.env.last);
    check(st == fmi2OK && I.env.n_since_mark == 0 && fabs(get1i(&I, VR_stats_n_time_events) - 500.0) <= 1.0,
          "Ts = 1e-6: 500 samples in 0.5 ms", detail);
    api.FreeInstance(I.c);
    /* ME: a jump of 1e7 s past nextEventTime */
    inst_new(&I, fmi2ModelExchange);
    init(&I, 0.0);
    api.NewDiscreteStates(I.c, &ei);
    api.EnterContinuousTimeMode(I.c);
    api.SetTime(I.c, 1e7);
    api.EnterEventMode(I.c);
    w = host_now();
    host_env_mark(&I.env);
    st = api.NewDiscreteStates(I.c, &ei);
    w = host_now() - w;
    snprintf(detail, sizeof detail, "status %d after %.3f s: %s", st, w, I.env.last);
    check(st == fmi2Error && strstr(I.env.last, "Ts = 0.0005") != NULL && w < 1.0, "ME jump of 1e7 s refused", detail);
    printf("{\"me_time_jump_1e7\": {\"status\": %d, \"wall_s\": %.4f, \"message\": \"%.200s\"}}\n", st, w, I.env.last);
    api.FreeInstance(I.c);
    (void)t; (void)k;
}

/* ------------------------------------------------------------------ time */

#define NSTEP 4000

/* 2 s of 0.5 ms steps from t0 (master time t0 + n h): the current after every step */
static int run_from(double t0, double *i_out, double *samples, double *x_end, inst_t *Ip) {
    const double h = 5e-4;
    int n;
#define I (*Ip)
    inst_new(&I, fmi2CoSimulation);
    if (init(&I, t0) != fmi2OK) return -1;
    for (n = 0; n <= NSTEP; n++) {   /* the sample at t0 + 2 s is taken at the start of step NSTEP */
        double u = 2.0 * sin(2.0 * M_PI * 5.0 * n * h);
        set1(&I, VR_u, u);
        host_env_mark(&I.env);
        if (api.DoStep(I.c, t0 + n * h, h, fmi2True) != fmi2OK || I.env.n_since_mark != 0) {
            printf("FAIL t0 = %g: step %d: %s\n", t0, n, I.env.last);
            api.FreeInstance(I.c);
            return -1;
        }
        i_out[n] = get1(&I, VR_i);
    }
    *samples = get1i(&I, VR_stats_n_time_events);
    *x_end = get1(&I, VR_x);
    return 0;
#undef I
}

static void large_start_times(void) {
    static double i0[NSTEP + 1], i1[NSTEP + 1];
    const double T0[2] = {1.7e9, 1e10};
    double s0, s1, x0, x1;
    char detail[1400];
    int k, st;
    inst_t I;
    if (run_from(0.0, i0, &s0, &x0, &I) != 0) { check(0, "t0 = 0 run", ""); return; }
    api.FreeInstance(I.c);
    for (k = 0; k < 2; k++) {
        if (run_from(T0[k], i1, &s1, &x1, &I) != 0) { check(0, "large t0 run", ""); continue; }
        snprintf(detail, sizeof detail, "t0 = %g: %g samples (t0 = 0: %g), currents %s, x %.17g vs %.17g", T0[k], s1,
                 s0, memcmp(i0, i1, sizeof i0) == 0 ? "identical" : "differ", x1, x0);
        check(s1 == s0 && s1 == NSTEP && memcmp(i0, i1, sizeof i0) == 0 && fabs(x1 - x0) < 1e-3,
              "large startTime: same samples as t0 = 0", detail);
        printf("{\"start_time\": %.17g, \"samples_in_2s\": %.0f, \"samples_t0_0\": %.0f, \"currents_identical\": %s, "
               "\"x_diff_m\": %.3g}\n", T0[k], s1, s0, memcmp(i0, i1, sizeof i0) == 0 ? "true" : "false", x1 - x0);
        host_env_mark(&I.env);
        st = api.DoStep(I.c, T0[k] + (NSTEP + 1) * 5e-4 + 2.5e-4, 5e-4, fmi2True);
        snprintf(detail, sizeof detail, "t0 = %g: status %d", T0[k], st);
        check(st == fmi2Error && strstr(I.env.last, "differs from the FMU's time") != NULL, "step Ts/2 off refused", detail);
        api.FreeInstance(I.c);
    }
    /* startTime 1e11 s: a double resolves 1.5e-5 s there, too coarse for Ts = 0.5 ms */
    inst_new(&I, fmi2CoSimulation);
    init(&I, 1e11);
    host_env_mark(&I.env);
    st = api.DoStep(I.c, 1e11, 5e-4, fmi2True);
    snprintf(detail, sizeof detail, "status %d: %s", st, I.env.last);
    check(st == fmi2Error && strstr(I.env.last, "too coarse") != NULL, "startTime 1e11 s refused", detail);
    api.FreeInstance(I.c);
}

/* ------------------------------------------------------------------ sequence, counters */

static void sequence_and_counters(void) {
    inst_t I;
    double dx[MODEL_NX], v;
    fmi2FMUstate s = NULL;
    unsigned char buf[8192];
    size_t len = 0, j;
    uint64_t u;
    uint32_t crc = 0xFFFFFFFFu;
    fmi2ValueReference r = VR_stats_n_steps;
    fmi2Integer iv = 0;
    int st, k;
    char detail[1400];
    inst_new(&I, fmi2ModelExchange);
    st = api.EnterEventMode(I.c);
    check(st == fmi2Error, "fmi2EnterEventMode from Instantiated refused", I.env.last);
    host_env_mark(&I.env);
    st = api.GetDerivatives(I.c, dx, MODEL_NX);
    snprintf(detail, sizeof detail, "status %d: %s", st, I.env.last);
    check(st == fmi2Error && I.env.n_since_mark > 0, "fmi2GetDerivatives after it not fmi2OK", detail);
    api.FreeInstance(I.c);
    /* a state with stats.n_steps = 3e9 (the solver counts are the payload's last 7 numbers: step,
     * controller memory, accepted steps, ...), its CRC recomputed */
    inst_new(&I, fmi2CoSimulation);
    init(&I, 0.0);
    api.DoStep(I.c, 0.0, 5e-4, fmi2True);
    api.GetFMUstate(I.c, &s);
    api.SerializedFMUstateSize(I.c, s, &len);
    api.SerializeFMUstate(I.c, s, (fmi2Byte *)buf, len);
    v = 3e9;
    memcpy(&u, &v, 8);
    for (k = 0; k < 8; k++) buf[len - 40 + k] = (unsigned char)(u >> (8 * k));
    for (j = 96; j < len; j++) {
        crc ^= buf[j];
        for (k = 0; k < 8; k++) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    crc = ~crc;
    for (k = 0; k < 4; k++) buf[92 + k] = (unsigned char)(crc >> (8 * k));
    st = api.DeSerializeFMUstate(I.c, (const fmi2Byte *)buf, len, &s);
    if (st == fmi2OK) st = api.SetFMUstate(I.c, s);
    if (st == fmi2OK) st = api.GetInteger(I.c, &r, 1, &iv);
    snprintf(detail, sizeof detail, "status %d, Integer %d: %s", st, (int)iv, I.env.last);
    check(st == fmi2OK && iv == INT_MAX, "stats.n_steps saturates", detail);
    api.FreeFMUstate(I.c, &s);
    api.FreeInstance(I.c);
}

int main(int argc, char **argv) {
    char err[512];
    const char *so = argc > 1 && strcmp(argv[1], "-") != 0 ? argv[1] : NULL;
    int j;
    double w0 = host_now();
    if (fmi_api_load(&api, so, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 2; }
    for (j = 0; j < MODEL_NVARS; j++)
        if (MODEL_VARS[j].type == 'R') real_vr[n_real++] = MODEL_VARS[j].vr;
    sequence_and_counters();
    large_start_times();
    budget();
    ranges();
    if (host_live_allocations() != 0) check(0, "allocations", "callback allocations left at the end");
    fmi_api_unload(&api);
    printf("wall %.1f s\n%ld passed, %ld failed\n", host_now() - w0, n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
}
