/* Fuzz test of the FMU's FMI 2.0 API: random call sequences over a few ME and CS instances with
 * random arguments (NaN, +-Inf, huge, negative and denormal values, unknown and mistyped value
 * references, NULL pointers where the standard lets the FMU check them, calls in the wrong
 * state, foreign FMU states and instances). Meant for the AddressSanitizer + UBSan build
 * (fuzz_fmi_san): any memory error or undefined behaviour aborts the run.
 *
 * The oracle keeps its own model of each instance's FMI state. Checks, per call:
 *   - the status is one of fmi2OK..fmi2Pending;
 *   - every answer other than fmi2OK comes with at least one logged message (except for a NULL
 *     or foreign component, which has no logger to use);
 *   - a call that the standard or this FMU's modelDescription makes certainly illegal in the
 *     modelled state (wrong state, unknown value reference, wrong type, NULL array, non-finite
 *     or out-of-[min, max] value, wrong array size, capability not provided, ...) is answered
 *     fmi2Error or fmi2Discard;
 *   - a certainly legal get (known value references of the right type, after initialisation) is
 *     answered fmi2OK.
 * After an fmi2Error the model no longer knows the FMU's state: the instance is "tainted" and
 * only the first two checks apply until fmi2Reset succeeds or it is freed.
 * Usage: fuzz_fmi [LinearMotorFeedDrive.so] [calls=200000] [seed=1].
 * Prints counts, the first failures, and "N passed, M failed" (N = calls whose checks passed). */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_oracle.h"

/* ---------------------------------------------------------------- calls */

static void after(inst_t *I, int status, int new_st);

/* the call the modelled state calls for, with valid arguments: keeps the runs going deep */
static void call_progress(inst_t *I) {
    int status, next = S_NONE, me = I->type == fmi2ModelExchange;
    host_env_mark(&I->env);
    switch (I->st) {
    case S_INST:
        if (chance(0.5)) {
            cur_fn = "fmi2SetupExperiment";
            I->stop_defined = chance(0.3);
            I->stop = 0.2;
            status = api.SetupExperiment(I->c, chance(0.5), 1e-6, 0.0, I->stop_defined, I->stop);
            I->time = 0.0;
        } else {
            cur_fn = "fmi2EnterInitializationMode";
            status = api.EnterInitializationMode(I->c);
            next = S_INIT;
        }
        break;
    case S_INIT:
        cur_fn = "fmi2ExitInitializationMode";
        status = api.ExitInitializationMode(I->c);
        next = me ? S_EVENT : S_STEP;
        break;
    case S_EVENT:
        if (chance(0.5)) {
            fmi2EventInfo ei;
            cur_fn = "fmi2NewDiscreteStates";
            status = api.NewDiscreteStates(I->c, &ei);
        } else {
            cur_fn = "fmi2EnterContinuousTimeMode";
            status = api.EnterContinuousTimeMode(I->c);
            next = S_CONT;
        }
        break;
    case S_CONT:
        if (chance(0.7)) {
            double x[MODEL_NX], dx[MODEL_NX];
            int j;
            cur_fn = "fmi2GetDerivatives";
            status = api.GetDerivatives(I->c, dx, MODEL_NX);
            judge(I, status, 0, 1, 1);
            check_finite(status, dx, MODEL_NX);
            if (status != fmi2OK) { after(I, status, S_NONE); return; }
            cur_fn = "fmi2GetContinuousStates";
            host_env_mark(&I->env);
            status = api.GetContinuousStates(I->c, x, MODEL_NX);
            judge(I, status, 0, 1, 1);
            check_finite(status, x, MODEL_NX);
            for (j = 0; j < MODEL_NX; j++) x[j] += 2e-5 * dx[j];
            I->time += 2e-5;
            cur_fn = "fmi2SetTime";
            host_env_mark(&I->env);
            status = api.SetTime(I->c, I->time);
            judge(I, status, -1, 0, 1);
            cur_fn = "fmi2SetContinuousStates";
            host_env_mark(&I->env);
            status = api.SetContinuousStates(I->c, x, MODEL_NX);
            if (status == fmi2OK) n_me_steps_ok++;
        } else {
            cur_fn = "fmi2EnterEventMode";
            status = api.EnterEventMode(I->c);
            next = S_EVENT;
        }
        break;
    case S_STEP:
        if (I->stop_defined && I->time + 1e-3 > I->stop) { cur_fn = "fmi2Terminate"; status = api.Terminate(I->c); next = S_TERM; break; }
        cur_fn = "fmi2DoStep";
        status = api.DoStep(I->c, I->time, 5e-4, fmi2True);
        if (status <= fmi2Warning) { I->time += 5e-4; n_dostep_ok++; }
        break;
    default:
        cur_fn = "fmi2Reset";
        status = api.Reset(I->c);
        if (status == fmi2OK) { I->st = S_INST; I->tainted = 0; I->time = 0.0; I->stop_defined = 0; }
        judge(I, status, -1, 0, 1);
        return;
    }
    judge(I, status, -1, 0, 1);
    after(I, status, next);
}

