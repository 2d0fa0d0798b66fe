/* The FMI 3.0 host's robustness parts (see fmi3_host.c): the FMU state (round trips continuing
 * bit-identically, every flipped byte and truncation refused), parameter limits, calls in wrong
 * states, and many instances created and freed. */
#include "fmi3_host.h"

/* ---------------------------------------------------------------- FMU state */

void part_state(void) {
    static cs_run_t a, b, d;
    env3_t env, env2;
    fmi3Instance c = cs_open(&env, 0, 1, &a), c2;
    fmi3FMUState s0 = NULL, s1 = NULL, s2 = NULL;
    fmi3Byte *buf;
    size_t size = 0, i;
    long flips = 0, flips_refused = 0, truncs = 0, truncs_refused = 0;
    const int K0 = 300, K1 = 600;
    cs_steps(c, &env, 0, &a, 0, K0);
    CHECK(fmi3GetFMUState(c, &s0) == fmi3OK && s0, "fmi3GetFMUState", &env);
    CHECK(fmi3SerializedFMUStateSize(c, s0, &size) == fmi3OK && size > 0, "fmi3SerializedFMUStateSize", &env);
    buf = (fmi3Byte *)malloc(size);
    if (!buf) fail("out of memory", NULL);
    CHECK(fmi3SerializeFMUState(c, s0, buf, size) == fmi3OK, "fmi3SerializeFMUState", &env);
    b = a;
    d = a;
    cs_steps(c, &env, 0, &a, K0, K1);
    /* back with fmi3SetFMUState of the kept state */
    CHECK(fmi3SetFMUState(c, s0) == fmi3OK, "fmi3SetFMUState", &env);
    cs_steps(c, &env, 0, &b, K0, K1);
    CHECK(memcmp(a.x, b.x, sizeof a.x) == 0, "continuing after fmi3SetFMUState is not bit-identical", NULL);
    /* the serialised state into the same instance */
    CHECK(fmi3DeserializeFMUState(c, buf, size, &s1) == fmi3OK && s1, "fmi3DeserializeFMUState", &env);
    CHECK(fmi3SetFMUState(c, s1) == fmi3OK, "fmi3SetFMUState of a deserialised state", &env);
    cs_steps(c, &env, 0, &b, K0, K1);
    CHECK(memcmp(a.x, b.x, sizeof a.x) == 0, "continuing after deserialising is not bit-identical", NULL);
    /* ... and into a fresh instance */
    c2 = cs_open(&env2, 0, 1, &b);
    CHECK(fmi3DeserializeFMUState(c2, buf, size, &s2) == fmi3OK && s2, "deserialise into a fresh instance", &env2);
    CHECK(fmi3SetFMUState(c2, s2) == fmi3OK, "fmi3SetFMUState into a fresh instance", &env2);
    cs_steps(c2, &env2, 0, &d, K0, K1);
    CHECK(memcmp(a.x + K0, d.x + K0, sizeof(double) * (K1 - K0 + 1)) == 0,
          "a fresh instance continuing from the deserialised state is not bit-identical", NULL);
    /* every flipped byte and every truncation is refused */
    for (i = 0; i < size; i++) {
        fmi3FMUState s = NULL;
        fmi3Status st;
        buf[i] ^= 0xFF;
        env.n_msgs = 0;
        st = fmi3DeserializeFMUState(c, buf, size, &s);
        buf[i] ^= 0xFF;
        flips++;
        if (st == fmi3Error && env.n_msgs > 0) flips_refused++;
        if (s) fmi3FreeFMUState(c, &s);
    }
    for (i = 0; i < size; i++) {
        fmi3FMUState s = NULL;
        fmi3Status st;
        fmi3Byte *cut = (fmi3Byte *)malloc(i + 1);   /* exactly i bytes readable (+1: malloc(0)) */
        if (!cut) fail("out of memory", NULL);
        memcpy(cut, buf, i);
        env.n_msgs = 0;
        st = fmi3DeserializeFMUState(c, cut, i, &s);
        free(cut);
        truncs++;
        if (st == fmi3Error && env.n_msgs > 0) truncs_refused++;
        if (s) fmi3FreeFMUState(c, &s);
    }
    CHECK(flips_refused == flips, "a state with a flipped byte was accepted", NULL);
    CHECK(truncs_refused == truncs, "a truncated state was accepted", NULL);
    CHECK(fmi3FreeFMUState(c, &s0) == fmi3OK && fmi3FreeFMUState(c, &s1) == fmi3OK &&
          fmi3FreeFMUState(c2, &s2) == fmi3OK && !s0 && !s1 && !s2, "fmi3FreeFMUState", &env);
    free(buf);
    fmi3FreeInstance(c);
    fmi3FreeInstance(c2);
    printf("{\"state\": {\"bytes\": %zu, \"continued_steps\": %d, \"bit_identical\": true, \"byte_flips\": %ld, "
           "\"flips_refused\": %ld, \"truncations\": %ld, \"truncations_refused\": %ld, \"x_at_0.6s\": %.17g}}\n",
           size, K1 - K0, flips, flips_refused, truncs, truncs_refused, a.x[K1]);
}

