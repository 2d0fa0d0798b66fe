/* Model exchange, every version: time, the continuous states, their derivatives and nominals,
 * the event indicators and the event update, each checked (sizes, NULL arrays, finite values,
 * the states' declared ranges) before anything is stored or returned. A view maps the
 * version's continuous states onto the model's (FMI 2.0: all of them; FMI 3.0: those of the
 * arrays' current dimension, fmi3_view.c). */
#include <math.h>
#include <string.h>

#include "instance.h"

static size_t at(const me_view_t *v, const model_t *m, size_t j) {
    return v->index ? (size_t)v->index(m, j) : j;
}

static int size_ok(instance_t *c, const char *fn, const me_view_t *v, const void *p, size_t n, size_t expected) {
    if (n != expected) {
        if (v->dim_name)
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: size %zu, this FMU has %zu (%s = %d)", fn, n, expected, v->dim_name,
                    v->dim);
        else
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: size %zu, this FMU has %zu", fn, n, expected);
        return 0;
    }
    if (n > 0 && !p) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL array", fn);
        return 0;
    }
    return 1;
}

fmi2Status fmu_me_set_time(instance_t *c, const char *fn, double time) {
    if (!c) return fmi2Error;
    if (!isfinite(time)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: time = %g is not finite", fn, time);
        return fmi2Error;
    }
    c->m.time = time;
    c->m.tau = time - c->m.t0;
    c->m.out_valid = 0;
    return fmi2OK;
}

/* an integrator step completed; the models never ask for Event Mode or the end there (the
 * entry point answers both false) */
fmi2Status fmu_me_completed_step(instance_t *c, const char *fn, int outputs_given) {
    if (!c) return fmi2Error;
    if (!outputs_given) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: NULL output argument", fn);
        return fmi2Error;
    }
    model_completed_step(c);
    return fmi2OK;
}

fmi2Status fmu_me_set_states(instance_t *c, const char *fn, const me_view_t *v, const double x[], size_t nx) {
    size_t j;
    if (!c) return fmi2Error;
    if (!size_ok(c, fn, v, x, nx, v->n)) return fmi2Error;
    for (j = 0; j < nx; j++) {
        unsigned vr = GLUE_STATE_VR[at(v, &c->m, j)];
        if (!isfinite(x[j])) {
            fmu_log(c, fmi2Error, LOG_ERROR, "%s: state %s = %g is not finite", fn, GLUE_VARS[GLUE_VR_INDEX[vr]].name,
                    x[j]);
            return fmi2Error;
        }
        if (!model_check_state(c, fn, vr, x[j])) return fmi2Error;
    }
    for (j = 0; j < nx; j++) c->m.y[at(v, &c->m, j)] = x[j];
    c->m.out_valid = 0;
    return fmi2OK;
}

fmi2Status fmu_me_get_derivatives(instance_t *c, const char *fn, const me_view_t *v, double dx[], size_t nx) {
    size_t j;
    if (!c) return fmi2Error;
    if (!size_ok(c, fn, v, dx, nx, v->n)) return fmi2Error;
    if (!fmu_finite_result(c, fn, NULL, 0)) return fmi2Error;
    model_derivatives(c);
    if (!fmu_finite_result(c, fn, c->m.dydt, GLUE_NX)) return fmi2Error;
    for (j = 0; j < nx; j++) dx[j] = c->m.dydt[at(v, &c->m, j)];
    return fmi2OK;
}

fmi2Status fmu_me_get_indicators(instance_t *c, const char *fn, const me_view_t *v, double z[], size_t nz) {
    if (!c) return fmi2Error;
    if (!size_ok(c, fn, v, z, nz, GLUE_NZ)) return fmi2Error;
    if (!fmu_finite_result(c, fn, NULL, 0)) return fmi2Error;
    model_indicators(c, z);
    return fmu_finite_result(c, fn, z, nz) ? fmi2OK : fmi2Error;
}

fmi2Status fmu_me_get_states(instance_t *c, const char *fn, const me_view_t *v, double x[], size_t nx) {
    size_t j;
    if (!c) return fmi2Error;
    if (!size_ok(c, fn, v, x, nx, v->n)) return fmi2Error;
    if (!fmu_finite_result(c, fn, c->m.y, GLUE_NX)) return fmi2Error;
    for (j = 0; j < nx; j++) x[j] = c->m.y[at(v, &c->m, j)];
    return fmi2OK;
}

fmi2Status fmu_me_get_nominals(instance_t *c, const char *fn, const me_view_t *v, double x[], size_t nx) {
    size_t j;
    if (!c) return fmi2Error;
    if (!size_ok(c, fn, v, x, nx, v->n)) return fmi2Error;
    for (j = 0; j < nx; j++) x[j] = GLUE_STATE_NOMINAL(at(v, &c->m, j));
    return fmi2OK;
}

/* the event update of model exchange at the instance's time: *changed also at a jump of the
 * right-hand side (FMI 2.0 allows false there, but only an importer that always resets would
 * then be right); the next time event */
fmi2Status fmu_me_event_update(instance_t *c, const char *fn, int *changed, int *next_defined, double *next) {
    fmi2Boolean ch = fmi2False;
    if (model_event_update(c, fn, c->m.time - c->m.t0, fmu_ulp_slack(c->m.time), &ch) < 0) return fmi2Error;
    *changed = ch != fmi2False;
    *next_defined = model_next_event(&c->m, next);
    return fmi2OK;
}
