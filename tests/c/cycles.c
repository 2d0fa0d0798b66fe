/* Life-cycle soak: N instantiate / set parameters / initialise / simulate 10 ms / FMU-state
 * get+serialize+deserialize+set+free / terminate / free cycles, alternating co-simulation (20
 * fmi2DoStep of 0.5 ms) and model exchange (20 current-loop samples with event iterations and
 * explicit-Euler continuous steps through the ME API). Checks that every allocation made through
 * the callbacks is freed after every cycle and that the resident set does not grow between the
 * first 10 % of the cycles and the end (a leak of even 8 bytes per cycle that bypassed the
 * callbacks would add 80 kB over 10 000 cycles; the limit is 64 KiB, the page-granular noise of
 * the allocator). Run under LeakSanitizer (the _san build) or valgrind for leaks outside the
 * callbacks (there pass "--no-rss" as third argument: their own heaps make the resident set
 * meaningless). Usage: cycles LinearMotorFeedDrive.so [cycles=10000] [--no-rss].
 * Prints PASS/FAIL lines and "N passed, M failed". */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi_host.h"
#include "model_vars.h"

/* anonymous resident memory (heap, stacks) in KiB: file-backed pages of code touched late are
 * not growth */
static long rss_kib(void) {
    char line[256];
    long kib = -1;
    FILE *f = fopen("/proc/self/status", "r");
    if (!f) return -1;
    while (fgets(line, sizeof line, f))
        if (sscanf(line, "RssAnon: %ld", &kib) == 1) break;
    fclose(f);
    return kib;
}