static void free_states(inst_t *I) {
    int j;
    for (j = 0; j < NSTATE; j++)
        if (I->fs[j]) { api.FreeFMUstate(I->c, &I->fs[j]); I->fs[j] = NULL; }
}

static void do_instantiate(inst_t *I) {
    int k = rint_(12);
    const char *name = "fuzz", *guid = MODEL_GUID;
    fmi2Type type = chance(0.5) ? fmi2ModelExchange : fmi2CoSimulation;
    int illegal = 0;
    const fmi2CallbackFunctions *cbp;
    memset(I, 0, sizeof *I);
    I->cb = host_callbacks(&I->env);
    cbp = &I->cb;
    if (k == 0) { name = NULL; illegal = 1; }
    else if (k == 1) { name = ""; illegal = 1; }
    else if (k == 2) { guid = "{00000000-0000-0000-0000-000000000000}"; illegal = 1; }
    else if (k == 3) { guid = NULL; illegal = 1; }
    else if (k == 4) { type = (fmi2Type)(2 + rint_(100)); illegal = 1; }
    else if (k == 5) { cbp = NULL; illegal = 1; }
    cur_fn = "fmi2Instantiate";
    host_env_mark(&I->env);
    I->c = api.Instantiate(name, type, guid, chance(0.5) ? "" : NULL, cbp, fmi2False, chance(0.3));
    n_calls++;
    if (illegal && I->c) { fail("illegal fmi2Instantiate returned an instance", 0, NULL); }
    else if (!illegal && !I->c) { fail("legal fmi2Instantiate returned NULL", 0, I); }
    else if (illegal && cbp && I->env.n_since_mark == 0) { fail("rejected fmi2Instantiate logged no message", 0, I); }
    else n_ok_checks++;
    if (I->c) { I->type = type; I->st = S_INST; }
}

static void do_free(inst_t *I) {
    free_states(I);
    api.FreeInstance(I->c);
    memset(I, 0, sizeof *I);
}

/* transitions after fmi2OK/Warning (or taint after Error/Fatal) */
static void after(inst_t *I, int status, int new_st) {
    if (status >= fmi2Error) { I->tainted = 1; return; }
    if (status <= fmi2Warning && new_st != S_NONE && !I->tainted) I->st = new_st;
}

