/* The controller FMU's C test host (see ctrl_host.h).
 * Usage: ctrl_host LIB|- hostile [case]     the hostile cases (all, or one), each printing the
 *                                            FMU's answer: "PASS|FAIL <case>: <answer>"
 *        ctrl_host LIB|- fuzz [calls] [seed] random FMI 2.0 / 3.0 calls and settings (ctrl_fuzz.c)
 *        ctrl_host LIB|- threads [seconds] [threads]   parallel == sequential (ctrl_threads.c)
 * LIB: DriveController.so (the plain build ctrl_host3, linked against DriveController3.so for
 * the FMI 3.0 calls), or - for the sources linked in (ctrl_host_san, ctrl_host_tsan). Ends with
 * "N passed, M failed"; exit 0 only without a failure. */
#include "ctrl_host.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
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

/* ---------------------------------------------------------------- the hostile cases */

static char answer[2048];
static int case_failed;

#define EXPECT(cond, ...) do { if (!(cond)) { case_failed = 1; snprintf(answer, sizeof answer, __VA_ARGS__); return; } } while (0)
#define SAY(...) snprintf(answer + strlen(answer), sizeof answer - strlen(answer), __VA_ARGS__)

static const char *ST2[] = {"fmi2OK", "fmi2Warning", "fmi2Discard", "fmi2Error", "fmi2Fatal", "fmi2Pending"};
static const char *st2(int s) { return s >= 0 && s <= 5 ? ST2[s] : "?"; }

/* a refused step: fmi2Error, a message with every needle, the FMU's time unchanged, and the
 * instance still steps afterwards (a refused call changes nothing) */
static void refused_step(fmi2Component c, host_env_t *env, double h, const char *needle1, const char *needle2) {
    fmi2Status st;
    fmi2Real t_after;
    host_env_mark(env);
    st = api.DoStep(c, 0.0, h, fmi2True);
    EXPECT(st == fmi2Error, "fmi2DoStep(h = %g) answered %s, expected fmi2Error", h, st2(st));
    EXPECT(strstr(env->last, needle1) && strstr(env->last, needle2), "message \"%s\" lacks \"%s\" / \"%s\"",
           env->last, needle1, needle2);
    EXPECT(api.GetRealStatus(c, fmi2LastSuccessfulTime, &t_after) == fmi2OK && t_after == 0.0,
           "the refused step moved the time to %g", t_after);
    SAY("fmi2DoStep(0, %g) -> %s \"%s\"; ", h, st2(st), env->last);
}

static void case_step_inf(void) {
    host_env_t env = {0};
    fmi2Component c = ctrl2_new(&env, "step_inf");
    EXPECT(c && ctrl2_init(c) == fmi2OK, "instantiate/initialise failed: %s", env.last);
    refused_step(c, &env, INFINITY, "communicationStepSize = inf", "finite communicationStepSize");
    if (case_failed) { api.FreeInstance(c); return; }
    refused_step(c, &env, NAN, "communicationStepSize = nan", "finite communicationStepSize");
    if (case_failed) { api.FreeInstance(c); return; }
    EXPECT(api.DoStep(c, 0.0, 5e-4, fmi2True) == fmi2OK, "a normal step after the refusals failed: %s", env.last);
    api.FreeInstance(c);
#ifdef CTRL_FMI3
    {
        env3_t e = {0};
        fmi3Boolean ev, term, early;
        fmi3Float64 last = -1.0;
        fmi3Status s;
        fmi3Instance i = fmi3InstantiateCoSimulation("step_inf3", CTRL_GUID, NULL, fmi3False, fmi3False, fmi3False,
                                                     fmi3False, NULL, 0, &e, env3_log, NULL);
        EXPECT(i && fmi3EnterInitializationMode(i, fmi3False, 0.0, 0.0, fmi3False, 0.0) == fmi3OK &&
               fmi3ExitInitializationMode(i) == fmi3OK, "FMI 3.0 instantiate/initialise failed: %s", e.last);
        env3_mark(&e);
        s = fmi3DoStep(i, 0.0, INFINITY, fmi3True, &ev, &term, &early, &last);
        EXPECT(s == fmi3Error && strstr(e.last, "fmi3DoStep") && strstr(e.last, "communicationStepSize = inf"),
               "fmi3DoStep(h = inf) answered %d \"%s\"", (int)s, e.last);
        EXPECT(last == 0.0, "fmi3DoStep(h = inf): lastSuccessfulTime = %g, expected 0", last);
        SAY("fmi3DoStep(0, inf) -> fmi3Error \"%s\"", e.last);
        fmi3FreeInstance(i);
    }
#endif
}

/* u of n samples (x_meas falling 1 um per sample), one step of Ts each */
static int run_u(fmi2Component c, int n, double *u) {
    fmi2ValueReference r = CVR_u, m = CVR_x_meas;
    int k;
    for (k = 0; k < n; k++) {
        fmi2Real x = 0.15 - 1e-6 * k;
        if (api.SetReal(c, &m, 1, &x) != fmi2OK || api.GetReal(c, &r, 1, &u[k]) != fmi2OK ||
            api.DoStep(c, k * 5e-4, 5e-4, fmi2True) != fmi2OK)
            return 0;
    }
    return 1;
}

