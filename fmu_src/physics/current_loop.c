/* Effect current_dynamics, Eq. 2: the sampled current loop as its exact difference equation
 *   i[k] = sum_{j=1..5} a_j i[k-j] + sum_{j=0..5} b_j u[k-j],
 * i held between samples (zero-order hold). Off (ideal): i = G(1) u. Its rules: no pole at z = 1
 * and every pole inside the unit circle (checked whether the effect is on or off). */
#include <math.h>
#include <stdio.h>

#include "effect.h"

void current_loop_init(const plant_params_t *p, plant_disc_t *d, double u0) {
    /* history at the steady state of u0: the drive has been holding u0 */
    double i0 = p->G1 * u0;
    int j;
    for (j = 0; j < PLANT_NA_MAX; j++) d->ih[j] = i0;
    for (j = 0; j < PLANT_NB_MAX; j++) d->uh[j] = u0;
    d->i = i0;
    d->k = 0;
}

void current_loop_sample(const plant_params_t *p, plant_disc_t *d, double u) {
    double i = p->cb[0] * u;
    int j;
    for (j = 0; j < PLANT_NA_MAX; j++) i += p->ca[j] * d->ih[j];
    for (j = 1; j < PLANT_NB_MAX; j++) i += p->cb[j] * d->uh[j - 1];
    for (j = PLANT_NA_MAX - 1; j > 0; j--) d->ih[j] = d->ih[j - 1];
    d->ih[0] = i;
    for (j = PLANT_NB_MAX - 1; j > 0; j--) d->uh[j] = d->uh[j - 1];
    d->uh[0] = u;
    d->i = i;
    d->k++;
}

double current_loop_output(const plant_params_t *p, const plant_disc_t *d, double u) {
    return p->current_dynamics ? d->i : p->G1 * u;
}

/* ---- effect current_dynamics: G(z)'s coefficients and its DC gain G(1) (off: i = G(1) u) */

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
 * the unit circle (an unstable loop's current grows without bound, whether or not the effect is
 * on: its DC gain G(1) is then meaningless too) */
static bool compile_current_dynamics(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    double sa = 0.0, sb = 0.0, k;
    int j, n = 0, bad;
    p->current_dynamics = val[VR_effects_current_dynamics] != 0.0;
    for (j = 1; j <= PLANT_NA_MAX; j++) {
        p->ca[j - 1] = val[VRA_current_a[j]];
        sa += p->ca[j - 1];
        if (p->ca[j - 1] != 0.0) n = j;
    }
    for (j = 0; j < PLANT_NB_MAX; j++) { p->cb[j] = val[VRA_current_b[j]]; sb += p->cb[j]; }
    if (fabs(1.0 - sa) < 1e-9) {
        snprintf(msg, msglen, "current.a[1..5] sum to %.17g: the current loop has a pole at z = 1 and no finite "
                 "DC gain; allowed: sum(current.a) != 1", sa);
        return false;
    }
    if ((bad = current_loop_unstable(p->ca, n, &k)) != 0) {
        snprintf(msg, msglen, "current.a[1..5] = %.9g, %.9g, %.9g, %.9g, %.9g: the current loop is unstable (a "
                 "root of its denominator z^n - a_1 z^(n-1) - ... - a_n, n = %d, lies on or outside the unit "
                 "circle: Schur-Cohn reflection coefficient k_%d = %.9g); allowed: every root inside |z| < 1 "
                 "(all |k_j| < 1)", p->ca[0], p->ca[1], p->ca[2], p->ca[3], p->ca[4], n, bad, k);
        return false;
    }
    p->G1 = sb / (1.0 - sa);
    return true;
}

const effect_t effect_current_dynamics = {
    "current_dynamics", VR_effects_current_dynamics, NULL, compile_current_dynamics, NULL, NULL, NULL, NULL};
