/* The per-sample scheme's guard and dispatch (fast_path.h): where it applies, and which update
 * takes an interval of constant current. */
#include <math.h>
#include <stdio.h>

#include "fast_path.h"

int fast_path_ok(const plant_params_t *p) {
    double K = 0.0, lim = FAST_MAX_RATE_TS / p->Ts;
    int j;
    /* the reduced system (x, v, summed slip force, C/S integral), its cheap Stribeck level and
     * the exact stuck update model neither the load on its spring (compliance: two more states,
     * up to 200 Hz) nor the friction profile p(x) (position_friction): the adaptive DP45 */
    if (p->compliance || p->posfric) return 0;
    if (p->sigma2[0] / p->m > lim || p->sigma2[1] / p->m > lim) return 0;
    if (!p->prerolling) return 1;
    for (j = 0; j < PLANT_NE_MAX; j++)
        if (p->active[j]) K += p->k[j];
    if (!(K / p->m <= lim * lim)) return 0;
    if (p->lag) {
        double S_min = p->Fc[0];
        for (j = 0; j < 2; j++) {
            if (p->Fc[j] < S_min) S_min = p->Fc[j];
            if (p->Fs[j] < S_min) S_min = p->Fs[j];
        }
        if (!(S_min > 0.0) || !(p->C / S_min <= lim)) return 0;
    }
    return 1;
}

int fast_indicators_positive(const plant_params_t *p, const plant_disc_t *d, const double *y,
                             const plant_in_t *in) {
    double z[PLANT_NZ];
    int j;
    plant_indicators(p, d, y, in, z);
    for (j = 0; j < PLANT_NZ; j++)
        if (!(z[j] > 0.0)) return 0;
    return 1;
}

int fast_step(const plant_params_t *p, const plant_disc_t *d, const plant_in_t *in, double h,
              const fast_tol_t *tol, int fresh, double *y, long long *n_rhs, fast_carry_t *carry,
              plant_memo_t *memo) {
    if (!(h > 0.0 && h <= p->Ts * (1.0 + 1e-9))) return 0;
    if (!fresh && !fast_indicators_positive(p, d, y, in)) return 0;
    if (!p->prerolling && d->st_stuck)
        return y[PLANT_IV] == 0.0;   /* Karnopp-stuck: v = 0 and a = 0 exactly, the indicator constant */
    if (p->prerolling && d->dir == 0 && stick_zoh_step(p, d, in, h, tol, y)) return 1;
    return fixed_step(p, d, in, h, tol, y, n_rhs, carry, memo);
}

/* layout: valid, age, rot_ok, w_ok, dir, st_dir, st_stuck, stuck[NE], y[NX], i, F_ext, Kf, k[4],
 * c1, s1, w1, E1 */
void fast_carry_pack(const fast_carry_t *cr, double *w) {
    int j, n = 0;
    w[n++] = cr->valid;
    w[n++] = cr->age;
    w[n++] = cr->rot_ok;
    w[n++] = cr->w_ok;
    w[n++] = cr->dir;
    w[n++] = cr->st_dir;
    w[n++] = cr->st_stuck;
    for (j = 0; j < PLANT_NE_MAX; j++) w[n++] = cr->stuck[j];
    for (j = 0; j < PLANT_NX; j++) w[n++] = cr->y[j];
    w[n++] = cr->i;
    w[n++] = cr->F_ext;
    w[n++] = cr->Kf;
    for (j = 0; j < 4; j++) w[n++] = cr->k[j];
    w[n++] = cr->c1;
    w[n++] = cr->s1;
    w[n++] = cr->w1;
    w[n++] = cr->E1;
}

bool fast_carry_unpack(const double *w, fast_carry_t *cr, char *msg, size_t msglen) {
    static const char *const NAMES[7] = {"valid", "age", "rot_ok", "w_ok", "dir", "st_dir", "st_stuck"};
    int j;
    for (j = 0; j < 7 + PLANT_NE_MAX; j++) {
        double v = w[j], lo = (j == 4 || j == 5) ? -1.0 : 0.0, hi = j == 1 ? FAST_REANCHOR : 1.0;
        if (!(v >= lo && v <= hi && v == floor(v))) {
            snprintf(msg, msglen, "per-sample scheme carry %s = %g: allowed an integer in [%g, %g]",
                     j < 7 ? NAMES[j] : "stuck", v, lo, hi);
            return false;
        }
    }
    for (j = 7 + PLANT_NE_MAX; j < FAST_CARRY_ND; j++) {
        if (!isfinite(w[j])) {
            snprintf(msg, msglen, "per-sample scheme carry value %d = %g: allowed finite values", j, w[j]);
            return false;
        }
    }
    cr->valid = (int)w[0];
    cr->age = (int)w[1];
    cr->rot_ok = (int)w[2];
    cr->w_ok = (int)w[3];
    cr->dir = (int)w[4];
    cr->st_dir = (int)w[5];
    cr->st_stuck = w[6] != 0.0;
    w += 7;
    for (j = 0; j < PLANT_NE_MAX; j++) cr->stuck[j] = w[j] != 0.0;
    w += PLANT_NE_MAX;
    for (j = 0; j < PLANT_NX; j++) cr->y[j] = w[j];
    w += PLANT_NX;
    cr->i = w[0];
    cr->F_ext = w[1];
    cr->Kf = w[2];
    for (j = 0; j < 4; j++) cr->k[j] = w[3 + j];
    cr->c1 = w[7];
    cr->s1 = w[8];
    cr->w1 = w[9];
    cr->E1 = w[10];
    return true;
}
