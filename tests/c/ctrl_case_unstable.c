/* Hostile unstable controllers: state space and linear, their states overflowing (see
 * ctrl_hostile.h). */
#include "ctrl_hostile.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

void case_unstable_state_space(void) {
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

/* an unstable linear controller (A = 2 I, C = [1, -1], fed by x_meas): the states overflow,
 * where u = inf - inf = NaN: the sample is refused naming lti.s, no getter answers OK with it */
void case_unstable_lti(void) {
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
