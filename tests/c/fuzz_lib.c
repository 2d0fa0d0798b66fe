/* Coverage-guided fuzz target (libFuzzer, clang -fsanitize=fuzzer,address,undefined) of the
 * FMU's state loader and its FMI call sequence. One input:
 *   byte 0, bit 0: instance type (0 model exchange, 1 co-simulation);
 *   bit 1 set: "state" input: the rest is a serialised FMU state handed to
 *     fmi2DeSerializeFMUstate (bit 2: its payload CRC-32 recomputed first, so mutations reach
 *     the field checks), then set and exercised for 10 steps;
 *   bit 1 clear: "calls" input: the rest is a program of FMI calls, one opcode byte each plus
 *     argument bytes (value reference index, value from a table or 8 raw bytes).
 * Oracle (abort = finding): no sanitizer report; no getter answers fmi2OK with a non-finite
 * value; every answer other than OK/Warning comes with a message; every callback allocation is
 * freed when the instance is. Seeds: tests/c/corpus/{state,calls} (written by fuzz_seeds). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi_host.h"
#include "model_vars.h"

#define HEADER_BYTES 96
#define CRC_AT 92
#define NSLOT 2

typedef struct { const uint8_t *d; size_t n, at; } prog_t;
typedef struct { fmi_api_t api; host_env_t env; fmi2CallbackFunctions cb; fmi2Component c; fmi2Type type;
                 fmi2FMUstate fs[NSLOT]; } ctx_t;

static uint8_t next_byte(prog_t *p) { return p->at < p->n ? p->d[p->at++] : 0; }

static double next_value(prog_t *p, unsigned vr) {
    static const double TABLE[] = {0.0, 1.0, -1.0, 1e-3, 1e3, 1e9, -1e9, 1e-6, 10.0, -10.0, 0.5, 1e308, 5e-324,
                                   1.7e9, 2.0, 1e-12, -1e-300, 100.0, 0.3, 16.1};
    uint8_t b = next_byte(p);
    const model_var_t *v = vr < MODEL_NVR && MODEL_VR_INDEX[vr] >= 0 ? &MODEL_VARS[MODEL_VR_INDEX[vr]] : NULL;
    if (b < 200) return TABLE[b % (sizeof TABLE / sizeof TABLE[0])];
    if (b < 210 && v) return v->min;
    if (b < 220 && v) return v->max;
    if (b < 230 && v) return v->start;
    if (b < 240) { double x; uint64_t u = 0; int j; for (j = 0; j < 8; j++) u |= (uint64_t)next_byte(p) << (8 * j);
                   memcpy(&x, &u, 8); return x; }
    return b == 240 ? NAN : (b == 241 ? HUGE_VAL : -HUGE_VAL);
}

static void require(int ok, const char *what) {
    if (ok) return;
    fprintf(stderr, "fuzz_lib finding: %s\n", what);
    abort();
}

/* status st of a call: an answer above Warning carries a message */
static int answered(ctx_t *x, int st) {
    require(st >= fmi2OK && st <= fmi2Pending, "status outside fmi2OK..fmi2Pending");
    if (st > fmi2Warning) require(x->env.n_since_mark > 0, "an error without a message");
    return st;
}

static void finite_if_ok(int st, const double *v, size_t n) {
    size_t j;
    if (st != fmi2OK) return;
    for (j = 0; j < n; j++) require(isfinite(v[j]), "fmi2OK with a non-finite value");
}

