/* FMI 3.0 get/set: the FMI 3.0 value references (model_vars3.h) expanded to the FMI 2.0 ones of
 * their elements (an array of dimension friction.N has N, a scalar one) and handed to the shared
 * get/set of fmi2_values.c (its checks: type, state, range; a rejected set changes nothing).
 * time and eventIndicators are computed here; the structural parameter friction.N is set only
 * in Configuration Mode. (Types the FMU has none of: fmi3_stubs.c.) */
#include <stdlib.h>
#include <string.h>

#include "fmi3_glue.h"

static int row3(unsigned vr) {
    int lo = 0, hi = MODEL3_NVARS - 1;
    while (lo <= hi) {   /* MODEL3_VARS is sorted by value reference */
        int mid = (lo + hi) / 2;
        if (MODEL3_VARS[mid].vr == vr) return mid;
        if (MODEL3_VARS[mid].vr < vr) lo = mid + 1; else hi = mid - 1;
    }
    return -1;
}

static size_t count3(const model_t *m, int r) {
    return MODEL3_VARS[r].kind == 1 ? (size_t)fmi3_n(m) : (size_t)MODEL3_VARS[r].count;
}

/* the FMI 2.0 value references of vr[0..nvr) (NULL when one is unknown, of another type or
 * nValues does not match; logged); *n their number. Free with free(). */
static unsigned *expand(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr, char type,
                        size_t n_values, size_t *n) {
    static const char *const TN[] = {"Float64", "Int32", "Boolean"};
    size_t k, total = 0, at = 0;
    unsigned *out;
    if (nvr > 0 && !vr) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL array with nValueReferences = %zu", fn, nvr); return NULL; }
    for (k = 0; k < nvr; k++) {
        int r = row3(vr[k]);
        if (r < 0) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: unknown value reference %u", fn, (unsigned)vr[k]); return NULL; }
        if (MODEL3_VARS[r].type != type) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s (value reference %u) is not of type %s", fn, MODEL3_VARS[r].name,
                    (unsigned)vr[k], TN[type == 'R' ? 0 : (type == 'I' ? 1 : 2)]);
            return NULL;
        }
        total += count3(&c->m, r);
    }
    if (total != n_values) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: nValues = %zu, the %zu variable(s) have %zu value(s) (arrays of "
                "dimension friction.N = %d)", fn, n_values, nvr, total, fmi3_n(&c->m));
        return NULL;
    }
    out = (unsigned *)calloc(total + 1, sizeof(unsigned));
    if (!out) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: out of memory", fn); return NULL; }
    for (k = 0; k < nvr; k++) {
        int r = row3(vr[k]);
        size_t j, cnt = count3(&c->m, r);
        for (j = 0; j < cnt; j++)
            out[at++] = MODEL3_VARS[r].kind == 0 || MODEL3_VARS[r].kind == 2 ? 0xFFFFFFFFu
                                                                            : MODEL3_ELEMS[MODEL3_VARS[r].first + j];
    }
    *n = total;
    return out;
}

/* time and the event indicators (Float64 only) */
static fmi2Status get_special(instance_t *c, const char *fn, int r, double *out) {
    model_t *m = &c->m;
    if (MODEL3_VARS[r].kind == 0) { out[0] = m->time; return fmi2OK; }
    if (!fmu_finite_result(c, fn, NULL, 0)) return fmi2Error;
    params_inputs(m->val, &m->in);
    plant_indicators(&m->p, &m->d, m->y, &m->in, out);
    return fmu_finite_result(c, fn, out, PLANT_NZ) ? fmi2OK : fmi2Error;
}

static fmi3Status get3(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr, char type,
                       void *values, size_t n_values) {
    size_t n, k, at = 0;
    unsigned *vr2;
    fmi2Status st = fmi2OK;
    int *tmp = NULL;
    if (!c) return fmi3Error;
    if (n_values > 0 && !values) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL values with nValues = %zu", fn, n_values); return fmi3Error; }
    if (!(vr2 = expand(c, fn, vr, nvr, type, n_values, &n))) return fmi3Error;
    if (type == 'B' && !(tmp = (int *)calloc(n + 1, sizeof(int)))) { free(vr2); return fmi3Error; }
    /* one run of FMI 2.0 references at a time, the computed ones between */
    for (k = 0; k < nvr && st == fmi2OK; k++) {
        int r = row3(vr[k]);
        size_t cnt = count3(&c->m, r);
        if (MODEL3_VARS[r].kind == 0 || MODEL3_VARS[r].kind == 2)
            st = get_special(c, fn, r, (double *)values + at);
        else if (type == 'R') st = fmu_get_values(c, fn, vr2 + at, cnt, 'R', (double *)values + at);
        else if (type == 'I') st = fmu_get_values(c, fn, vr2 + at, cnt, 'I', (fmi3Int32 *)values + at);
        else st = fmu_get_values(c, fn, vr2 + at, cnt, 'B', tmp + at);
        at += cnt;
    }
    if (type == 'B' && st == fmi2OK)
        for (k = 0; k < n; k++) ((fmi3Boolean *)values)[k] = tmp[k] != 0;
    free(tmp);
    free(vr2);
    return (fmi3Status)st;
}