static void call_get_set(inst_t *I, int is_set) {
    static const char T[3] = {'R', 'I', 'B'};
    char type = T[rint_(3)];
    size_t n = (size_t)rint_(5), j;
    fmi2ValueReference vr[8];
    double rv[8];
    fmi2Integer iv[8];
    fmi2Boolean bv[8];
    int bad = 0, rows[8], status, all_valid = 1;
    int null_vr = n > 0 && chance(0.04), null_val = n > 0 && chance(0.04);
    for (j = 0; j < n; j++) {
        int b = 0;
        vr[j] = pick_vr(type, &b, &rows[j]);
        if (b) bad = 1;
        if (rows[j] < 0) { all_valid = 0; continue; }
        if (is_set) {
            const model_var_t *v = &MODEL_VARS[rows[j]];
            if (!settable(rows[j], I->st)) bad = 1;
            if (type == 'R') {
                rv[j] = pick_real(rows[j]);
                if (!isfinite(rv[j]) || rv[j] < v->min || rv[j] > v->max) {
                    bad = 1;
                    snprintf(cur_detail, sizeof cur_detail, " (%s = %g, declared [%g, %g])", v->name, rv[j], v->min, v->max);
                }
            } else if (type == 'I') {
                int k = rint_(6);
                iv[j] = k < 3 ? (fmi2Integer)v->start : (k == 3 ? -1 : (k == 4 ? 2147483647 : (fmi2Integer)rint_(20)));
                if ((double)iv[j] < v->min || (double)iv[j] > v->max) bad = 1;
            } else {
                int k = rint_(8);
                bv[j] = k < 6 ? (fmi2Boolean)(k & 1) : (k == 6 ? 2 : -1);
                if (bv[j] != 0 && bv[j] != 1) bad = 1;
            }
        }
    }
    if (null_vr || null_val) bad = 1;
    if (!is_set && !getable_state(I->st) && !I->tainted) bad = 1;
    if (is_set && I->st == S_TERM) bad = 1;
    if (!bad) cur_detail[0] = 0;
    host_env_mark(&I->env);
    if (is_set) {
        cur_fn = type == 'R' ? "fmi2SetReal" : type == 'I' ? "fmi2SetInteger" : "fmi2SetBoolean";
        if (type == 'R') status = api.SetReal(I->c, null_vr ? NULL : vr, n, null_val ? NULL : rv);
        else if (type == 'I') status = api.SetInteger(I->c, null_vr ? NULL : vr, n, null_val ? NULL : iv);
        else status = api.SetBoolean(I->c, null_vr ? NULL : vr, n, null_val ? NULL : bv);
        judge(I, status, bad ? 1 : -1, 0, 1);
    } else {
        cur_fn = type == 'R' ? "fmi2GetReal" : type == 'I' ? "fmi2GetInteger" : "fmi2GetBoolean";
        if (type == 'R') status = api.GetReal(I->c, null_vr ? NULL : vr, n, null_val ? NULL : rv);
        else if (type == 'I') status = api.GetInteger(I->c, null_vr ? NULL : vr, n, null_val ? NULL : iv);
        else status = api.GetBoolean(I->c, null_vr ? NULL : vr, n, null_val ? NULL : bv);
        if (type == 'R' && !null_vr && !null_val) check_finite(status, rv, n);
        judge(I, status, bad ? 1 : (all_valid && I->st != S_INIT ? 0 : -1), 1, 1);
    }
    after(I, status, S_NONE);
}

static void call_string(inst_t *I) {
    fmi2ValueReference vr = (fmi2ValueReference)rint_(MODEL_NVR + 5);
    fmi2String s = "text";
    size_t n = (size_t)rint_(2);
    int status;
    host_env_mark(&I->env);
    if (chance(0.5)) { cur_fn = "fmi2GetString"; status = api.GetString(I->c, &vr, n, &s); }
    else { cur_fn = "fmi2SetString"; status = api.SetString(I->c, &vr, n, &s); }
    judge(I, status, n > 0 ? 1 : -1, 0, 1);
    after(I, status, S_NONE);
}

static void call_setup(inst_t *I) {
    fmi2Boolean tol_def = chance(0.7), stop_def = chance(0.4);
    double tol = chance(0.8) ? pow(10.0, -3.0 - 7.0 * runif()) : special();
    double start = chance(0.8) ? 0.0 : (chance(0.5) ? 10.0 * runif() : special());
    double stop = chance(0.8) ? start + 0.05 + runif() : special();
    int illegal = I->st != S_INST || !isfinite(start) ||
                  (tol_def && (!isfinite(tol) || tol <= 0.0)) || (stop_def && (!isfinite(stop) || stop < start));
    int status;
    cur_fn = "fmi2SetupExperiment";
    host_env_mark(&I->env);
    status = api.SetupExperiment(I->c, tol_def, tol, start, stop_def, stop);
    judge(I, status, illegal ? 1 : -1, 0, 1);
    if (status == fmi2OK && !I->tainted) { I->time = start; I->stop_defined = stop_def; I->stop = stop; }
    after(I, status, S_NONE);
}

