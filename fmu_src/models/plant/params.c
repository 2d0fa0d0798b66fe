/* The value table by value reference: start values (from modelDescription.xml), every check
 * (one message per rule), the compilation of the FMU's values into plant_params_t with the
 * effect switches applied, and the transfer of inputs, states and outputs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "params.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

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

#define SUM_NU_TOL 1e-3   /* |sum(nu_i) - 1| allowed; Eq. 12 needs sum(nu) = 1 */

/* the shortest decimal form that reads back exactly (%.15g when enough, else %.17g) */
static const char *num(char *buf, size_t n, double v) {
    snprintf(buf, n, "%.15g", v);
    if (strtod(buf, NULL) != v) snprintf(buf, n, "%.17g", v);
    return buf;
}

static const char *var_name(unsigned vr) {
    return (vr < MODEL_NVR && MODEL_VR_INDEX[vr] >= 0) ? MODEL_VARS[MODEL_VR_INDEX[vr]].name : "?";
}
static const char *var_unit(unsigned vr) {
    return (vr < MODEL_NVR && MODEL_VR_INDEX[vr] >= 0) ? MODEL_VARS[MODEL_VR_INDEX[vr]].unit : "";
}

/* Range rules for single values: lo/hi with open (1) or closed (0) ends. */
typedef struct { double lo; int lo_open; double hi; int hi_open; } range_t;

static bool range_of(unsigned vr, range_t *r) {
    static const range_t POS = {0.0, 1, HUGE_VAL, 1}, NONNEG = {0.0, 0, HUGE_VAL, 1},
                         UNIT = {0.0, 0, 1.0, 0}, NEL = {1.0, 0, (double)PLANT_NE_MAX, 0};
    int j;
    /* parameters only: an input (set every sample) has no range beyond its declared one */
    if (vr >= MODEL_NVR || MODEL_VR_INDEX[vr] < 0 || MODEL_VARS[MODEL_VR_INDEX[vr]].causality != 'p') return false;
    if (vr == VR_m || vr == VR_Ts || vr == VR_friction_F_s || vr == VR_friction_V_s ||
        vr == VR_friction_delta || vr == VR_friction_C) { *r = POS; return true; }
    if (vr == VR_friction_F_c || vr == VR_friction_sigma2) { *r = NONNEG; return true; }
    if (vr == VR_friction_N) { *r = NEL; return true; }
    if (vr == VR_solver_tol) {   /* (0, declared max]: a tolerance of 0 controls nothing */
        r->lo = 0.0; r->lo_open = 1; r->hi = MODEL_VARS[MODEL_VR_INDEX[VR_solver_tol]].max; r->hi_open = 0;
        return true;
    }
    for (j = 1; j <= PLANT_NE_MAX; j++) {
        if (vr == VRA_friction_nu[j]) { *r = UNIT; return true; }
        if (vr == VRA_friction_k[j]) { *r = POS; return true; }
    }
    for (j = 1; j <= PLANT_NH_MAX; j++)
        if (vr == VRA_cogging_lambda[j] || vr == VRA_ripple_lambda[j]) { *r = POS; return true; }
    return false;
}

static void fmt_range(char *buf, size_t n, const range_t *r) {
    char lo[32], hi[32];
    if (isinf(r->lo)) snprintf(lo, sizeof lo, "-inf"); else num(lo, sizeof lo, r->lo);
    if (isinf(r->hi)) snprintf(hi, sizeof hi, "inf"); else num(hi, sizeof hi, r->hi);
    snprintf(buf, n, "%s%s, %s%s", r->lo_open ? "(" : "[", lo, hi, r->hi_open ? ")" : "]");
}