/* ---------------------------------------------------------------- parameter limits */

void part_limits(void) {
    env3_t env;
    fmi3Instance c = cs_new(&env, "limits", 0, 0);
    long vars = 0, beyond = 0, nan_refused = 0;
    int r;
    CHECK(c != NULL, "CS instantiation", &env);
    for (r = 0; r < MODEL3_NVARS; r++) {
        const model_var3_t *v3 = &MODEL3_VARS[r];
        const model_var_t *v;
        fmi3ValueReference vr = v3->vr;
        size_t n = v3->kind == 1 ? 5 : 1, j;   /* arrays: friction.N = 5 (the default) */
        fmi3Float64 vals[NX_MAX], probe[3];
        int p;
        if (v3->type != 'R' || (v3->kind != 1 && v3->kind != 3)) continue;
        v = &MODEL_VARS[MODEL_VR_INDEX[MODEL3_ELEMS[v3->first]]];
        if (v->causality != 'p' && v->causality != 'i') continue;
        vars++;
        probe[0] = NAN;
        probe[1] = v->max < 1e300 ? v->max + fmax(1.0, fabs(v->max)) : NAN;
        probe[2] = v->min > -1e300 ? v->min - fmax(1.0, fabs(v->min)) : NAN;
        for (p = 0; p < 3; p++) {
            if (p > 0 && isnan(probe[p])) continue;
            for (j = 0; j < n; j++) vals[j] = v->start;
            vals[n - 1] = probe[p];
            env.last[0] = '\0';
            CHECK(fmi3SetFloat64(c, &vr, 1, vals, n) == fmi3Error, "a value out of range or NaN was accepted",
                  NULL);
            if (!strstr(env.last, v3->name)) {
                char why[1400];
                snprintf(why, sizeof why, "%s = %g refused without naming it: %s", v3->name, probe[p], env.last);
                fail("message", why);
            }
            if (p == 0) nan_refused++; else beyond++;
        }
    }
    /* the instance is still usable: nothing was set */
    CHECK(initialise(c, 0.0) == 0, "initialisation after refused sets", &env);
    fmi3FreeInstance(c);
    printf("{\"limits\": {\"variables\": %ld, \"nan_refused\": %ld, \"beyond_refused\": %ld, "
           "\"message_names_variable\": true}}\n", vars, nan_refused, beyond);
}

/* ---------------------------------------------------------------- wrong states */

static long wrong_refused;

static void refused(fmi3Status st, env3_t *env, const char *call) {
    n_checks++;
    if (st != fmi3Error) fail("a call in a wrong state was not refused", call);
    if (!strstr(env->last, call)) {
        char why[1400];
        snprintf(why, sizeof why, "%s refused without naming itself: %s", call, env->last);
        fail("message", why);
    }
    wrong_refused++;
}

