/* Eqs. 6-7: polynomial + Fourier series with any wavelengths. When every wavelength is the
 * fundamental's divided by an integer (the paper's 37.5, 18.75, 12.5 mm), one sin/cos pair and
 * the angle-addition recurrence replace a sin/cos pair per term.
 * The four effects of the two maps, one term each of the same two equations: cogging_periodic and
 * ripple_periodic (the Fourier parts), cogging_aperiodic and ripple_aperiodic (the polynomial
 * parts; K_f keeps its constant c0 when off). Each refuses a stroke the maps cannot be evaluated
 * on (they are evaluated at x clamped to [stroke.x_min, stroke.x_max]). */
#include <math.h>
#include <stdio.h>

#include "effect.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

void posmap_prepare(posmap_t *m) {
    int j, k;
    m->harmonic = 0;
    m->kmax = 0;
    m->kw0 = 0.0;
    for (k = 0; k <= PLANT_NMULT; k++) m->ha[k] = m->hb[k] = 0.0;
    if (m->nh == 0) return;
    m->kw0 = m->kw[0];
    for (j = 1; j < m->nh; j++)
        if (m->kw[j] < m->kw0) m->kw0 = m->kw[j];
    for (j = 0; j < m->nh; j++) {
        double r = m->kw[j] / m->kw0;
        double n = floor(r + 0.5);
        if (fabs(r - n) > 1e-12 * r || n > PLANT_NMULT) return;   /* not harmonic: general path */
    }
    for (j = 0; j < m->nh; j++) {
        k = (int)floor(m->kw[j] / m->kw0 + 0.5);
        m->ha[k] += m->a[j];
        m->hb[k] += m->b[j];
        if (k > m->kmax) m->kmax = k;
    }
    m->harmonic = 1;
}

double posmap_eval(const posmap_t *m, double x) {
    double f = posmap_poly(m, x);
    int k;
    if (m->nh == 0) return f;
    if (m->harmonic) {
        double th = m->kw0 * x, c1 = cos(th), s1 = sin(th), ck = c1, sk = s1, t;
        for (k = 1;; k++) {
            f += m->ha[k] * ck + m->hb[k] * sk;
            if (k == m->kmax) break;
            t = ck * c1 - sk * s1;
            sk = sk * c1 + ck * s1;
            ck = t;
        }
        return f;
    }
    for (k = 0; k < m->nh; k++) {
        double th = m->kw[k] * x;
        f += m->a[k] * cos(th) + m->b[k] * sin(th);
    }
    return f;
}

/* Both maps at one position; one sin/cos pair when they share the fundamental (the paper's
 * cogging and ripple both use the magnet pitch). */
void posmap_eval_pair(const posmap_t *m1, const posmap_t *m2, double x, double *f1, double *f2) {
    if (!(m1->harmonic && m2->harmonic && m1->kw0 == m2->kw0)) {
        *f1 = posmap_eval(m1, x);
        *f2 = posmap_eval(m2, x);
        return;
    }
    posmap_sum_pair(m1, m2, x, cos(m1->kw0 * x), sin(m1->kw0 * x), f1, f2);
}

/* ---- the effects of the maps */

/* the Fourier part of a map from the slots lambda/a/b[1..PLANT_NH_MAX] (slots with a = b = 0 are
 * left out), nothing when off */
static void map_periodic(const double *val, posmap_t *m, const unsigned *vl, const unsigned *va,
                         const unsigned *vb, bool on) {
    int j;
    m->nh = 0;
    if (on) {
        for (j = 1; j <= PLANT_NH_MAX; j++) {
            double a = val[va[j]], b = val[vb[j]];
            if (a == 0.0 && b == 0.0) continue;
            m->kw[m->nh] = 2.0 * M_PI / val[vl[j]];
            m->a[m->nh] = a;
            m->b[m->nh] = b;
            m->nh++;
        }
    }
    posmap_prepare(m);
}