/* the min/max of modelDescription.xml (the interval that keeps the arithmetic finite) */
static bool declared_range_ok(unsigned vr, double value, char *msg, size_t msglen) {
    const model_var_t *v;
    char vb[40], lo[40], hi[40];
    if (vr >= MODEL_NVR || MODEL_VR_INDEX[vr] < 0) return true;
    v = &MODEL_VARS[MODEL_VR_INDEX[vr]];
    if (value >= v->min && value <= v->max) return true;
    if (isinf(v->min)) snprintf(lo, sizeof lo, "-inf"); else num(lo, sizeof lo, v->min);
    if (isinf(v->max)) snprintf(hi, sizeof hi, "inf"); else num(hi, sizeof hi, v->max);
    snprintf(msg, msglen, "%s = %s is out of range: allowed [%s, %s] %s", v->name, num(vb, sizeof vb, value),
             lo, hi, v->unit);
    return false;
}

bool params_check_value(unsigned vr, double value, char *msg, size_t msglen) {
    range_t r;
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
        snprintf(msg, msglen, "%s = %s is out of range: allowed %s %s", var_name(vr), num(vb, sizeof vb, value),
                 rs, var_unit(vr));
        return false;
    }
    return declared_range_ok(vr, value, msg, msglen);
}

static void map_compile(const double *val, posmap_t *m, const unsigned *vc, int npoly,
                        const unsigned *vl, const unsigned *va, const unsigned *vb,
                        bool periodic, bool aperiodic, bool keep_c0) {
    int k, j;
    m->npoly = npoly;
    for (k = 0; k < npoly; k++)
        m->c[k] = (aperiodic || (keep_c0 && k == 0)) ? val[vc[k]] : 0.0;
    m->nh = 0;
    if (!periodic) { posmap_prepare(m); return; }
    for (j = 1; j <= PLANT_NH_MAX; j++) {
        double a = val[va[j]], b = val[vb[j]];
        if (a == 0.0 && b == 0.0) continue;
        m->kw[m->nh] = 2.0 * M_PI / val[vl[j]];
        m->a[m->nh] = a;
        m->b[m->nh] = b;
        m->nh++;
    }
    posmap_prepare(m);
}

#define FAIL(...) do { snprintf(msg, msglen, __VA_ARGS__); return false; } while (0)

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

/* Schur-Cohn (step-down) test of the denominator z^n - a_1 z^(n-1) - ... - a_n of Eq. 2:
 * with alpha_i = -a_i (A(z) = 1 + sum alpha_i z^-i), the reflection coefficient of order j is
 * k_j = alpha_j^(j) and the order j - 1 coefficients alpha_i^(j-1) = (alpha_i - k_j alpha_(j-i))
 * / (1 - k_j^2); every root lies inside the unit circle iff |k_j| < 1 for j = n..1. Returns 0 when
 * stable, else the order j whose |k_j| >= 1 (its value in *k). */
static int current_loop_unstable(const double *a, int n, double *k) {
    double al[PLANT_NA_MAX + 1], nx[PLANT_NA_MAX + 1];
    int i, j;
    for (i = 1; i <= n; i++) al[i] = -a[i - 1];
    for (j = n; j >= 1; j--) {
        *k = al[j];
        if (!(fabs(*k) < 1.0)) return j;
        for (i = 1; i < j; i++) nx[i] = (al[i] - *k * al[j - i]) / (1.0 - *k * *k);
        for (i = 1; i < j; i++) al[i] = nx[i];
    }
    return 0;
}

/* G(z) coefficients and its DC gain (Eq. 2); refuses a pole at z = 1 and any pole on or outside
 * the unit circle (an unstable loop's current grows without bound, whether or not
 * effects.current_dynamics is on: its DC gain G(1) is then meaningless too) */
