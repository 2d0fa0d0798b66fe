/* The FMI 3.0 view of the variables: the FMI 3.0 value references (model_vars3.h) expanded to
 * the FMI 2.0 ones of their elements (an array of the dimension of the structural parameter
 * MODEL_STRUCTURAL_VR, friction.N for the plant, has N, a scalar one) and handed to the core's
 * get/set (values.c: type, state, range; a rejected set changes nothing); time and
 * eventIndicators are computed here; the structural parameter is set only in Configuration
 * Mode. The continuous states of the view: those of the model but the array elements past the
 * dimension. (Types the FMU has none of: fmi3_stubs.c.) */
#include <stdlib.h>
#include <string.h>

#include "fmi3_view.h"

/* the model's arrays have the dimension of its structural parameter (MODEL_HAS_ARRAYS) */
#if MODEL_HAS_ARRAYS
#define STRUCTURAL_NAME GLUE_VARS[GLUE_VR_INDEX[MODEL_STRUCTURAL_VR]].name
#else
#define STRUCTURAL_NAME "(no structural parameter)"
#endif

const char *fmi3_structural_name(void) { return STRUCTURAL_NAME; }

static int row3(unsigned vr) {
    int lo = 0, hi = MODEL3_NVARS - 1;
    while (lo <= hi) {   /* MODEL3_VARS is sorted by value reference */
        int mid = (lo + hi) / 2;
        if (MODEL3_VARS[mid].vr == vr) return mid;
        if (MODEL3_VARS[mid].vr < vr) lo = mid + 1; else hi = mid - 1;
    }
    return -1;
}

/* the counts of a get/set: no more than an array can hold, values not NULL when n_values > 0 */
static int counts_ok(instance_t *c, const char *fn, size_t nvr, const void *values, size_t n_values) {
    if (nvr > FMU_MAX_VALUES || n_values > FMU_MAX_VALUES) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: nValueReferences = %zu, nValues = %zu: allowed at most %zu (no array "
                "holds more values)", fn, nvr, n_values, FMU_MAX_VALUES);
        return 0;
    }
    if (n_values > 0 && !values) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL array of values with nValues = %zu", fn, n_values);
        return 0;
    }
    return 1;
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
        if (MODEL_HAS_ARRAYS)
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: nValues = %zu, the %zu variable(s) have %zu value(s) (arrays of "
                    "dimension %s = %d)", fn, n_values, nvr, total, STRUCTURAL_NAME, fmi3_n(&c->m));
        else
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: nValues = %zu must equal nValueReferences = %zu (this FMU has no "
                    "arrays)", fn, n_values, nvr);
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
    model_indicators(c, out);
    return fmu_finite_result(c, fn, out, GLUE_NZ) ? fmi2OK : fmi2Error;
}

fmi3Status fmi3_get_values(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr, char type,
                       void *values, size_t n_values) {
    size_t n, k, at = 0;
    unsigned *vr2;
    fmi2Status st = fmi2OK;
    int *tmp = NULL;
    if (!c) return fmi3Error;
    if (!counts_ok(c, fn, nvr, values, n_values)) return fmi3Error;
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

/* the structural parameter in Configuration Mode (nothing else may be set there) */
static fmi3Status set_structural(instance_t *c, const char *fn, const unsigned *vr2, size_t n, const fmi3Int32 *v) {
#if MODEL_HAS_ARRAYS
    size_t k;
    for (k = 0; k < n; k++) {
        if (vr2[k] != MODEL_STRUCTURAL_VR) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s cannot be set in Configuration Mode (only the structural "
                    "parameter %s)", fn, GLUE_VARS[GLUE_VR_INDEX[vr2[k]]].name, STRUCTURAL_NAME);
            return fmi3Error;
        }
        if (!model_check_value(c, fn, GLUE_VR_INDEX[MODEL_STRUCTURAL_VR], (double)v[k])) return fmi3Error;
    }
    for (k = 0; k < n; k++) c->m.val[MODEL_STRUCTURAL_VR] = (double)v[k];
    return fmi3OK;
#else
    (void)c; (void)fn; (void)vr2; (void)n; (void)v;
    return fmi3Error;   /* no Configuration Mode without a structural parameter */
#endif
}

fmi3Status fmi3_set_values(instance_t *c, const char *fn, const fmi3ValueReference vr[], size_t nvr, char type,
                       const void *values, size_t n_values) {
    size_t n, k;
    unsigned *vr2;
    fmi2Status st;
    int *tmp = NULL;
    if (!c) return fmi3Error;
    if (!counts_ok(c, fn, nvr, values, n_values)) return fmi3Error;
    if (!(vr2 = expand(c, fn, vr, nvr, type, n_values, &n))) return fmi3Error;
    for (k = 0; k < n; k++) {
        const char *what = vr2[k] == 0xFFFFFFFFu ? "a calculated variable"
                         : (vr2[k] == MODEL_STRUCTURAL_VR && c->m.fsm != ST_CONFIG) ? "structural" : NULL;
        if (what) {
            if (vr2[k] == 0xFFFFFFFFu)
                fmu_log(c, fmi2Error, LOG_ERROR, "%s: time and eventIndicators are %s", fn, what);
            else
                fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s is %s: set it in Configuration Mode "
                        "(fmi3EnterConfigurationMode)", fn, STRUCTURAL_NAME, what);
            free(vr2);
            return fmi3Error;
        }
    }
    if (c->m.fsm == ST_CONFIG) {
        fmi3Status s3 = type == 'I' ? set_structural(c, fn, vr2, n, (const fmi3Int32 *)values) : fmi3Error;
        if (type != 'I' && n > 0)
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: %s cannot be set in Configuration Mode (only the structural "
                    "parameter %s)", fn, GLUE_VARS[GLUE_VR_INDEX[vr2[0]]].name, STRUCTURAL_NAME);
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

/* the continuous states of the FMI 3.0 view */

int fmi3_n(const model_t *m) {
#if MODEL_HAS_ARRAYS
    return (int)m->val[MODEL_STRUCTURAL_VR];
#else
    (void)m;
    return 0;
#endif
}

/* is FMI 2.0 state j an element past the dimension N of an array? */
static int state_unused(const model_t *m, int j) {
    int r, p, n = fmi3_n(m);
    for (r = 0; r < MODEL3_NVARS; r++) {
        if (MODEL3_VARS[r].kind != 1) continue;
        for (p = 0; p < MODEL3_VARS[r].count; p++)
            if (MODEL3_ELEMS[MODEL3_VARS[r].first + p] == GLUE_STATE_VR[j]) return p >= n;
    }
    return 0;
}

size_t fmi3_nx(const model_t *m) {
    size_t n = 0;
    int j;
    for (j = 0; j < GLUE_NX; j++) n += !state_unused(m, j);
    return n;
}

int fmi3_state_index(const model_t *m, size_t j) {
    int k;
    for (k = 0; k < GLUE_NX; k++)
        if (!state_unused(m, k) && j-- == 0) return k;
    return -1;
}

