/* An FMI 3.0 host of the plant's FMI 3.0 glue (fmu_src/fmi3_*.c), built with the FMU's sources
 * compiled in under AddressSanitizer + UBSan (build/tests_c/fmi3_host_san, tests/test_c_fmi3.py).
 * The FMI 2.0 glue is linked in as well, so the FMI 2.0 co-simulation of the same input runs in
 * the same process for the comparison. It covers:
 *   instantiation (ME; CS with eventModeUsed x earlyReturnAllowed; a wrong token and required
 *   intermediate variables refused), Configuration Mode (friction.N = 1, 5, 10: number of states,
 *   arrays of dimension N got and set, a wrong nValues and N out of range refused), a model-exchange
 *   loop (forward Euler on fmi3GetContinuousStateDerivatives, event indicators, fmi3UpdateDiscreteStates
 *   at sign changes and time events), a 1 s co-simulation of u = U sin(2 pi f t) in the four
 *   event-mode / early-return combinations against FMI 2.0 (max |dx|), the FMU state (get, set,
 *   serialise, deserialise: continuing bit-identically; every flipped byte and every truncation
 *   refused), out-of-range and NaN parameters refused naming the variable, calls in wrong states
 *   refused, and many instances created and freed (leaks: run with ASAN_OPTIONS=detect_leaks=1).
 * Prints one JSON line per part and a last line "fmi3_host: <n> checks, 0 failed"; the first
 * failed check prints "FAIL: <reason>" and exits 1. With --leave-states only the many-instances part
 * runs, its FMU states left to fmi3FreeInstance, which must free them (LeakSanitizer checks). */
#include "fmi3_host.h"

long n_checks;
static double x_fmi2[N_CS + 1];   /* the FMI 2.0 co-simulation's x at the communication points */
int leave_states;

void fail(const char *what, const char *detail) {
    printf("FAIL: %s%s%s\n", what, detail && *detail ? ": " : "", detail ? detail : "");
    fflush(stdout);
    exit(1);
}

static void log3(fmi3InstanceEnvironment e, fmi3Status status, fmi3String category, fmi3String message) {
    env3_t *env = (env3_t *)e;
    (void)category;
    env->n_msgs++;
    if ((int)status > env->worst) env->worst = (int)status;
    snprintf(env->last, sizeof env->last, "%s", message ? message : "");
}

void check(int ok, const char *what, const env3_t *env) {
    n_checks++;
    if (!ok) fail(what, env ? env->last : NULL);
}

double u_of(double t) { return U_AMP * sin(2.0 * M_PI * U_FREQ * t); }

fmi3Instance me_new(env3_t *env, const char *name) {
    memset(env, 0, sizeof *env);
    return fmi3InstantiateModelExchange(name, MODEL_GUID, NULL, fmi3False, fmi3False, env, log3);
}

fmi3Instance cs_new(env3_t *env, const char *name, int event_mode, int early) {
    memset(env, 0, sizeof *env);
    return fmi3InstantiateCoSimulation(name, MODEL_GUID, NULL, fmi3False, fmi3False, event_mode ? fmi3True : fmi3False,
                                       early ? fmi3True : fmi3False, NULL, 0, env, log3, NULL);
}

/* Configuration Mode: friction.N = n (n <= 0: the default) */
int configure(fmi3Instance c, int n) {
    const fmi3ValueReference vr = VR_friction_N;
    const fmi3Int32 v = n;
    if (n <= 0) return 0;
    if (fmi3EnterConfigurationMode(c) != fmi3OK) return -1;
    if (fmi3SetInt32(c, &vr, 1, &v, 1) != fmi3OK) return -1;
    return fmi3ExitConfigurationMode(c) == fmi3OK ? 0 : -1;
}

