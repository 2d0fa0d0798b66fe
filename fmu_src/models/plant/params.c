/* The value table by value reference: start values (from modelDescription.xml), every check
 * (one message per rule), the compilation of the FMU's values into plant_params_t, and the
 * transfer of inputs, states and outputs. The parameters that belong to no effect are compiled and
 * checked here (m, Ts, solver.tol, the stroke's ends: the maps, which are evaluated on the stroke,
 * refuse an empty one); every effect's rules and compilation are in the effect's own file,
 * reached through the effect table PLANT_EFFECTS (effect.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "effect.h"
#include "params.h"

/* The plant's counts must be those of modelDescription.xml (model_vars.h is generated from it).
 * C99 has no _Static_assert: a negative array size fails the build, naming the check. */
#define COMPILE_CHECK(name, cond) typedef char compile_check_##name[(cond) ? 1 : -1]
#define COUNT(a) (sizeof(a) / sizeof((a)[0]))
COMPILE_CHECK(continuous_states_match_xml, PLANT_NX == MODEL_NX);
COMPILE_CHECK(event_indicators_match_xml, PLANT_NZ == MODEL_NZ);
COMPILE_CHECK(friction_elements_match_xml, COUNT(VRA_friction_nu) == PLANT_NE_MAX + 1 &&
              COUNT(VRA_friction_k) == PLANT_NE_MAX + 1 && COUNT(VRA_friction_F) == PLANT_NE_MAX + 1);
COMPILE_CHECK(fourier_slots_match_xml, COUNT(VRA_cogging_lambda) == PLANT_NH_MAX + 1 &&
              COUNT(VRA_ripple_lambda) == PLANT_NH_MAX + 1);
COMPILE_CHECK(friction_profile_match_xml, COUNT(VRA_friction_profile_c) == PLANT_NPF_MAX + 1);
COMPILE_CHECK(current_loop_match_xml, COUNT(VRA_current_a) == PLANT_NA_MAX + 1 &&
              COUNT(VRA_current_b) == PLANT_NB_MAX);

static const char *var_name(unsigned vr) {
    return (vr < MODEL_NVR && MODEL_VR_INDEX[vr] >= 0) ? MODEL_VARS[MODEL_VR_INDEX[vr]].name : "?";
}
static const char *var_unit(unsigned vr) {
    return (vr < MODEL_NVR && MODEL_VR_INDEX[vr] >= 0) ? MODEL_VARS[MODEL_VR_INDEX[vr]].unit : "";
}

/* Range rules for single values: lo/hi with open (1) or closed (0) ends; the parameters of no
 * effect here, every effect's from its entry */
static bool range_of(unsigned vr, param_range_t *r) {
    static const param_range_t POS = {0.0, 1, HUGE_VAL, 1};
    int j;
    /* parameters only: an input (set every sample) has no range beyond its declared one */
    if (vr >= MODEL_NVR || MODEL_VR_INDEX[vr] < 0 || MODEL_VARS[MODEL_VR_INDEX[vr]].causality != 'p') return false;
    if (vr == VR_m || vr == VR_Ts) { *r = POS; return true; }
    if (vr == VR_solver_tol) {   /* (0, declared max]: a tolerance of 0 controls nothing */
        r->lo = 0.0; r->lo_open = 1; r->hi = MODEL_VARS[MODEL_VR_INDEX[VR_solver_tol]].max; r->hi_open = 0;
        return true;
    }
    for (j = 0; j < MODEL_NEFFECTS; j++)
        if (PLANT_EFFECTS[j]->range && PLANT_EFFECTS[j]->range(vr, r)) return true;
    return false;
}

static void fmt_range(char *buf, size_t n, const param_range_t *r) {
    char lo[32], hi[32];
    if (isinf(r->lo)) snprintf(lo, sizeof lo, "-inf"); else effect_num(lo, sizeof lo, r->lo);
    if (isinf(r->hi)) snprintf(hi, sizeof hi, "inf"); else effect_num(hi, sizeof hi, r->hi);
    snprintf(buf, n, "%s%s, %s%s", r->lo_open ? "(" : "[", lo, hi, r->hi_open ? ")" : "]");
}

/* the min/max of modelDescription.xml (the interval that keeps the arithmetic finite) */
static bool declared_range_ok(unsigned vr, double value, char *msg, size_t msglen) {
    const model_var_t *v;
    char vb[40], lo[40], hi[40];
    if (vr >= MODEL_NVR || MODEL_VR_INDEX[vr] < 0) return true;
    v = &MODEL_VARS[MODEL_VR_INDEX[vr]];
    if (value >= v->min && value <= v->max) return true;
    if (isinf(v->min)) snprintf(lo, sizeof lo, "-inf"); else effect_num(lo, sizeof lo, v->min);
    if (isinf(v->max)) snprintf(hi, sizeof hi, "inf"); else effect_num(hi, sizeof hi, v->max);
    snprintf(msg, msglen, "%s = %s is out of range: allowed [%s, %s] %s", v->name, effect_num(vb, sizeof vb, value),
             lo, hi, v->unit);
    return false;
}

bool params_check_value(unsigned vr, double value, char *msg, size_t msglen) {
    param_range_t r;
    char rs[80];
    if (!isfinite(value)) {
        snprintf(msg, msglen, "%s = %g is not a finite number: allowed values are finite%s%s",
                 var_name(vr), value, *var_unit(vr) ? " [" : "", *var_unit(vr) ? var_unit(vr) : "");
        if (*var_unit(vr)) strncat(msg, "]", msglen - strlen(msg) - 1);
        return false;
    }
    if (range_of(vr, &r) &&
        ((r.lo_open ? value <= r.lo : value < r.lo) || (r.hi_open ? value >= r.hi : value > r.hi))) {
        fmt_range(rs, sizeof rs, &r);
        char vb[40];
        snprintf(msg, msglen, "%s = %s is out of range: allowed %s %s", var_name(vr), effect_num(vb, sizeof vb, value),
                 rs, var_unit(vr));
        return false;
    }
    return declared_range_ok(vr, value, msg, msglen);
}

