/* The clock functions of the plant FMU, which has no clocks: each answers through the glue's
 * fmi3_refuse (fmi3_log.h), fmi3Error with a message naming the function (fmi3OK for a get/set
 * of no clock). The controller FMU has an input clock (controller/ctrl_fmi3.c). */
#include "fmi3_log.h"

#define NO_CLOCKS "this FMU has no clocks"

fmi3Status fmi3GetClock(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Clock v[]) {
    (void)vr; (void)v;
    return fmi3_refuse(i, "fmi3GetClock", nvr ? NO_CLOCKS : NULL);
}

fmi3Status fmi3SetClock(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Clock v[]) {
    (void)vr; (void)v;
    return fmi3_refuse(i, "fmi3SetClock", nvr ? NO_CLOCKS : NULL);
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3Float64 a[], fmi3IntervalQualifier b[]) {
    (void)vr; (void)n; (void)a; (void)b;
    return fmi3_refuse(instance, "fmi3GetIntervalDecimal", NO_CLOCKS);
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3UInt64 a[], fmi3UInt64 b[], fmi3IntervalQualifier q[]) {
    (void)vr; (void)n; (void)a; (void)b; (void)q;
    return fmi3_refuse(instance, "fmi3GetIntervalFraction", NO_CLOCKS);
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3Float64 a[]) {
    (void)vr; (void)n; (void)a;
    return fmi3_refuse(instance, "fmi3GetShiftDecimal", NO_CLOCKS);
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, fmi3UInt64 a[], fmi3UInt64 b[]) {
    (void)vr; (void)n; (void)a; (void)b;
    return fmi3_refuse(instance, "fmi3GetShiftFraction", NO_CLOCKS);
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3Float64 a[]) {
    (void)vr; (void)n; (void)a;
    return fmi3_refuse(instance, "fmi3SetIntervalDecimal", NO_CLOCKS);
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 a[], const fmi3UInt64 b[]) {
    (void)vr; (void)n; (void)a; (void)b;
    return fmi3_refuse(instance, "fmi3SetIntervalFraction", NO_CLOCKS);
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3Float64 a[]) {
    (void)vr; (void)n; (void)a;
    return fmi3_refuse(instance, "fmi3SetShiftDecimal", NO_CLOCKS);
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n, const fmi3UInt64 a[], const fmi3UInt64 b[]) {
    (void)vr; (void)n; (void)a; (void)b;
    return fmi3_refuse(instance, "fmi3SetShiftFraction", NO_CLOCKS);
}