int initialise(fmi3Instance c, double u0) {
    const fmi3ValueReference vr = VR_u;
    if (fmi3SetFloat64(c, &vr, 1, &u0, 1) != fmi3OK) return -1;
    if (fmi3EnterInitializationMode(c, fmi3False, 0.0, 0.0, fmi3False, 0.0) != fmi3OK) return -1;
    return fmi3ExitInitializationMode(c) == fmi3OK ? 0 : -1;
}

/* ---------------------------------------------------------------- instantiation */

static void part_instantiate(void) {
    env3_t env;
    const fmi3ValueReference req = VR_x;
    fmi3Instance c;
    int em, er, n = 0;
    c = me_new(&env, "me");
    CHECK(c != NULL, "fmi3InstantiateModelExchange failed", &env);
    CHECK(initialise(c, 0.0) == 0, "ME initialisation failed", &env);
    fmi3FreeInstance(c);
    n++;
    for (em = 0; em < 2; em++)
        for (er = 0; er < 2; er++) {
            c = cs_new(&env, "cs", em, er);
            CHECK(c != NULL, "fmi3InstantiateCoSimulation failed", &env);
            CHECK(initialise(c, 0.0) == 0, "CS initialisation failed", &env);
            if (em) {   /* event mode used: initialised into Event Mode */
                fmi3Boolean a, b, d, e, f;
                fmi3Float64 t;
                CHECK(fmi3UpdateDiscreteStates(c, &a, &b, &d, &e, &f, &t) == fmi3OK, "CS initial event update", &env);
                CHECK(fmi3EnterStepMode(c) == fmi3OK, "fmi3EnterStepMode after initialisation", &env);
            }
            fmi3FreeInstance(c);
            n++;
        }
    memset(&env, 0, sizeof env);
    c = fmi3InstantiateModelExchange("token", "{not-the-token}", NULL, fmi3False, fmi3False, &env, log3);
    CHECK(c == NULL && env.n_msgs > 0, "a wrong instantiation token was accepted (or refused silently)", &env);
    memset(&env, 0, sizeof env);
    c = fmi3InstantiateCoSimulation("req", MODEL_GUID, NULL, fmi3False, fmi3False, fmi3False, fmi3False, &req, 1, &env,
                                    log3, NULL);
    CHECK(c == NULL && strstr(env.last, "intermediate") != NULL, "required intermediate variables accepted", &env);
    printf("{\"instantiate\": {\"instances\": %d, \"wrong_token_refused\": true, \"intermediate_refused\": true}}\n", n);
}

/* ---------------------------------------------------------------- Configuration Mode, ME loop */

typedef struct {
    int n;
    size_t nx;
    long steps, state_events, time_events, updates;
    double x_end, v_end;
} me_run_t;

/* event mode at t: update until no more updates are needed; states re-read when they changed */
static void me_event(fmi3Instance c, env3_t *env, me_run_t *r, fmi3Float64 *x, size_t nx, double *next_time) {
    fmi3Boolean need = fmi3True, term, nom, val, defd;
    fmi3Float64 tn = 0.0;
    while (need) {
        CHECK(fmi3UpdateDiscreteStates(c, &need, &term, &nom, &val, &defd, &tn) == fmi3OK, "fmi3UpdateDiscreteStates", env);
        r->updates++;
        CHECK(!term, "the FMU asked to terminate", env);
        *next_time = defd ? tn : INFINITY;
        if (val) CHECK(fmi3GetContinuousStates(c, x, nx) == fmi3OK, "fmi3GetContinuousStates after an event", env);
    }
}

/* forward Euler with step h over [0, T] on the input u_of(t) held over each H_CS (as the
 * co-simulation gets it), friction.N = n, effects.current_dynamics on or off (on: a time event
 * at every current-loop sample) */
