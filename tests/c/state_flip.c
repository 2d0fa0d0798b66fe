/* Corrupted FMU states: a serialised state of a co-simulation and of a model-exchange instance
 * (taken mid-run, with friction elements slipping and current-loop history) is
 *   - flipped at every bit (raw: the checksum then fails unless the flip is in a field the header
 *     checks itself),
 *   - flipped at every bit with the payload's CRC-32 recomputed (forged: every field check of the
 *     loader is exercised),
 *   - truncated at every length and extended by 8 bytes,
 * and each variant is handed to fmi2DeSerializeFMUstate + fmi2SetFMUstate. Each load must be
 * refused with a logged message, or be accepted and then run (10 steps of 0.5 ms, every Real
 * read back after each) with every answer fmi2OK/fmi2Warning with finite values, or fmi2Error
 * with a message. Meant for the ASan + UBSan build (state_flip_san): any memory error aborts.
 * Also: a state of the other interface, of another GUID and of another structure is refused with
 * a message naming what differs, and a serialise/deserialise round trip continues bit-identically.
 * Usage: state_flip [LinearMotorFeedDrive.so|-]. Prints one JSON line of counts and
 * "N passed, M failed". */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi_host.h"
#include "model_vars.h"

#define HEADER_BYTES 96   /* state_format.h: header, its last 4 bytes the payload's CRC-32 */
#define CRC_AT 92
#define NX_AT 76          /* the "continuous states" field of the header's structure */
#define GUID_AT 16

static fmi_api_t api;
static long n_pass, n_fail;
static double reals_buf[MODEL_NVARS];
static fmi2ValueReference real_vr[MODEL_NVARS];
static size_t n_real;

static void check(int ok, const char *what, const char *detail) {
    if (ok) { n_pass++; return; }
    n_fail++;
    if (n_fail <= 20) printf("FAIL %s: %s\n", what, detail);
}

static void put_u32(unsigned char *b, uint32_t v) {
    int j;
    for (j = 0; j < 4; j++) b[j] = (unsigned char)(v >> (8 * j));
}

/* an instance of type, run mid-way: CS 0.2 s of a 5 Hz sinusoid in u; ME the same by explicit
 * Euler through the ME calls up to 20 ms */
static fmi2Component start(fmi2Type type, host_env_t *env, fmi2CallbackFunctions *cb) {
    const fmi2ValueReference u_vr = VR_u;
    fmi2Component c;
    double t = 0.0, x[MODEL_NX], dx[MODEL_NX], u;
    fmi2EventInfo ei;
    fmi2Boolean enter, term;
    int k, j;
    memset(env, 0, sizeof *env);
    *cb = host_callbacks(env);
    c = api.Instantiate("flip", type, MODEL_GUID, "", cb, fmi2False, fmi2False);
    if (!c || api.SetupExperiment(c, fmi2True, 1e-6, 0.0, fmi2False, 0.0) != fmi2OK ||
        api.EnterInitializationMode(c) != fmi2OK || api.ExitInitializationMode(c) != fmi2OK) return NULL;
    if (type == fmi2CoSimulation) {
        for (k = 0; k < 400; k++, t += 5e-4) {
            u = 2.0 * sin(2.0 * M_PI * 5.0 * t);
            if (api.SetReal(c, &u_vr, 1, &u) != fmi2OK || api.DoStep(c, t, 5e-4, fmi2True) != fmi2OK) return NULL;
        }
        return c;
    }
    if (api.NewDiscreteStates(c, &ei) != fmi2OK || api.EnterContinuousTimeMode(c) != fmi2OK) return NULL;
    for (k = 0; k < 400; k++) {
        t += 5e-5;
        u = 2.0 * sin(2.0 * M_PI * 5.0 * t);
        if (api.GetContinuousStates(c, x, MODEL_NX) != fmi2OK || api.GetDerivatives(c, dx, MODEL_NX) != fmi2OK)
            return NULL;
        for (j = 0; j < MODEL_NX; j++) x[j] += 5e-5 * dx[j];
        if (api.SetTime(c, t) != fmi2OK || api.SetContinuousStates(c, x, MODEL_NX) != fmi2OK ||
            api.SetReal(c, &u_vr, 1, &u) != fmi2OK || api.CompletedIntegratorStep(c, fmi2True, &enter, &term) != fmi2OK)
            return NULL;
        if (k % 10 == 9) {
            if (api.EnterEventMode(c) != fmi2OK || api.NewDiscreteStates(c, &ei) != fmi2OK ||
                api.EnterContinuousTimeMode(c) != fmi2OK) return NULL;
        }
    }
    return c;
}

