/* Hostile cases of the FMI 3.0 interface only: NULL arrays, the input clock and Event Mode,
 * Boolean array sizes (see ctrl_hostile.h). */
#include "ctrl_hostile.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef CTRL_FMI3
static fmi3Instance ctrl3_ready(env3_t *e, const char *name) {
    fmi3Instance i = fmi3InstantiateCoSimulation(name, CTRL_GUID, NULL, fmi3False, fmi3False, fmi3False, fmi3False,
                                                 NULL, 0, e, env3_log, NULL);
    if (!i) return NULL;
    if (fmi3EnterInitializationMode(i, fmi3False, 0.0, 0.0, fmi3False, 0.0) != fmi3OK ||
        fmi3ExitInitializationMode(i) != fmi3OK) {
        fmi3FreeInstance(i);
        return NULL;
    }
    return i;
}

void case_get_float64_null(void) {
    env3_t e = {0};
    fmi3Instance i = ctrl3_ready(&e, "null_vr");
    fmi3Float64 v[2] = {0.0, 0.0};
    fmi3ValueReference vr[2] = {CVR_u, 0};
    fmi3Status s;
    EXPECT(i, "FMI 3.0 instantiate/initialise failed: %s", e.last);
    env3_mark(&e);
    s = fmi3GetFloat64(i, NULL, 1, v, 1);
    EXPECT(s == fmi3Error && e.n_since_mark > 0 && strstr(e.last, "NULL array"),
           "fmi3GetFloat64(NULL, 1) answered %d \"%s\"", (int)s, e.last);
    SAY("fmi3GetFloat64(instance, NULL, 1, v, 1) -> fmi3Error \"%s\"; ", e.last);
    env3_mark(&e);
    s = fmi3GetFloat64(i, vr, 2, NULL, 2);
    EXPECT(s == fmi3Error && strstr(e.last, "NULL array"), "fmi3GetFloat64(vr, NULL values) answered %d \"%s\"",
           (int)s, e.last);
    /* the time (value reference 0) beside an output still answers */
    EXPECT(fmi3GetFloat64(i, vr, 2, v, 2) == fmi3OK && v[1] == 0.0 && isfinite(v[0]), "u and time not read");
    fmi3FreeInstance(i);
}

/* the input clock tick (value reference 9, the description's) and Event Mode: NULL arrays and
 * output arguments, a reference that is no clock, the clock set in Step Mode, Event Mode entered
 * twice, a tick at an instant that is no sample instant, Step Mode left with a tick not taken,
 * a step in Event Mode and one past an untaken tick, Event Mode on an instance made without it:
 * each fmi3Error with the rule named; the ticks between them still sample (u finite, the
 * interval Ts) */
#define VR3_TICK 9u
#define REFUSED3(call, needle) do { env3_mark(&e); s = (call); \
        EXPECT(s == fmi3Error && e.n_since_mark > 0 && strstr(e.last, needle), "%s answered %d \"%s\"", #call, \
               (int)s, e.last); } while (0)