static void get_everything(ctx_t *x) {
    fmi2ValueReference vr[MODEL_NVARS];
    double v[MODEL_NVARS], st_x[MODEL_NX], z[MODEL_NZ];
    size_t n = 0;
    int j;
    for (j = 0; j < MODEL_NVARS; j++) if (MODEL_VARS[j].type == 'R') vr[n++] = MODEL_VARS[j].vr;
    host_env_mark(&x->env);
    finite_if_ok(answered(x, x->api.GetReal(x->c, vr, n, v)), v, n);
    if (x->type != fmi2ModelExchange) return;
    host_env_mark(&x->env);
    finite_if_ok(answered(x, x->api.GetDerivatives(x->c, st_x, MODEL_NX)), st_x, MODEL_NX);
    host_env_mark(&x->env);
    finite_if_ok(answered(x, x->api.GetEventIndicators(x->c, z, MODEL_NZ)), z, MODEL_NZ);
    host_env_mark(&x->env);
    finite_if_ok(answered(x, x->api.GetContinuousStates(x->c, st_x, MODEL_NX)), st_x, MODEL_NX);
}

static double fmu_time(ctx_t *x) {
    double t = 0.0;
    x->api.GetRealStatus(x->c, fmi2LastSuccessfulTime, &t);
    return t;
}

/* serialise slot j, mutate one byte from the program, load it back */
static void state_round_trip(ctx_t *x, prog_t *p, int j) {
    size_t size = 0;
    uint8_t *buf;
    fmi2FMUstate s = NULL;
    if (!x->fs[j] || x->api.SerializedFMUstateSize(x->c, x->fs[j], &size) != fmi2OK) return;
    buf = (uint8_t *)malloc(size);
    if (x->api.SerializeFMUstate(x->c, x->fs[j], (fmi2Byte *)buf, size) == fmi2OK) {
        size_t at = ((size_t)next_byte(p) << 8 | next_byte(p)) % size;
        buf[at] ^= next_byte(p);
        host_env_mark(&x->env);
        if (answered(x, x->api.DeSerializeFMUstate(x->c, (const fmi2Byte *)buf, size, &s)) == fmi2OK) {
            host_env_mark(&x->env);
            answered(x, x->api.SetFMUstate(x->c, s));
            x->api.FreeFMUstate(x->c, &s);
        }
    }
    free(buf);
}

static void one_call(ctx_t *x, prog_t *p) {
    uint8_t op = next_byte(p) % 22, a = next_byte(p);
    fmi2ValueReference vr = (fmi2ValueReference)MODEL_VARS[a % MODEL_NVARS].vr;
    double v, xs[MODEL_NX], out;
    fmi2Integer iv;
    fmi2Boolean bv, e1, e2;
    fmi2EventInfo ei;
    fmi2Integer order = 1;
    int j;
    host_env_mark(&x->env);
    switch (op) {
    case 0: v = next_value(p, vr); answered(x, x->api.SetReal(x->c, &vr, 1, &v)); break;
    case 1: iv = (fmi2Integer)(int8_t)next_byte(p); answered(x, x->api.SetInteger(x->c, &vr, 1, &iv)); break;
    case 2: bv = next_byte(p) & 1; answered(x, x->api.SetBoolean(x->c, &vr, 1, &bv)); break;
    case 3: answered(x, x->api.SetupExperiment(x->c, a & 1, 1e-6, next_value(p, 0), (a >> 1) & 1, next_value(p, 0))); break;
    case 4: answered(x, x->api.EnterInitializationMode(x->c)); break;
    case 5: answered(x, x->api.ExitInitializationMode(x->c)); break;
    case 6: answered(x, x->api.DoStep(x->c, (a & 1) ? next_value(p, 0) : fmu_time(x), 1e-4 * (1 + next_byte(p) % 100),
                                      fmi2True)); break;
    case 7: get_everything(x); break;
    case 8: answered(x, x->api.EnterEventMode(x->c)); break;
    case 9: answered(x, x->api.NewDiscreteStates(x->c, &ei)); break;
    case 10: answered(x, x->api.EnterContinuousTimeMode(x->c)); break;
    case 11: answered(x, x->api.SetTime(x->c, (a & 1) ? next_value(p, 0) : fmu_time(x) + 1e-5 * (1 + a))); break;
    case 12:
        if (x->api.GetContinuousStates(x->c, xs, MODEL_NX) != fmi2OK) for (j = 0; j < MODEL_NX; j++) xs[j] = 0.0;
        xs[a % MODEL_NX] += next_value(p, 0);
        host_env_mark(&x->env);
        answered(x, x->api.SetContinuousStates(x->c, xs, MODEL_NX));
        break;
    case 13: answered(x, x->api.CompletedIntegratorStep(x->c, fmi2True, &e1, &e2)); break;
    case 14: answered(x, x->api.GetFMUstate(x->c, &x->fs[a % NSLOT])); break;
    case 15: if (x->fs[a % NSLOT]) answered(x, x->api.SetFMUstate(x->c, x->fs[a % NSLOT])); break;
    case 16: state_round_trip(x, p, a % NSLOT); break;
    case 17: answered(x, x->api.Reset(x->c)); break;
    case 18: answered(x, x->api.Terminate(x->c)); break;
    case 19: vr = (a & 1) ? VR_x : VR_v;
             finite_if_ok(answered(x, x->api.GetRealOutputDerivatives(x->c, &vr, 1, &order, &out)), &out, 1); break;
    case 20: answered(x, x->api.FreeFMUstate(x->c, &x->fs[a % NSLOT])); break;
    default: v = (double)(a % 2 ? 10 : -10); vr = VR_u; answered(x, x->api.SetReal(x->c, &vr, 1, &v)); break;
    }
}

