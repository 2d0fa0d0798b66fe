/* Random calls into the controller FMU (FMI 2.0, and FMI 3.0 when CTRL_FMI3): a few instances
 * of each, random call sequences with random arguments (NaN, +-Inf, huge, tiny, denormal and
 * out-of-range values, unknown and mistyped value references, NULL arrays, nValueReferences =
 * SIZE_MAX, nValues != nValueReferences, steps of every size, calls in the wrong state and the
 * functions the FMU does not provide), and random settings: up to 12 parameters at extreme
 * values inside their declared ranges, initialised and run for 50 samples.
 * Meant for the AddressSanitizer + UBSan build: a memory error, a leak or undefined behaviour
 * aborts the run. Checks, per call:
 *   - the status is a valid one (FMI 2.0: OK..Fatal, no Pending; FMI 3.0: OK..Fatal);
 *   - an answer other than OK from a live instance comes with a logged message;
 *   - a call whose arguments make it illegal whatever the state (NULL array with a count > 0, a
 *     count no array can hold, nValues != nValueReferences, unknown or mistyped value reference,
 *     a non-finite or out-of-[min, max] value, a non-finite or non-positive step, an unknown log
 *     category, a function the FMU does not provide) is answered Error;
 *   - a getter that answers OK gives finite values only;
 *   - every callback allocation is freed with the instances.
 * Prints the counts and "N passed, M failed" (N = calls whose checks passed). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ctrl_host.h"

#define NSLOT 5
#define N_SAMPLES_SETTING 50

typedef struct {
    void *c;
    int v3;                       /* an FMI 3.0 instance */
    host_env_t env;               /* FMI 2.0 logger */
    env3_t e3;                    /* FMI 3.0 logger */
    int st;                       /* modelled state */
    double time, Ts;
} slot_t;
enum { S_NONE, S_INST, S_INIT, S_STEP, S_TERM, S_TAINTED };

static uint64_t rng_state = 88172645463325252ull;
static long n_calls, n_pass, n_fail, n_illegal, n_finite_gets, n_values_checked, n_settings, n_set_refused,
    n_init_refused, n_diverged, n_ran, n_steps_ok, n_fmi3_calls;
static const char *cur_fn = "";
/* what the refusals named, counted: the variable of a refusal at initialisation (the message's
 * first word after "fn: "), the number that left the finite ones in a stopped setting (the text
 * between "s: " and " = ") */
#define NRULES 48
typedef struct { char name[NRULES][64]; long count[NRULES]; } tally_t;
static tally_t init_rules, stop_causes;

static void tally(tally_t *t, const char *p, size_t n) {
    int k;
    if (n >= sizeof t->name[0]) n = sizeof t->name[0] - 1;
    for (k = 0; k < NRULES && t->name[k][0]; k++)
        if (strlen(t->name[k]) == n && !strncmp(t->name[k], p, n)) { t->count[k]++; return; }
    if (k == NRULES) return;
    memcpy(t->name[k], p, n);
    t->name[k][n] = 0;
    t->count[k] = 1;
}

static void count_rule(const char *msg) {
    const char *p = strstr(msg, ": "), *q;
    p = p ? p + 2 : msg;
    q = strchr(p, ' ');
    tally(&init_rules, p, q ? (size_t)(q - p) : strlen(p));
}

static void count_cause(const char *msg) {
    const char *p = strstr(msg, " s: "), *q;
    p = p ? p + 4 : msg;
    q = strstr(p, " = ");
    tally(&stop_causes, p, q ? (size_t)(q - p) : strlen(p));
}

static void print_tally(const char *what, const tally_t *t) {
    int j;
    printf("%s:", what);
    for (j = 0; j < NRULES && t->name[j][0]; j++) printf("%s %s %ld", j ? "," : "", t->name[j], t->count[j]);
    printf("%s\n", t->name[0][0] ? "" : " none");
}

static uint64_t rnd(void) {
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return rng_state;
}
static double unif(void) { return (double)(rnd() >> 11) * (1.0 / 9007199254740992.0); }
static int chance(double p) { return unif() < p; }
static int rint_(int n) { return (int)(rnd() % (uint64_t)n); }

