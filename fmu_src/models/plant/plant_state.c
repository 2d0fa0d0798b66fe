/* The plant's discrete state as a flat array of numbers (for saved FMU states) and the check of
 * every field when one is read back: flags 0/1, directions -1/0/+1, finite currents, counts >= 0
 * and exact. Memory safety of a loaded state rests on this: no field is an index or a length. */
#include <math.h>
#include <stdio.h>

#include "plant.h"

/* layout: i, ih[NA], uh[NB], k, stuck[NE], dir, st_stuck, st_dir, n_stick, n_slip, n_time, n_state */
void plant_disc_pack(const plant_disc_t *d, double *w) {
    int j, n = 0;
    w[n++] = d->i;
    for (j = 0; j < PLANT_NA_MAX; j++) w[n++] = d->ih[j];
    for (j = 0; j < PLANT_NB_MAX; j++) w[n++] = d->uh[j];
    w[n++] = (double)d->k;
    for (j = 0; j < PLANT_NE_MAX; j++) w[n++] = d->stuck[j] ? 1.0 : 0.0;
    w[n++] = d->dir;
    w[n++] = d->st_stuck ? 1.0 : 0.0;
    w[n++] = d->st_dir;
    w[n++] = (double)d->n_stick;
    w[n++] = (double)d->n_slip;
    w[n++] = (double)d->n_time_events;
    w[n++] = (double)d->n_state_events;
}

#define MAX_COUNT 9007199254740992.0   /* 2^53: every count below is exact in a double */

static bool finite_ok(double v, const char *what, int j, char *msg, size_t msglen) {
    if (isfinite(v)) return true;
    snprintf(msg, msglen, "discrete state %s[%d] = %g: allowed finite values", what, j, v);
    return false;
}

static bool one_of(double v, double lo, const char *what, int j, char *msg, size_t msglen) {
    if (v == lo || v == lo + 1.0 || (lo < 0.0 && v == 1.0)) return true;
    snprintf(msg, msglen, "discrete state %s[%d] = %g: allowed %s", what, j, v, lo < 0.0 ? "-1, 0 or 1" : "0 or 1");
    return false;
}

static bool count_ok(double v, const char *what, char *msg, size_t msglen) {
    if (v >= 0.0 && v <= MAX_COUNT && v == floor(v)) return true;
    snprintf(msg, msglen, "discrete state %s = %g: allowed an integer in [0, 2^53]", what, v);
    return false;
}

bool plant_disc_unpack(const double *w, plant_disc_t *d, char *msg, size_t msglen) {
    static const char *const COUNTS[] = {"n_stick", "n_slip", "n_time_events", "n_state_events"};
    long long *cnt[4];
    int j, n = 0;
    cnt[0] = &d->n_stick; cnt[1] = &d->n_slip; cnt[2] = &d->n_time_events; cnt[3] = &d->n_state_events;
    if (!finite_ok(w[n], "i", 0, msg, msglen)) return false;
    d->i = w[n++];
    for (j = 0; j < PLANT_NA_MAX; j++, n++) {
        if (!finite_ok(w[n], "ih", j, msg, msglen)) return false;
        d->ih[j] = w[n];
    }
    for (j = 0; j < PLANT_NB_MAX; j++, n++) {
        if (!finite_ok(w[n], "uh", j, msg, msglen)) return false;
        d->uh[j] = w[n];
    }
    if (!count_ok(w[n], "k", msg, msglen)) return false;
    d->k = (long long)w[n++];
    for (j = 0; j < PLANT_NE_MAX; j++, n++) {
        if (!one_of(w[n], 0.0, "stuck", j, msg, msglen)) return false;
        d->stuck[j] = w[n] != 0.0;
    }
    if (!one_of(w[n], -1.0, "dir", 0, msg, msglen)) return false;
    d->dir = (int)w[n++];
    if (!one_of(w[n], 0.0, "st_stuck", 0, msg, msglen)) return false;
    d->st_stuck = w[n++] != 0.0;
    if (!one_of(w[n], -1.0, "st_dir", 0, msg, msglen)) return false;
    d->st_dir = (int)w[n++];
    for (j = 0; j < 4; j++, n++) {
        if (!count_ok(w[n], COUNTS[j], msg, msglen)) return false;
        *cnt[j] = (long long)w[n];
    }
    return true;
}
