/* One host, built for Linux (cc, dlopen) and for Windows (mingw-w64, LoadLibrary, run under Wine),
 * that drives the FMUs' binaries the same way on both and prints what they computed, so that
 * tests/test_win64.py compares the win64 binaries with the linux64 ones number for number:
 *   cs2  plant FMI 2.0 + controller FMI 2.0 in closed loop, 1 s of co-simulation (fmi2DoStep)
 *   cs2late  the same loop started at t = T_LATE with a reference that lasts LONG_REF: its
 *        sample count passes 2^31 (sample counts and indices are 64-bit on Windows too, where a
 *        long has 32 bits)
 *   cs3  plant FMI 3.0 + controller FMI 3.0, the same loop through fmi3DoStep
 *   me2  plant FMI 2.0 model exchange: fmi2GetDerivatives at three set states
 *   me3  plant FMI 3.0 model exchange: fmi3GetContinuousStateDerivatives at the same states
 *   msg2 plant FMI 2.0: the status and message of calls it refuses (values out of range, a NULL
 *        category list), whose text the FMU formats with %g, %.17g and %zu
 * Usage: win_host PLANT2 CTRL2 PLANT3 CTRL3 (the four libraries). Output lines:
 *   cs2|cs2late|cs3 k t x v u   every 10 ms of the run
 *   me2|me3 s j x_j dx_j   state s (0..2), element j
 *   msg2 status message    one refused call
 *   done                   all four parts ran (exit status 0); a failure prints "error: ..." and
 *                          exits 1. Numbers are printed with 17 significant digits (exact). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2FunctionTypes.h"
#include "fmi3FunctionTypes.h"
#include "model_vars.h"
#include "ctrl_vars.h"

#if defined(_WIN32)
#include <windows.h>
typedef HMODULE lib_t;
static lib_t lib_open(const char *path) { return LoadLibraryA(path); }
static void *lib_sym(lib_t lib, const char *name) {
    FARPROC p = GetProcAddress(lib, name);
    void *q;
    memcpy(&q, &p, sizeof q);
    return q;
}
static void lib_close(lib_t lib) { FreeLibrary(lib); }
#else
#include <dlfcn.h>
typedef void *lib_t;
static lib_t lib_open(const char *path) { return dlopen(path, RTLD_NOW | RTLD_LOCAL); }
static void *lib_sym(lib_t lib, const char *name) { return dlsym(lib, name); }
static void lib_close(lib_t lib) { dlclose(lib); }
#endif

#define T_END 1.0          /* [s] the co-simulation run */
#define PRINT_EVERY 0.01   /* [s] */
#define X_START 0.14       /* [m] the reference's bottom reversal: centre - amplitude */
#define AMPLITUDE 0.01     /* [m] */
#define PERIOD 0.5         /* [s] two back-and-forth strokes in the run: four velocity reversals */
#define T_LATE 1.2e6       /* [s] */
#define LONG_REF 1e7       /* [s] 2e10 controller samples of 0.5 ms */