static void call_mode(inst_t *I) {
    int k = rint_(7), status = 0, illegal = -1, next = S_NONE;
    int me = I->type == fmi2ModelExchange;
    host_env_mark(&I->env);
    switch (k) {
    case 0:
        cur_fn = "fmi2EnterInitializationMode";
        status = api.EnterInitializationMode(I->c);
        illegal = I->st != S_INST; next = S_INIT; break;
    case 1:
        cur_fn = "fmi2ExitInitializationMode";
        status = api.ExitInitializationMode(I->c);
        illegal = I->st != S_INIT ? 1 : -1; next = me ? S_EVENT : S_STEP; break;
    case 2:
        cur_fn = "fmi2Terminate";
        status = api.Terminate(I->c);
        illegal = !(I->st == S_EVENT || I->st == S_CONT || I->st == S_STEP) ? 1 : -1; next = S_TERM; break;
    case 3:
        cur_fn = "fmi2Reset";
        status = api.Reset(I->c);
        illegal = -1;
        if (status == fmi2OK) { I->tainted = 0; I->st = S_INST; I->time = 0.0; I->stop_defined = 0; }
        judge(I, status, -1, 0, 1);
        return;
    case 4:
        cur_fn = "fmi2EnterEventMode";
        status = api.EnterEventMode(I->c);
        illegal = (!me || I->st == S_INST || I->st == S_INIT || I->st == S_TERM || I->st == S_STEP) ? 1 : -1;
        next = S_EVENT; break;
    case 5:
        cur_fn = "fmi2EnterContinuousTimeMode";
        status = api.EnterContinuousTimeMode(I->c);
        illegal = (!me || I->st != S_EVENT) ? 1 : -1; next = S_CONT; break;
    case 6: {
        fmi2EventInfo ei;
        int null = chance(0.1);
        cur_fn = "fmi2NewDiscreteStates";
        status = api.NewDiscreteStates(I->c, null ? NULL : &ei);
        illegal = (!me || I->st != S_EVENT || null) ? 1 : -1; break;
    }
    }
    judge(I, status, illegal, 0, 1);
    after(I, status, next);
}

static void call_me_continuous(inst_t *I) {
    int k = rint_(7), status = 0, illegal = -1, me = I->type == fmi2ModelExchange;
    size_t nx = chance(0.9) ? MODEL_NX : (size_t)rint_(30), nz = chance(0.9) ? MODEL_NZ : (size_t)rint_(30);
    double x[32], z[32];
    int null = chance(0.05), j;
    int st_ok_get = I->st == S_EVENT || I->st == S_CONT || I->st == S_TERM;
    host_env_mark(&I->env);
    switch (k) {
    case 0:
        cur_fn = "fmi2SetTime";
        {
            double t = chance(0.85) ? I->time + 1e-5 * runif() : special();
            status = api.SetTime(I->c, t);
            illegal = (!me || !(I->st == S_EVENT || I->st == S_CONT) || !isfinite(t)) ? 1 : -1;
            if (status == fmi2OK && isfinite(t)) I->time = t;
        }
        break;
    case 1:
        cur_fn = "fmi2SetContinuousStates";
        if (me && (I->st == S_CONT || I->st == S_EVENT) && api.GetContinuousStates(I->c, x, MODEL_NX) != fmi2OK)
            for (j = 0; j < MODEL_NX; j++) x[j] = 0.0;
        host_env_mark(&I->env);
        {
            int nonfinite = 0;
            for (j = 0; j < (int)nx && j < 32; j++) {
                if (chance(0.05)) x[j] = special();
                else if (j >= MODEL_NX) x[j] = 0.0;
                else x[j] += 1e-7 * (runif() - 0.5);
                if (j < MODEL_NX && !isfinite(x[j])) nonfinite = 1;
            }
            status = api.SetContinuousStates(I->c, null ? NULL : x, nx);
            illegal = (!me || I->st == S_INST || I->st == S_INIT || I->st == S_TERM || I->st == S_STEP || null ||
                       nx != MODEL_NX || nonfinite) ? 1 : -1;
        }
        break;
    case 2:
        cur_fn = "fmi2GetDerivatives";
        status = api.GetDerivatives(I->c, null ? NULL : x, nx);
        if (!null && nx <= MODEL_NX) check_finite(status, x, nx);
        illegal = (!me || I->st == S_INST || I->st == S_STEP || null || nx != MODEL_NX) ? 1 : (st_ok_get ? 0 : -1);
        break;
    case 3:
        cur_fn = "fmi2GetEventIndicators";
        status = api.GetEventIndicators(I->c, null ? NULL : z, nz);
        if (!null && nz <= MODEL_NZ) check_finite(status, z, nz);
        illegal = (!me || I->st == S_INST || I->st == S_STEP || null || nz != MODEL_NZ) ? 1 : (st_ok_get ? 0 : -1);
        break;
    case 4:
        cur_fn = "fmi2GetContinuousStates";
        status = api.GetContinuousStates(I->c, null ? NULL : x, nx);
        if (!null && nx <= MODEL_NX) check_finite(status, x, nx);
        illegal = (!me || I->st == S_INST || I->st == S_STEP || null || nx != MODEL_NX) ? 1 : (st_ok_get ? 0 : -1);
        break;
    case 5:
        cur_fn = "fmi2GetNominalsOfContinuousStates";
        status = api.GetNominalsOfContinuousStates(I->c, null ? NULL : x, nx);
        illegal = (!me || I->st == S_STEP || null || nx != MODEL_NX) ? 1 : -1;
        break;
    case 6: {
        fmi2Boolean a, b;
        int nul = chance(0.1);
        cur_fn = "fmi2CompletedIntegratorStep";
        status = api.CompletedIntegratorStep(I->c, fmi2True, nul ? NULL : &a, &b);
        illegal = (!me || I->st != S_CONT || nul) ? 1 : -1;
        break;
    }
    }
    judge(I, status, illegal, 1, 1);
    after(I, status, S_NONE);
}