static void case_step_huge(void) {
    host_env_t env = {0}, env0 = {0};
    fmi2Component c = ctrl2_new(&env, "step_huge"), c0 = ctrl2_new(&env0, "fresh");
    double u[20], u0[20];
    EXPECT(c && c0 && ctrl2_init(c) == fmi2OK && ctrl2_init(c0) == fmi2OK, "instantiate/initialise failed: %s", env.last);
    /* 1e9 s at Ts = 0.5 ms: 2e12 samples */
    refused_step(c, &env, 1e9, "spans 2000000000000 samples of Ts = 0.0005 s", "allowed at most 1000000 samples");
    if (!case_failed) {   /* the refused step changed nothing: the run goes on as a fresh instance's, to the bit */
        EXPECT(run_u(c, 20, u) && run_u(c0, 20, u0), "the run after the refusal failed: %s", env.last);
        EXPECT(memcmp(u, u0, sizeof u) == 0, "after the refused step u differs from a fresh run: %.17g vs %.17g", u[19], u0[19]);
    }
    api.FreeInstance(c);
    api.FreeInstance(c0);
}

static void case_step_tiny_ts(void) {
    host_env_t env = {0};
    fmi2Component c = ctrl2_new(&env, "step_tiny_ts");
    EXPECT(c && ctrl2_set(c, CVR_Ts, 1e-9) == fmi2OK && ctrl2_init(c) == fmi2OK, "initialise failed: %s", env.last);
    /* 0.1 s at Ts = 1 ns (the declared minimum): 1e8 samples */
    refused_step(c, &env, 0.1, "spans 100000000 samples of Ts = 1e-09 s", "communicationStepSize <= 0.001 s");
    if (!case_failed)   /* 1e4 samples: within the budget */
        EXPECT(api.DoStep(c, 0.0, 1e-5, fmi2True) == fmi2OK, "a step of 1e4 samples failed: %s", env.last);
    api.FreeInstance(c);
}

/* sample instants a double cannot tell apart: startTime 1e12 s (ulp 1.2e-4 s) at Ts = 0.5 ms */
static void case_step_coarse_time(void) {
    host_env_t env = {0};
    fmi2Component c = ctrl2_new(&env, "coarse_time");
    fmi2Status s;
    fmi2Real t_after = 0.0;
    EXPECT(c && api.SetupExperiment(c, fmi2False, 0.0, 1e12, fmi2False, 0.0) == fmi2OK &&
           api.EnterInitializationMode(c) == fmi2OK && api.ExitInitializationMode(c) == fmi2OK,
           "initialise at startTime 1e12 s failed: %s", env.last);
    host_env_mark(&env);
    s = api.DoStep(c, 1e12, 5e-4, fmi2True);
    EXPECT(s == fmi2Error && strstr(env.last, "a double resolves only 0.00012207 s") &&
           strstr(env.last, "16 ulp(t) <= Ts/8"), "a step at t = 1e12 s answered %s \"%s\"", st2(s), env.last);
    EXPECT(api.GetRealStatus(c, fmi2LastSuccessfulTime, &t_after) == fmi2OK && t_after == 1e12,
           "the refused step moved the time to %.17g", t_after);
    SAY("fmi2DoStep(1e12, 5e-4) -> %s \"%s\"", st2(s), env.last);
    api.FreeInstance(c);
}

#ifdef CTRL_FMI3
static fmi3Instance ctrl3_ready(env3_t *e, const char *name) {
    fmi3Instance i = fmi3InstantiateCoSimulation(name, CTRL_GUID, NULL, fmi3False, fmi3False, fmi3False, fmi3False,
                                                 NULL, 0, e, env3_log, NULL);
    if (!i) return NULL;
    if (fmi3EnterInitializationMode(i, fmi3False, 0.0, 0.0, fmi3False, 0.0) != fmi3OK ||
        fmi3ExitInitializationMode(i) != fmi3OK) {
        fmi3FreeInstance(i);
        return NULL;
    }
    return i;
}

static void case_get_float64_null(void) {
    env3_t e = {0};
    fmi3Instance i = ctrl3_ready(&e, "null_vr");
    fmi3Float64 v[2] = {0.0, 0.0};
    fmi3ValueReference vr[2] = {CVR_u, 0};
    fmi3Status s;
    EXPECT(i, "FMI 3.0 instantiate/initialise failed: %s", e.last);
    env3_mark(&e);
    s = fmi3GetFloat64(i, NULL, 1, v, 1);
    EXPECT(s == fmi3Error && e.n_since_mark > 0 && strstr(e.last, "NULL array"),
           "fmi3GetFloat64(NULL, 1) answered %d \"%s\"", (int)s, e.last);
    SAY("fmi3GetFloat64(instance, NULL, 1, v, 1) -> fmi3Error \"%s\"; ", e.last);
    env3_mark(&e);
    s = fmi3GetFloat64(i, vr, 2, NULL, 2);
    EXPECT(s == fmi3Error && strstr(e.last, "NULL array"), "fmi3GetFloat64(vr, NULL values) answered %d \"%s\"",
           (int)s, e.last);
    /* the time (value reference 0) beside an output still answers */
    EXPECT(fmi3GetFloat64(i, vr, 2, v, 2) == fmi3OK && v[1] == 0.0 && isfinite(v[0]), "u and time not read");
    fmi3FreeInstance(i);
}

