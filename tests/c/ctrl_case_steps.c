/* Hostile cases of fmi2DoStep (a step size that is not finite, spans too many samples or a
 * time a double cannot resolve) and of ctrl.delay (see ctrl_hostile.h). */
#include "ctrl_hostile.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

void case_step_inf(void) {
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

void case_step_huge(void) {
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

void case_step_tiny_ts(void) {
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
void case_step_coarse_time(void) {
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

/* ctrl.delay: out of its range 0..1 refused naming it; fixed, so refused after initialisation;
 * with 1, the sample at t_k runs on the x_meas of t_k-1 -- what a delay-0 instance gives a
 * master that reads u after the step and sets x_meas after the read (Jacobi): 40 samples of
 * the PID (x_ref 0.15 m, x_meas falling 1 um per sample) equal to the bit */
void case_delay(void) {
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