/* every Real readable: fmi2OK with finite values, or refused with a message */
static int reals_clean(fmi2Component c, host_env_t *env) {
    size_t j;
    int st;
    host_env_mark(env);
    st = api.GetReal(c, real_vr, n_real, reals_buf);
    if (st > fmi2Warning) return env->n_since_mark > 0;
    for (j = 0; j < n_real; j++) if (!isfinite(reals_buf[j])) return 0;
    return 1;
}

/* an accepted state: 10 steps of 0.5 ms (CS), or 10 ME time steps with event checks */
static int exercise(fmi2Component c, fmi2Type type, host_env_t *env) {
    double t = 0.0, x[MODEL_NX], dx[MODEL_NX], z[MODEL_NZ];
    fmi2Boolean enter, term;
    fmi2EventInfo ei;
    int k, j, st;
    if (type == fmi2CoSimulation) {
        api.GetRealStatus(c, fmi2LastSuccessfulTime, &t);
        for (k = 0; k < 10; k++, t += 5e-4) {
            host_env_mark(env);
            st = api.DoStep(c, t, 5e-4, fmi2True);
            if (st > fmi2Warning) return env->n_since_mark > 0;
            if (!reals_clean(c, env)) return 0;
        }
        return 1;
    }
    for (k = 0; k < 10; k++) {
        host_env_mark(env);
        if (api.GetContinuousStates(c, x, MODEL_NX) > fmi2Warning || api.GetDerivatives(c, dx, MODEL_NX) > fmi2Warning ||
            api.GetEventIndicators(c, z, MODEL_NZ) > fmi2Warning) return env->n_since_mark > 0;
        for (j = 0; j < MODEL_NX; j++) if (!isfinite(x[j]) || !isfinite(dx[j])) return 0;
        for (j = 0; j < MODEL_NZ; j++) if (!isfinite(z[j])) return 0;
        for (j = 0; j < MODEL_NX; j++) x[j] += 5e-5 * dx[j];
        if (api.SetContinuousStates(c, x, MODEL_NX) > fmi2Warning ||
            api.CompletedIntegratorStep(c, fmi2True, &enter, &term) > fmi2Warning ||
            api.EnterEventMode(c) > fmi2Warning || api.NewDiscreteStates(c, &ei) > fmi2Warning ||
            api.EnterContinuousTimeMode(c) > fmi2Warning) return env->n_since_mark > 0;
        if (!reals_clean(c, env)) return 0;
    }
    return 1;
}

typedef struct { long refused, accepted; } tally_t;

/* one corrupted state: refused with a message, or accepted and clean */
static void probe(fmi2Component c, fmi2Type type, host_env_t *env, const unsigned char *b, size_t len,
                  tally_t *t, const char *what) {
    fmi2FMUstate s = NULL;
    char detail[1200];
    host_env_mark(env);
    if (api.DeSerializeFMUstate(c, (const fmi2Byte *)b, len, &s) > fmi2Warning) {
        t->refused++;
        snprintf(detail, sizeof detail, "%s: refused without a message", what);
        check(env->n_since_mark > 0, "load", detail);
        return;
    }
    host_env_mark(env);
    if (api.SetFMUstate(c, s) > fmi2Warning) {
        t->refused++;
        check(env->n_since_mark > 0, "set", what);
    } else {
        t->accepted++;
        snprintf(detail, sizeof detail, "%s: accepted, then a non-finite value or a silent error (%s)", what,
                 env->last);
        check(exercise(c, type, env), "run", detail);
    }
    api.FreeFMUstate(c, &s);
}