static void call_cs(inst_t *I) {
    int k = rint_(10), status = 0, illegal = -1, cs = I->type == fmi2CoSimulation;
    host_env_mark(&I->env);
    if (k < 6) {
        double t = chance(0.9) ? I->time : (chance(0.5) ? I->time + 1e-3 : special());
        double h;
        int q = rint_(20);
        if (q < 16) h = 5e-4 * (0.05 + 3.0 * runif());
        else if (q == 16) h = 0.0;
        else if (q == 17) h = -1e-3;
        else if (q == 18) h = NAN;
        else h = I->stop_defined ? 1e300 : 5e-324;
        cur_fn = "fmi2DoStep";
        status = api.DoStep(I->c, t, h, fmi2True);
        if (status == fmi2OK) n_dostep_ok++;
        illegal = (!cs || I->st != S_STEP || !isfinite(t) || !isfinite(h) || h <= 0.0 ||
                   fabs(t - I->time) > 1e-6 * (fabs(t) > 1.0 ? fabs(t) : 1.0) ||
                   (I->stop_defined && t + h > I->stop + 1e-6)) ? 1 : -1;
        if (status <= fmi2Warning && !I->tainted) I->time = t + h;
    } else if (k == 6) {
        cur_fn = "fmi2CancelStep";
        status = api.CancelStep(I->c);
        illegal = 1;
    } else if (k == 7) {
        fmi2ValueReference vr = VR_u;
        fmi2Integer order = 1;
        double v = 1.0;
        size_t n = (size_t)rint_(2);
        cur_fn = "fmi2SetRealInputDerivatives";
        status = api.SetRealInputDerivatives(I->c, &vr, n, &order, &v);
        illegal = n > 0 ? 1 : -1;
    } else if (k == 8) {
        static const fmi2ValueReference OK_VR[2] = {VR_x, VR_v};
        fmi2ValueReference vr = chance(0.8) ? OK_VR[rint_(2)] : (fmi2ValueReference)rint_(MODEL_NVR + 10);
        fmi2Integer order = chance(0.8) ? 1 : (fmi2Integer)rint_(5) - 1;
        double v;
        int known = vr == VR_x || vr == VR_v;
        cur_fn = "fmi2GetRealOutputDerivatives";
        status = api.GetRealOutputDerivatives(I->c, &vr, 1, &order, &v);
        check_finite(status, &v, 1);
        illegal = (!cs || I->st == S_INST || I->st == S_INIT || order != 1 || (!known && vr != VR_i)) ? 1
                  : ((I->st == S_STEP || I->st == S_TERM) && known ? 0 : -1);
    } else {
        fmi2Status s;
        fmi2Real r;
        fmi2Integer i;
        fmi2Boolean b;
        fmi2String str;
        int w = rint_(5);
        fmi2StatusKind kind = (fmi2StatusKind)rint_(4);
        cur_fn = "fmi2Get*Status";
        status = w == 0 ? api.GetStatus(I->c, kind, &s) : w == 1 ? api.GetRealStatus(I->c, kind, &r)
               : w == 2 ? api.GetIntegerStatus(I->c, kind, &i) : w == 3 ? api.GetBooleanStatus(I->c, kind, &b)
               : api.GetStringStatus(I->c, kind, &str);
        judge(I, status, -1, 0, 1);
        return;   /* no state change, not an error of the simulation */
    }
    judge(I, status, illegal, 1, 1);
    after(I, status, S_NONE);
}