/* the input clock tick (value reference 9, the description's) and Event Mode: NULL arrays and
 * output arguments, a reference that is no clock, the clock set in Step Mode, Event Mode entered
 * twice, a tick at an instant that is no sample instant, Step Mode left with a tick not taken,
 * a step in Event Mode and one past an untaken tick, Event Mode on an instance made without it:
 * each fmi3Error with the rule named; the ticks between them still sample (u finite, the
 * interval Ts) */
#define VR3_TICK 9u
#define REFUSED3(call, needle) do { env3_mark(&e); s = (call); \
        EXPECT(s == fmi3Error && e.n_since_mark > 0 && strstr(e.last, needle), "%s answered %d \"%s\"", #call, \
               (int)s, e.last); } while (0)
static void case_clock(void) {
    env3_t e = {0};
    fmi3Instance i = fmi3InstantiateCoSimulation("clock", CTRL_GUID, NULL, fmi3False, fmi3False, fmi3True, fmi3False,
                                                 NULL, 0, &e, env3_log, NULL), plain;
    fmi3ValueReference tick = VR3_TICK, bad = CVR_x_meas, ru = CVR_u;
    fmi3Clock on = fmi3ClockActive, off = fmi3ClockInactive;
    fmi3Boolean b1, b2, b3, b4, b5, ev, term, early;
    fmi3Float64 t_next, u = NAN, iv = 0.0, last;
    fmi3IntervalQualifier q;
    fmi3Status s;
    EXPECT(i && fmi3EnterInitializationMode(i, fmi3False, 0.0, 0.0, fmi3False, 0.0) == fmi3OK &&
           fmi3ExitInitializationMode(i) == fmi3OK, "instantiate with Event Mode and initialise: %s", e.last);
    /* in Event Mode after initialisation: the arguments */
    REFUSED3(fmi3SetClock(i, NULL, 1, &on), "NULL array");
    SAY("fmi3SetClock(NULL, 1) -> \"%s\"; ", e.last);
    REFUSED3(fmi3SetClock(i, &tick, 1, NULL), "NULL array");
    REFUSED3(fmi3SetClock(i, &bad, 1, &on), "no clock");
    SAY("x_meas as clock -> \"%s\"; ", e.last);
    REFUSED3(fmi3UpdateDiscreteStates(i, NULL, &b2, &b3, &b4, &b5, &t_next), "NULL output argument");
    REFUSED3(fmi3GetIntervalDecimal(i, &tick, 1, &iv, NULL), "NULL array");
    EXPECT(fmi3GetIntervalDecimal(i, &tick, 1, &iv, &q) == fmi3OK && iv == 5e-4 && q == fmi3IntervalChanged,
           "interval %g, qualifier %d: %s", iv, (int)q, e.last);
    /* the tick of t_0 */
    EXPECT(fmi3SetClock(i, &tick, 1, &on) == fmi3OK &&
           fmi3UpdateDiscreteStates(i, &b1, &b2, &b3, &b4, &b5, &t_next) == fmi3OK && !b1 && !b2 &&
           fmi3GetFloat64(i, &ru, 1, &u, 1) == fmi3OK && isfinite(u) && fmi3EnterStepMode(i) == fmi3OK,
           "the tick of t_0: %s", e.last);
    REFUSED3(fmi3SetClock(i, &tick, 1, &on), "Event Mode only");
    SAY("set in Step Mode -> \"%s\"; ", e.last);
    REFUSED3(fmi3DoStep(i, 0.0, 1e-3, fmi3True, &ev, &term, &early, &last), "passes the clock tick");
    SAY("step past a tick -> \"%s\"; ", e.last);
    EXPECT(fmi3DoStep(i, 0.0, 5e-4, fmi3True, &ev, &term, &early, &last) == fmi3OK && last == 5e-4 && !ev,
           "the step to the next tick: %s", e.last);
    EXPECT(fmi3EnterEventMode(i) == fmi3OK, "Event Mode at t_1: %s", e.last);
    REFUSED3(fmi3EnterEventMode(i), "already");
    SAY("Event Mode twice -> \"%s\"; ", e.last);
    REFUSED3(fmi3DoStep(i, 5e-4, 5e-4, fmi3True, &ev, &term, &early, &last), "Event Mode");
    EXPECT(fmi3SetClock(i, &tick, 1, &on) == fmi3OK, "the tick of t_1: %s", e.last);
    REFUSED3(fmi3EnterStepMode(i), "fmi3UpdateDiscreteStates first");
    EXPECT(fmi3UpdateDiscreteStates(i, &b1, &b2, &b3, &b4, &b5, &t_next) == fmi3OK &&
           fmi3GetFloat64(i, &ru, 1, &u, 1) == fmi3OK && isfinite(u), "the tick of t_1: %s", e.last);
    /* a second tick at t_1: no sample instant any more */
    EXPECT(fmi3SetClock(i, &tick, 1, &on) == fmi3OK, "set again: %s", e.last);
    REFUSED3(fmi3UpdateDiscreteStates(i, &b1, &b2, &b3, &b4, &b5, &t_next), "next sample instant");
    SAY("tick off the sample instants -> \"%s\"; ", e.last);
    EXPECT(fmi3SetClock(i, &tick, 1, &off) == fmi3OK && fmi3EnterStepMode(i) == fmi3OK, "deactivate: %s", e.last);
    fmi3FreeInstance(i);
    plain = ctrl3_ready(&e, "plain");
    EXPECT(plain, "instantiate without Event Mode: %s", e.last);
    REFUSED3(fmi3EnterEventMode(plain), "eventModeUsed = false");
    SAY("no Event Mode -> \"%s\"", e.last);
    fmi3FreeInstance(plain);
}