static void fail(const char *what, const slot_t *s) {
    n_fail++;
    if (n_fail <= 20)
        printf("FAIL call %ld %s: %s (last message: %s)\n", n_calls, cur_fn, what,
               s ? (s->v3 ? s->e3.last : s->env.last) : "-");
}

static void mark(slot_t *s) {
    host_env_mark(&s->env);
    env3_mark(&s->e3);
}
static long msgs_since(const slot_t *s) { return s->env.n_since_mark + s->e3.n_since_mark; }

/* the checks every call gets: a valid status, a message with any answer but OK, Error for a
 * certainly illegal call; a failed call taints the modelled state */
static void judge(slot_t *s, int status, int illegal) {
    int ok = 1;
    n_calls++;
    if (s->v3) n_fmi3_calls++;
    if (status < 0 || status > 4) { fail("status out of range", s); ok = 0; }
    else if (status != 0 && msgs_since(s) == 0) { fail("non-OK answer without a message", s); ok = 0; }
    if (illegal) {
        n_illegal++;
        if (status != 3) { fail("certainly illegal call not answered Error", s); ok = 0; }
    }
    if (ok) n_pass++;
    if (status > 1) s->st = S_TAINTED;
}

/* ---------------------------------------------------------------- values */

static int random_row(void) { return rint_(CTRL_NVARS); }

static int is_param(int row) { return CTRL_VARS[row].causality == 'p'; }

/* a value for row: mostly inside [min, max] at its edges or spread over its decades, sometimes
 * outside it or not finite; *illegal when it is out of range or not finite */
static double random_value(int row, int *illegal) {
    const ctrl_var_t *v = &CTRL_VARS[row];
    double lo = v->min, hi = v->max, x;
    int k = rint_(14);
    if (v->type == 'B') { *illegal = 0; return (double)rint_(2); }
    switch (k) {
    case 0: x = lo; break;
    case 1: x = hi; break;
    case 2: x = v->start; break;
    case 3: x = 0.0; break;
    case 4: x = 5e-324; break;
    case 5: x = -0.0; break;
    case 6: x = NAN; break;
    case 7: x = chance(0.5) ? INFINITY : -INFINITY; break;
    case 8: x = isfinite(hi) ? nextafter(hi, INFINITY) * (chance(0.5) ? 1.0 : 10.0) : 1e308; break;
    case 9: x = isfinite(lo) ? lo - (fabs(lo) + 1.0) : -1e308; break;
    default: {   /* log-uniform magnitude, random sign, clipped into the range */
        x = pow(10.0, -300.0 + 600.0 * unif()) * (chance(0.5) ? -1.0 : 1.0);
        if (chance(0.5)) x = pow(10.0, -6.0 + 12.0 * unif()) * (chance(0.3) ? -1.0 : 1.0);
        if (x < lo) x = lo;
        if (x > hi) x = hi;
    }
    }
    if (v->type == 'I') {
        if (!isfinite(x) || fabs(x) > 2e9) x = x > 0 ? 2147483647.0 : -2147483647.0;
        x = trunc(x);
    }
    *illegal = !isfinite(x) || x < lo || x > hi;
    return x;
}

/* ---------------------------------------------------------------- FMI 2.0 / 3.0 calls */

static int do_set(slot_t *s, int row, double x, char type) {
    unsigned vr = row >= 0 ? CTRL_VARS[row].vr : (unsigned)rnd();
#ifdef CTRL_FMI3
    if (s->v3) {
        fmi3ValueReference r = vr;
        if (type == 'R') { fmi3Float64 v = x; return fmi3SetFloat64(s->c, &r, 1, &v, 1); }
        if (type == 'I') { fmi3Int32 v = (fmi3Int32)x; return fmi3SetInt32(s->c, &r, 1, &v, 1); }
        { fmi3Boolean v = x != 0.0; return fmi3SetBoolean(s->c, &r, 1, &v, 1); }
    }
#endif
    {
        fmi2ValueReference r = vr;
        if (type == 'R') { fmi2Real v = x; return api.SetReal(s->c, &r, 1, &v); }
        if (type == 'I') { fmi2Integer v = (fmi2Integer)x; return api.SetInteger(s->c, &r, 1, &v); }
        { fmi2Boolean v = (fmi2Boolean)x; return api.SetBoolean(s->c, &r, 1, &v); }
    }
}