static bool compile_current_loop(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    double sa = 0.0, sb = 0.0, k;
    int j, n = 0, bad;
    p->current_dynamics = val[VR_effects_current_dynamics] != 0.0;
    for (j = 1; j <= PLANT_NA_MAX; j++) {
        p->ca[j - 1] = val[VRA_current_a[j]];
        sa += p->ca[j - 1];
        if (p->ca[j - 1] != 0.0) n = j;
    }
    for (j = 0; j < PLANT_NB_MAX; j++) { p->cb[j] = val[VRA_current_b[j]]; sb += p->cb[j]; }
    if (fabs(1.0 - sa) < 1e-9)
        FAIL("current.a[1..5] sum to %.17g: the current loop has a pole at z = 1 and no finite DC gain; "
             "allowed: sum(current.a) != 1", sa);
    if ((bad = current_loop_unstable(p->ca, n, &k)) != 0)
        FAIL("current.a[1..5] = %.9g, %.9g, %.9g, %.9g, %.9g: the current loop is unstable (a root of its "
             "denominator z^n - a_1 z^(n-1) - ... - a_n, n = %d, lies on or outside the unit circle: Schur-Cohn "
             "reflection coefficient k_%d = %.9g); allowed: every root inside |z| < 1 (all |k_j| < 1)",
             p->ca[0], p->ca[1], p->ca[2], p->ca[3], p->ca[4], n, bad, k);
    p->G1 = sb / (1.0 - sa);
    return true;
}

/* cogging F_cg(x) and force constant K_f(x) (Eqs. 6, 7) and the stroke they are evaluated on */
static bool compile_position_maps(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    map_compile(val, &p->cog, VRA_cogging_c, 4, VRA_cogging_lambda, VRA_cogging_a, VRA_cogging_b,
                val[VR_effects_cogging_periodic] != 0.0, val[VR_effects_cogging_aperiodic] != 0.0, false);
    map_compile(val, &p->rip, VRA_ripple_c, 3, VRA_ripple_lambda, VRA_ripple_a, VRA_ripple_b,
                val[VR_effects_ripple_periodic] != 0.0, val[VR_effects_ripple_aperiodic] != 0.0, true);
    p->x_min = val[VR_stroke_x_min];
    p->x_max = val[VR_stroke_x_max];
    if (!(p->x_max > p->x_min))
        FAIL("stroke.x_max = %.17g must exceed stroke.x_min = %.17g: allowed stroke.x_max in (%.17g, inf) m",
             p->x_max, p->x_min, p->x_min);
    return true;
}

/* the asymmetry's shift of the levels for v < 0 (effect asymmetric_friction) */
static bool compile_asymmetry(const double *val, plant_params_t *p, bool viscous, char *msg, size_t msglen) {
    double dF = val[VR_asymmetry_dF], ds = val[VR_asymmetry_dsigma2];
    if (p->Fc[0] + dF < 0.0 || p->Fs[0] + dF <= 0.0)
        FAIL("asymmetry.dF = %.17g makes the friction level for v < 0 negative: allowed [%.17g, inf) N",
             dF, -p->Fc[0]);
    if (p->sigma2[0] + ds < 0.0)
        FAIL("asymmetry.dsigma2 = %.17g makes the viscous coefficient for v < 0 negative: "
             "allowed [%.17g, inf) N.s/m", ds, -p->sigma2[0]);
    p->Fs[1] += dF;
    p->Fc[1] += dF;
    p->sigma2[1] += viscous ? ds : 0.0;
    return true;
}