static me_run_t me_loop(int n, double T, double h, int current_dynamics) {
    env3_t env;
    me_run_t r;
    fmi3Instance c = me_new(&env, "me-loop");
    fmi3Float64 x[NX_MAX], dx[NX_MAX], z[NZ], z_prev[NZ], t = 0.0, next_time = INFINITY, out[2];
    const fmi3ValueReference vr_u = VR_u, vr_xv[2] = {VR_x, VR_v}, vr_cd = VR_effects_current_dynamics;
    fmi3ValueReference vr_F = VR3_friction_F, vr_k = VR3_friction_k;
    fmi3Float64 arr[NX_MAX];
    fmi3Boolean cd = current_dynamics ? fmi3True : fmi3False, enter, term;
    size_t nx = 0, j, nz = 0;
    memset(&r, 0, sizeof r);
    r.n = n;
    CHECK(c != NULL, "ME instantiation", &env);
    CHECK(configure(c, n) == 0, "Configuration Mode: set friction.N", &env);
    CHECK(fmi3GetNumberOfContinuousStates(c, &nx) == fmi3OK && nx == (size_t)(MODEL_NX - 10 + n),
          "number of continuous states is not MODEL_NX - 10 + friction.N", &env);
    CHECK(fmi3GetNumberOfEventIndicators(c, &nz) == fmi3OK && nz == NZ, "number of event indicators", &env);
    r.nx = nx;
    CHECK(fmi3SetBoolean(c, &vr_cd, 1, &cd, 1) == fmi3OK, "set current_dynamics", &env);
    /* an array of dimension N: friction.k has N values (get, set back), N + 1 is refused */
    /* friction.nu of dimension N must sum to 1 (Eq. 12): N equal fractions unless N is the default 5 */
    if (n != 5) {
        fmi3ValueReference vr_nu = VR3_friction_nu;
        for (j = 0; j < (size_t)n; j++) arr[j] = 1.0 / n;
        CHECK(fmi3SetFloat64(c, &vr_nu, 1, arr, (size_t)n + 1) == fmi3Error, "set friction.nu with N + 1 values", &env);
        CHECK(fmi3SetFloat64(c, &vr_nu, 1, arr, (size_t)n) == fmi3OK, "set friction.nu with N values", &env);
    }
    CHECK(fmi3GetFloat64(c, &vr_k, 1, arr, (size_t)n) == fmi3OK, "get friction.k with N values", &env);
    CHECK(fmi3SetFloat64(c, &vr_k, 1, arr, (size_t)n) == fmi3OK, "set friction.k with N values", &env);
    CHECK(initialise(c, u_of(0.0)) == 0, "ME initialisation", &env);
    CHECK(fmi3GetFloat64(c, &vr_k, 1, arr, (size_t)n) == fmi3OK, "get friction.k with N values", &env);
    CHECK(fmi3GetFloat64(c, &vr_k, 1, arr, (size_t)n + 1) == fmi3Error && strstr(env.last, "friction.N"),
          "get friction.k with N + 1 values was not refused naming friction.N", &env);
    CHECK(fmi3GetFloat64(c, &vr_F, 1, arr, (size_t)n) == fmi3OK, "get friction.F with N values", &env);
    CHECK(fmi3GetContinuousStates(c, x, nx) == fmi3OK, "fmi3GetContinuousStates", &env);
    me_event(c, &env, &r, x, nx, &next_time);
    CHECK(fmi3EnterContinuousTimeMode(c) == fmi3OK, "fmi3EnterContinuousTimeMode", &env);
    CHECK(fmi3GetEventIndicators(c, z_prev, NZ) == fmi3OK, "fmi3GetEventIndicators", &env);
    while (t < T - 0.5 * h) {
        double t_new = t + h;
        int time_event = 0, state_event = 0;
        size_t k;
        if (t_new >= next_time) { t_new = next_time; time_event = 1; }
        CHECK(fmi3GetContinuousStateDerivatives(c, dx, nx) == fmi3OK, "fmi3GetContinuousStateDerivatives", &env);
        for (j = 0; j < nx; j++) x[j] += (t_new - t) * dx[j];
        t = t_new;
        CHECK(fmi3SetTime(c, t) == fmi3OK, "fmi3SetTime", &env);
        CHECK(fmi3SetContinuousStates(c, x, nx) == fmi3OK, "fmi3SetContinuousStates", &env);
        {
            fmi3Float64 u = u_of(floor(t / H_CS + 1e-9) * H_CS);
            CHECK(fmi3SetFloat64(c, &vr_u, 1, &u, 1) == fmi3OK, "set u", &env);
        }
        CHECK(fmi3CompletedIntegratorStep(c, fmi3True, &enter, &term) == fmi3OK && !term, "fmi3CompletedIntegratorStep",
              &env);
        CHECK(fmi3GetEventIndicators(c, z, NZ) == fmi3OK, "fmi3GetEventIndicators", &env);
        for (k = 0; k < NZ; k++)
            if ((z_prev[k] > 0.0) != (z[k] > 0.0)) state_event = 1;
        r.steps++;
        if (state_event || time_event || enter) {
            r.state_events += state_event;
            r.time_events += time_event;
            CHECK(fmi3EnterEventMode(c) == fmi3OK, "fmi3EnterEventMode", &env);
            me_event(c, &env, &r, x, nx, &next_time);
            CHECK(fmi3EnterContinuousTimeMode(c) == fmi3OK, "fmi3EnterContinuousTimeMode", &env);
            CHECK(fmi3GetEventIndicators(c, z, NZ) == fmi3OK, "fmi3GetEventIndicators after an event", &env);
        }
        memcpy(z_prev, z, sizeof z);
    }
    CHECK(fmi3GetFloat64(c, vr_xv, 2, out, 2) == fmi3OK && isfinite(out[0]) && isfinite(out[1]), "get x, v", &env);
    r.x_end = out[0];
    r.v_end = out[1];
    CHECK(fmi3Terminate(c) == fmi3OK, "fmi3Terminate", &env);
    fmi3FreeInstance(c);
    return r;
}