#define CHECK(call)                                                                                  \
    do {                                                                                             \
        if ((call) > fmi2Warning) {                                                                  \
            fprintf(stderr, "cycle %ld: %s failed: %s\n", cyc, #call, env.last);                    \
            return -1;                                                                               \
        }                                                                                            \
    } while (0)

static int one_cycle(const fmi_api_t *api, long cyc) {
    host_env_t env;
    fmi2CallbackFunctions cb;
    fmi2Component c;
    fmi2Type type = (cyc % 2) ? fmi2ModelExchange : fmi2CoSimulation;
    const fmi2ValueReference par_vr[3] = {VR_m, VR_friction_C, VR_u};
    const double par[3] = {16.1 + 1e-4 * (double)(cyc % 100), 1.08e4, 0.3};
    const fmi2ValueReference u_vr = VR_u;
    fmi2FMUstate st = NULL, st2 = NULL;
    size_t size = 0;
    fmi2Byte *buf;
    double u, x[MODEL_NX], dx[MODEL_NX], z[MODEL_NZ];
    int k, j, s;
    memset(&env, 0, sizeof env);
    cb = host_callbacks(&env);
    c = api->Instantiate("cycle", type, MODEL_GUID, "", &cb, fmi2False, fmi2False);
    if (!c) { fprintf(stderr, "cycle %ld: fmi2Instantiate returned NULL: %s\n", cyc, env.last); return -1; }
    CHECK(api->SetupExperiment(c, fmi2True, 1e-6, 0.0, fmi2True, 0.01));
    CHECK(api->SetReal(c, par_vr, 3, par));
    CHECK(api->EnterInitializationMode(c));
    CHECK(api->ExitInitializationMode(c));
    if (type == fmi2CoSimulation) {
        for (k = 0; k < 20; k++) {
            u = 0.3 * (k % 7) - 0.5;
            CHECK(api->SetReal(c, &u_vr, 1, &u));
            CHECK(api->DoStep(c, k * 5e-4, 5e-4, fmi2True));
            if (k == 10) CHECK(api->GetFMUstate(c, &st));
        }
    } else {
        fmi2EventInfo ei;
        fmi2Boolean enter, term;
        double t = 0.0, hstep = 5e-5;
        for (k = 0; k < 20; k++) {
            if (k > 0) CHECK(api->EnterEventMode(c));
            u = 0.3 * (k % 7) - 0.5;
            CHECK(api->SetReal(c, &u_vr, 1, &u));
            memset(&ei, 0, sizeof ei);
            ei.newDiscreteStatesNeeded = fmi2True;
            for (j = 0; j < 10 && ei.newDiscreteStatesNeeded; j++) CHECK(api->NewDiscreteStates(c, &ei));
            CHECK(api->EnterContinuousTimeMode(c));
            CHECK(api->GetContinuousStates(c, x, MODEL_NX));
            for (s = 0; s < 10; s++) {
                CHECK(api->GetDerivatives(c, dx, MODEL_NX));
                for (j = 0; j < MODEL_NX; j++) x[j] += hstep * dx[j];
                t = k * 5e-4 + (s + 1) * hstep;
                CHECK(api->SetTime(c, t));
                CHECK(api->SetContinuousStates(c, x, MODEL_NX));
                CHECK(api->GetEventIndicators(c, z, MODEL_NZ));
                CHECK(api->CompletedIntegratorStep(c, fmi2True, &enter, &term));
            }
            if (k == 10) CHECK(api->GetFMUstate(c, &st));
        }
    }
    CHECK(api->SerializedFMUstateSize(c, st, &size));
    buf = (fmi2Byte *)malloc(size);
    CHECK(api->SerializeFMUstate(c, st, buf, size));
    CHECK(api->DeSerializeFMUstate(c, buf, size, &st2));
    free(buf);
    CHECK(api->SetFMUstate(c, st2));
    CHECK(api->FreeFMUstate(c, &st));
    CHECK(api->FreeFMUstate(c, &st2));
    CHECK(api->Terminate(c));
    if (cyc % 3 == 0) {     /* a reset instance goes round again before it is freed */
        CHECK(api->Reset(c));
        CHECK(api->SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
        CHECK(api->EnterInitializationMode(c));
        CHECK(api->ExitInitializationMode(c));
        CHECK(api->Terminate(c));
    }
    api->FreeInstance(c);
    return 0;
}

int main(int argc, char **argv) {
    fmi_api_t api;
    char err[512];
    long n = argc > 2 ? atol(argv[2]) : 10000, cyc, rss_early = -1, rss_end, live_bad = 0;
    int n_pass = 0, n_fail = 0, ok;
    double w0;
    if (fmi_api_load(&api, argc > 1 ? argv[1] : NULL, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 2; }
    w0 = host_now();
    for (cyc = 0; cyc < n; cyc++) {
        if (one_cycle(&api, cyc) != 0) { printf("FAIL cycle %ld\n", cyc); printf("0 passed, 1 failed\n"); return 1; }
        if (host_live_allocations() != 0) live_bad++;
        if (cyc == n / 10) rss_early = rss_kib();
        if (getenv("CYCLES_TRACE") && cyc % 1000 == 0) fprintf(stderr, "cycle %ld rss %ld KiB\n", cyc, rss_kib());
    }
    rss_end = rss_kib();
    printf("%ld cycles in %.2f s, %ld allocations through the callbacks, anonymous resident memory %ld KiB after %ld cycles, "
           "%ld KiB at the end\n", n, host_now() - w0, host_total_allocations(), rss_early, n / 10, rss_end);
    ok = live_bad == 0;
    printf("%s every callback allocation freed after every cycle (%ld cycles left some live)\n", ok ? "PASS" : "FAIL",
           live_bad);
    ok ? n_pass++ : n_fail++;
    if (!(argc > 3 && strcmp(argv[3], "--no-rss") == 0)) {
        ok = rss_early > 0 && rss_end - rss_early <= 64;
        printf("%s anonymous resident memory growth %ld KiB <= 64 KiB\n", ok ? "PASS" : "FAIL", rss_end - rss_early);
        ok ? n_pass++ : n_fail++;
    }
    fmi_api_unload(&api);
    printf("peak bytes held through the callbacks at once: %ld\n", host_peak_bytes());
    printf("%d passed, %d failed\n", n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
}