void part_wrong_states(void) {
    env3_t env;
    fmi3Instance c;
    fmi3Boolean a, b, d, e, f;
    fmi3Float64 t, x[NX_MAX] = {0};
    const fmi3ValueReference vr_N = VR_friction_N;
    const fmi3Int32 five = 5;
    /* co-simulation */
    c = cs_new(&env, "wrong", 0, 0);
    refused(fmi3DoStep(c, 0.0, 1e-3, fmi3False, &a, &b, &d, &t), &env, "fmi3DoStep");
    fmi3FreeInstance(c);
    c = cs_new(&env, "wrong", 0, 0);
    refused(fmi3ExitInitializationMode(c), &env, "fmi3ExitInitializationMode");
    fmi3FreeInstance(c);
    c = cs_new(&env, "wrong", 0, 0);
    initialise(c, 0.0);
    refused(fmi3EnterEventMode(c), &env, "fmi3EnterEventMode");   /* eventModeUsed = false */
    fmi3FreeInstance(c);
    c = cs_new(&env, "wrong", 0, 0);
    initialise(c, 0.0);
    refused(fmi3EnterConfigurationMode(c), &env, "fmi3EnterConfigurationMode");
    fmi3FreeInstance(c);
    c = cs_new(&env, "wrong", 0, 0);
    initialise(c, 0.0);
    refused(fmi3GetContinuousStateDerivatives(c, x, 7), &env, "fmi3GetContinuousStateDerivatives");
    fmi3FreeInstance(c);
    c = cs_new(&env, "wrong", 1, 0);
    initialise(c, 0.0);
    refused(fmi3DoStep(c, 0.0, 1e-3, fmi3False, &a, &b, &d, &t), &env, "fmi3DoStep");   /* still in Event Mode */
    fmi3FreeInstance(c);
    c = cs_new(&env, "wrong", 0, 0);
    initialise(c, 0.0);
    refused(fmi3UpdateDiscreteStates(c, &a, &b, &d, &e, &f, &t), &env, "fmi3UpdateDiscreteStates");   /* Step Mode */
    fmi3FreeInstance(c);
    c = cs_new(&env, "wrong", 0, 0);
    initialise(c, 0.0);
    fmi3Terminate(c);
    refused(fmi3DoStep(c, 0.0, 1e-3, fmi3False, &a, &b, &d, &t), &env, "fmi3DoStep");   /* terminated */
    fmi3FreeInstance(c);
    /* model exchange */
    c = me_new(&env, "wrong");
    refused(fmi3DoStep(c, 0.0, 1e-3, fmi3False, &a, &b, &d, &t), &env, "fmi3DoStep");
    fmi3FreeInstance(c);
    c = me_new(&env, "wrong");
    refused(fmi3ExitConfigurationMode(c), &env, "fmi3ExitConfigurationMode");
    fmi3FreeInstance(c);
    c = me_new(&env, "wrong");
    initialise(c, 0.0);
    refused(fmi3SetContinuousStates(c, x, 7), &env, "fmi3SetContinuousStates");   /* Event Mode */
    fmi3FreeInstance(c);
    c = me_new(&env, "wrong");
    initialise(c, 0.0);
    refused(fmi3EnterInitializationMode(c, fmi3False, 0.0, 0.0, fmi3False, 0.0), &env, "fmi3EnterInitializationMode");
    fmi3FreeInstance(c);
    c = me_new(&env, "wrong");
    initialise(c, 0.0);
    fmi3EnterContinuousTimeMode(c);
    refused(fmi3UpdateDiscreteStates(c, &a, &b, &d, &e, &f, &t), &env, "fmi3UpdateDiscreteStates");
    fmi3FreeInstance(c);
    c = me_new(&env, "wrong");
    initialise(c, 0.0);
    refused(fmi3EnterStepMode(c), &env, "fmi3EnterStepMode");
    fmi3FreeInstance(c);
    c = me_new(&env, "wrong");
    initialise(c, 0.0);
    fmi3EnterContinuousTimeMode(c);
    refused(fmi3SetInt32(c, &vr_N, 1, &five, 1), &env, "friction.N");   /* structural, not in Configuration Mode */
    fmi3FreeInstance(c);
    printf("{\"wrong_states\": {\"refused\": %ld}}\n", wrong_refused);
}

/* ---------------------------------------------------------------- many instances */

void part_many(void) {
    enum { N = 300 };
    static fmi3Instance inst[N];
    static env3_t envs[N];
    int k, round;
    long made = 0;
    for (round = 0; round < 3; round++) {
        for (k = 0; k < N; k++) {
            inst[k] = k % 2 ? cs_new(&envs[k], "many", k % 4 == 1, k % 8 < 4) : me_new(&envs[k], "many");
            CHECK(inst[k] != NULL, "instantiation of many instances", &envs[k]);
            made++;
            if (k % 3 == 0) CHECK(initialise(inst[k], 0.1) == 0, "initialisation of many instances", &envs[k]);
            if (k % 5 == 0) {
                fmi3FMUState s = NULL;
                CHECK(fmi3GetFMUState(inst[k], &s) == fmi3OK, "fmi3GetFMUState of many instances", &envs[k]);
                /* freed here; with --leave-states left to fmi3FreeInstance, which (the FMI 3.0 standard)
                 * frees all memory the FMU's functions allocated */
                if (!leave_states)
                    CHECK(fmi3FreeFMUState(inst[k], &s) == fmi3OK && !s, "fmi3FreeFMUState", &envs[k]);
            }
        }
        for (k = 0; k < N; k++) fmi3FreeInstance(inst[(k * 7) % N]);   /* in another order */
    }
    fmi3FreeInstance(NULL);
    printf("{\"many\": {\"instances\": %ld, \"alive_at_once\": %d}}\n", made, N);
}