static void part_configuration(void) {
    env3_t env;
    const fmi3ValueReference vr = VR_friction_N;
    fmi3Int32 bad[2] = {0, 11}, got = 0;
    int k;
    fmi3Instance c;
    for (k = 0; k < 2; k++) {
        c = me_new(&env, "config");
        CHECK(fmi3EnterConfigurationMode(c) == fmi3OK, "fmi3EnterConfigurationMode", &env);
        CHECK(fmi3SetInt32(c, &vr, 1, &bad[k], 1) == fmi3Error && strstr(env.last, "friction.N"),
              "friction.N out of [1, 10] not refused naming friction.N", &env);
        CHECK(fmi3ExitConfigurationMode(c) == fmi3OK, "fmi3ExitConfigurationMode", &env);
        CHECK(fmi3GetInt32(c, &vr, 1, &got, 1) == fmi3OK && got == 5, "a refused friction.N changed it (default 5)", &env);
        fmi3FreeInstance(c);
    }
    c = me_new(&env, "config");
    CHECK(fmi3SetInt32(c, &vr, 1, &bad[0], 1) == fmi3Error && strstr(env.last, "Configuration Mode"),
          "friction.N set outside Configuration Mode not refused", &env);
    fmi3FreeInstance(c);
    printf("{\"configuration\": {\"N_out_of_range_refused\": [0, 11], \"outside_configuration_refused\": true}}\n");
}

