/* The FMI 3.0 host's robustness parts (see fmi3_host.c): the FMU state (round trips continuing
 * bit-identically, every flipped byte and truncation refused; states of another friction.N, of
 * Event Mode without eventModeUsed and with a continuous state out of range refused), parameter
 * limits, calls in wrong states, and many instances created and freed. */
#include <stdint.h>

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

/* ---------------------------------------------------------------- structure and ranges of a state */

static uint32_t rd_u32(const unsigned char *b) {
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}
static void wr_u32(unsigned char *b, uint32_t v) {
    int j;
    for (j = 0; j < 4; j++) b[j] = (unsigned char)(v >> (8 * j));
}

/* the serialised state of instance c (malloc'ed, *size bytes) */
static fmi3Byte *serialised(fmi3Instance c, env3_t *env, size_t *size) {
    fmi3FMUState s = NULL;
    fmi3Byte *buf;
    CHECK(fmi3GetFMUState(c, &s) == fmi3OK && fmi3SerializedFMUStateSize(c, s, size) == fmi3OK, "get a state", env);
    buf = (fmi3Byte *)malloc(*size);
    if (!buf) fail("out of memory", NULL);
    CHECK(fmi3SerializeFMUState(c, s, buf, *size) == fmi3OK && fmi3FreeFMUState(c, &s) == fmi3OK, "serialise", env);
    return buf;
}

/* deserialising b into c is refused with a message containing `what` */
static int refused_with(fmi3Instance c, env3_t *env, const fmi3Byte *b, size_t size, const char *what) {
    fmi3FMUState s = NULL;
    fmi3Status st;
    env->n_msgs = 0;
    st = fmi3DeserializeFMUState(c, b, size, &s);
    if (s) fmi3FreeFMUState(c, &s);
    return st == fmi3Error && env->n_msgs > 0 && strstr(env->last, what) != NULL;
}

/* A state carries what the instance was made with: a state of friction.N = 5 into an instance
 * at N = 9, a state saved in Event Mode into an instance made with eventModeUsed = false, and a
 * continuous state beyond its declared range with the CRC recomputed (v = 1e300, x = -2000 m) are
 * refused naming what differs; the refused instance then steps on. */
void part_state_structure(void) {
    static cs_run_t r;
    env3_t env_e, env_p, env_9;
    const fmi3ValueReference vr_nu = VR3_friction_nu;
    const fmi3Float64 nu9[9] = {1.0 / 9, 1.0 / 9, 1.0 / 9, 1.0 / 9, 1.0 / 9, 1.0 / 9, 1.0 / 9, 1.0 / 9, 1.0 - 8.0 / 9};
    fmi3Instance ev = cs_open(&env_e, 1, 0, &r), plain, n9;
    fmi3Boolean a, b, d, e, f;
    fmi3Float64 t;
    fmi3Byte *s_event, *s_step;
    size_t n_event, n_step, hb;
    long refused = 0;
    /* saved in Event Mode (after a step's event handling) */
    cs_steps(ev, &env_e, 1, &r, 0, 100);
    CHECK(fmi3EnterEventMode(ev) == fmi3OK, "fmi3EnterEventMode", &env_e);
    s_event = serialised(ev, &env_e, &n_event);
    CHECK(fmi3UpdateDiscreteStates(ev, &a, &b, &d, &e, &f, &t) == fmi3OK && fmi3EnterStepMode(ev) == fmi3OK,
          "back to Step Mode", &env_e);
    s_step = serialised(ev, &env_e, &n_step);
    plain = cs_open(&env_p, 0, 0, &r);
    CHECK(refused_with(plain, &env_p, s_event, n_event, "saved in Event Mode"), "an Event Mode state loads into an "
          "instance made with eventModeUsed = false", &env_p);
    refused++;
    CHECK(!refused_with(plain, &env_p, s_step, n_step, "?"), "a Step Mode state is refused without event mode",
          &env_p);
    /* friction.N = 9 against the states' 5 */
    n9 = cs_new(&env_9, "n9", 0, 0);
    CHECK(n9 && configure(n9, 9) == 0 && fmi3SetFloat64(n9, &vr_nu, 1, nu9, 9) == fmi3OK &&
          initialise(n9, 0.5) == 0, "instance with friction.N = 9", &env_9);
    CHECK(refused_with(n9, &env_9, s_step, n_step, "friction.N = 5, this instance 9"),
          "a state of friction.N = 5 loads into an instance at N = 9", &env_9);
    refused++;
    {
        fmi3Float64 F[9];
        const fmi3ValueReference vr_F = VR3_friction_F;
        fmi3Boolean ev9, term, early;
        CHECK(fmi3DoStep(n9, 0.0, 1e-3, fmi3False, &ev9, &term, &early, &t) == fmi3OK &&
              fmi3GetFloat64(n9, &vr_F, 1, F, 9) == fmi3OK, "the refused instance steps on with 9 elements", &env_9);
    }
    /* a continuous state beyond its range, the checksum recomputed: x = y[0], v = y[1] follow the
     * call-sequence state, flags and five f64 times (state_format.h, plant_snapshot.c) */
    hb = rd_u32(s_step + 8);
    {
        const double bad[2] = {-2000.0, 1e300};
        const char *what[2] = {"state x = -2000 is out of range", "state v = 1e+300 is out of range"};
        int j;
        for (j = 0; j < 2; j++) {
            fmi3Byte *forged = (fmi3Byte *)malloc(n_step);
            uint64_t u;
            int q;
            if (!forged) fail("out of memory", NULL);
            memcpy(forged, s_step, n_step);
            memcpy(&u, &bad[j], sizeof u);
            for (q = 0; q < 8; q++) forged[hb + 8 + 5 * 8 + 8 * (size_t)j + (size_t)q] = (unsigned char)(u >> (8 * q));
            wr_u32(forged + hb - 4, host_crc32(forged + hb, n_step - hb));
            CHECK(refused_with(plain, &env_p, forged, n_step, what[j]), "a forged out-of-range state loads", &env_p);
            refused++;
            free(forged);
        }
    }
    free(s_event);
    free(s_step);
    fmi3FreeInstance(ev);
    fmi3FreeInstance(plain);
    fmi3FreeInstance(n9);
    printf("{\"state_structure\": {\"refused\": %ld}}\n", refused);
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