static int campaign(fmi2Type type, const char *name) {
    host_env_t env;
    fmi2CallbackFunctions cb;
    fmi2Component c = start(type, &env, &cb);
    fmi2FMUstate s = NULL;
    unsigned char *ref, *buf;
    size_t len = 0, i;
    tally_t raw = {0, 0}, forged = {0, 0}, trunc = {0, 0};
    char what[64];
    if (!c) { printf("FAIL %s: set-up run failed: %s\n", name, env.last); n_fail++; return -1; }
    if (api.GetFMUstate(c, &s) != fmi2OK || api.SerializedFMUstateSize(c, s, &len) != fmi2OK) return -1;
    ref = (unsigned char *)malloc(len + 8);
    buf = (unsigned char *)malloc(len + 8);
    if (api.SerializeFMUstate(c, s, (fmi2Byte *)ref, len) != fmi2OK) return -1;
    api.FreeFMUstate(c, &s);
    for (i = 0; i < 8 * len; i++) {
        memcpy(buf, ref, len);
        buf[i / 8] ^= (unsigned char)(1u << (i % 8));
        snprintf(what, sizeof what, "%s bit %zu", name, i);
        probe(c, type, &env, buf, len, &raw, what);
        if (i / 8 >= HEADER_BYTES) put_u32(buf + CRC_AT, host_crc32(buf + HEADER_BYTES, len - HEADER_BYTES));
        else continue;
        snprintf(what, sizeof what, "%s forged bit %zu", name, i);
        probe(c, type, &env, buf, len, &forged, what);
    }
    for (i = 0; i < len; i++) {
        snprintf(what, sizeof what, "%s truncated to %zu", name, i);
        probe(c, type, &env, ref, i, &trunc, what);
    }
    memcpy(buf, ref, len);
    memset(buf + len, 0, 8);
    probe(c, type, &env, buf, len + 8, &trunc, "extended by 8 bytes");
    check(trunc.accepted == 0, "truncations", "a truncated or extended state was accepted");
    printf("{\"interface\": \"%s\", \"bytes\": %zu, \"bit_flips\": %zu, \"flips_refused\": %ld, "
           "\"flips_accepted_clean\": %ld, \"forged_flips\": %ld, \"forged_refused\": %ld, "
           "\"forged_accepted_clean\": %ld, \"truncations\": %ld, \"truncations_refused\": %ld}\n",
           name, len, 8 * len, raw.refused, raw.accepted, forged.refused + forged.accepted, forged.refused,
           forged.accepted, trunc.refused + trunc.accepted, trunc.refused);
    free(ref);
    free(buf);
    api.FreeInstance(c);
    return 0;
}

/* refused, with a message containing `needle` */
static void refused_naming(fmi2Component c, host_env_t *env, const unsigned char *b, size_t len, const char *needle,
                           const char *what) {
    fmi2FMUstate s = NULL;
    char detail[1200];
    int st;
    host_env_mark(env);
    st = api.DeSerializeFMUstate(c, (const fmi2Byte *)b, len, &s);
    snprintf(detail, sizeof detail, "%s: status %d, message \"%s\" (expected to name \"%s\")", what, st, env->last,
             needle);
    check(st == fmi2Error && strstr(env->last, needle) != NULL, what, detail);
    if (s) api.FreeFMUstate(c, &s);
}

/* 20 steps of 0.5 ms from the instance's time: x, v, F_friction at the end */
static void continue_cs(fmi2Component c, double *out) {
    const fmi2ValueReference u_vr = VR_u, vr[3] = {VR_x, VR_v, VR_F_friction};
    double t = 0.0, u;
    int k;
    api.GetRealStatus(c, fmi2LastSuccessfulTime, &t);
    for (k = 0; k < 20; k++, t += 5e-4) {
        u = 2.0 * sin(2.0 * M_PI * 5.0 * t);
        api.SetReal(c, &u_vr, 1, &u);
        api.DoStep(c, t, 5e-4, fmi2True);
    }
    api.GetReal(c, vr, 3, out);
}