static void part_me(me_run_t *runs) {
    static const int NS[3] = {1, 5, 10};
    const int k_end = (int)(0.25 / H_CS + 0.5);
    int k;
    for (k = 0; k < 3; k++) {
        runs[k] = me_loop(NS[k], 0.25, 1e-5, 1);
        /* the FMI 2.0 co-simulation of the same input at 0.25 s (friction.N = 5, the default) */
        printf("{\"me\": {\"N\": %d, \"nx\": %zu, \"steps\": %ld, \"state_events\": %ld, \"time_events\": %ld, "
               "\"updates\": %ld, \"x_end\": %.9g, \"v_end\": %.9g, \"cs_x_at_0.25s\": %.9g}}\n", runs[k].n, runs[k].nx,
               runs[k].steps, runs[k].state_events, runs[k].time_events, runs[k].updates, runs[k].x_end, runs[k].v_end,
               x_fmi2[k_end]);
    }
    runs[3] = me_loop(5, 0.05, 1e-5, 0);
    printf("{\"me_no_current_dynamics\": {\"N\": 5, \"steps\": %ld, \"state_events\": %ld, \"time_events\": %ld, "
           "\"x_end\": %.9g}}\n", runs[3].steps, runs[3].state_events, runs[3].time_events, runs[3].x_end);
}

/* ---------------------------------------------------------------- co-simulation */

static void cs_event(fmi3Instance c, env3_t *env) {
    fmi3Boolean need = fmi3True, term, nom, val, defd;
    fmi3Float64 tn;
    CHECK(fmi3EnterEventMode(c) == fmi3OK, "CS fmi3EnterEventMode", env);
    while (need) CHECK(fmi3UpdateDiscreteStates(c, &need, &term, &nom, &val, &defd, &tn) == fmi3OK, "CS update", env);
    CHECK(fmi3EnterStepMode(c) == fmi3OK, "fmi3EnterStepMode", env);
}

/* communication steps k0 .. k1 - 1 of the sinusoidal input on an initialised CS instance (u(kH) held) */
void cs_steps(fmi3Instance c, env3_t *env, int event_mode, cs_run_t *r, int k0, int k1) {
    const fmi3ValueReference vr_u = VR_u, vr_x = VR_x;
    int k;
    for (k = k0; k < k1; k++) {
        /* the FMI 2.0 reference's arguments: fmi2DoStep(k H, H) */
        double t = k * H_CS, t_next = k * H_CS + H_CS;
        fmi3Float64 u = u_of(t);
        CHECK(fmi3SetFloat64(c, &vr_u, 1, &u, 1) == fmi3OK, "CS set u", env);
        while (t < t_next) {
            fmi3Boolean ev, term, early;
            fmi3Float64 last;
            CHECK(fmi3DoStep(c, t, t == k * H_CS ? H_CS : t_next - t, fmi3False, &ev, &term, &early, &last) == fmi3OK && !term, "fmi3DoStep",
                  env);
            r->dosteps++;
            if (early) {
                CHECK(last > t && last < t_next, "early return outside the step", env);
                r->early_returns++;
                t = last;
            } else {
                CHECK(last == t_next, "lastSuccessfulTime is not the step's end", env);
                t = t_next;
            }
            if (ev) {
                CHECK(event_mode, "eventHandlingNeeded without eventModeUsed", env);
                r->events++;
                cs_event(c, env);
            }
        }
        CHECK(fmi3GetFloat64(c, &vr_x, 1, &r->x[k + 1], 1) == fmi3OK, "CS get x", env);
    }
}

fmi3Instance cs_open(env3_t *env, int event_mode, int early, cs_run_t *r) {
    const fmi3ValueReference vr_x = VR_x;
    fmi3Instance c = cs_new(env, "cs-loop", event_mode, early);
    CHECK(c != NULL, "CS instantiation", env);
    CHECK(initialise(c, u_of(0.0)) == 0, "CS initialisation", env);
    if (event_mode) {
        fmi3Boolean a, b, d, e, f;
        fmi3Float64 t;
        CHECK(fmi3UpdateDiscreteStates(c, &a, &b, &d, &e, &f, &t) == fmi3OK, "CS initial update", env);
        CHECK(fmi3EnterStepMode(c) == fmi3OK, "CS fmi3EnterStepMode", env);
    }
    memset(r, 0, sizeof *r);
    CHECK(fmi3GetFloat64(c, &vr_x, 1, &r->x[0], 1) == fmi3OK, "CS get x(0)", env);
    return c;
}

