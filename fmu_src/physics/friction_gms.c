/* Generalized Maxwell-Slip friction (Eqs. 8-11), as docs/model.md states it:
 *   stuck:   dF_i/dt = k_i v            until sgn(F_i) = sgn(v) and |F_i| >= nu_i S(|v|)
 *   slipping dF_i/dt = (C/S)(nu_i s(v) - F_i)   until v crosses zero (then every slipping element sticks)
 * Switching is hybrid: discrete stuck/slip flags changed only in event updates.
 *   indicator of a stuck element i:   nu_i S(|v|) - sgn(v) F_i     (> 0 while it holds; sgn(0) = 0)
 *   indicator of the slipping set:    dir v + PLANT_V_HYS           (> 0 while moving in dir)
 * With every element stuck there is no velocity indicator, so the ~54 Hz ringing of a stage at
 * rest causes no event. frictional_lag off: a slipping element's force is nu_i s(v) at once.
 * S is the level at the position, p(x) S(|v|) (friction_position.c; p = 1 without position_friction). */
#include <math.h>

#include "plant.h"

int friction_sign(double v) { return (v > 0.0) - (v < 0.0); }

double friction_level(const plant_params_t *p, double v, int side) {
    double Fs = p->Fs[side], Fc = p->Fc[side];
    if (Fs == Fc) return Fs;
    return Fc + (Fs - Fc) * exp(-pow(fabs(v) / p->Vs, p->delta));
}

void gms_element_forces(const plant_params_t *p, const plant_disc_t *d, const double *y, plant_memo_t *memo,
                        double *Fe) {
    int j;
    double S = 0.0;
    if (d->dir != 0 && !p->lag) S = friction_level_memo(p, memo, y[PLANT_IV], y[PLANT_IX], d->dir < 0);
    for (j = 0; j < PLANT_NE_MAX; j++) {
        if (!p->active[j]) Fe[j] = 0.0;
        else if (d->stuck[j] || p->lag) Fe[j] = y[PLANT_IF + j];
        else Fe[j] = p->nu[j] * d->dir * S;
    }
}

void gms_derivatives(const plant_params_t *p, const plant_disc_t *d, const double *y, plant_memo_t *memo,
                     double *dF) {
    int j;
    double v = y[PLANT_IV], S = 1.0, rate = 0.0;
    if (d->dir != 0 && p->lag) {
        S = friction_level_memo(p, memo, v, y[PLANT_IX], d->dir < 0);
        rate = p->C / S;
    }
    for (j = 0; j < PLANT_NE_MAX; j++) {
        if (!p->active[j]) dF[j] = 0.0;
        else if (d->stuck[j]) dF[j] = p->k[j] * v;
        else if (p->lag) dF[j] = rate * (p->nu[j] * d->dir * S - y[PLANT_IF + j]);
        else dF[j] = 0.0;
    }
}

void gms_indicators(const plant_params_t *p, const plant_disc_t *d, const double *y, double *z) {
    int j, sg = friction_sign(y[PLANT_IV]);
    double S = -1.0;
    for (j = 0; j < PLANT_NE_MAX; j++) {
        if (!p->active[j] || !d->stuck[j]) { z[j] = 1.0; continue; }
        if (S < 0.0) S = friction_level_at(p, y[PLANT_IV], y[PLANT_IX], sg < 0);
        z[j] = p->nu[j] * S - sg * y[PLANT_IF + j];
    }
    z[PLANT_NE_MAX] = d->dir != 0 ? d->dir * y[PLANT_IV] + PLANT_V_HYS : 1.0;
}

void gms_init(const plant_params_t *p, plant_disc_t *d, const double *y) {
    int j;
    (void)y;
    for (j = 0; j < PLANT_NE_MAX; j++) d->stuck[j] = p->active[j];
    d->dir = 0;
}