static int fail(const char *what, const char *detail) {
    printf("error: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    return -1;
}

/* a symbol of lib as a function pointer of type T into *dst; 0 or -1 */
#define SYM(lib, dst, name)                                                          \
    do {                                                                             \
        void *p_ = lib_sym(lib, name);                                               \
        if (!p_) return fail("missing export", name);                                \
        memcpy(&(dst), &p_, sizeof p_);                                              \
    } while (0)

/* ---------- FMI 2.0 ---------- */
static char last_msg[1024];
static void host_log2(fmi2ComponentEnvironment env, fmi2String name, fmi2Status st, fmi2String cat, fmi2String msg, ...) {
    (void)env; (void)name; (void)st; (void)cat;
    snprintf(last_msg, sizeof last_msg, "%s", msg);   /* the FMUs double every '%' */
}
static void host_log3(fmi3InstanceEnvironment env, fmi3Status st, fmi3String cat, fmi3String msg) {
    (void)env; (void)st; (void)cat;
    snprintf(last_msg, sizeof last_msg, "%s", msg);
}

typedef struct {
    fmi2InstantiateTYPE *Instantiate;
    fmi2FreeInstanceTYPE *FreeInstance;
    fmi2SetupExperimentTYPE *SetupExperiment;
    fmi2EnterInitializationModeTYPE *EnterInit;
    fmi2ExitInitializationModeTYPE *ExitInit;
    fmi2SetRealTYPE *SetReal;
    fmi2SetIntegerTYPE *SetInteger;
    fmi2GetRealTYPE *GetReal;
    fmi2DoStepTYPE *DoStep;
    fmi2NewDiscreteStatesTYPE *NewDiscreteStates;
    fmi2EnterContinuousTimeModeTYPE *EnterCT;
    fmi2GetContinuousStatesTYPE *GetStates;
    fmi2SetContinuousStatesTYPE *SetStates;
    fmi2GetDerivativesTYPE *GetDerivatives;
    fmi2SetDebugLoggingTYPE *SetDebugLogging;
} api2_t;

static int load2(lib_t lib, api2_t *a) {
    memset(a, 0, sizeof *a);   /* the model-exchange entries stay NULL for the controller */
    SYM(lib, a->Instantiate, "fmi2Instantiate");
    SYM(lib, a->FreeInstance, "fmi2FreeInstance");
    SYM(lib, a->SetupExperiment, "fmi2SetupExperiment");
    SYM(lib, a->EnterInit, "fmi2EnterInitializationMode");
    SYM(lib, a->ExitInit, "fmi2ExitInitializationMode");
    SYM(lib, a->SetReal, "fmi2SetReal");
    SYM(lib, a->SetInteger, "fmi2SetInteger");
    SYM(lib, a->GetReal, "fmi2GetReal");
    SYM(lib, a->DoStep, "fmi2DoStep");
    SYM(lib, a->SetDebugLogging, "fmi2SetDebugLogging");
    return 0;
}
static int load2_me(lib_t lib, api2_t *a) {
    SYM(lib, a->NewDiscreteStates, "fmi2NewDiscreteStates");
    SYM(lib, a->EnterCT, "fmi2EnterContinuousTimeMode");
    SYM(lib, a->GetStates, "fmi2GetContinuousStates");
    SYM(lib, a->SetStates, "fmi2SetContinuousStates");
    SYM(lib, a->GetDerivatives, "fmi2GetDerivatives");
    return 0;
}

static const fmi2CallbackFunctions CB2 = {host_log2, calloc, free, NULL, NULL};

/* the controller's sinusoidal reference and the plant at its start, both initialised */
static int setup_ctrl2(const api2_t *c, fmi2Component cc, double t0, double duration) {
    const fmi2ValueReference ivr = CVR_ref_source;
    const fmi2Integer src = 1;
    const fmi2ValueReference rvr[4] = {CVR_ref_amplitude, CVR_ref_period, CVR_ref_centre, CVR_ref_duration};
    const fmi2Real rv[4] = {AMPLITUDE, PERIOD, X_START + AMPLITUDE, duration};
    if (c->SetupExperiment(cc, fmi2False, 0.0, t0, fmi2True, t0 + T_END) != fmi2OK ||
        c->SetInteger(cc, &ivr, 1, &src) != fmi2OK || c->SetReal(cc, rvr, 4, rv) != fmi2OK ||
        c->EnterInit(cc) != fmi2OK || c->ExitInit(cc) != fmi2OK)
        return fail("controller FMI 2.0 initialisation", last_msg);
    return 0;
}

static int run_cs2(lib_t plant, lib_t ctrl, double t0, double duration, const char *tag) {
    api2_t p, c;
    fmi2Component pc, cc;
    const fmi2ValueReference px = VR_x, pout[2] = {VR_x, VR_v}, pu = VR_u, cx = CVR_x_meas, cu = CVR_u;
    const fmi2Real x0 = X_START;
    fmi2Real xv[2], u, Ts;
    const fmi2ValueReference cts = CVR_Ts;
    long long k, n, every;
    if (load2(plant, &p) || load2(ctrl, &c)) return -1;
    pc = p.Instantiate("plant", fmi2CoSimulation, MODEL_GUID, "", &CB2, fmi2False, fmi2False);
    cc = c.Instantiate("ctrl", fmi2CoSimulation, CTRL_GUID, "", &CB2, fmi2False, fmi2False);
    if (!pc || !cc) return fail("fmi2Instantiate", last_msg);
    if (setup_ctrl2(&c, cc, t0, duration)) return -1;
    if (p.SetupExperiment(pc, fmi2False, 0.0, t0, fmi2True, t0 + T_END) != fmi2OK || p.SetReal(pc, &px, 1, &x0) != fmi2OK ||
        p.EnterInit(pc) != fmi2OK || p.ExitInit(pc) != fmi2OK)
        return fail("plant FMI 2.0 initialisation", last_msg);
    if (c.GetReal(cc, &cts, 1, &Ts) != fmi2OK) return fail("controller Ts", last_msg);
    n = (long long)(T_END / Ts + 0.5);
    every = (long long)(PRINT_EVERY / Ts + 0.5);
    for (k = 0; k <= n; k++) {
        const double t = t0 + (double)k * Ts;
        if (p.GetReal(pc, pout, 2, xv) != fmi2OK || c.SetReal(cc, &cx, 1, &xv[0]) != fmi2OK ||
            c.GetReal(cc, &cu, 1, &u) != fmi2OK || p.SetReal(pc, &pu, 1, &u) != fmi2OK)
            return fail("FMI 2.0 exchange", last_msg);
        if (k % every == 0) printf("%s %lld %.17g %.17g %.17g %.17g\n", tag, k, t, xv[0], xv[1], u);
        if (k == n) break;
        if (c.DoStep(cc, t, Ts, fmi2True) != fmi2OK || p.DoStep(pc, t, Ts, fmi2True) != fmi2OK)
            return fail("fmi2DoStep", last_msg);
    }
    p.FreeInstance(pc);
    c.FreeInstance(cc);
    return 0;
}

/* the three states of the derivative check: the initial one, then moving up and moving down
 * 1 mm higher (v the second element after x) */
static void state_set(int s, double *x) {
    if (s >= 1) x[1] = s == 1 ? 0.05 : -0.05;
    if (s == 2) x[0] += 1e-3;
}

static int run_me2(lib_t plant) {
    api2_t p;
    fmi2Component pc;
    const fmi2ValueReference pu = VR_u;
    const fmi2Real u = 1.5;
    fmi2EventInfo ev;
    double x0[MODEL_NX], x[MODEL_NX], dx[MODEL_NX];
    int s;
    size_t j;
    if (MODEL_STATE_VR[0] != VR_x || MODEL_STATE_VR[1] != VR_v) return fail("state order", "x, v first expected");
    if (load2(plant, &p) || load2_me(plant, &p)) return -1;
    pc = p.Instantiate("plant_me", fmi2ModelExchange, MODEL_GUID, "", &CB2, fmi2False, fmi2False);
    if (!pc) return fail("fmi2Instantiate (model exchange)", last_msg);
    if (p.SetupExperiment(pc, fmi2False, 0.0, 0.0, fmi2False, 0.0) != fmi2OK || p.SetReal(pc, &pu, 1, &u) != fmi2OK ||
        p.EnterInit(pc) != fmi2OK || p.ExitInit(pc) != fmi2OK)
        return fail("plant FMI 2.0 model-exchange initialisation", last_msg);
    memset(&ev, 0, sizeof ev);
    ev.newDiscreteStatesNeeded = fmi2True;
    while (ev.newDiscreteStatesNeeded)
        if (p.NewDiscreteStates(pc, &ev) != fmi2OK) return fail("fmi2NewDiscreteStates", last_msg);
    if (p.EnterCT(pc) != fmi2OK || p.GetStates(pc, x0, MODEL_NX) != fmi2OK) return fail("continuous-time mode", last_msg);
    for (s = 0; s < 3; s++) {
        memcpy(x, x0, sizeof x);
        state_set(s, x);
        if (p.SetStates(pc, x, MODEL_NX) != fmi2OK || p.GetDerivatives(pc, dx, MODEL_NX) != fmi2OK)
            return fail("fmi2GetDerivatives", last_msg);
        for (j = 0; j < MODEL_NX; j++) printf("me2 %d %zu %.17g %.17g\n", s, j, x[j], dx[j]);
    }
    p.FreeInstance(pc);
    return 0;
}

/* calls the plant refuses, each with its status and the message it logged */
static int run_msg2(lib_t plant) {
    static const double bad_m[] = {-5.0, 1e30, 2.5e-320};   /* m: allowed [0.001, 10000] kg */
    api2_t p;
    fmi2Component pc;
    const fmi2ValueReference vm = VR_m;
    size_t j;
    if (load2(plant, &p)) return -1;
    pc = p.Instantiate("plant_msg", fmi2CoSimulation, MODEL_GUID, "", &CB2, fmi2False, fmi2False);
    if (!pc) return fail("fmi2Instantiate", last_msg);
    for (j = 0; j < sizeof bad_m / sizeof bad_m[0]; j++) {
        fmi2Status st;
        last_msg[0] = 0;
        st = p.SetReal(pc, &vm, 1, &bad_m[j]);
        printf("msg2 %d %s\n", (int)st, last_msg);
    }
    last_msg[0] = 0;
    printf("msg2 %d ", (int)p.SetDebugLogging(pc, fmi2True, 2, NULL));
    printf("%s\n", last_msg);
    p.FreeInstance(pc);
    return 0;
}

/* ---------- FMI 3.0 ---------- */
typedef struct {
    fmi3InstantiateCoSimulationTYPE *InstantiateCS;
    fmi3InstantiateModelExchangeTYPE *InstantiateME;
    fmi3FreeInstanceTYPE *FreeInstance;
    fmi3EnterInitializationModeTYPE *EnterInit;
    fmi3ExitInitializationModeTYPE *ExitInit;
    fmi3SetFloat64TYPE *SetFloat64;
    fmi3GetFloat64TYPE *GetFloat64;
    fmi3SetInt32TYPE *SetInt32;
    fmi3DoStepTYPE *DoStep;
    fmi3UpdateDiscreteStatesTYPE *UpdateDiscreteStates;
    fmi3EnterContinuousTimeModeTYPE *EnterCT;
    fmi3GetContinuousStatesTYPE *GetStates;
    fmi3SetContinuousStatesTYPE *SetStates;
    fmi3GetContinuousStateDerivativesTYPE *GetDerivatives;
    fmi3GetNumberOfContinuousStatesTYPE *GetNx;
} api3_t;

static int load3(lib_t lib, api3_t *a, int me) {
    memset(a, 0, sizeof *a);
    SYM(lib, a->InstantiateCS, "fmi3InstantiateCoSimulation");
    SYM(lib, a->FreeInstance, "fmi3FreeInstance");
    SYM(lib, a->EnterInit, "fmi3EnterInitializationMode");
    SYM(lib, a->ExitInit, "fmi3ExitInitializationMode");
    SYM(lib, a->SetFloat64, "fmi3SetFloat64");
    SYM(lib, a->GetFloat64, "fmi3GetFloat64");
    SYM(lib, a->SetInt32, "fmi3SetInt32");
    SYM(lib, a->DoStep, "fmi3DoStep");
    if (!me) return 0;
    SYM(lib, a->InstantiateME, "fmi3InstantiateModelExchange");
    SYM(lib, a->UpdateDiscreteStates, "fmi3UpdateDiscreteStates");
    SYM(lib, a->EnterCT, "fmi3EnterContinuousTimeMode");
    SYM(lib, a->GetStates, "fmi3GetContinuousStates");
    SYM(lib, a->SetStates, "fmi3SetContinuousStates");
    SYM(lib, a->GetDerivatives, "fmi3GetContinuousStateDerivatives");
    SYM(lib, a->GetNx, "fmi3GetNumberOfContinuousStates");
    return 0;
}

static fmi3Instance cs3_new(const api3_t *a, const char *name, const char *token) {
    return a->InstantiateCS(name, token, NULL, fmi3False, fmi3False, fmi3False, fmi3False, NULL, 0, NULL, host_log3, NULL);
}

static int run_cs3(lib_t plant, lib_t ctrl) {
    api3_t p, c;
    fmi3Instance pc, cc;
    const fmi3ValueReference px = VR_x, pout[2] = {VR_x, VR_v}, pu = VR_u, cx = CVR_x_meas, cu = CVR_u;
    const fmi3ValueReference ivr = CVR_ref_source, cts = CVR_Ts;
    const fmi3ValueReference rvr[3] = {CVR_ref_amplitude, CVR_ref_period, CVR_ref_centre};
    const fmi3Float64 rv[3] = {AMPLITUDE, PERIOD, X_START + AMPLITUDE}, x0 = X_START;
    const fmi3Int32 src = 1;
    fmi3Float64 xv[2], u, Ts, t_ok;
    fmi3Boolean ev, term, early;
    long long k, n, every;
    if (load3(plant, &p, 0) || load3(ctrl, &c, 0)) return -1;
    pc = cs3_new(&p, "plant3", MODEL_GUID);
    cc = cs3_new(&c, "ctrl3", CTRL_GUID);
    if (!pc || !cc) return fail("fmi3InstantiateCoSimulation", last_msg);
    if (c.SetInt32(cc, &ivr, 1, &src, 1) != fmi3OK || c.SetFloat64(cc, rvr, 3, rv, 3) != fmi3OK ||
        c.EnterInit(cc, fmi3False, 0.0, 0.0, fmi3True, T_END) != fmi3OK || c.ExitInit(cc) != fmi3OK)
        return fail("controller FMI 3.0 initialisation", last_msg);
    if (p.SetFloat64(pc, &px, 1, &x0, 1) != fmi3OK || p.EnterInit(pc, fmi3False, 0.0, 0.0, fmi3True, T_END) != fmi3OK ||
        p.ExitInit(pc) != fmi3OK)
        return fail("plant FMI 3.0 initialisation", last_msg);
    if (c.GetFloat64(cc, &cts, 1, &Ts, 1) != fmi3OK) return fail("controller Ts", last_msg);
    n = (long long)(T_END / Ts + 0.5);
    every = (long long)(PRINT_EVERY / Ts + 0.5);
    for (k = 0; k <= n; k++) {
        const double t = (double)k * Ts;
        if (p.GetFloat64(pc, pout, 2, xv, 2) != fmi3OK || c.SetFloat64(cc, &cx, 1, &xv[0], 1) != fmi3OK ||
            c.GetFloat64(cc, &cu, 1, &u, 1) != fmi3OK || p.SetFloat64(pc, &pu, 1, &u, 1) != fmi3OK)
            return fail("FMI 3.0 exchange", last_msg);
        if (k % every == 0) printf("cs3 %lld %.17g %.17g %.17g %.17g\n", k, t, xv[0], xv[1], u);
        if (k == n) break;
        if (c.DoStep(cc, t, Ts, fmi3True, &ev, &term, &early, &t_ok) != fmi3OK ||
            p.DoStep(pc, t, Ts, fmi3True, &ev, &term, &early, &t_ok) != fmi3OK)
            return fail("fmi3DoStep", last_msg);
    }
    p.FreeInstance(pc);
    c.FreeInstance(cc);
    return 0;
}

static int run_me3(lib_t plant) {
    api3_t p;
    fmi3Instance pc;
    const fmi3ValueReference pu = VR_u;
    const fmi3Float64 u = 1.5;
    fmi3Boolean need = fmi3True, term, nom, val, defd;
    fmi3Float64 tn;
    double x0[MODEL_NX], x[MODEL_NX], dx[MODEL_NX];
    int s;
    size_t j, nx;
    if (load3(plant, &p, 1)) return -1;
    pc = p.InstantiateME("plant3_me", MODEL_GUID, NULL, fmi3False, fmi3False, NULL, host_log3);
    if (!pc) return fail("fmi3InstantiateModelExchange", last_msg);
    if (p.SetFloat64(pc, &pu, 1, &u, 1) != fmi3OK || p.EnterInit(pc, fmi3False, 0.0, 0.0, fmi3False, 0.0) != fmi3OK ||
        p.ExitInit(pc) != fmi3OK)
        return fail("plant FMI 3.0 model-exchange initialisation", last_msg);
    while (need)
        if (p.UpdateDiscreteStates(pc, &need, &term, &nom, &val, &defd, &tn) != fmi3OK)
            return fail("fmi3UpdateDiscreteStates", last_msg);
    if (p.GetNx(pc, &nx) != fmi3OK || nx < 2 || nx > MODEL_NX) return fail("fmi3GetNumberOfContinuousStates", last_msg);
    if (p.EnterCT(pc) != fmi3OK || p.GetStates(pc, x0, nx) != fmi3OK) return fail("continuous-time mode", last_msg);
    for (s = 0; s < 3; s++) {
        memcpy(x, x0, sizeof x);
        state_set(s, x);
        if (p.SetStates(pc, x, nx) != fmi3OK || p.GetDerivatives(pc, dx, nx) != fmi3OK)
            return fail("fmi3GetContinuousStateDerivatives", last_msg);
        for (j = 0; j < nx; j++) printf("me3 %d %zu %.17g %.17g\n", s, j, x[j], dx[j]);
    }
    p.FreeInstance(pc);
    return 0;
}

int main(int argc, char **argv) {
    lib_t lib[4];
    int j, rc;
    if (argc != 5) {
        fprintf(stderr, "usage: %s PLANT2 CTRL2 PLANT3 CTRL3 (the FMUs' shared libraries)\n", argv[0]);
        return 2;
    }
    for (j = 0; j < 4; j++) {
        lib[j] = lib_open(argv[j + 1]);
        if (!lib[j]) { fail("cannot load", argv[j + 1]); return 1; }
    }
    rc = run_cs2(lib[0], lib[1], 0.0, 2.0 * T_END, "cs2") || run_cs2(lib[0], lib[1], T_LATE, LONG_REF, "cs2late") ||
         run_me2(lib[0]) || run_msg2(lib[0]) || run_cs3(lib[2], lib[3]) || run_me3(lib[2]);
    for (j = 0; j < 4; j++) lib_close(lib[j]);
    if (rc) return 1;
    printf("done\n");
    return 0;
}