static void call_set(slot_t *s) {
    int row = chance(0.05) ? -1 : random_row(), illegal = 0;
    char type = row >= 0 ? CTRL_VARS[row].type : "RIB"[rint_(3)];
    double x;
    if (row >= 0 && chance(0.05)) { type = "RIB"[rint_(3)]; illegal = type != CTRL_VARS[row].type; }
    if (row < 0) {
        unsigned vr = (unsigned)rnd();
        illegal = !(vr < CTRL_NVR && CTRL_VR_INDEX[vr] >= 0);
        x = 1.0;
    } else if (type == CTRL_VARS[row].type) {
        int bad;
        x = random_value(row, &bad);
        illegal |= bad;
    } else {
        x = 1.0;
    }
    if (!s->v3 && type == 'B' && row >= 0 && chance(0.05)) { x = 7.0; illegal = 1; }   /* not an fmi2Boolean */
    if (row >= 0 && (CTRL_VARS[row].causality == 'o')) illegal = 1;   /* outputs are never set */
    cur_fn = "set";
    mark(s);
    judge(s, do_set(s, row, x, type), illegal);
    if (row >= 0 && CTRL_VARS[row].vr == CVR_Ts && !illegal && s->st == S_INST) s->Ts = x;
}

/* get n random variables of one type; OK => every value finite */
static void call_get(slot_t *s) {
    unsigned vr[4];
    double r[4];
    int n = 1 + rint_(4), k, illegal = 0, status;
    char type = "RRIB"[rint_(4)];
    for (k = 0; k < n; k++) {
        int row = random_row();
        if (chance(0.02)) { vr[k] = (unsigned)rnd(); if (!(vr[k] < CTRL_NVR && CTRL_VR_INDEX[vr[k]] >= 0)) illegal = 1; continue; }
        while (CTRL_VARS[row].type != type && !chance(0.02)) row = random_row();
        vr[k] = CTRL_VARS[row].vr;
        if (CTRL_VARS[row].type != type) illegal = 1;
    }
    if (illegal) {   /* an unknown value reference can be a known one by chance: judge by the table */
        illegal = 0;
        for (k = 0; k < n; k++)
            if (!(vr[k] < CTRL_NVR && CTRL_VR_INDEX[vr[k]] >= 0) || CTRL_VARS[CTRL_VR_INDEX[vr[k]]].type != type)
                illegal = 1;
    }
    cur_fn = "get";
    mark(s);
#ifdef CTRL_FMI3
    if (s->v3) {
        if (type == 'R') {
            fmi3Float64 v[4];
            if (chance(0.1)) vr[rint_(n)] = 0;   /* the FMI 3.0 time */
            status = fmi3GetFloat64(s->c, vr, (size_t)n, v, (size_t)n);
            for (k = 0; k < n; k++) r[k] = v[k];
            illegal = 0;
            for (k = 0; k < n; k++)
                if (vr[k] != 0 && (!(vr[k] < CTRL_NVR && CTRL_VR_INDEX[vr[k]] >= 0) ||
                                   CTRL_VARS[CTRL_VR_INDEX[vr[k]]].type != 'R'))
                    illegal = 1;
        } else if (type == 'I') {
            fmi3Int32 v[4];
            status = fmi3GetInt32(s->c, vr, (size_t)n, v, (size_t)n);
        } else {
            fmi3Boolean v[4];
            status = fmi3GetBoolean(s->c, vr, (size_t)n, v, (size_t)n);
        }
    } else
#endif
    {
        if (type == 'R') status = api.GetReal(s->c, vr, (size_t)n, r);
        else if (type == 'I') { fmi2Integer v[4]; status = api.GetInteger(s->c, vr, (size_t)n, v); }
        else { fmi2Boolean v[4]; status = api.GetBoolean(s->c, vr, (size_t)n, v); }
    }
    judge(s, status, illegal);
    if (status == 0 && type == 'R') {
        n_finite_gets++;
        for (k = 0; k < n; k++) {
            n_values_checked++;
            if (!isfinite(r[k])) { fail("getter answered OK with a non-finite value", s); break; }
        }
    }
}

