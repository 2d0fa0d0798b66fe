/* Coverage-guided fuzz target (libFuzzer, clang -fsanitize=fuzzer,address,undefined) of the
 * controller FMU's call sequence, FMI 2.0 and 3.0 (the controller's sources linked in). One
 * input is a program of calls, one opcode byte each plus argument bytes (a variable by index into
 * its table, a value from a table of edge cases, the variable's min/max/start, or 8 raw bytes), on
 * one FMI 2.0 and one FMI 3.0 instance.
 * Oracle (abort = finding): no sanitizer report; no getter answers OK with a non-finite value;
 * every answer other than OK comes with a message; no step takes more than the budget of
 * samples (the call returns); every callback allocation is freed with the instance. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ctrl_host.h"

fmi_api_t api;   /* ctrl_host.h's table (ctrl_host.c is not linked here) */

typedef struct { const uint8_t *d; size_t n, at; } prog_t;
typedef struct { host_env_t env; fmi2Component c; env3_t e3; fmi3Instance i; } ctx_t;

void env3_mark(env3_t *e) { e->worst = -1; e->n_since_mark = 0; }
void env3_log(fmi3InstanceEnvironment env, fmi3Status status, fmi3String category, fmi3String message) {
    env3_t *e = (env3_t *)env;
    (void)category;
    e->n_msgs++;
    e->n_since_mark++;
    if ((int)status > e->worst) e->worst = (int)status;
    snprintf(e->last, sizeof e->last, "%s", message ? message : "(null)");
}

static uint8_t next_byte(prog_t *p) { return p->at < p->n ? p->d[p->at++] : 0; }

static const ctrl_var_t *next_var(prog_t *p) {
    unsigned k = (unsigned)next_byte(p) << 8 | next_byte(p);
    return &CTRL_VARS[k % CTRL_NVARS];
}

static double next_value(prog_t *p, const ctrl_var_t *v) {
    static const double TABLE[] = {0.0, 1.0, -1.0, 1e-3, 1e3, 1e9, -1e9, 1e-6, 10.0, -10.0, 0.5, 1e308, 5e-324,
                                   1e-9, 2.0, 1e-12, -1e-300, 100.0, 0.15, 5e-4, 1e15, -1e15, 1e12, 0.999};
    uint8_t b = next_byte(p);
    if (b < 180) return TABLE[b % (sizeof TABLE / sizeof TABLE[0])];
    if (b < 200) return v->min;
    if (b < 220) return v->max;
    if (b < 235) return v->start;
    if (b < 250) {
        double x;
        uint64_t u = 0;
        int j;
        for (j = 0; j < 8; j++) u |= (uint64_t)next_byte(p) << (8 * j);
        memcpy(&x, &u, 8);
        return x;
    }
    return b == 250 ? NAN : (b == 251 ? INFINITY : -INFINITY);
}

static void require(int ok, const char *what, const char *last) {
    if (ok) return;
    fprintf(stderr, "ctrl_fuzz_lib finding: %s (last message: %s)\n", what, last);
    abort();
}

static int answered2(ctx_t *x, int st) {
    require(st >= fmi2OK && st <= fmi2Fatal, "FMI 2.0 status outside fmi2OK..fmi2Fatal", x->env.last);
    if (st != fmi2OK) require(x->env.n_since_mark > 0, "an FMI 2.0 answer other than OK without a message", "");
    return st;
}
static int answered3(ctx_t *x, int st) {
    require(st >= fmi3OK && st <= fmi3Fatal, "FMI 3.0 status outside fmi3OK..fmi3Fatal", x->e3.last);
    if (st != fmi3OK) require(x->e3.n_since_mark > 0, "an FMI 3.0 answer other than OK without a message", "");
    return st;
}

/* every Real (FMI 3.0: also the time, value reference 0): finite when OK */
static void get_everything(ctx_t *x, int v3) {
    unsigned vr[CTRL_NVARS + 1];
    double v[CTRL_NVARS + 1];
    size_t n = 0, j;
    int st;
    if (v3) vr[n++] = 0;
    for (j = 0; j < CTRL_NVARS; j++) if (CTRL_VARS[j].type == 'R') vr[n++] = CTRL_VARS[j].vr;
    if (v3) { env3_mark(&x->e3); st = answered3(x, fmi3GetFloat64(x->i, vr, n, v, n)); }
    else { host_env_mark(&x->env); st = answered2(x, api.GetReal(x->c, vr, n, v)); }
    if (st == 0)
        for (j = 0; j < n; j++) require(isfinite(v[j]), "a getter answered OK with a non-finite value", "");
}

