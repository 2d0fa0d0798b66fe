/* The per-sample scheme of co-simulation (README "Co-simulation: the per-sample fast path").
 * Between two current-loop samples the current i and the inputs are constant, so one interval
 * (at most Ts long) is taken in one go:
 *   stick_zoh.c    every GMS element stuck: the exact update of the (locally linear) plant;
 *   solver_fixed.c otherwise: one embedded Runge-Kutta 4(3) step of the reduced system
 *                  (x, v, the summed force of the slipping elements, the integral of C/S);
 *   Karnopp-stuck static friction (prerolling off): nothing moves (v = 0, a = 0 exactly);
 * each with the DP45's error test. A step the test rejects, or at whose end an event indicator
 * has changed sign, is not taken: the caller falls back to the adaptive, event-locating DP45
 * over that interval (models/plant/plant_step.c). Where the scheme applies at all is fast_path_ok(). Pure
 * functions of the plant's data: no FMI, no allocation. */
#ifndef FAST_PATH_H
#define FAST_PATH_H

#include "plant.h"

/* The error weights of the adaptive solver: state j is weighted by atol[j] + rtol max(|y0|, |y1|),
 * the RMS is taken over n_norm states (PLANT_NX: the same test as the DP45's). inv_atol[j] =
 * 1 / atol[j] (rounded): the fixed step's cheap bound of that norm (solver_fixed.c). */
typedef struct {
    double rtol;
    const double *atol;       /* PLANT_NX values */
    const double *inv_atol;   /* PLANT_NX values */
    int n_norm;
} fast_tol_t;

/* stick_zoh.c: every active GMS element stuck (prerolling on, d->dir == 0). Advances y by h
 * exactly for the plant linearised in x at the start of the interval (the maps' curvature is
 * the only approximation: bounded, and the update is refused when the bound exceeds a tenth
 * of the tolerance). Returns 1 (y advanced), 0 (not applicable here or an indicator would
 * cross: y untouched). */
int stick_zoh_step(const plant_params_t *p, const plant_disc_t *d, const plant_in_t *in, double h,
                   const fast_tol_t *tol, double *y);

/* The derivative at the end of the last accepted fixed step, reused as the next step's first
 * stage when it starts from that very state (FSAL across a sample; the owner sets valid = 0
 * whenever the parameters are compiled again). */
typedef struct {
    int valid;
    double y[PLANT_NX];
    bool stuck[PLANT_NE_MAX], st_stuck;
    int dir, st_dir;
    double i, F_ext, Kf;     /* the current and force it was computed with, K_f there */
    double k[4];             /* d/dt of x, v, F_sl, L */
    /* the bases of the cheap maps and level at the end point (from the last stage) */
    int age, rot_ok, w_ok;
    double c1, s1, w1, E1;
} fast_carry_t;

/* steps between exact libm evaluations of the carried bases */
#define FAST_REANCHOR 64
/* fast_path.c: the carry as FAST_CARRY_ND numbers (saved FMU states: a restored state continues
 * bit-identically); unpack checks every field and names the first bad one in msg */
#define FAST_CARRY_ND (7 + PLANT_NE_MAX + PLANT_NX + 3 + 4 + 4)
void fast_carry_pack(const fast_carry_t *cr, double *w);
bool fast_carry_unpack(const double *w, fast_carry_t *cr, char *msg, size_t msglen);

/* solver_fixed.c: one RK4(3) step of h with the discrete state d fixed. Returns 1 (accepted:
 * error test passed, no indicator crossed, y advanced), 0 (y untouched). *n_rhs counts the
 * right-hand-side evaluations; carry (may be NULL) is used and renewed; memo (may be NULL)
 * receives the maps at the end point. */
int fixed_step(const plant_params_t *p, const plant_disc_t *d, const plant_in_t *in, double h,
               const fast_tol_t *tol, double *y, long long *n_rhs, fast_carry_t *carry, plant_memo_t *memo);

/* fast_path.c ---------------------------------------------------------------------------- */
/* Largest rate * Ts of the plant the scheme takes on (the stiffness guard): the classical RK4's
 * stability region reaches 2.8 on the negative real axis and 2.8 on the imaginary one; a factor
 * of 2.8 below that keeps the embedded error estimate, not stability, in charge. */
#define FAST_MAX_RATE_TS 1.0

/* The guard: 1 where the scheme applies (README "Co-simulation: the per-sample scheme"), 0 where
 * fmi2DoStep must use the adaptive DP45 throughout: a rate of the plant beyond
 * FAST_MAX_RATE_TS / Ts (the slip relaxation C / S, the frequency sqrt(sum k_j / m) of the stuck
 * elements, sigma2 / m). The one place to add an effect the reduced system (solver_fixed.c,
 * stick_zoh.c) does not model: return 0 when it is on. */
int fast_path_ok(const plant_params_t *p);

/* every event indicator at (d, y, in) strictly positive (the state an event update leaves) */
int fast_indicators_positive(const plant_params_t *p, const plant_disc_t *d, const double *y,
                             const plant_in_t *in);

/* One interval of h <= Ts with constant current and inputs, by the update the discrete state
 * calls for (Karnopp-stuck, stick_zoh_step, else fixed_step). fresh: an event update has just
 * been made (otherwise the indicators are checked to be positive first). Returns 1 (y advanced
 * to the interval's end, *n_rhs counted), 0 (y untouched: the adaptive solver takes it). */
int fast_step(const plant_params_t *p, const plant_disc_t *d, const plant_in_t *in, double h,
              const fast_tol_t *tol, int fresh, double *y, long long *n_rhs, fast_carry_t *carry,
              plant_memo_t *memo);

#endif
