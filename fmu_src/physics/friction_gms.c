/* Generalized Maxwell-Slip friction (Eqs. 8-11), as docs/model.md states it:
 *   stuck:   dF_i/dt = k_i v            until sgn(F_i) = sgn(v) and |F_i| >= nu_i S(|v|)
 *   slipping dF_i/dt = (C/S)(nu_i s(v) - F_i)   until v crosses zero (then every slipping element sticks)
 * Switching is hybrid: discrete stuck/slip flags changed only in event updates.
 *   indicator of a stuck element i:   nu_i S(|v|) - sgn(v) F_i     (> 0 while it holds; sgn(0) = 0)
 *   indicator of the slipping set:    dir v + PLANT_V_HYS           (> 0 while moving in dir)
 * With every element stuck there is no velocity indicator, so the ~54 Hz ringing of a stage at
 * rest causes no event. frictional_lag off: a slipping element's force is nu_i s(v) at once.
 * S is the level at the position, p(x) S(|v|) (friction_position.c; p = 1 without position_friction),
 * S(|v|) the Stribeck level of friction_levels.c.
 * Its two effects (the entries at the end): prerolling (the elements: off, the memoryless static
 * model of friction_static.c) and frictional_lag (the finite attraction C of Eq. 11, a term of the
 * slipping element's law: off, its force is nu_i s(v) at once). */
#include <math.h>
#include <stdio.h>

#include "effect.h"

#define SUM_NU_TOL 1e-3   /* |sum(nu_i) - 1| allowed; Eq. 12 needs sum(nu) = 1 */

int friction_sign(double v) { return (v > 0.0) - (v < 0.0); }

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

/* ---- effect prerolling: the elements N, nu_i, k_i (Eqs. 9, 12) */
static bool range_prerolling(unsigned vr, param_range_t *r) {
    static const param_range_t POS = {0.0, 1, HUGE_VAL, 1}, UNIT = {0.0, 0, 1.0, 0},
                               NEL = {1.0, 0, (double)PLANT_NE_MAX, 0};
    int j;
    if (vr == VR_friction_N) { *r = NEL; return true; }
    for (j = 1; j <= PLANT_NE_MAX; j++) {
        if (vr == VRA_friction_nu[j]) { *r = UNIT; return true; }
        if (vr == VRA_friction_k[j]) { *r = POS; return true; }
    }
    return false;
}

static bool compile_prerolling(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    int j;
    (void)msg; (void)msglen;
    p->prerolling = val[VR_effects_prerolling] != 0.0;
    p->N = (int)val[VR_friction_N];
    for (j = 0; j < PLANT_NE_MAX; j++) {
        p->nu[j] = val[VRA_friction_nu[j + 1]];
        p->k[j] = val[VRA_friction_k[j + 1]];
        p->active[j] = p->prerolling && j < p->N && p->nu[j] > 0.0;
    }
    return true;
}

/* N an integer (on or off); sum(nu) = 1 over the elements in use when on */
static bool check_prerolling(const double *val, const plant_params_t *p, char *msg, size_t msglen) {
    double sum_nu = 0.0;
    int j;
    if ((double)p->N != val[VR_friction_N]) {
        snprintf(msg, msglen, "friction.N = %.17g is not an integer: allowed 1..%d", val[VR_friction_N], PLANT_NE_MAX);
        return false;
    }
    for (j = 0; j < p->N; j++) sum_nu += p->nu[j];
    if (p->prerolling && fabs(sum_nu - 1.0) > SUM_NU_TOL) {
        snprintf(msg, msglen, "friction.nu[1..%d] sum to %.17g: allowed 1 +- %g (Eq. 12 needs sum(nu) = 1; "
                 "set friction.nu[%d] = 1 - sum of the others)", p->N, sum_nu, SUM_NU_TOL, p->N);
        return false;
    }
    return true;
}

/* the frequency sqrt(k_j / m) of a stuck element in use */
static bool rate_prerolling(const double *val, const plant_params_t *p, effect_rate_t *best, char *buf, size_t n) {
    int j;
    (void)val; (void)buf; (void)n;
    for (j = 0; j < PLANT_NE_MAX; j++)
        if (p->active[j]) effect_rate_candidate(best, VRA_friction_k[j + 1], sqrt(p->k[j] / p->m));
    return false;
}

/* the force of an element not in use is 0 */
static void init_prerolling(const plant_params_t *p, double *y) {
    int j;
    for (j = 0; j < PLANT_NE_MAX; j++) if (!p->active[j]) y[PLANT_IF + j] = 0.0;
}

const effect_t effect_prerolling = {
    "prerolling", VR_effects_prerolling, range_prerolling, compile_prerolling, check_prerolling, rate_prerolling,
    init_prerolling, gms_retune};

/* ---- effect frictional_lag: the attraction C of Eq. 11 */
static bool range_frictional_lag(unsigned vr, param_range_t *r) {
    if (vr != VR_friction_C) return false;
    r->lo = 0.0; r->lo_open = 1; r->hi = HUGE_VAL; r->hi_open = 1;
    return true;
}

static bool compile_frictional_lag(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    (void)msg; (void)msglen;
    p->lag = val[VR_effects_frictional_lag] != 0.0;
    p->C = val[VR_friction_C];
    return true;
}

/* the lag rate C / S(|v|) at the lowest level S_min the elements can slip at (the Coulomb level of
 * the lower side, scaled by the least p(x) = 1 + min c_j of the B-spline's hull); no bound when S_min
 * is 0 (or the quotient overflows) */
static bool rate_frictional_lag(const double *val, const plant_params_t *p, effect_rate_t *best, char *buf, size_t n) {
    double S_min = p->Fc[0] < p->Fc[1] ? p->Fc[0] : p->Fc[1];
    char vb[40], mb[40];
    int j;
    (void)val;
    if (!(p->prerolling && p->lag && p->C > 0.0)) return false;
    if (p->posfric) {
        double c_min = 0.0;
        for (j = 0; j < p->pf_n; j++) if (p->pf_c[j] < c_min) c_min = p->pf_c[j];
        S_min *= 1.0 + c_min;
    }
    if (!(p->C / S_min < HUGE_VAL)) {
        snprintf(buf, n, "%s = %s N (with effects.frictional_lag the lag rate friction.C / S(|v|) has no bound: "
                 "the level S(|v|) falls to it as |v| grows; friction.C = %s N/s)",
                 p->Fc[0] <= p->Fc[1] ? "friction.F_c" : "friction.F_c + asymmetry.dF",
                 effect_num(vb, sizeof vb, S_min), effect_num(mb, sizeof mb, p->C));
        return true;
    }
    effect_rate_candidate(best, VR_friction_C, p->C / S_min);
    return false;
}

const effect_t effect_frictional_lag = {
    "frictional_lag", VR_effects_frictional_lag, range_frictional_lag, compile_frictional_lag, NULL,
    rate_frictional_lag, NULL, NULL};