static void call_state(inst_t *I) {
    int k = rint_(7), j = rint_(NSTATE), status = 0, illegal = -1;
    host_env_mark(&I->env);
    switch (k) {
    case 0: case 1:
        cur_fn = "fmi2GetFMUstate";
        if (chance(0.05)) { status = api.GetFMUstate(I->c, NULL); illegal = 1; break; }
        status = api.GetFMUstate(I->c, &I->fs[j]);
        if (status == fmi2OK) { I->fs_st[j] = I->tainted ? -1 : I->st; I->fs_time[j] = I->time; }
        break;
    case 2: {
        inst_t *o = &slot[rint_(NSLOT)];
        int foreign = o != I;
        fmi2FMUstate s = o->c ? o->fs[j] : NULL;
        int q = rint_(10);
        cur_fn = "fmi2SetFMUstate";
        if (q == 0) { status = api.SetFMUstate(I->c, NULL); illegal = 1; break; }
        if (q == 1) { status = api.SetFMUstate(I->c, (fmi2FMUstate)fake); illegal = 1; break; }
        if (!s) return;
        status = api.SetFMUstate(I->c, s);
        if (status == fmi2OK) {
            if (foreign || o->fs_st[j] < 0) I->tainted = 1;      /* the state of another instance type or time */
            else { I->st = I->fs_st[j]; I->time = I->fs_time[j]; I->tainted = 0; }
        }
        break;
    }
    case 3:
        cur_fn = "fmi2FreeFMUstate";
        if (chance(0.1)) { fmi2FMUstate f = (fmi2FMUstate)fake; status = api.FreeFMUstate(I->c, &f); illegal = 1; break; }
        status = api.FreeFMUstate(I->c, &I->fs[j]);
        illegal = 0;
        break;
    case 4: case 5: {
        size_t size = 0;
        fmi2Byte *buf;
        cur_fn = "fmi2SerializedFMUstateSize";
        if (!I->fs[j]) { status = api.SerializedFMUstateSize(I->c, NULL, &size); illegal = 1; break; }
        status = api.SerializedFMUstateSize(I->c, I->fs[j], chance(0.05) ? NULL : &size);
        if (status != fmi2OK) { illegal = size == 0 ? 1 : -1; break; }
        judge(I, status, 0, 1, 1);
        buf = (fmi2Byte *)malloc(size + 16);
        host_env_mark(&I->env);
        cur_fn = "fmi2SerializeFMUstate";
        {
            size_t given = chance(0.1) ? size / 2 : size;
            status = api.SerializeFMUstate(I->c, I->fs[j], buf, given);
            judge(I, status, given < size ? 1 : 0, 1, 1);
        }
        host_env_mark(&I->env);
        cur_fn = "fmi2DeSerializeFMUstate";
        {
            int q = rint_(6), jj = rint_(NSTATE);
            size_t given = size;
            if (q == 0) buf[rint_((int)size)] ^= 0xFF;      /* may or may not hit the checked header */
            if (q == 1) given = size + 8;
            if (q == 2) memset(buf, 0, 16);
            status = api.DeSerializeFMUstate(I->c, buf, given, &I->fs[jj]);
            if (status == fmi2OK) I->fs_st[jj] = q == 0 ? -1 : (I->fs_st[j]);
            if (status == fmi2OK) I->fs_time[jj] = I->fs_time[j];
            illegal = (q == 1 || q == 2) ? 1 : -1;
        }
        free(buf);
        break;
    }
    case 6: {
        fmi2ValueReference u = VR_x, kn = VR_u;
        double dv = 1.0, out;
        cur_fn = "fmi2GetDirectionalDerivative";
        status = api.GetDirectionalDerivative(I->c, &u, 1, &kn, 1, &dv, &out);
        illegal = 1;
        break;
    }
    }
    /* a rejected state call changes nothing: no taint */
    judge(I, status, illegal, 0, 1);
}

static void call_debug(inst_t *I) {
    static const char *const CATS[] = {"logEvents", "logStatusWarning", "logStatusError", "nonsense", NULL};
    const char *cats[3];
    size_t n = (size_t)rint_(4), j;
    int bad = 0, status, null = n > 0 && chance(0.1);
    for (j = 0; j < n; j++) {
        cats[j] = CATS[rint_(5)];
        if (j < 3 && (!cats[j] || strcmp(cats[j], "nonsense") == 0)) bad = 1;
    }
    cur_fn = "fmi2SetDebugLogging";
    host_env_mark(&I->env);
    status = api.SetDebugLogging(I->c, chance(0.5), n, null ? NULL : cats);
    judge(I, status, (bad || null) ? 1 : -1, 0, 1);
}