static void case_boolean_size_max3(void) {
    env3_t e = {0};
    fmi3Instance i = ctrl3_ready(&e, "bool_max");
    fmi3ValueReference *vr = (fmi3ValueReference *)malloc(sizeof *vr);
    fmi3Boolean *v = (fmi3Boolean *)malloc(sizeof *v);
    fmi3Status s;
    EXPECT(i && vr && v, "FMI 3.0 instantiate/initialise failed: %s", e.last);
    vr[0] = CVR_zpetc_on;
    v[0] = fmi3False;
    env3_mark(&e);
    s = fmi3GetBoolean(i, vr, SIZE_MAX, v, SIZE_MAX);
    EXPECT(s == fmi3Error && strstr(e.last, "allowed at most"), "fmi3GetBoolean(n = SIZE_MAX) answered %d \"%s\"",
           (int)s, e.last);
    SAY("fmi3GetBoolean(n = SIZE_MAX) -> fmi3Error \"%s\"; ", e.last);
    env3_mark(&e);
    s = fmi3SetBoolean(i, vr, SIZE_MAX, v, SIZE_MAX);
    EXPECT(s == fmi3Error && strstr(e.last, "allowed at most"), "fmi3SetBoolean(n = SIZE_MAX) answered %d \"%s\"",
           (int)s, e.last);
    SAY("fmi3SetBoolean(n = SIZE_MAX) -> fmi3Error \"%s\"", e.last);
    EXPECT(fmi3GetBoolean(i, vr, 1, v, 1) == fmi3OK && v[0] == fmi3False, "one Boolean no longer reads");
    free(vr);
    free(v);
    fmi3FreeInstance(i);
}
#endif

static void case_boolean_size_max2(void) {
    host_env_t env = {0};
    fmi2Component c = ctrl2_new(&env, "bool_max2");
    fmi2ValueReference *vr = (fmi2ValueReference *)malloc(sizeof *vr);
    fmi2Boolean *v = (fmi2Boolean *)malloc(sizeof *v);
    fmi2Real *r = (fmi2Real *)malloc(sizeof *r);
    fmi2Status s;
    EXPECT(c && vr && v && r && ctrl2_init(c) == fmi2OK, "instantiate/initialise failed: %s", env.last);
    vr[0] = CVR_pid_anti_windup;
    v[0] = fmi2False;
    host_env_mark(&env);
    s = api.GetBoolean(c, vr, SIZE_MAX, v);
    EXPECT(s == fmi2Error && strstr(env.last, "allowed at most"), "fmi2GetBoolean(nvr = SIZE_MAX) answered %s \"%s\"",
           st2(s), env.last);
    SAY("fmi2GetBoolean(nvr = SIZE_MAX) -> %s \"%s\"; ", st2(s), env.last);
    s = api.SetBoolean(c, vr, SIZE_MAX, v);
    EXPECT(s == fmi2Error && strstr(env.last, "allowed at most"), "fmi2SetBoolean(nvr = SIZE_MAX) answered %s", st2(s));
    vr[0] = CVR_u;
    s = api.GetReal(c, vr, SIZE_MAX, r);
    EXPECT(s == fmi2Error && strstr(env.last, "allowed at most"), "fmi2GetReal(nvr = SIZE_MAX) answered %s", st2(s));
    vr[0] = CVR_pid_Kp;
    r[0] = 1.0;
    s = api.SetReal(c, vr, SIZE_MAX, r);
    EXPECT(s == fmi2Error && strstr(env.last, "allowed at most"), "fmi2SetReal(nvr = SIZE_MAX) answered %s", st2(s));
    SAY("fmi2SetBoolean/GetReal/SetReal(nvr = SIZE_MAX) -> fmi2Error");
    free(vr);
    free(v);
    free(r);
    api.FreeInstance(c);
}

/* an unstable state-space controller (Ac = 2 I, Cc = [1, -1]): its states double every sample
 * until they overflow, where u = inf - inf = NaN; no getter may answer OK with it */
static const unsigned UNSTABLE_VR[6] = {CVRA2_ss_Ac[1][1], CVRA2_ss_Ac[2][2], CVRA_ss_By[1], CVRA_ss_By[2],
                                        CVRA_ss_Cc[1], CVRA_ss_Cc[2]};
