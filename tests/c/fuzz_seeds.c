/* Writes the seed corpora of fuzz_lib (see fuzz_lib.c for the input layout) into DIR/state and
 * DIR/calls: serialised states of a co-simulation and a model-exchange instance taken mid-run
 * (as they are and with the CRC-fixing flag), and call programs of a co-simulation and a
 * model-exchange life cycle. Usage: fuzz_seeds [LinearMotorFeedDrive.so|-] DIR. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi_host.h"
#include "model_vars.h"

static fmi_api_t api;

static int write_file(const char *dir, const char *sub, const char *name, unsigned char head,
                      const unsigned char *b, size_t n) {
    char path[1024];
    FILE *f;
    snprintf(path, sizeof path, "%s/%s/%s", dir, sub, name);
    if (!(f = fopen(path, "wb"))) { fprintf(stderr, "cannot write %s\n", path); return -1; }
    fputc(head, f);
    fwrite(b, 1, n, f);
    fclose(f);
    return 0;
}

/* the serialised state of an instance of type after 0.1 s of a 5 Hz sinusoid */
static size_t state_of(fmi2Type type, unsigned char *out, size_t cap) {
    host_env_t env;
    fmi2CallbackFunctions cb;
    fmi2Component c;
    const fmi2ValueReference u_vr = VR_u;
    fmi2FMUstate s = NULL;
    fmi2EventInfo ei;
    fmi2Boolean e1, e2;
    double t = 0.0, u, x[MODEL_NX], dx[MODEL_NX];
    size_t n = 0;
    int k, j;
    memset(&env, 0, sizeof env);
    cb = host_callbacks(&env);
    c = api.Instantiate("seed", type, MODEL_GUID, "", &cb, fmi2False, fmi2False);
    api.SetupExperiment(c, fmi2True, 1e-6, 0.0, fmi2False, 0.0);
    api.EnterInitializationMode(c);
    api.ExitInitializationMode(c);
    if (type == fmi2ModelExchange) { api.NewDiscreteStates(c, &ei); api.EnterContinuousTimeMode(c); }
    for (k = 0; k < 200; k++, t += 5e-4) {
        u = 2.0 * sin(2.0 * M_PI * 5.0 * t);
        api.SetReal(c, &u_vr, 1, &u);
        if (type == fmi2CoSimulation) { api.DoStep(c, t, 5e-4, fmi2True); continue; }
        api.GetContinuousStates(c, x, MODEL_NX);
        api.GetDerivatives(c, dx, MODEL_NX);
        for (j = 0; j < MODEL_NX; j++) x[j] += 5e-4 * dx[j];
        api.SetTime(c, t + 5e-4);
        api.SetContinuousStates(c, x, MODEL_NX);
        api.CompletedIntegratorStep(c, fmi2True, &e1, &e2);
        api.EnterEventMode(c);
        api.NewDiscreteStates(c, &ei);
        api.EnterContinuousTimeMode(c);
    }
    if (api.GetFMUstate(c, &s) != fmi2OK || api.SerializedFMUstateSize(c, s, &n) != fmi2OK || n > cap ||
        api.SerializeFMUstate(c, s, (fmi2Byte *)out, n) != fmi2OK) n = 0;
    api.FreeFMUstate(c, &s);
    api.FreeInstance(c);
    return n;
}

int main(int argc, char **argv) {
    /* op bytes of fuzz_lib.c's one_call: 3 setup, 4/5 enter/exit init, 6 step, 7 get all, 8 event
     * mode, 9 new discrete states, 10 continuous mode, 11 set time, 12 set states, 13 completed
     * step, 14 get state, 15 set state, 16 serialise round trip, 21 u = +-10 V, 0 SetReal */
    static const unsigned char CS[] = {3, 1, 0, 0, 4, 0, 5, 0, 21, 1, 6, 0, 4, 6, 0, 4, 7, 0, 14, 0, 6, 0, 99,
                                       16, 0, 1, 2, 8, 15, 0, 6, 0, 4, 7, 0, 21, 0, 6, 0, 50, 7, 0};
    static const unsigned char ME[] = {3, 1, 0, 0, 4, 0, 5, 0, 9, 0, 10, 0, 21, 1, 11, 0, 13, 0, 7, 0, 11, 9,
                                       12, 1, 3, 13, 0, 8, 0, 9, 0, 10, 0, 7, 0, 14, 1, 16, 1, 0, 40, 1, 15, 1, 7, 0};
    unsigned char buf[8192];
    const char *so = strcmp(argv[1], "-") != 0 ? argv[1] : NULL;
    char err[256];
    size_t n;
    if (argc < 3) { fprintf(stderr, "usage: fuzz_seeds SO|- DIR\n"); return 2; }
    if (fmi_api_load(&api, so, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 2; }
    n = state_of(fmi2CoSimulation, buf, sizeof buf);
    if (!n || write_file(argv[2], "state", "cs.bin", 0x03, buf, n) || write_file(argv[2], "state", "cs_crc.bin", 0x07, buf, n))
        return 1;
    n = state_of(fmi2ModelExchange, buf, sizeof buf);
    if (!n || write_file(argv[2], "state", "me.bin", 0x02, buf, n) || write_file(argv[2], "state", "me_crc.bin", 0x06, buf, n))
        return 1;
    if (write_file(argv[2], "calls", "cs_life.bin", 0x01, CS, sizeof CS) ||
        write_file(argv[2], "calls", "me_life.bin", 0x00, ME, sizeof ME)) return 1;
    fmi_api_unload(&api);
    return 0;
}