static void cross_checks(void) {
    host_env_t ea, eb;
    fmi2CallbackFunctions ca, cb;
    fmi2Component a = start(fmi2CoSimulation, &ea, &ca), b = start(fmi2ModelExchange, &eb, &cb);
    fmi2FMUstate sa = NULL, sb = NULL, s1 = NULL;
    unsigned char bufa[8192], bufb[8192];
    size_t la = 0, lb = 0;
    double xa[3], xb[3];
    char detail[256];
    if (!a || !b) { check(0, "cross set-up", ea.last); return; }
    api.GetFMUstate(a, &sa);
    api.GetFMUstate(b, &sb);
    api.SerializedFMUstateSize(a, sa, &la);
    api.SerializedFMUstateSize(b, sb, &lb);
    if (la > sizeof bufa || lb > sizeof bufb) { check(0, "cross", "state larger than 8 KiB"); return; }
    api.SerializeFMUstate(a, sa, (fmi2Byte *)bufa, la);
    api.SerializeFMUstate(b, sb, (fmi2Byte *)bufb, lb);
    refused_naming(a, &ea, bufb, lb, "model exchange", "ME state into a CS instance");
    refused_naming(b, &eb, bufa, la, "co-simulation", "CS state into an ME instance");
    host_env_mark(&ea);
    check(api.SetFMUstate(a, sb) == fmi2Error && strstr(ea.last, "model exchange") != NULL,
          "fmi2SetFMUstate of an ME snapshot into CS", ea.last);
    bufa[GUID_AT + 1] ^= 1;
    refused_naming(a, &ea, bufa, la, "GUID", "state of another GUID");
    bufa[GUID_AT + 1] ^= 1;
    put_u32(bufa + NX_AT, 10);
    refused_naming(a, &ea, bufa, la, "continuous states 10", "state of another structure");
    put_u32(bufa + NX_AT, MODEL_NX);
    /* round trip: continue from the original and from its serialised copy */
    check(api.DeSerializeFMUstate(a, (const fmi2Byte *)bufa, la, &s1) == fmi2OK, "round trip load", ea.last);
    continue_cs(a, xa);
    check(api.SetFMUstate(a, s1) == fmi2OK, "round trip set", ea.last);
    continue_cs(a, xb);
    snprintf(detail, sizeof detail, "x %.17g vs %.17g, v %.17g vs %.17g, F_friction %.17g vs %.17g", xa[0], xb[0],
             xa[1], xb[1], xa[2], xb[2]);
    check(memcmp(xa, xb, sizeof xa) == 0, "round trip continues bit-identically", detail);
    api.FreeFMUstate(a, &sa);
    api.FreeFMUstate(a, &s1);
    api.FreeFMUstate(b, &sb);
    api.FreeInstance(a);
    api.FreeInstance(b);
}

int main(int argc, char **argv) {
    char err[512];
    const char *so = argc > 1 && strcmp(argv[1], "-") != 0 ? argv[1] : NULL;
    int j;
    double w0 = host_now();
    if (fmi_api_load(&api, so, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 2; }
    for (j = 0; j < MODEL_NVARS; j++)
        if (MODEL_VARS[j].type == 'R') real_vr[n_real++] = MODEL_VARS[j].vr;
    cross_checks();
    campaign(fmi2CoSimulation, "co-simulation");
    campaign(fmi2ModelExchange, "model exchange");
    if (host_live_allocations() != 0) check(0, "allocations", "callback allocations left at the end");
    fmi_api_unload(&api);
    printf("wall %.1f s\n%ld passed, %ld failed\n", host_now() - w0, n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
}