static const double UNSTABLE_VALUE[6] = {2.0, 2.0, 1.0, 2.0, 1.0, -1.0};
static const unsigned UNSTABLE_IVR[2] = {CVR_ctrl_type, CVR_ss_n};
static const int UNSTABLE_IVALUE[2] = {1, 2};

static void unstable_values(fmi2Component c) {
    api.SetInteger(c, UNSTABLE_IVR, 2, UNSTABLE_IVALUE);
    api.SetReal(c, UNSTABLE_VR, 6, UNSTABLE_VALUE);
}

static void case_unstable_state_space(void) {
    host_env_t env = {0};
    fmi2Component c = ctrl2_new(&env, "unstable");
    fmi2ValueReference vr[4] = {CVR_u, CVR_x_cmd, CVR_u_ff, CVR_r_x};
    fmi2Real v[4];
    int k, errored = 0;
    EXPECT(c, "instantiate failed: %s", env.last);
    unstable_values(c);
    EXPECT(ctrl2_init(c) == fmi2OK, "initialise failed: %s", env.last);
    for (k = 0; k < 4000 && !errored; k++) {
        fmi2Status s;
        host_env_mark(&env);
        s = api.GetReal(c, vr, 4, v);
        if (s == fmi2OK)
            EXPECT(isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]) && isfinite(v[3]),
                   "sample %d: fmi2GetReal answered fmi2OK with u = %g, x_cmd = %g", k, v[0], v[1]);
        else errored = 1;
        if (!errored) {
            host_env_mark(&env);
            s = api.DoStep(c, k * 5e-4, 5e-4, fmi2True);
            if (s != fmi2OK) errored = 1;
        }
        if (errored)
            EXPECT(s == fmi2Error && strstr(env.last, "state-space state s[") && strstr(env.last, "not finite"),
                   "sample %d: answered %s \"%s\"", k, st2(s), env.last);
    }
    EXPECT(errored, "4000 samples of an unstable controller all answered fmi2OK");
    SAY("sample %d -> %s \"%s\"; ", k - 1, "fmi2Error", env.last);
    /* in state Error the outputs are those of the last finite sample */
    EXPECT(api.GetReal(c, vr, 4, v) <= fmi2Error && isfinite(v[0]), "after the error u = %g", v[0]);
    api.FreeInstance(c);
#ifdef CTRL_FMI3
    {
        env3_t e = {0};
        fmi3Instance i = fmi3InstantiateCoSimulation("unstable3", CTRL_GUID, NULL, fmi3False, fmi3False, fmi3False,
                                                     fmi3False, NULL, 0, &e, env3_log, NULL);
        fmi3Float64 u;
        fmi3ValueReference r = CVR_u;
        fmi3Boolean ev, term, early;
        fmi3Float64 last;
        fmi3Status s = fmi3OK;
        EXPECT(i, "FMI 3.0 instantiate failed: %s", e.last);
        EXPECT(fmi3SetInt32(i, UNSTABLE_IVR, 2, UNSTABLE_IVALUE, 2) == fmi3OK &&
               fmi3SetFloat64(i, UNSTABLE_VR, 6, UNSTABLE_VALUE, 6) == fmi3OK, "FMI 3.0 values refused: %s", e.last);
        EXPECT(fmi3EnterInitializationMode(i, fmi3False, 0.0, 0.0, fmi3False, 0.0) == fmi3OK &&
               fmi3ExitInitializationMode(i) == fmi3OK, "FMI 3.0 initialise failed: %s", e.last);
        for (k = 0; k < 4000 && s == fmi3OK; k++) {
            s = fmi3GetFloat64(i, &r, 1, &u, 1);
            if (s == fmi3OK) EXPECT(isfinite(u), "FMI 3.0 sample %d: fmi3GetFloat64 answered fmi3OK with u = %g", k, u);
            if (s == fmi3OK) s = fmi3DoStep(i, k * 5e-4, 5e-4, fmi3True, &ev, &term, &early, &last);
        }
        EXPECT(s == fmi3Error && strstr(e.last, "not finite"), "FMI 3.0: answered %d \"%s\"", (int)s, e.last);
        SAY("FMI 3.0 -> fmi3Error \"%s\"", e.last);
        fmi3FreeInstance(i);
    }
#endif
}

/* a parameter outside its declared range refused at the set, one inside it whose derived
 * sample count does not fit refused at initialisation; both name the variable and the rule */
static void case_ref_duration(void) {
    host_env_t env = {0};
    fmi2Component c = ctrl2_new(&env, "ref_duration");
    fmi2Status s;
    EXPECT(c, "instantiate failed");
    host_env_mark(&env);
    s = ctrl2_set(c, CVR_ref_duration, 1e308);
    EXPECT(s == fmi2Error && strstr(env.last, "ref.duration = 1e+308") && strstr(env.last, "allowed"),
           "ref.duration = 1e308 answered %s \"%s\"", st2(s), env.last);
    SAY("ref.duration = 1e308 -> %s \"%s\"; ", st2(s), env.last);
    EXPECT(ctrl2_init(c) == fmi2OK, "initialise after the refusal failed: %s", env.last);
    api.FreeInstance(c);
}