/* arguments illegal whatever the state: NULL arrays, SIZE_MAX counts, nValues != nValueReferences */
static void call_bad_arrays(slot_t *s) {
    unsigned vr[1] = {CVR_u};
    double v[1];
    /* counts no array can hold (more than PTRDIFF_MAX bytes of fmi2Real / fmi3Float64) */
    size_t n = chance(0.5) ? SIZE_MAX : (size_t)PTRDIFF_MAX / 8 + 1 + (size_t)rint_(1000);
    int k = rint_(6), status;
    cur_fn = "bad arrays";
    mark(s);
#ifdef CTRL_FMI3
    if (s->v3) {
        fmi3Boolean b[1];
        switch (k) {
        case 0: status = fmi3GetFloat64(s->c, NULL, 1, v, 1); break;
        case 1: status = fmi3GetFloat64(s->c, vr, 1, NULL, 1); break;
        case 2: status = fmi3GetBoolean(s->c, vr, n, b, n); break;
        case 3: status = fmi3SetBoolean(s->c, vr, n, b, n); break;
        case 4: status = fmi3SetFloat64(s->c, vr, 1, v, 2); break;
        default: status = fmi3GetInt32(s->c, NULL, n, NULL, n); break;
        }
        judge(s, status, 1);
        return;
    }
#endif
    {
        fmi2Boolean b[1] = {0};
        fmi2Integer i[1];
        switch (k) {
        case 0: status = api.GetReal(s->c, NULL, 1, v); break;
        case 1: status = api.SetReal(s->c, vr, 1, NULL); break;
        case 2: status = api.GetBoolean(s->c, vr, n, b); break;
        case 3: status = api.SetBoolean(s->c, vr, n, b); break;
        case 4: status = api.GetInteger(s->c, vr, n, i); break;
        default: status = api.SetInteger(s->c, NULL, n, NULL); break;
        }
    }
    judge(s, status, 1);
}

static int do_step(slot_t *s, double t, double h) {
#ifdef CTRL_FMI3
    if (s->v3) {
        fmi3Boolean ev, term, early;
        fmi3Float64 last;
        return fmi3DoStep(s->c, t, h, chance(0.5), &ev, &term, &early, &last);
    }
#endif
    return api.DoStep(s->c, t, h, fmi2True);
}

static void call_step(slot_t *s) {
    static const double BAD[] = {NAN, INFINITY, -INFINITY, 0.0, -1e-3, -0.0};
    double Ts = s->Ts > 0.0 ? s->Ts : 5e-4, h, t = s->time;
    int illegal = 0, status;
    int k = rint_(10);
    if (k < 6) h = Ts * (double)(1 + rint_(20)) * (chance(0.3) ? 0.37 : 1.0);
    else if (k == 6) { h = BAD[rint_(6)]; illegal = 1; }
    else if (k == 7) h = Ts < 1.0 && chance(0.5) ? 1e9 : 1e300;   /* beyond the budget of 1e6 samples */
    else if (k == 8) h = 1e-12 * (1 + rint_(1000));
    else { h = Ts; if (chance(0.5)) { t = s->time + 1.0; illegal = 1; } }   /* not the FMU's time */
    if (!isfinite(t)) illegal = 1;
    cur_fn = "DoStep";
    mark(s);
    status = do_step(s, t, h);
    judge(s, status, illegal);
    if (status == 0) { s->time = t + h; n_steps_ok++; }
}

/* one life-cycle call without arguments beyond the instance, on the slot's FMI version */
#ifdef CTRL_FMI3
#define LIFE(fn) fmi3##fn, api.fn
static int life_call(const slot_t *s, const char *name, fmi3Status (*f3)(fmi3Instance),
                     fmi2Status (*f2)(fmi2Component)) {
    cur_fn = name;
    return s->v3 ? (int)f3(s->c) : (int)f2(s->c);
}
#else
#define LIFE(fn) api.fn
static int life_call(const slot_t *s, const char *name, fmi2Status (*f2)(fmi2Component)) {
    cur_fn = name;
    return (int)f2(s->c);
}
#endif

