/* Hostile sizes and values: SIZE_MAX arrays, reference parameters out of range or with too
 * many samples, the linear controller at its largest order (see ctrl_hostile.h). */
#include "ctrl_hostile.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void case_boolean_size_max2(void) {
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

/* a parameter outside its declared range refused at the set, one inside it whose derived
 * sample count does not fit refused at initialisation; both name the variable and the rule */
void case_ref_duration(void) {
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

void case_ref_duration_samples(void) {
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

void case_ref_point_to_point(void) {
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

void case_ref_p2p_samples(void) {
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
void case_lti_full_order(void) {
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