void case_clock(void) {
    env3_t e = {0};
    fmi3Instance i = fmi3InstantiateCoSimulation("clock", CTRL_GUID, NULL, fmi3False, fmi3False, fmi3True, fmi3False,
                                                 NULL, 0, &e, env3_log, NULL), plain;
    fmi3ValueReference tick = VR3_TICK, bad = CVR_x_meas, ru = CVR_u;
    fmi3Clock on = fmi3ClockActive, off = fmi3ClockInactive;
    fmi3Boolean b1, b2, b3, b4, b5, ev, term, early;
    fmi3Float64 t_next, u = NAN, iv = 0.0, last;
    fmi3IntervalQualifier q;
    fmi3Status s;
    EXPECT(i && fmi3EnterInitializationMode(i, fmi3False, 0.0, 0.0, fmi3False, 0.0) == fmi3OK &&
           fmi3ExitInitializationMode(i) == fmi3OK, "instantiate with Event Mode and initialise: %s", e.last);
    /* in Event Mode after initialisation: the arguments */
    REFUSED3(fmi3SetClock(i, NULL, 1, &on), "NULL array");
    SAY("fmi3SetClock(NULL, 1) -> \"%s\"; ", e.last);
    REFUSED3(fmi3SetClock(i, &tick, 1, NULL), "NULL array");
    REFUSED3(fmi3SetClock(i, &bad, 1, &on), "no clock");
    SAY("x_meas as clock -> \"%s\"; ", e.last);
    REFUSED3(fmi3UpdateDiscreteStates(i, NULL, &b2, &b3, &b4, &b5, &t_next), "NULL output argument");
    REFUSED3(fmi3GetIntervalDecimal(i, &tick, 1, &iv, NULL), "NULL array");
    EXPECT(fmi3GetIntervalDecimal(i, &tick, 1, &iv, &q) == fmi3OK && iv == 5e-4 && q == fmi3IntervalChanged,
           "interval %g, qualifier %d: %s", iv, (int)q, e.last);
    /* the tick of t_0 */
    EXPECT(fmi3SetClock(i, &tick, 1, &on) == fmi3OK &&
           fmi3UpdateDiscreteStates(i, &b1, &b2, &b3, &b4, &b5, &t_next) == fmi3OK && !b1 && !b2 &&
           fmi3GetFloat64(i, &ru, 1, &u, 1) == fmi3OK && isfinite(u) && fmi3EnterStepMode(i) == fmi3OK,
           "the tick of t_0: %s", e.last);
    REFUSED3(fmi3SetClock(i, &tick, 1, &on), "Event Mode only");
    SAY("set in Step Mode -> \"%s\"; ", e.last);
    REFUSED3(fmi3DoStep(i, 0.0, 1e-3, fmi3True, &ev, &term, &early, &last), "passes the clock tick");
    SAY("step past a tick -> \"%s\"; ", e.last);
    EXPECT(fmi3DoStep(i, 0.0, 5e-4, fmi3True, &ev, &term, &early, &last) == fmi3OK && last == 5e-4 && !ev,
           "the step to the next tick: %s", e.last);
    EXPECT(fmi3EnterEventMode(i) == fmi3OK, "Event Mode at t_1: %s", e.last);
    REFUSED3(fmi3EnterEventMode(i), "already");
    SAY("Event Mode twice -> \"%s\"; ", e.last);
    REFUSED3(fmi3DoStep(i, 5e-4, 5e-4, fmi3True, &ev, &term, &early, &last), "Event Mode");
    EXPECT(fmi3SetClock(i, &tick, 1, &on) == fmi3OK, "the tick of t_1: %s", e.last);
    REFUSED3(fmi3EnterStepMode(i), "fmi3UpdateDiscreteStates first");
    EXPECT(fmi3UpdateDiscreteStates(i, &b1, &b2, &b3, &b4, &b5, &t_next) == fmi3OK &&
           fmi3GetFloat64(i, &ru, 1, &u, 1) == fmi3OK && isfinite(u), "the tick of t_1: %s", e.last);
    /* a second tick at t_1: no sample instant any more */
    EXPECT(fmi3SetClock(i, &tick, 1, &on) == fmi3OK, "set again: %s", e.last);
    REFUSED3(fmi3UpdateDiscreteStates(i, &b1, &b2, &b3, &b4, &b5, &t_next), "next sample instant");
    SAY("tick off the sample instants -> \"%s\"; ", e.last);
    EXPECT(fmi3SetClock(i, &tick, 1, &off) == fmi3OK && fmi3EnterStepMode(i) == fmi3OK, "deactivate: %s", e.last);
    fmi3FreeInstance(i);
    plain = ctrl3_ready(&e, "plain");
    EXPECT(plain, "instantiate without Event Mode: %s", e.last);
    REFUSED3(fmi3EnterEventMode(plain), "eventModeUsed = false");
    SAY("no Event Mode -> \"%s\"", e.last);
    fmi3FreeInstance(plain);
}

void case_boolean_size_max3(void) {
    env3_t e = {0};
    fmi3Instance i = ctrl3_ready(&e, "bool_max");
    fmi3ValueReference *vr = (fmi3ValueReference *)malloc(sizeof *vr);
    fmi3Boolean *v = (fmi3Boolean *)malloc(sizeof *v);
    fmi3Status s;
    EXPECT(i && vr && v, "FMI 3.0 instantiate/initialise failed: %s", e.last);
    vr[0] = CVR_zpetc_on;
    v[0] = fmi3False;
    env3_mark(&e);
    s = fmi3GetBoolean(i, vr, SIZE_MAX, v, SIZE_MAX);
    EXPECT(s == fmi3Error && strstr(e.last, "allowed at most"), "fmi3GetBoolean(n = SIZE_MAX) answered %d \"%s\"",
           (int)s, e.last);
    SAY("fmi3GetBoolean(n = SIZE_MAX) -> fmi3Error \"%s\"; ", e.last);
    env3_mark(&e);
    s = fmi3SetBoolean(i, vr, SIZE_MAX, v, SIZE_MAX);
    EXPECT(s == fmi3Error && strstr(e.last, "allowed at most"), "fmi3SetBoolean(n = SIZE_MAX) answered %d \"%s\"",
           (int)s, e.last);
    SAY("fmi3SetBoolean(n = SIZE_MAX) -> fmi3Error \"%s\"", e.last);
    EXPECT(fmi3GetBoolean(i, vr, 1, v, 1) == fmi3OK && v[0] == fmi3False, "one Boolean no longer reads");
    free(vr);
    free(v);
    fmi3FreeInstance(i);
}
#endif