/* a serialised state: loaded, set, 10 steps (CS) or 10 ME rounds, everything read back */
static void load_state(ctx_t *x, const uint8_t *d, size_t n, int fix_crc) {
    uint8_t *buf = (uint8_t *)malloc(n ? n : 1);
    fmi2FMUstate s = NULL;
    prog_t run = {(const uint8_t *)"\x06\x00\x04\x07\x00\x0b\x00\x09\x00\x0a\x00\x07", 12, 0};
    int k;
    memcpy(buf, d, n);
    if (fix_crc && n > HEADER_BYTES) {
        uint32_t c = host_crc32(buf + HEADER_BYTES, n - HEADER_BYTES);
        for (k = 0; k < 4; k++) buf[CRC_AT + k] = (uint8_t)(c >> (8 * k));
    }
    host_env_mark(&x->env);
    if (answered(x, x->api.DeSerializeFMUstate(x->c, (const fmi2Byte *)buf, n, &s)) == fmi2OK) {
        host_env_mark(&x->env);
        if (answered(x, x->api.SetFMUstate(x->c, s)) == fmi2OK)
            for (k = 0; k < 10; k++) { run.at = 0; while (run.at < run.n) one_call(x, &run); }
        x->api.FreeFMUstate(x->c, &s);
    }
    free(buf);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    ctx_t x;
    char err[256];
    prog_t p = {data, size, 1};
    int j, steps = 0;
    if (size < 1) return 0;
    memset(&x, 0, sizeof x);
    if (fmi_api_load(&x.api, NULL, err, sizeof err) != 0) require(0, err);
    x.type = (data[0] & 1) ? fmi2CoSimulation : fmi2ModelExchange;
    x.cb = host_callbacks(&x.env);
    x.c = x.api.Instantiate("fuzz", x.type, MODEL_GUID, "", &x.cb, fmi2False, fmi2False);
    require(x.c != NULL, "fmi2Instantiate failed");
    if (data[0] & 2) {
        x.api.SetupExperiment(x.c, fmi2True, 1e-6, 0.0, fmi2False, 0.0);
        x.api.EnterInitializationMode(x.c);
        x.api.ExitInitializationMode(x.c);
        load_state(&x, data + 1, size - 1, (data[0] & 4) != 0);
    } else {
        while (p.at < p.n && steps++ < 400) one_call(&x, &p);
    }
    for (j = 0; j < NSLOT; j++) if (x.fs[j]) x.api.FreeFMUstate(x.c, &x.fs[j]);
    x.api.FreeInstance(x.c);
    require(host_live_allocations() == 0, "callback allocations left after fmi2FreeInstance");
    fmi_api_unload(&x.api);
    return 0;
}