static void case_ref_duration_samples(void) {
    host_env_t env = {0};
    fmi2Component c = ctrl2_new(&env, "ref_duration_samples");
    fmi2Status s;
    EXPECT(c && ctrl2_set(c, CVR_Ts, 1e-9) == fmi2OK && ctrl2_set(c, CVR_ref_source, 1) == fmi2OK &&
           ctrl2_set(c, CVR_ref_duration, 1e9) == fmi2OK, "in-range values refused: %s", env.last);
    host_env_mark(&env);
    s = ctrl2_init(c);
    EXPECT(s == fmi2Error && strstr(env.last, "ref.duration = 1000000000 s") && strstr(env.last, "allowed at most 1e+15 samples"),
           "ref.duration = 1e9 s at Ts = 1e-9 s answered %s \"%s\"", st2(s), env.last);
    SAY("ref.duration = 1e9 s at Ts = 1 ns -> %s \"%s\"", st2(s), env.last);
    api.FreeInstance(c);
}

static void case_ref_point_to_point(void) {
    host_env_t env = {0};
    fmi2Component c = ctrl2_new(&env, "ref_p2p");
    fmi2Status s;
    EXPECT(c && ctrl2_set(c, CVR_ref_source, 2) == fmi2OK, "instantiate failed");
    host_env_mark(&env);
    s = ctrl2_set(c, CVR_ref_speed, 1e-300);
    EXPECT(s == fmi2Error && strstr(env.last, "ref.speed = 1e-300") && strstr(env.last, "allowed"),
           "ref.speed = 1e-300 answered %s \"%s\"", st2(s), env.last);
    SAY("ref.speed = 1e-300 -> %s \"%s\"; ", st2(s), env.last);
    s = ctrl2_set(c, CVR_ref_accel, 1e300);
    EXPECT(s == fmi2Error && strstr(env.last, "ref.accel = 1") && strstr(env.last, "e+300 is out of range"),
           "ref.accel = 1e300 answered %s \"%s\"", st2(s), env.last);
    api.FreeInstance(c);
}

static void case_ref_p2p_samples(void) {
    host_env_t env = {0};
    fmi2Component c = ctrl2_new(&env, "ref_p2p_samples");
    fmi2Status s;
    EXPECT(c && ctrl2_set(c, CVR_ref_source, 2) == fmi2OK, "instantiate failed");
    /* inside the ranges: a 2 km move at 1 nm/s, sampled every ns: 2e21 samples */
    EXPECT(ctrl2_set(c, CVR_Ts, 1e-9) == fmi2OK && ctrl2_set(c, CVR_ref_speed, 1e-9) == fmi2OK &&
           ctrl2_set(c, CVR_ref_accel, 1e6) == fmi2OK && ctrl2_set(c, CVR_ref_x_start, -1000.0) == fmi2OK &&
           ctrl2_set(c, CVR_ref_x_end, 1000.0) == fmi2OK, "in-range values refused: %s", env.last);
    host_env_mark(&env);
    s = ctrl2_init(c);
    EXPECT(s == fmi2Error && strstr(env.last, "ref.speed = 1.0000000000000001e-09 m/s") &&
           strstr(env.last, "allowed at most 1e+15 samples"), "the 2e21-sample move answered %s \"%s\"", st2(s), env.last);
    SAY("2 km at 1 nm/s, Ts = 1 ns -> %s \"%s\"", st2(s), env.last);
    api.FreeInstance(c);
    /* a move inside the limits runs: the reference leaves ref.x_start */
    {
        fmi2ValueReference r = CVR_r_x;
        fmi2Real x = 0.0;
        int k;
        c = ctrl2_new(&env, "ref_p2p_runs");
        EXPECT(c && ctrl2_set(c, CVR_ref_source, 2) == fmi2OK && ctrl2_set(c, CVR_ref_dwell, 0.0) == fmi2OK &&
               ctrl2_init(c) == fmi2OK, "the default move did not initialise: %s", env.last);
        for (k = 0; k < 100; k++) EXPECT(api.DoStep(c, k * 5e-4, 5e-4, fmi2True) == fmi2OK, "step %d failed", k);
        EXPECT(api.GetReal(c, &r, 1, &x) == fmi2OK && x > 0.13 + 1e-6, "the move stayed at its start: r_x = %.17g", x);
        api.FreeInstance(c);
    }
}

/* the linear controller (ctrl.type 4) at its largest order, every element of lti.* set: A a
 * stable coupled 8 x 8 (0.6 I plus off-diagonal 0.02), B, C, L, s0, s0_r all nonzero, a clamp that
 * acts; the order past the table (lti.n = 9) refused first; 3000 samples of a moving x_meas all
 * answer fmi2OK with |u| <= u_limit; then a non-finite element is refused naming the variable,
 * and the instance keeps running */
