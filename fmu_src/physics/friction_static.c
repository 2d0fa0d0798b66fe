/* The memoryless alternative (prerolling off): Eq. 12, s(v) + sigma2 v, with Karnopp stiction
 * at v = 0 handled exactly by events:
 *   stuck  (v = 0 held, a = 0): friction balances the applied force F_app while
 *          |F_app| < F_s (side of F_app); indicator F_s - |F_app|;
 *   (levels at the position: p(x) S(|v|) and p(x) F_s, friction_position.c)
 *   sliding in dir: friction dir S(|v|) + sigma2 v; indicator dir v + PLANT_V_HYS;
 *          at the crossing the stage sticks (v := 0) unless |F_app| >= F_s, in which case it
 *          reverses at once (v := 0, dir := sgn(F_app)). */
#include <math.h>

#include "plant.h"

static int side_of(double f) { return f < 0.0; }

double static_friction(const plant_params_t *p, const plant_disc_t *d, double x, double v, double F_app) {
    int side;
    if (d->st_stuck) return F_app;
    side = d->st_dir < 0;
    return d->st_dir * friction_level_at(p, v, x, side) + p->sigma2[v < 0.0] * v;
}

double static_indicator(const plant_params_t *p, const plant_disc_t *d, double x, double v, double F_app) {
    if (d->st_stuck) return friction_break_away(p, x, side_of(F_app)) - fabs(F_app);
    return d->st_dir * v + PLANT_V_HYS;
}

void static_init(const plant_params_t *p, plant_disc_t *d, double *y, double F_app) {
    double v = y[PLANT_IV];
    if (v == 0.0 && fabs(F_app) < friction_break_away(p, y[PLANT_IX], side_of(F_app))) {
        d->st_stuck = true;
        d->st_dir = 0;
    } else {
        d->st_stuck = false;
        d->st_dir = v != 0.0 ? friction_sign(v) : friction_sign(F_app);
    }
}

int static_update(const plant_params_t *p, plant_disc_t *d, double *y, double F_app, bool *y_changed) {
    if (d->st_stuck) {
        if (friction_break_away(p, y[PLANT_IX], side_of(F_app)) - fabs(F_app) > 0.0) return 0;
        d->st_stuck = false;
        d->st_dir = friction_sign(F_app);
        d->n_slip++;
        return 1;
    }
    if (d->st_dir * y[PLANT_IV] + PLANT_V_HYS > 0.0) return 0;
    y[PLANT_IV] = 0.0;
    *y_changed = true;
    if (fabs(F_app) < friction_break_away(p, y[PLANT_IX], side_of(F_app))) {
        d->st_stuck = true;
        d->st_dir = 0;
        d->n_stick++;
    } else {
        d->st_dir = friction_sign(F_app);
    }
    return 1;
}