/* friction.N in Configuration Mode (nothing else may be set there) */
static fmi3Status set_structural(instance_t *c, const char *fn, const unsigned *vr2, size_t n, const fmi3Int32 *v) {
    char msg[512];
    size_t k;
    for (k = 0; k < n; k++) {
        if (vr2[k] != VR_friction_N) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s cannot be set in Configuration Mode (only the structural "
                    "parameter friction.N)", fn, MODEL_VARS[MODEL_VR_INDEX[vr2[k]]].name);
            return fmi3Error;
        }
        if (!params_check_value(VR_friction_N, (double)v[k], msg, sizeof msg)) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s", fn, msg);
            return fmi3Error;
        }
    }
    for (k = 0; k < n; k++) c->m.val[VR_friction_N] = (double)v[k];
    return fmi3OK;
}

static fmi3Status set3(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr, char type,
                       const void *values, size_t n_values) {
    size_t n, k;
    unsigned *vr2;
    fmi2Status st;
    int *tmp = NULL;
    if (!c) return fmi3Error;
    if (n_values > 0 && !values) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL values with nValues = %zu", fn, n_values); return fmi3Error; }
    if (!(vr2 = expand(c, fn, vr, nvr, type, n_values, &n))) return fmi3Error;
    for (k = 0; k < n; k++) {
        const char *what = vr2[k] == 0xFFFFFFFFu ? "a calculated variable"
                         : (vr2[k] == VR_friction_N && c->m.fsm != ST_CONFIG) ? "structural" : NULL;
        if (what) {
            fmu_log(c, fmi2Error, LOG_ERROR, vr2[k] == 0xFFFFFFFFu ? "%s: time and eventIndicators are %s"
                    : "%s: friction.N is %s: set it in Configuration Mode (fmi3EnterConfigurationMode)", fn, what);
            free(vr2);
            return fmi3Error;
        }
    }
    if (c->m.fsm == ST_CONFIG) {
        fmi3Status s3 = type == 'I' ? set_structural(c, fn, vr2, n, (const fmi3Int32 *)values) : fmi3Error;
        if (type != 'I' && n > 0)
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s cannot be set in Configuration Mode (only the structural "
                    "parameter friction.N)", fn, MODEL_VARS[MODEL_VR_INDEX[vr2[0]]].name);
        free(vr2);
        return n == 0 ? fmi3OK : s3;
    }
    if (type == 'B') {
        if (!(tmp = (int *)calloc(n + 1, sizeof(int)))) { free(vr2); return fmi3Error; }
        for (k = 0; k < n; k++) tmp[k] = ((const fmi3Boolean *)values)[k] ? fmi2True : fmi2False;
        st = fmu_set_values(c, fn, vr2, n, 'B', tmp);
    } else {
        st = fmu_set_values(c, fn, vr2, n, type, values);   /* fmi3Float64 = double, fmi3Int32 = int */
    }
    free(tmp);
    free(vr2);
    return (fmi3Status)st;
}

fmi3Status fmi3GetFloat64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 v[], size_t nv) {
    return get3(FMU_ENTER(i, fmi3GetFloat64), "fmi3GetFloat64", vr, nvr, 'R', v, nv);
}
fmi3Status fmi3GetInt32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Int32 v[], size_t nv) {
    return get3(FMU_ENTER(i, fmi3GetInt32), "fmi3GetInt32", vr, nvr, 'I', v, nv);
}
fmi3Status fmi3GetBoolean(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, fmi3Boolean v[], size_t nv) {
    return get3(FMU_ENTER(i, fmi3GetBoolean), "fmi3GetBoolean", vr, nvr, 'B', v, nv);
}
fmi3Status fmi3SetFloat64(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Float64 v[], size_t nv) {
    return set3(FMU_ENTER(i, fmi3SetFloat64), "fmi3SetFloat64", vr, nvr, 'R', v, nv);
}
fmi3Status fmi3SetInt32(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Int32 v[], size_t nv) {
    return set3(FMU_ENTER(i, fmi3SetInt32), "fmi3SetInt32", vr, nvr, 'I', v, nv);
}
fmi3Status fmi3SetBoolean(fmi3Instance i, const fmi3ValueReference vr[], size_t nvr, const fmi3Boolean v[], size_t nv) {
    return set3(FMU_ENTER(i, fmi3SetBoolean), "fmi3SetBoolean", vr, nvr, 'B', v, nv);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates) {
    instance_t *c = FMU_ENTER(instance, fmi3GetNumberOfContinuousStates);
    if (!c) return fmi3Error;
    if (!nContinuousStates) { fmu_log(c, fmi2Error, LOG_ERROR, "fmi3GetNumberOfContinuousStates: NULL argument"); return fmi3Error; }
    *nContinuousStates = fmi3_nx(&c->m);
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators) {
    instance_t *c = FMU_ENTER(instance, fmi3GetNumberOfEventIndicators);
    if (!c) return fmi3Error;
    if (!nEventIndicators) { fmu_log(c, fmi2Error, LOG_ERROR, "fmi3GetNumberOfEventIndicators: NULL argument"); return fmi3Error; }
    *nEventIndicators = PLANT_NZ;
    return fmi3OK;
}