/* every single-value rule, for every parameter */
static bool check_each_parameter(const double *val, char *msg, size_t msglen) {
    int j;
    for (j = 0; j < MODEL_NVARS; j++) {
        unsigned vr = MODEL_VARS[j].vr;
        if (MODEL_VARS[j].causality != 'p') continue;
        if (!params_check_value(vr, val[vr], msg, msglen)) return false;
    }
    return true;
}

/* m, Ts and the stroke, then every effect's compilation and every effect's rules of combination,
 * in the table's order (the order of the messages when several rules are broken) */
bool params_compile(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    int j;
    if (!check_each_parameter(val, msg, msglen)) return false;
    memset(p, 0, sizeof *p);
    p->m = val[VR_m];
    p->Ts = val[VR_Ts];
    p->x_min = val[VR_stroke_x_min];
    p->x_max = val[VR_stroke_x_max];
    for (j = 0; j < MODEL_NEFFECTS; j++)
        if (!PLANT_EFFECTS[j]->compile(val, p, msg, msglen)) return false;
    for (j = 0; j < MODEL_NEFFECTS; j++)
        if (PLANT_EFFECTS[j]->check && !PLANT_EFFECTS[j]->check(val, p, msg, msglen)) return false;
    return true;
}

void params_defaults(double *val) {
    int j;
    for (j = 0; j < MODEL_NVARS; j++) val[MODEL_VARS[j].vr] = MODEL_VARS[j].start;
}

void params_inputs(const double *val, plant_in_t *in) {
    in->u = val[VR_u];
    in->F_ext = val[VR_F_ext];
}

void params_states(const double *val, double *y) {
    int j;
    for (j = 0; j < MODEL_NX; j++) y[j] = val[MODEL_STATE_VR[j]];
}

void params_store_derivatives(double *val, const double *y, const double *dydt) {
    int j;
    for (j = 0; j < MODEL_NX; j++) val[MODEL_DER_VR[j]] = dydt[j];
    for (j = 0; j < MODEL_NX; j++) val[MODEL_STATE_VR[j]] = y[j];
}

void params_store_outputs(double *val, const double *y, const plant_out_t *o, const plant_disc_t *d) {
    int j;
    for (j = 0; j < MODEL_NX; j++) val[MODEL_STATE_VR[j]] = y[j];
    val[VR_i] = o->i;
    val[VR_F_motor] = o->F_motor;
    val[VR_F_cogging] = o->F_cg;
    val[VR_F_friction] = o->F_fric;
    val[VR_K_f] = o->K_f;
    val[VR_n_stuck] = o->n_stuck;
    val[VR_x_measured] = o->x_meas;
    val[VR_x_load] = o->x_load;
    val[VR_v_load] = o->v_load;
    val[VR_compliance_F] = o->F_load;
    val[VR_stats_n_stick] = (double)d->n_stick;
    val[VR_stats_n_slip] = (double)d->n_slip;
    val[VR_stats_n_time_events] = (double)d->n_time_events;
    val[VR_stats_n_state_events] = (double)d->n_state_events;
    /* friction.F[j] reports the element's effective force (nu_j s(v) when lag is off) */
    for (j = 0; j < PLANT_NE_MAX; j++) val[VRA_friction_F[j + 1]] = o->F_elem[j];
    for (j = 0; j < PLANT_NE_MAX; j++) val[VRA_friction_stuck[j + 1]] = d->stuck[j] ? 1.0 : 0.0;
}

void params_fastest_rate(const double *val, const plant_params_t *p, char *buf, size_t n) {
    effect_rate_t best = {0.0, VR_Ts};
    char vb[40], mb[40];
    int j;
    for (j = 0; j < MODEL_NEFFECTS; j++)
        if (PLANT_EFFECTS[j]->rate && PLANT_EFFECTS[j]->rate(val, p, &best, buf, n)) return;
    if (best.rate < 1.0 / p->Ts) { best.rate = 1.0 / p->Ts; best.vr = VR_Ts; }
    snprintf(buf, n, "%s = %s (rate %.3g 1/s with m = %s kg)", var_name(best.vr),
             effect_num(vb, sizeof vb, val[best.vr]), best.rate, effect_num(mb, sizeof mb, p->m));
}

void params_state_cause(const plant_params_t *p, const double *y, const plant_in_t *in, const plant_out_t *o,
                        int j, char *buf, size_t n) {
    if (j == PLANT_IX)
        snprintf(buf, n, "the slide travelled beyond it at v = %g m/s", y[PLANT_IV]);
    else if (j == PLANT_IV)
        snprintf(buf, n, "the forces on the slide accelerate it at a = %g m/s^2 (F_motor = %g N, F_ext = %g N, "
                 "F_friction = %g N, F_cogging = %g N, m = %g kg)", o->a, o->F_motor, in->F_ext, o->F_fric, o->F_cg,
                 p->m);
    else if (j >= PLANT_IF && j < PLANT_IF + PLANT_NE_MAX)
        snprintf(buf, n, "the element's stiffness friction.k[%d] = %g N/m deflected by the slide's motion "
                 "(v = %g m/s)", j - PLANT_IF + 1, p->k[j - PLANT_IF], y[PLANT_IV]);
    else
        snprintf(buf, n, "the load m2 = %g kg on its spring (k2 = %g N/m) driven by the slide's acceleration "
                 "a = %g m/s^2", p->m2, p->k2, o->a);
}