static void case_lti_full_order(void) {
    host_env_t env = {0};
    fmi2Component c = ctrl2_new(&env, "lti_full_order");
    fmi2ValueReference r = CVR_u;
    fmi2Real u;
    fmi2Status st;
    int i, j, k, clamped = 0;
    EXPECT(c, "instantiate failed: %s", env.last);
    st = ctrl2_set(c, CVR_lti_n, 9);
    EXPECT(st == fmi2Error && strstr(env.last, "lti.n") && strstr(env.last, "9"), "lti.n = 9: %s \"%s\"", st2(st), env.last);
    EXPECT(ctrl2_set(c, CVR_ctrl_type, 4) == fmi2OK && ctrl2_set(c, CVR_lti_n, 8) == fmi2OK &&
           ctrl2_set(c, CVR_u_limit, 0.5) == fmi2OK, "the switches were refused: %s", env.last);
    for (i = 1; i <= 8; i++) {
        for (j = 1; j <= 8; j++)
            EXPECT(ctrl2_set(c, CVRA2_lti_A[i][j], i == j ? 0.6 : 0.02) == fmi2OK, "lti.A refused: %s", env.last);
        EXPECT(ctrl2_set(c, CVRA2_lti_B[i][1], 10.0 * i) == fmi2OK && ctrl2_set(c, CVRA2_lti_B[i][2], -10.0 * i) == fmi2OK &&
               ctrl2_set(c, CVRA_lti_C[i], 0.5 / i) == fmi2OK && ctrl2_set(c, CVRA_lti_L[i], 0.1) == fmi2OK &&
               ctrl2_set(c, CVRA_lti_s0[i], 1e-3 * i) == fmi2OK && ctrl2_set(c, CVRA_lti_s0_r[i], -1e-3) == fmi2OK,
               "lti.B/C/L/s0 refused: %s", env.last);
    }
    EXPECT(ctrl2_set(c, CVRA_lti_D[1], 100.0) == fmi2OK && ctrl2_set(c, CVRA_lti_D[2], -100.0) == fmi2OK,
           "lti.D refused: %s", env.last);
    EXPECT(ctrl2_init(c) == fmi2OK, "initialise failed: %s", env.last);
    for (k = 0; k < 3000; k++) {
        fmi2ValueReference m = CVR_x_meas;
        fmi2Real x = 0.15 + 0.01 * sin(k * 1e-2);
        EXPECT(api.SetReal(c, &m, 1, &x) == fmi2OK && api.GetReal(c, &r, 1, &u) == fmi2OK, "sample %d: %s", k, env.last);
        EXPECT(isfinite(u) && fabs(u) <= 0.5, "sample %d: u = %g", k, u);
        clamped += fabs(u) == 0.5;
        EXPECT(api.DoStep(c, k * 5e-4, 5e-4, fmi2True) == fmi2OK, "step %d: %s", k, env.last);
    }
    EXPECT(clamped > 0, "the clamp never acted");
    st = ctrl2_set(c, CVRA2_lti_A[8][8], NAN);
    EXPECT(st == fmi2Error && strstr(env.last, "lti.A[8,8]") && strstr(env.last, "finite"),
           "lti.A[8,8] = NaN: %s \"%s\"", st2(st), env.last);
    EXPECT(api.GetReal(c, &r, 1, &u) == fmi2OK && isfinite(u) && api.DoStep(c, 3000 * 5e-4, 5e-4, fmi2True) == fmi2OK,
           "after the refusal: %s", env.last);
    SAY("%d of 3000 samples clamped; lti.n = 9 and lti.A[8,8] = NaN refused", clamped);
    api.FreeInstance(c);
}

/* an unstable linear controller (A = 2 I, C = [1, -1], fed by x_meas): the states overflow,
 * where u = inf - inf = NaN: the sample is refused naming lti.s, no getter answers OK with it */
static void case_unstable_lti(void) {
    host_env_t env = {0};
    fmi2Component c = ctrl2_new(&env, "unstable_lti");
    fmi2ValueReference r = CVR_u;
    fmi2Real u;
    fmi2Status s = fmi2OK;
    int k;
    EXPECT(c, "instantiate failed: %s", env.last);
    EXPECT(ctrl2_set(c, CVR_ctrl_type, 4) == fmi2OK && ctrl2_set(c, CVR_lti_n, 2) == fmi2OK &&
           ctrl2_set(c, CVRA2_lti_A[1][1], 2.0) == fmi2OK && ctrl2_set(c, CVRA2_lti_A[2][2], 2.0) == fmi2OK &&
           ctrl2_set(c, CVRA2_lti_B[1][2], 1.0) == fmi2OK && ctrl2_set(c, CVRA2_lti_B[2][2], 2.0) == fmi2OK &&
           ctrl2_set(c, CVRA_lti_C[1], 1.0) == fmi2OK && ctrl2_set(c, CVRA_lti_C[2], -1.0) == fmi2OK &&
           ctrl2_init(c) == fmi2OK, "set-up failed: %s", env.last);
    for (k = 0; k < 4000 && s == fmi2OK; k++) {
        s = api.GetReal(c, &r, 1, &u);
        if (s == fmi2OK) EXPECT(isfinite(u), "sample %d: fmi2GetReal answered fmi2OK with u = %g", k, u);
        if (s == fmi2OK) s = api.DoStep(c, k * 5e-4, 5e-4, fmi2True);
    }
    EXPECT(s == fmi2Error && strstr(env.last, "lti.s[") && strstr(env.last, "not finite"),
           "sample %d: answered %s \"%s\"", k, st2(s), env.last);
    SAY("sample %d -> fmi2Error \"%s\"", k - 1, env.last);
    api.FreeInstance(c);
}