/* the next call of the life cycle with valid arguments: runs get deep */
static void call_progress(slot_t *s) {
    int status;
    mark(s);
    switch (s->st) {
    case S_INST:
        cur_fn = "EnterInitializationMode";
#ifdef CTRL_FMI3
        if (s->v3) status = fmi3EnterInitializationMode(s->c, fmi3False, 0.0, 0.0, fmi3False, 0.0);
        else
#endif
        {
            status = api.SetupExperiment(s->c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
            if (status == 0) status = api.EnterInitializationMode(s->c);
        }
        judge(s, status, 0);
        if (status == 0) { s->st = S_INIT; s->time = 0.0; }
        return;
    case S_INIT:
        status = life_call(s, "ExitInitializationMode", LIFE(ExitInitializationMode));
        judge(s, status, 0);
        if (status == 0) s->st = S_STEP;
        return;
    case S_STEP:
        if (chance(0.9)) { call_step(s); return; }
        status = life_call(s, "Terminate", LIFE(Terminate));
        judge(s, status, 0);
        if (status == 0) s->st = S_TERM;
        return;
    default:
        status = life_call(s, "Reset", LIFE(Reset));
        judge(s, status, 0);
        if (status == 0) { s->st = S_INST; s->time = 0.0; s->Ts = 5e-4; }
    }
}

/* fmi2/fmi3SetDebugLogging with known, unknown and NULL categories (legal in any state) */
static void call_logging(slot_t *s) {
    static const char *const CAT[] = {"logEvents", "logStatusWarning", "logStatusError", "logDebug", "logNothing",
                                      "", NULL};
    const char *cats[4];
    size_t n = (size_t)rint_(5), k;
    int illegal = 0, null_array = n > 0 && chance(0.05), status;
    for (k = 0; k < n; k++) {
        cats[k] = CAT[rint_(7)];
        if (!cats[k] || !cats[k][0] || !strcmp(cats[k], "logNothing")) illegal = 1;
    }
    if (null_array) illegal = 1;
    cur_fn = "SetDebugLogging";
    mark(s);
#ifdef CTRL_FMI3
    if (s->v3) status = fmi3SetDebugLogging(s->c, chance(0.5), n, null_array ? NULL : cats);
    else
#endif
        status = api.SetDebugLogging(s->c, chance(0.5), n, null_array ? NULL : cats);
    judge(s, status, illegal);
}

/* functions the FMU does not provide: Error with a message, in any state */
static void call_refused(slot_t *s) {
    int status;
    mark(s);
#ifdef CTRL_FMI3
    if (s->v3) {
        fmi3FMUState fs = NULL;
        fmi3Float64 x[2];
        size_t n;
        switch (rint_(5)) {
        case 0: cur_fn = "fmi3GetFMUState"; status = fmi3GetFMUState(s->c, &fs); break;
        case 1: cur_fn = "fmi3EnterEventMode"; status = fmi3EnterEventMode(s->c); break;
        case 2: cur_fn = "fmi3GetContinuousStates"; status = fmi3GetContinuousStates(s->c, x, 2); break;
        case 3: cur_fn = "fmi3EnterConfigurationMode"; status = fmi3EnterConfigurationMode(s->c); break;
        default: cur_fn = "fmi3GetNumberOfContinuousStates"; status = fmi3GetNumberOfContinuousStates(s->c, &n); break;
        }
        judge(s, status, 1);
        return;
    }
#endif
    {
        fmi2FMUstate fs = NULL;
        fmi2Real x[2];
        switch (rint_(4)) {
        case 0: cur_fn = "fmi2GetFMUstate"; status = api.GetFMUstate(s->c, &fs); break;
        case 1: cur_fn = "fmi2GetDerivatives"; status = api.GetDerivatives(s->c, x, 2); break;
        case 2: cur_fn = "fmi2CancelStep"; status = api.CancelStep(s->c); break;
        default: cur_fn = "fmi2EnterEventMode"; status = api.EnterEventMode(s->c); break;
        }
    }
    judge(s, status, 1);
}

/* ---------------------------------------------------------------- instances */

static void slot_free(slot_t *s) {
    if (!s->c) return;
#ifdef CTRL_FMI3
    if (s->v3) fmi3FreeInstance(s->c);
    else
#endif
        api.FreeInstance(s->c);
    s->c = NULL;
    s->st = S_NONE;
}

/* a new instance; with a small chance illegal arguments, which must give NULL (FMI 3.0: an
 * instance made with eventModeUsed is legal, the clocked one; it is not fuzzed here, its calls
 * are the host case `clock`, so these instances are made without it) */
static void slot_new(slot_t *s, int v3) {
    int k = rint_(14), illegal = k < 3 || (k == 3 && !v3);
    const char *name = k == 0 ? NULL : (k == 1 ? "" : "fuzz"), *guid = k == 2 ? "{bad}" : CTRL_GUID;
    memset(s, 0, sizeof *s);
    s->v3 = v3;
    s->Ts = 5e-4;
    cur_fn = "Instantiate";
#ifdef CTRL_FMI3
    if (v3)
        s->c = fmi3InstantiateCoSimulation(name, guid, NULL, fmi3False, chance(0.2), fmi3False, fmi3False, NULL, 0, &s->e3,
                                           env3_log, NULL);
    else
#endif
    {
        fmi2CallbackFunctions cb = host_callbacks(&s->env);
        s->c = api.Instantiate(name, k == 3 ? fmi2ModelExchange : fmi2CoSimulation, guid, "", &cb, fmi2False,
                               chance(0.2));
    }
    n_calls++;
    if (illegal == (s->c != NULL)) { fail(illegal ? "illegal instantiation answered" : "legal instantiation refused", s); }
    else n_pass++;
    if (s->c) s->st = S_INST;
}

/* a parameter that acts in a setting of this controller type, reference source, ZPETC, feedforward */
static int relevant(int row, int type, int source, int zpetc, int ff) {
    const char *n = CTRL_VARS[row].name;
    if (!is_param(row)) return 0;
    if (!strncmp(n, "ss.", 3)) return type == 1;
    if (!strncmp(n, "lti.", 4)) return type == 4;
    if (!strncmp(n, "pid.", 4)) return type == 2 || type == 3;
    if (!strncmp(n, "lead.", 5)) return type == 3;
    if (!strncmp(n, "zpetc.", 6)) return zpetc;
    if (!strncmp(n, "ref.", 4)) return source != 0;
    if (!strncmp(n, "ff.", 3) || !strncmp(n, "plant.", 6)) return ff;
    return 1;
}

/* a random setting: the controller type, reference source, ZPETC and feedforward switches, then
 * up to 12 of the parameters that act in it at values inside their ranges; initialised, 50 samples */
static void random_setting(slot_t *s) {
    int n = 1 + rint_(12), j, status;
    int type = 1 + rint_(4), source = rint_(3), zpetc = chance(0.3), ff = chance(0.3);
    n_settings++;
    cur_fn = "setting: switches";
    mark(s);
    if (do_set(s, (int)CTRL_VR_INDEX[CVR_ctrl_type], type, 'I') || do_set(s, (int)CTRL_VR_INDEX[CVR_ref_source], source, 'I') ||
        do_set(s, (int)CTRL_VR_INDEX[CVR_zpetc_on], zpetc, 'B') || do_set(s, (int)CTRL_VR_INDEX[CVR_ff_on], ff, 'B'))
        fail("the switches of a setting refused", s);
    for (j = 0; j < n; j++) {
        int row = random_row(), bad = 1, tries = 0;
        double x = 0.0;
        while (!relevant(row, type, source, zpetc, ff)) row = random_row();
        while (bad && tries++ < 20) x = random_value(row, &bad);
        if (bad) continue;
        if (CTRL_VARS[row].vr == CVR_Ts) x = pow(10.0, -9.0 + 12.0 * unif());   /* any sample time: h = Ts below */
        cur_fn = "setting: set";
        mark(s);
        status = do_set(s, row, x, CTRL_VARS[row].type);
        judge(s, status, 0);
        if (status != 0) { n_set_refused++; s->st = S_INST; }   /* a refused set changes nothing: go on */
        else if (CTRL_VARS[row].vr == CVR_Ts) s->Ts = x;
    }
    call_progress(s);
    if (s->st == S_INIT) call_progress(s);
    if (s->st != S_STEP) { n_init_refused++; count_rule(s->v3 ? s->e3.last : s->env.last); return; }
    for (j = 0; j < N_SAMPLES_SETTING; j++) {
        double r[4];
        unsigned vr[4] = {CVR_u, CVR_x_cmd, CVR_u_ff, CVR_r_x};
        cur_fn = "setting: get outputs";
        mark(s);
#ifdef CTRL_FMI3
        if (s->v3) status = fmi3GetFloat64(s->c, vr, 4, r, 4);
        else
#endif
            status = api.GetReal(s->c, vr, 4, r);
        judge(s, status, 0);
        if (status == 0) {
            int k;
            n_finite_gets++;
            for (k = 0; k < 4; k++) {
                n_values_checked++;
                if (!isfinite(r[k])) fail("getter answered OK with a non-finite value", s);
            }
        }
        if (status != 0) break;
        cur_fn = "setting: DoStep";
        mark(s);
        status = do_step(s, s->time, s->Ts);
        judge(s, status, 0);
        if (status != 0) break;
        s->time += s->Ts;
        n_steps_ok++;
    }
    if (j == N_SAMPLES_SETTING) n_ran++;
    else {
        n_diverged++;
        count_cause(s->v3 ? s->e3.last : s->env.last);
        if (!strstr(s->v3 ? s->e3.last : s->env.last, "not finite") &&
            !strstr(s->v3 ? s->e3.last : s->env.last, "resolves"))
            fail("a setting stopped without naming a non-finite value", s);
    }
}

int fuzz_main(int argc, char **argv) {
    long calls = argc > 0 ? atol(argv[0]) : 200000, seed = argc > 1 ? atol(argv[1]) : 1;
    slot_t slots[NSLOT];
    long live0 = host_live_allocations();
    int j;
    memset(slots, 0, sizeof slots);
    rng_state ^= (uint64_t)seed * 0x9E3779B97F4A7C15ull;
    for (j = 0; j < 10; j++) rnd();
    while (n_calls < calls) {
        int k = rint_(NSLOT), a = rint_(100);
        slot_t *s = &slots[k];
#ifdef CTRL_FMI3
        int v3 = k >= 3;   /* slots 3, 4: FMI 3.0 */
#else
        int v3 = 0;
#endif
        if (!s->c) { slot_new(s, v3); continue; }
        if (a < 30) call_progress(s);
        else if (a < 50) call_get(s);
        else if (a < 68) call_set(s);
        else if (a < 74) call_bad_arrays(s);
        else if (a < 80) call_step(s);
        else if (a < 84) call_refused(s);
        else if (a < 90) {   /* a fresh instance with a random setting */
            slot_free(s);
            slot_new(s, v3);
            if (s->c) random_setting(s);
        } else if (a < 92) slot_free(s);
        else if (a < 95) call_logging(s);
        else call_progress(s);
    }
    for (j = 0; j < NSLOT; j++) slot_free(&slots[j]);
    if (host_live_allocations() != live0) {
        n_fail++;
        printf("FAIL %ld callback allocations left after every instance was freed\n", host_live_allocations() - live0);
    }
    print_tally("settings refused at initialisation, by the variable named", &init_rules);
    print_tally("settings stopped by a non-finite number, by the number", &stop_causes);
    printf("calls: %ld (FMI 3.0: %ld), illegal calls checked: %ld, OK getters checked finite: %ld (%ld values), "
           "steps OK: %ld\n", n_calls, n_fmi3_calls, n_illegal, n_finite_gets, n_values_checked, n_steps_ok);
    printf("settings tried: %ld (%ld sets refused), refused at initialisation: %ld, stopped by a non-finite value: "
           "%ld, ran %d samples: %ld\n", n_settings, n_set_refused, n_init_refused, n_diverged, N_SAMPLES_SETTING, n_ran);
    printf("%ld passed, %ld failed\n", n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
}
