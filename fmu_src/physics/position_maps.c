/* Eqs. 6-7: polynomial + Fourier series with any wavelengths. When every wavelength is the
 * fundamental's divided by an integer (the paper's 37.5, 18.75, 12.5 mm), one sin/cos pair and
 * the angle-addition recurrence replace a sin/cos pair per term. */
#include <math.h>

#include "plant.h"

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
    double f = 0.0;
    int k;
    for (k = m->npoly - 1; k >= 0; k--) f = f * x + m->c[k];
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

/* Both maps of a shared fundamental at x, given c1 = cos(kw0 x) and s1 = sin(kw0 x) (however
 * the caller got them): the polynomials and one recurrence for every harmonic. */
void posmap_sum_pair(const posmap_t *m1, const posmap_t *m2, double x, double c1, double s1,
                     double *f1, double *f2) {
    double ck = c1, sk = s1, t, a = 0.0, b = 0.0;
    int k, kmax = m1->kmax > m2->kmax ? m1->kmax : m2->kmax;
    for (k = m1->npoly - 1; k >= 0; k--) a = a * x + m1->c[k];
    for (k = m2->npoly - 1; k >= 0; k--) b = b * x + m2->c[k];
    for (k = 1;; k++) {
        a += m1->ha[k] * ck + m1->hb[k] * sk;
        b += m2->ha[k] * ck + m2->hb[k] * sk;
        if (k == kmax) break;
        t = ck * c1 - sk * s1;
        sk = sk * c1 + ck * s1;
        ck = t;
    }
    *f1 = a;
    *f2 = b;
}