/* the sliding levels F_s, F_c, sigma2 per direction and the Stribeck curve (Eqs. 8, 10) */
static bool compile_friction_levels(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    bool e_str = val[VR_effects_stribeck] != 0.0, e_visc = val[VR_effects_viscous] != 0.0;
    int j;
    p->prerolling = val[VR_effects_prerolling] != 0.0;
    p->lag = val[VR_effects_frictional_lag] != 0.0;
    if (val[VR_friction_F_c] > val[VR_friction_F_s])
        FAIL("friction.F_c = %.17g exceeds friction.F_s = %.17g: allowed friction.F_c in [0, friction.F_s] N",
             val[VR_friction_F_c], val[VR_friction_F_s]);
    /* without the Stribeck drop the level is the Coulomb one everywhere (the effect catalogue: F_s = F_c) */
    p->Fs[0] = e_str ? val[VR_friction_F_s] : val[VR_friction_F_c];
    p->Fc[0] = val[VR_friction_F_c];
    p->sigma2[0] = e_visc ? val[VR_friction_sigma2] : 0.0;
    p->Fs[1] = p->Fs[0];
    p->Fc[1] = p->Fc[0];
    p->sigma2[1] = p->sigma2[0];
    if (val[VR_effects_asymmetric_friction] != 0.0 && !compile_asymmetry(val, p, e_visc, msg, msglen))
        return false;
    p->Vs = val[VR_friction_V_s];
    p->delta = val[VR_friction_delta];
    p->delta_bc[0] = 1.0;
    for (j = 1; j <= PLANT_NBIN; j++) p->delta_bc[j] = p->delta_bc[j - 1] * (p->delta - (j - 1)) * (1.0 / j);
    p->C = val[VR_friction_C];
    return true;
}

/* the GMS elements in use (Eqs. 9, 11, 12): N, nu_i, k_i; sum(nu) = 1 when prerolling */
static bool compile_elements(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    double sum_nu = 0.0;
    int j;
    p->N = (int)val[VR_friction_N];
    if ((double)p->N != val[VR_friction_N])
        FAIL("friction.N = %.17g is not an integer: allowed 1..%d", val[VR_friction_N], PLANT_NE_MAX);
    for (j = 0; j < PLANT_NE_MAX; j++) {
        p->nu[j] = val[VRA_friction_nu[j + 1]];
        p->k[j] = val[VRA_friction_k[j + 1]];
        p->active[j] = p->prerolling && j < p->N && p->nu[j] > 0.0;
        if (j < p->N) sum_nu += p->nu[j];
    }
    if (p->prerolling && fabs(sum_nu - 1.0) > SUM_NU_TOL)
        FAIL("friction.nu[1..%d] sum to %.17g: allowed 1 +- %g (Eq. 12 needs sum(nu) = 1; "
             "set friction.nu[%d] = 1 - sum of the others)", p->N, sum_nu, SUM_NU_TOL, p->N);
    return true;
}

/* the friction-level profile p(x) (effect position_friction, friction_position.c): knots and
 * spacing; always checked, like the stroke, so a model's profile is valid whether on or off */
static bool compile_position_friction(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    double x0 = val[VR_friction_profile_x_start], x1 = val[VR_friction_profile_x_end];
    double n = val[VR_friction_profile_n];
    int j;
    if (!(x1 > x0))
        FAIL("friction_profile.x_end = %.17g must exceed friction_profile.x_start = %.17g: "
             "allowed friction_profile.x_end in (%.17g, inf) m", x1, x0, x0);
    if ((double)(int)n != n)
        FAIL("friction_profile.n = %.17g is not an integer: allowed 2..%d", n, PLANT_NPF_MAX);
    p->posfric = val[VR_effects_position_friction] != 0.0;
    p->pf_n = (int)n;
    p->pf_x0 = x0;
    p->pf_h = (x1 - x0) / (double)(p->pf_n - 1);
    for (j = 0; j < PLANT_NPF_MAX; j++) p->pf_c[j] = j < p->pf_n ? val[VRA_friction_profile_c[j + 1]] : 0.0;
    return true;
}
/* the load on its spring-damper (compliance.c): k2 = m2 w^2, c2 = 2 zeta m2 w, w = 2 pi f */
static void compile_compliance(const double *val, plant_params_t *p) {
    double w = 2.0 * M_PI * val[VR_compliance_f];
    p->compliance = val[VR_effects_compliance] != 0.0;
    p->m2 = val[VR_compliance_m2];
    p->k2 = p->m2 * w * w;
    p->c2 = 2.0 * val[VR_compliance_zeta] * p->m2 * w;
    p->sensor_side = (int)val[VR_compliance_sensor_side];
}