/* NULL or foreign component: fmi2Error, no logger to use */
static void call_bad_component(void) {
    fmi2Component c = chance(0.5) ? NULL : (fmi2Component)fake;
    fmi2ValueReference vr = VR_x;
    double v;
    int status;
    switch (rint_(5)) {
    case 0: cur_fn = "fmi2GetReal(bad component)"; status = api.GetReal(c, &vr, 1, &v); break;
    case 1: cur_fn = "fmi2DoStep(bad component)"; status = api.DoStep(c, 0.0, 1e-3, fmi2True); break;
    case 2: cur_fn = "fmi2EnterEventMode(bad component)"; status = api.EnterEventMode(c); break;
    case 3: cur_fn = "fmi2Reset(bad component)"; status = api.Reset(c); break;
    default: cur_fn = "fmi2SetupExperiment(bad component)"; status = api.SetupExperiment(c, 0, 0, 0, 0, 0); break;
    }
    judge(NULL, status, 1, 0, 0);
    if (rint_(4) == 0) api.FreeInstance(c);     /* must ignore it */
}

int main(int argc, char **argv) {
    char err[512];
    const char *so = argc > 1 && strcmp(argv[1], "-") != 0 ? argv[1] : NULL;
    long N = argc > 2 ? atol(argv[2]) : 200000, it;
    unsigned long long seed = argc > 3 ? strtoull(argv[3], NULL, 10) : 1;
    int k;
    double w0 = host_now();
    if (fmi_api_load(&api, so, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 2; }
    fuzz_seed(seed);
    if (strcmp(api.GetVersion(), "2.0") != 0 || strcmp(api.GetTypesPlatform(), "default") != 0)
        fail("version or types platform", 0, NULL);
    for (it = 0; it < N; it++) {
        inst_t *I;
        int r = rint_(100), sl;
        if (r < 2) { call_bad_component(); continue; }
        sl = rint_(NSLOT);
        I = &slot[sl];
        if (!I->c) { do_instantiate(I); continue; }
        if (r < 3 || (I->tainted && r < 20)) {
            if (chance(0.5)) { do_free(I); continue; }
            host_env_mark(&I->env);
            cur_fn = "fmi2Reset";
            k = api.Reset(I->c);
            judge(I, k, -1, 0, 1);
            if (k == fmi2OK) { I->tainted = 0; I->st = S_INST; I->time = 0.0; I->stop_defined = 0; }
            continue;
        }
        if (!I->tainted && chance(0.45)) { call_progress(I); continue; }
        /* bias toward progress: mostly the calls the modelled state calls for */
        if (r < 30) call_get_set(I, 1);
        else if (r < 42) call_get_set(I, 0);
        else if (r < 44) call_string(I);
        else if (r < 48) call_setup(I);
        else if (r < 60) call_mode(I);
        else if (r < 75) call_me_continuous(I);
        else if (r < 90) call_cs(I);
        else if (r < 97) call_state(I);
        else call_debug(I);
    }
    for (k = 0; k < NSLOT; k++)
        if (slot[k].c) do_free(&slot[k]);
    fmi_api_unload(&api);
    printf("%ld calls in %.1f s: %ld illegal calls checked for fmi2Error/fmi2Discard, %ld legal gets checked for "
           "fmi2OK, %ld calls on tainted instances; statuses OK %ld, Warning %ld, Discard %ld, Error %ld, Fatal %ld; "
           "successful fmi2DoStep %ld, ME Euler steps %ld; live callback allocations at the end %ld\n", n_calls, host_now() - w0, n_illegal_checked, n_legal_checked,
           n_tainted_calls, n_by_status[0], n_by_status[1], n_by_status[2], n_by_status[3], n_by_status[4],
           n_dostep_ok, n_me_steps_ok, host_live_allocations());
    if (host_live_allocations() != 0) fail("callback allocations left after every instance was freed", 0, NULL);
    printf("%ld passed, %ld failed\n", n_ok_checks, n_fail);
    return n_fail == 0 ? 0 : 1;
}