static double step_size(prog_t *p) {
    static const double H[] = {5e-4, 1e-3, 2.5e-4, 1e-2, 0.1, 1.0, 1e-9, 1e-6};
    uint8_t b = next_byte(p);
    return b < 200 ? H[b % 8] : next_value(p, &CTRL_VARS[0]);
}

static void one_call(ctx_t *x, prog_t *p) {
    uint8_t op = next_byte(p) % 16;
    const ctrl_var_t *var = next_var(p);
    unsigned vr = var->vr;
    double v, t = 0.0;
    fmi2Integer iv;
    fmi2Boolean bv;
    fmi3Boolean b3[2] = {fmi3False, fmi3False}, ev, term, early;
    fmi3Float64 last;
    size_t n;
    host_env_mark(&x->env);
    env3_mark(&x->e3);
    switch (op) {
    case 0: v = next_value(p, var); answered2(x, api.SetReal(x->c, &vr, 1, &v)); break;
    case 1: iv = (fmi2Integer)(int8_t)next_byte(p); answered2(x, api.SetInteger(x->c, &vr, 1, &iv)); break;
    case 2: bv = next_byte(p) & 1; answered2(x, api.SetBoolean(x->c, &vr, 1, &bv)); break;
    case 3: get_everything(x, 0); break;
    case 4:
        api.GetRealStatus(x->c, fmi2LastSuccessfulTime, &t);
        answered2(x, api.DoStep(x->c, t, step_size(p), fmi2True));
        break;
    case 5:
        if (next_byte(p) & 1) answered2(x, api.SetupExperiment(x->c, fmi2False, 0.0, next_byte(p) & 1 ? 1e12 : 0.0,
                                                               fmi2False, 0.0));
        host_env_mark(&x->env);
        answered2(x, api.EnterInitializationMode(x->c));
        host_env_mark(&x->env);
        answered2(x, api.ExitInitializationMode(x->c));
        break;
    case 6: answered2(x, next_byte(p) & 1 ? api.Terminate(x->c) : api.Reset(x->c)); break;
    case 7: v = next_value(p, var); answered3(x, fmi3SetFloat64(x->i, &vr, 1, &v, 1)); break;
    case 8: iv = (fmi3Int32)(int8_t)next_byte(p); answered3(x, fmi3SetInt32(x->i, &vr, 1, &iv, 1)); break;
    case 9:
        n = next_byte(p) & 1 ? 1 : SIZE_MAX;
        b3[0] = next_byte(p) & 1;
        answered3(x, next_byte(p) & 1 ? fmi3SetBoolean(x->i, &vr, n, b3, n) : fmi3GetBoolean(x->i, &vr, n, b3, n));
        break;
    case 10: get_everything(x, 1); break;
    case 11:
        fmi3GetFloat64(x->i, (const fmi3ValueReference[]){0}, 1, &t, 1);
        answered3(x, fmi3DoStep(x->i, t, step_size(p), fmi3True, &ev, &term, &early, &last));
        break;
    case 12:
        answered3(x, fmi3EnterInitializationMode(x->i, fmi3False, 0.0, 0.0, fmi3False, 0.0));
        env3_mark(&x->e3);
        answered3(x, fmi3ExitInitializationMode(x->i));
        break;
    case 13: answered3(x, next_byte(p) & 1 ? fmi3Terminate(x->i) : fmi3Reset(x->i)); break;
    case 14: answered3(x, fmi3GetFloat64(x->i, next_byte(p) & 1 ? NULL : &vr, 1, &v, 1)); break;
    default: answered2(x, api.GetReal(x->c, next_byte(p) & 1 ? NULL : &vr, next_byte(p) & 1 ? 1 : SIZE_MAX, &v)); break;
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static int loaded;
    char err[256];
    ctx_t x;
    prog_t p = {data, size, 0};
    fmi2CallbackFunctions cb;
    long live0;
    int k;
    if (!loaded) {
        require(fmi_api_load(&api, NULL, err, sizeof err) == 0, "fmi_api_load", err);
        loaded = 1;
    }
    memset(&x, 0, sizeof x);
    live0 = host_live_allocations();
    cb = host_callbacks(&x.env);
    x.c = api.Instantiate("fuzz2", fmi2CoSimulation, CTRL_GUID, "", &cb, fmi2False, fmi2False);
    x.i = fmi3InstantiateCoSimulation("fuzz3", CTRL_GUID, NULL, fmi3False, fmi3False, fmi3False, fmi3False, NULL, 0,
                                      &x.e3, env3_log, NULL);
    require(x.c && x.i, "instantiation failed", x.env.last);
    for (k = 0; k < 64 && p.at < p.n; k++) one_call(&x, &p);
    api.FreeInstance(x.c);
    fmi3FreeInstance(x.i);
    require(host_live_allocations() == live0, "callback allocations left after fmi2FreeInstance", "");
    return 0;
}