bool params_compile(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    if (!check_each_parameter(val, msg, msglen)) return false;
    memset(p, 0, sizeof *p);
    p->m = val[VR_m];
    p->Ts = val[VR_Ts];
    if (!compile_current_loop(val, p, msg, msglen) || !compile_position_maps(val, p, msg, msglen) ||
        !compile_friction_levels(val, p, msg, msglen) || !compile_elements(val, p, msg, msglen) ||
        !compile_position_friction(val, p, msg, msglen))
        return false;
    p->F_off = val[VR_effects_offset_force] != 0.0 ? val[VR_offset_F] : 0.0;
    compile_compliance(val, p);
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

/* one candidate of params_fastest_rate: a rate [1/s] and the parameter it comes from */
static void rate_candidate(unsigned vr, double rate, double *best, unsigned *best_vr) {
    if (rate > *best) { *best = rate; *best_vr = vr; }
}

void params_fastest_rate(const double *val, const plant_params_t *p, char *buf, size_t n) {
    double best = 0.0, S_min = p->Fc[0] < p->Fc[1] ? p->Fc[0] : p->Fc[1];
    unsigned best_vr = VR_Ts;
    char vb[40], mb[40];
    int j;
    if (p->posfric) {   /* the level scaled by p(x) >= 1 + min c_j (the B-spline's hull) */
        double c_min = 0.0;
        for (j = 0; j < p->pf_n; j++) if (p->pf_c[j] < c_min) c_min = p->pf_c[j];
        S_min *= 1.0 + c_min;
    }
    if (p->prerolling && p->lag && p->C > 0.0 && !(p->C / S_min < HUGE_VAL)) {
        /* C / S(|v|) with S falling to S_min = 0 (or so near 0 that the quotient overflows) as |v|
         * grows: no bound to print as a rate */
        snprintf(buf, n, "%s = %s N (with effects.frictional_lag the lag rate friction.C / S(|v|) has no bound: "
                 "the level S(|v|) falls to it as |v| grows; friction.C = %s N/s)",
                 p->Fc[0] <= p->Fc[1] ? "friction.F_c" : "friction.F_c + asymmetry.dF", num(vb, sizeof vb, S_min),
                 num(mb, sizeof mb, p->C));
        return;
    }
    if (p->prerolling && p->lag && p->C > 0.0) rate_candidate(VR_friction_C, p->C / S_min, &best, &best_vr);
    for (j = 0; j < PLANT_NE_MAX; j++)
        if (p->active[j]) rate_candidate(VRA_friction_k[j + 1], sqrt(p->k[j] / p->m), &best, &best_vr);
    rate_candidate(VR_friction_sigma2, (p->sigma2[0] > p->sigma2[1] ? p->sigma2[0] : p->sigma2[1]) / p->m,
                   &best, &best_vr);
    for (j = 1; j <= PLANT_NH_MAX; j++) {
        double kw = 2.0 * M_PI / val[VRA_cogging_lambda[j]];
        rate_candidate(VRA_cogging_a[j], sqrt(fabs(val[VRA_cogging_a[j]]) * kw / p->m), &best, &best_vr);
        rate_candidate(VRA_cogging_b[j], sqrt(fabs(val[VRA_cogging_b[j]]) * kw / p->m), &best, &best_vr);
    }
    if (p->compliance)   /* the coupled mode: w sqrt(1 + m2/m) */
        rate_candidate(VR_compliance_f, sqrt(p->k2 / p->m2 * (1.0 + p->m2 / p->m)), &best, &best_vr);
    if (best < 1.0 / p->Ts) { best = 1.0 / p->Ts; best_vr = VR_Ts; }
    snprintf(buf, n, "%s = %s (rate %.3g 1/s with m = %s kg)", var_name(best_vr), num(vb, sizeof vb, val[best_vr]),
             best, num(mb, sizeof mb, p->m));
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
