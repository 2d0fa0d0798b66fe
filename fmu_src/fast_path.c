/* The per-sample scheme's guard and dispatch (fast_path.h): where it applies, and which update
 * takes an interval of constant current. */
#include <math.h>

#include "fast_path.h"

int fast_path_ok(const plant_params_t *p) {
    double K = 0.0, lim = FAST_MAX_RATE_TS / p->Ts;
    int j;
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
              const fast_tol_t *tol, int fresh, double *y, long *n_rhs, fast_carry_t *carry,
              plant_memo_t *memo) {
    if (!(h > 0.0 && h <= p->Ts * (1.0 + 1e-9))) return 0;
    if (!fresh && !fast_indicators_positive(p, d, y, in)) return 0;
    if (!p->prerolling && d->st_stuck)
        return y[PLANT_IV] == 0.0;   /* Karnopp-stuck: v = 0 and a = 0 exactly, the indicator constant */
    if (p->prerolling && d->dir == 0 && stick_zoh_step(p, d, in, h, tol, y)) return 1;
    return fixed_step(p, d, in, h, tol, y, n_rhs, carry, memo);
}
