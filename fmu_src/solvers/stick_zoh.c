/* Every GMS element stuck: the exact zero-order-hold update over one interval of constant
 * current (fast_path.h). With all N elements stuck F_j = F_j0 + k_j (x - x0) exactly, so
 *   m dv/dt = K_f(x) i - F_cg(x) - F_ext - F_off - sigma2 v - sum F_j0 - K (x - x0),  K = sum k_j,
 * and with the maps linearised at x0 (value and slope) this is a damped oscillator
 *   dx' = v,  m v' = b - kappa dx - sigma2 v,   kappa = K - (K_f'(x0) i - F_cg'(x0)),
 * solved in closed form (the ~54 Hz ringing of a stage at rest). The one approximation is the
 * maps' curvature: |K_f(x) i - F_cg(x) - linearisation| <= M2 dx^2 / 2 with M2 = max|K_f''| |i| +
 * max|F_cg''| over the stroke (from the coefficients), dx bounded by the oscillator's envelope;
 * the update is refused (0) when that force error, over the step, exceeds a tenth of the
 * solver's absolute tolerance in x or v. Refused too: a sign change of v with asymmetric sigma2,
 * an over-damped or unstable linearisation, a position at or beyond a stroke end (the maps are
 * clamped there), and a stuck element whose indicator nu_j S(|v|) - sgn(v) F_j ends <= 0 (the
 * event is then located by the adaptive solver). */
#include <math.h>

#include "fast_path.h"

/* value and slope at x of one map, and a bound of |f''| over [-X, X] */
static void map_slope(const posmap_t *m, double x, double X, double *f, double *df, double *d2max) {
    double v = posmap_poly(m, x), s = 0.0, b2 = 0.0, xp = 1.0;
    int k;
    for (k = m->npoly - 1; k >= 1; k--) s = s * x + k * m->c[k];
    for (k = 2; k < m->npoly; k++, xp *= X) b2 += k * (k - 1) * fabs(m->c[k]) * xp;
    if (m->harmonic) {
        double c1 = cos(m->kw0 * x), s1 = sin(m->kw0 * x), ck = c1, sk = s1, t;
        for (k = 1; k <= m->kmax; k++) {
            double w = k * m->kw0;
            v += m->ha[k] * ck + m->hb[k] * sk;
            s += w * (m->hb[k] * ck - m->ha[k] * sk);
            b2 += (fabs(m->ha[k]) + fabs(m->hb[k])) * w * w;
            t = ck * c1 - sk * s1;
            sk = sk * c1 + ck * s1;
            ck = t;
        }
    } else {
        for (k = 0; k < m->nh; k++) {
            double th = m->kw[k] * x, c = cos(th), sn = sin(th);
            v += m->a[k] * c + m->b[k] * sn;
            s += m->kw[k] * (m->b[k] * c - m->a[k] * sn);
            b2 += (fabs(m->a[k]) + fabs(m->b[k])) * m->kw[k] * m->kw[k];
        }
    }
    *f = v;
    *df = s;
    *d2max = b2;
}

int stick_zoh_step(const plant_params_t *p, const plant_disc_t *d, const plant_in_t *in, double h,
                   const fast_tol_t *tol, double *y) {
    double x0 = y[PLANT_IX], v0 = y[PLANT_IV], K = 0.0, F0 = 0.0, X, i;
    double Kf, dKf, b2Kf, Fcg, dFcg, b2cg, sig, b, kap, a, w02, wd, xs, e0, E, C, Sn, e1, v1, dx1;
    double amp, dxm, r, S, F1[PLANT_NE_MAX];
    int j, sg;
    if (!p->prerolling || d->dir != 0 || !(h > 0.0)) return 0;
    if (!(x0 > p->x_min && x0 < p->x_max)) return 0;
    for (j = 0; j < PLANT_NE_MAX; j++) {
        if (!p->active[j]) continue;
        if (!d->stuck[j]) return 0;
        K += p->k[j];
        F0 += y[PLANT_IF + j];
    }
    X = fabs(p->x_min) > fabs(p->x_max) ? fabs(p->x_min) : fabs(p->x_max);
    i = current_loop_output(p, d, in->u);
    map_slope(&p->rip, x0, X, &Kf, &dKf, &b2Kf);
    map_slope(&p->cog, x0, X, &Fcg, &dFcg, &b2cg);
    sig = p->sigma2[v0 < 0.0];
    b = Kf * i - Fcg - in->F_ext - p->F_off - F0;
    kap = K - (dKf * i - dFcg);
    if (!(kap > 0.0) || !(sig >= 0.0)) return 0;
    a = sig / (2.0 * p->m);
    w02 = kap / p->m;
    if (!(w02 - a * a > 0.0)) return 0;
    wd = sqrt(w02 - a * a);
    xs = b / kap;
    e0 = -xs;
    E = exp(-a * h);
    C = cos(wd * h);
    Sn = sin(wd * h);
    e1 = E * (e0 * C + (v0 + a * e0) / wd * Sn);
    v1 = E * (v0 * C - (a * v0 + w02 * e0) / wd * Sn);
    dx1 = xs + e1;
    if (p->sigma2[0] != p->sigma2[1] && (v1 < 0.0) != (v0 < 0.0)) return 0;
    /* |dx(t)| <= |xs| + the envelope of the free oscillation about xs */
    amp = sqrt(e0 * e0 + (v0 + a * e0) * (v0 + a * e0) / (wd * wd));
    dxm = fabs(xs) + amp;
    r = 0.5 * (b2Kf * fabs(i) + b2cg) * dxm * dxm;      /* force error bound [N] */
    if (!(r * h / p->m <= 0.1 * tol->atol[PLANT_IV]) || !(r * h * h / (2.0 * p->m) <= 0.1 * tol->atol[PLANT_IX]))
        return 0;
    if (!(x0 + dx1 > p->x_min && x0 + dx1 < p->x_max) || !isfinite(v1)) return 0;
    /* the stuck elements' indicators at the end (gms_indicators) */
    sg = friction_sign(v1);
    S = friction_level(p, v1, sg < 0);
    for (j = 0; j < PLANT_NE_MAX; j++) {
        if (!p->active[j]) continue;
        F1[j] = y[PLANT_IF + j] + p->k[j] * dx1;
        if (!(p->nu[j] * S - sg * F1[j] > 0.0)) return 0;
    }
    y[PLANT_IX] = x0 + dx1;
    y[PLANT_IV] = v1;
    for (j = 0; j < PLANT_NE_MAX; j++)
        if (p->active[j]) y[PLANT_IF + j] = F1[j];
    return 1;
}
