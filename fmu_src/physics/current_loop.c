/* Eq. 2: the sampled current loop as its exact difference equation
 *   i[k] = sum_{j=1..5} a_j i[k-j] + sum_{j=0..5} b_j u[k-j],
 * i held between samples (zero-order hold). Off (ideal): i = G(1) u. */
#include "plant.h"

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