/* the FMI 2.0 co-simulation of the same input (the FMI 2.0 glue linked into this program) */
static void cs_fmi2(double *x) {
    host_env_t env;
    fmi2CallbackFunctions cb;
    fmi2Component c;
    const fmi2ValueReference vr_u = VR_u, vr_x = VR_x;
    fmi2Real u;
    int k;
    memset(&env, 0, sizeof env);
    cb = host_callbacks(&env);
    c = fmi2Instantiate("fmi2", fmi2CoSimulation, MODEL_GUID, "", &cb, fmi2False, fmi2False);
    if (!c) fail("fmi2Instantiate", env.last);
    u = u_of(0.0);
    if (fmi2SetReal(c, &vr_u, 1, &u) != fmi2OK || fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) != fmi2OK ||
        fmi2EnterInitializationMode(c) != fmi2OK || fmi2ExitInitializationMode(c) != fmi2OK ||
        fmi2GetReal(c, &vr_x, 1, &x[0]) != fmi2OK)
        fail("FMI 2.0 initialisation", env.last);
    for (k = 0; k < N_CS; k++) {
        u = u_of(k * H_CS);
        if (fmi2SetReal(c, &vr_u, 1, &u) != fmi2OK || fmi2DoStep(c, k * H_CS, H_CS, fmi2True) != fmi2OK ||
            fmi2GetReal(c, &vr_x, 1, &x[k + 1]) != fmi2OK)
            fail("FMI 2.0 fmi2DoStep", env.last);
    }
    fmi2FreeInstance(c);
    n_checks++;
}

static void part_cs(void) {
    double *x2 = x_fmi2;
    static cs_run_t r;
    env3_t env;
    int em, er, k;
    double x_min = INFINITY, x_max = -INFINITY;
    for (k = 0; k <= N_CS; k++) { x_min = fmin(x_min, x2[k]); x_max = fmax(x_max, x2[k]); }
    for (em = 0; em < 2; em++)
        for (er = 0; er < 2; er++) {
            fmi3Instance c = cs_open(&env, em, er, &r);
            double dmax = 0.0;
            cs_steps(c, &env, em, &r, 0, N_CS);
            fmi3FreeInstance(c);
            for (k = 0; k <= N_CS; k++) dmax = fmax(dmax, fabs(r.x[k] - x2[k]));
            printf("{\"cs\": {\"event_mode\": %d, \"early_return\": %d, \"dosteps\": %ld, \"early_returns\": %ld, "
                   "\"events\": %ld, \"x_end\": %.17g, \"fmi2_x_end\": %.17g, \"max_abs_dx_vs_fmi2_m\": %.3g, "
                   "\"x_range_m\": %.6g}}\n", em, er, r.dosteps, r.early_returns, r.events, r.x[N_CS], x2[N_CS], dmax,
                   x_max - x_min);
            if (er) CHECK(r.early_returns > 0, "no early return in 1 s of a sinusoidal input", NULL);
            else CHECK(r.early_returns == 0, "an early return without earlyReturnAllowed", NULL);
            CHECK(dmax == 0.0, "the FMI 3.0 co-simulation differs from the FMI 2.0 one", NULL);
        }
}

int main(int argc, char **argv) {
    static me_run_t me[4];
        setvbuf(stdout, NULL, _IOLBF, 0);
    leave_states = argc > 1 && strcmp(argv[1], "--leave-states") == 0;
    if (leave_states) {
        part_many();
        printf("fmi3_host: %ld checks, 0 failed\n", n_checks);
        return 0;
    }
    part_instantiate();
    cs_fmi2(x_fmi2);
    part_configuration();
    part_me(me);
    part_cs();
    part_state();
    part_state_structure();
    part_limits();
    part_wrong_states();
    part_many();
    printf("fmi3_host: %ld checks, 0 failed\n", n_checks);
    return 0;
}