/* the polynomial part c[0..npoly-1] of a map; off: 0 (c0 kept when keep_c0) */
static void map_aperiodic(const double *val, posmap_t *m, const unsigned *vc, int npoly, bool on, bool keep_c0) {
    int k;
    m->npoly = npoly;
    for (k = 0; k < npoly; k++) m->c[k] = (on || (keep_c0 && k == 0)) ? val[vc[k]] : 0.0;
}

static bool stroke_ok(const plant_params_t *p, char *msg, size_t msglen) {
    if (p->x_max > p->x_min) return true;
    snprintf(msg, msglen, "stroke.x_max = %.17g must exceed stroke.x_min = %.17g: "
             "allowed stroke.x_max in (%.17g, inf) m", p->x_max, p->x_min, p->x_min);
    return false;
}

static bool range_lambda(unsigned vr, param_range_t *r, const unsigned *vl) {
    int j;
    for (j = 1; j <= PLANT_NH_MAX; j++)
        if (vr == vl[j]) {
            r->lo = 0.0; r->lo_open = 1; r->hi = HUGE_VAL; r->hi_open = 1;
            return true;
        }
    return false;
}
static bool range_cogging_lambda(unsigned vr, param_range_t *r) { return range_lambda(vr, r, VRA_cogging_lambda); }
static bool range_ripple_lambda(unsigned vr, param_range_t *r) { return range_lambda(vr, r, VRA_ripple_lambda); }

static bool compile_cogging_periodic(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    map_periodic(val, &p->cog, VRA_cogging_lambda, VRA_cogging_a, VRA_cogging_b,
                 val[VR_effects_cogging_periodic] != 0.0);
    return stroke_ok(p, msg, msglen);
}
static bool compile_cogging_aperiodic(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    map_aperiodic(val, &p->cog, VRA_cogging_c, 4, val[VR_effects_cogging_aperiodic] != 0.0, false);
    return stroke_ok(p, msg, msglen);
}
static bool compile_ripple_periodic(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    map_periodic(val, &p->rip, VRA_ripple_lambda, VRA_ripple_a, VRA_ripple_b, val[VR_effects_ripple_periodic] != 0.0);
    return stroke_ok(p, msg, msglen);
}
static bool compile_ripple_aperiodic(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    map_aperiodic(val, &p->rip, VRA_ripple_c, 3, val[VR_effects_ripple_aperiodic] != 0.0, true);
    return stroke_ok(p, msg, msglen);
}

/* the cogging stiffness sqrt(|a_j| 2 pi / (lambda_j m)) of every slot, whether or not the Fourier part
 * is on (a candidate of the fastest rate) */
static bool rate_cogging(const double *val, const plant_params_t *p, effect_rate_t *best, char *buf, size_t n) {
    int j;
    (void)buf; (void)n;
    for (j = 1; j <= PLANT_NH_MAX; j++) {
        double kw = 2.0 * M_PI / val[VRA_cogging_lambda[j]];
        effect_rate_candidate(best, VRA_cogging_a[j], sqrt(fabs(val[VRA_cogging_a[j]]) * kw / p->m));
        effect_rate_candidate(best, VRA_cogging_b[j], sqrt(fabs(val[VRA_cogging_b[j]]) * kw / p->m));
    }
    return false;
}

const effect_t effect_cogging_periodic = {
    "cogging_periodic", VR_effects_cogging_periodic, range_cogging_lambda, compile_cogging_periodic, NULL,
    rate_cogging, NULL, NULL};
const effect_t effect_cogging_aperiodic = {
    "cogging_aperiodic", VR_effects_cogging_aperiodic, NULL, compile_cogging_aperiodic, NULL, NULL, NULL, NULL};
const effect_t effect_ripple_periodic = {
    "ripple_periodic", VR_effects_ripple_periodic, range_ripple_lambda, compile_ripple_periodic, NULL, NULL, NULL,
    NULL};
const effect_t effect_ripple_aperiodic = {
    "ripple_aperiodic", VR_effects_ripple_aperiodic, NULL, compile_ripple_aperiodic, NULL, NULL, NULL, NULL};