/* ctrl.delay: out of its range 0..1 refused naming it; fixed, so refused after initialisation;
 * with 1, the sample at t_k runs on the x_meas of t_k-1 -- what a delay-0 instance gives a
 * master that reads u after the step and sets x_meas after the read (Jacobi): 40 samples of
 * the PID (x_ref 0.15 m, x_meas falling 1 um per sample) equal to the bit */
static void case_delay(void) {
    host_env_t env = {0};
    fmi2Component a = ctrl2_new(&env, "delay1"), b;
    fmi2ValueReference r = CVR_u, m = CVR_x_meas;
    double ua[40], ub[40];
    int k;
    EXPECT(a != NULL, "instantiate failed: %s", env.last);
    EXPECT(ctrl2_set(a, CVR_ctrl_delay, 2) == fmi2Error && strstr(env.last, "ctrl.delay = 2") &&
           strstr(env.last, "out of range"), "ctrl.delay = 2: \"%s\"", env.last);
    SAY("ctrl.delay = 2 -> \"%s\"; ", env.last);
    EXPECT(ctrl2_set(a, CVR_ctrl_delay, -1) == fmi2Error && strstr(env.last, "ctrl.delay = -1"),
           "ctrl.delay = -1: \"%s\"", env.last);
    EXPECT(ctrl2_set(a, CVR_ctrl_delay, 1) == fmi2OK && ctrl2_set(a, CVR_x_ref, 0.15) == fmi2OK &&
           ctrl2_init(a) == fmi2OK, "ctrl.delay = 1 and initialise: %s", env.last);
    EXPECT(ctrl2_set(a, CVR_ctrl_delay, 0) == fmi2Error && strstr(env.last, "ctrl.delay"),
           "ctrl.delay set after initialisation: \"%s\"", env.last);
    SAY("after initialisation -> \"%s\"; ", env.last);
    EXPECT(run_u(a, 40, ua), "the delay-1 run failed: %s", env.last);
    api.FreeInstance(a);
    b = ctrl2_new(&env, "jacobi");
    EXPECT(b && ctrl2_set(b, CVR_x_ref, 0.15) == fmi2OK && ctrl2_init(b) == fmi2OK,
           "instantiate/initialise failed: %s", env.last);
    for (k = 0; k < 40; k++) {
        fmi2Real x = 0.15 - 1e-6 * k;
        if (k == 0) EXPECT(api.SetReal(b, &m, 1, &x) == fmi2OK, "x_meas: %s", env.last);
        EXPECT(api.GetReal(b, &r, 1, &ub[k]) == fmi2OK && api.SetReal(b, &m, 1, &x) == fmi2OK &&
               api.DoStep(b, k * 5e-4, 5e-4, fmi2True) == fmi2OK, "Jacobi sample %d: %s", k, env.last);
    }
    api.FreeInstance(b);
    for (k = 0; k < 40; k++)
        EXPECT(ua[k] == ub[k], "sample %d: u = %.17g with ctrl.delay 1, %.17g read before the set", k, ua[k], ub[k]);
    EXPECT(ua[39] != ua[1], "u did not change over the run (%.17g)", ua[1]);
    SAY("40 samples equal to the bit (u[39] = %.6g V)", ua[39]);
}

typedef struct { const char *name; void (*run)(void); } case_t;
static const case_t CASES[] = {
    {"step_inf", case_step_inf},
    {"step_huge", case_step_huge},
    {"step_tiny_ts", case_step_tiny_ts},
    {"step_coarse_time", case_step_coarse_time},
#ifdef CTRL_FMI3
    {"get_float64_null", case_get_float64_null},
    {"boolean_size_max3", case_boolean_size_max3},
    {"clock", case_clock},
#endif
    {"boolean_size_max2", case_boolean_size_max2},
    {"unstable_state_space", case_unstable_state_space},
    {"unstable_lti", case_unstable_lti},
    {"lti_full_order", case_lti_full_order},
    {"ref_duration", case_ref_duration},
    {"ref_duration_samples", case_ref_duration_samples},
    {"ref_point_to_point", case_ref_point_to_point},
    {"ref_p2p_samples", case_ref_p2p_samples},
    {"delay", case_delay},
};

static int hostile_main(int argc, char **argv) {
    size_t k;
    int n_pass = 0, n_fail = 0;
    long live0 = host_live_allocations();
    for (k = 0; k < sizeof CASES / sizeof CASES[0]; k++) {
        if (argc > 0 && strcmp(argv[0], CASES[k].name) != 0) continue;
        answer[0] = 0;
        case_failed = 0;
        CASES[k].run();
        printf("%s %s: %s\n", case_failed ? "FAIL" : "PASS", CASES[k].name, answer);
        fflush(stdout);
        if (case_failed) n_fail++; else n_pass++;
    }
    if (n_pass + n_fail == 0) { fprintf(stderr, "no case %s\n", argc > 0 ? argv[0] : ""); return 2; }
    if (host_live_allocations() != live0) {
        printf("FAIL leak: %ld callback allocations left\n", host_live_allocations() - live0);
        n_fail++;
    }
    printf("%d passed, %d failed\n", n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
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