int gms_update(const plant_params_t *p, plant_disc_t *d, double *y, plant_memo_t *memo, bool *y_changed) {
    int j, n = 0, sg;
    double v = y[PLANT_IV], S;
    if (d->dir != 0 && d->dir * v + PLANT_V_HYS <= 0.0) {
        /* the velocity crossed zero: every slipping element sticks */
        S = friction_level_memo(p, memo, v, y[PLANT_IX], d->dir < 0);
        for (j = 0; j < PLANT_NE_MAX; j++) {
            if (!p->active[j] || d->stuck[j]) continue;
            d->stuck[j] = true;
            d->n_stick++;
            n++;
            if (!p->lag) { y[PLANT_IF + j] = p->nu[j] * d->dir * S; *y_changed = true; }
        }
        d->dir = 0;
    }
    sg = friction_sign(v);
    if (sg == 0) return n;
    S = friction_level_memo(p, memo, v, y[PLANT_IX], sg < 0);
    for (j = 0; j < PLANT_NE_MAX; j++) {
        if (!p->active[j] || !d->stuck[j]) continue;
        if (p->nu[j] * S - sg * y[PLANT_IF + j] > 0.0) continue;
        if (d->dir != 0 && d->dir != sg) {
            /* cannot happen with consistent states; keep the invariant "one slip direction" */
            int q;
            for (q = 0; q < PLANT_NE_MAX; q++)
                if (p->active[q] && !d->stuck[q]) { d->stuck[q] = true; d->n_stick++; n++; }
        }
        d->stuck[j] = false;
        d->dir = sg;
        d->n_slip++;
        n++;
        if (!p->lag) { y[PLANT_IF + j] = p->nu[j] * sg * S; *y_changed = true; }
    }
    return n;
}

int gms_n_stuck(const plant_params_t *p, const plant_disc_t *d) {
    int j, n = 0;
    for (j = 0; j < PLANT_NE_MAX; j++) n += p->active[j] && d->stuck[j];
    return n;
}

void gms_retune(const plant_params_t *old, const plant_params_t *p, plant_disc_t *d, double *y) {
    int j;
    for (j = 0; j < PLANT_NE_MAX; j++) {
        if (p->active[j] == old->active[j]) continue;
        y[PLANT_IF + j] = 0.0;
        d->stuck[j] = p->active[j];
    }
}

/* ---- GMS along a sampled motion (feedforward; Python friction_gms.gms_force, same pieces) */
void gms_track_init(gms_track_t *g) {
    int j;
    for (j = 0; j < PLANT_NE_MAX; j++) { g->F[j] = 0.0; g->stuck[j] = true; }
    g->x = g->v = g->last_dir = 0.0;
    g->started = false;
}

static double sgn_d(double v) { return (double)((v > 0.0) - (v < 0.0)); }

/* one constant-direction piece: displacement dx, direction s, level S, decay factor dec */
static void gms_track_piece(const plant_params_t *p, gms_track_t *g, double dx, double s, double S,
                            double dec) {
    int j;
    bool rev = s != 0.0 && g->last_dir != 0.0 && g->last_dir == -s;
    if (s != 0.0) g->last_dir = s;
    for (j = 0; j < PLANT_NE_MAX; j++) {
        double lim, t;
        if (!p->active[j]) continue;
        if (rev) g->stuck[j] = true;
        if (s == 0.0) continue;
        lim = p->nu[j] * S;
        if (g->stuck[j]) {
            g->F[j] += p->k[j] * dx;
            if (s * g->F[j] >= lim) { g->F[j] = s * lim; g->stuck[j] = false; }
        } else {
            t = s * lim;
            g->F[j] = t + (g->F[j] - t) * dec;
        }
    }
}

/* a piece at mean speed `speed` and mid position xm (the level p(xm) S(speed) held over it) */
static void gms_track_part(const plant_params_t *p, gms_track_t *g, double dx, double s, double speed,
                           double xm, double tau) {
    double S = friction_level_at(p, speed, xm, s < 0.0);
    double dec = p->lag ? exp(-p->C * tau / S) : 0.0;
    gms_track_piece(p, g, dx, s, S, dec);
}

double gms_track_step(const plant_params_t *p, gms_track_t *g, double x, double v, double dt) {
    double F = 0.0, rest = 0.0;
    int j, first = 1;
    if (g->started) {
        double v0 = g->v, dx = x - g->x;
        if (v0 * v < 0.0) {
            double th = v0 / (v0 - v), dxa = v0 * th * dt / 2;
            gms_track_part(p, g, dxa, sgn_d(v0), 0.5 * fabs(v0), g->x + 0.5 * dxa, th * dt);
            gms_track_part(p, g, dx - dxa, sgn_d(v), 0.5 * fabs(v), g->x + dxa + 0.5 * (dx - dxa),
                           (1 - th) * dt);
        } else {
            double s = sgn_d(v0 + v);
            if (s == 0.0) s = sgn_d(dx);
            gms_track_part(p, g, dx, s, 0.5 * (fabs(v0) + fabs(v)), g->x + 0.5 * dx, dt);
        }
    }
    g->started = true;
    g->x = x;
    g->v = v;
    /* numpy's row sum: the first element, then the rest */
    for (j = 0; j < PLANT_NE_MAX; j++) {
        if (!p->active[j]) continue;
        if (first) { F = g->F[j]; first = 0; } else rest += g->F[j];
    }
    return F + rest + p->sigma2[v < 0.0] * v;
}
