/* Dormand-Prince 5(4) explicit Runge-Kutta integrator with error control, FSAL,
 * Hairer's 4th-order continuous extension (dense output) and event location.
 *
 * The solver knows nothing of FMI or of the physics: the caller supplies the
 * right-hand side f(t, y) and the event indicators g(t, y) as callbacks, plus an
 * opaque context pointer handed back to both.
 *
 * No global mutable state, no allocation: a dp45_t is embedded in the caller's
 * instance (sizeof(dp45_t) < 4 KiB). Instances are independent, so many can run
 * in parallel threads. The struct holds no pointers into itself, so it may be
 * copied with memcpy (e.g. for fmi2GetFMUstate / fmi2SetFMUstate).
 *
 * Contract with the caller:
 *  - Between dp45_advance calls the solver assumes that t, y and the right-hand
 *    side are unchanged. If the caller changes y (event update, state reset) or
 *    the indicator functions, it calls dp45_restart(). If only the right-hand side
 *    changed (e.g. piecewise-constant inputs were updated at a communication
 *    point) it may call the cheaper dp45_drop_derivative(), which keeps the
 *    indicator memory. A change of *t between calls is detected and acts as a
 *    restart.
 *  - Event semantics: indicator j "changes sign" over a step when
 *    g_prev > 0 && g_new <= 0, or g_prev < 0 && g_new >= 0, checked at the end
 *    of every accepted step (two crossings within one step go unseen: bound the
 *    step with h_max if that matters). An indicator exactly 0 at the start of a
 *    step is never reported there; if it is nonzero at the step's end, the sign it
 *    takes just after the start (dense output at t + root_tol * max(1, |t|)) is
 *    its reference, so a later crossing in the same step is still found.
 *  - Tolerances: rtol >= 0 and every atol_j > 0, else dp45_advance fails.
 */
#ifndef FEEDDRIVE_SOLVER_DP45_H
#define FEEDDRIVE_SOLVER_DP45_H

#define DP45_MAX_N 16 /* states */
#define DP45_MAX_G 16 /* event indicators */

#define DP45_DEFAULT_MAX_STEPS 100000L /* step attempts per dp45_advance call */
#define DP45_DEFAULT_ROOT_TOL 1e-12    /* root bracket width / max(1, |t|) */

typedef void (*dp45_rhs_fn)(void *ctx, double t, const double *y, double *dydt);
typedef void (*dp45_ind_fn)(void *ctx, double t, const double *y, double *g);

enum { DP45_REACHED = 0, DP45_ROOT = 1, DP45_BOUND = 2, DP45_ERROR = -1 };

typedef struct {
    /* ---- configuration (set by dp45_init, may be changed between calls) ---- */
    int n, ng;              /* number of states (1..DP45_MAX_N), indicators (0..DP45_MAX_G) */
    int n_norm;             /* the error norms are RMS over n_norm >= n states (dp45_init: n); the
                             * n_norm - n not integrated are constant and add zero error */
    double rtol;            /* relative tolerance */
    double atol[DP45_MAX_N];/* absolute tolerance per state */
    double h;               /* next step-size proposal (<= h_max); <= 0: estimate at next advance */
    double h_max;           /* largest step (up to rounding); +inf when unlimited */
    double h_min;           /* a rejected step shrinking below this (or below 16 ulp(t)) is an error */
    double root_tol;        /* events are located to root_tol * max(1, |t|) seconds */
    long long max_steps;         /* step attempts allowed per dp45_advance call */
    int bounded;            /* 1: y_lo/y_hi hold bounds of the states (dp45_init: 0) */
    double y_lo[DP45_MAX_N], y_hi[DP45_MAX_N]; /* an accepted step ending outside returns DP45_BOUND */

    /* ---- statistics (cumulative since dp45_init) ---- */
    long long n_steps;           /* accepted steps */
    long long n_rejected;        /* rejected steps (error test or non-finite values) */
    long long n_rhs;             /* right-hand-side evaluations */
    long long n_ind;             /* indicator-function evaluations */
    long long n_roots;           /* DP45_ROOT returns */

    /* ---- last accepted step, for dp45_dense ---- */
    double t_old, t_new;    /* step interval */
    double h_last;          /* step size used (t_new - t_old up to rounding) */
    int dense_ok;           /* 1 while the data of the last accepted step are intact */

    /* ---- internal ---- */
    int fsal_ok;            /* k[i_k1] holds f(t_cur, y) */
    int g_ok;               /* g_prev holds the indicators at t_cur */
    int i_k1;               /* slot (0 or 6) of the current k1; the other one takes k7 */
    int dense_k1;           /* slot of k1 of the last accepted step */
    int reject_prev;        /* previous attempt was rejected: no step growth */
    double t_cur;           /* time of the carried-over derivative and indicators */
    double log2_facold;     /* log2 of the previous accepted error (PI controller) */
    double k[7][DP45_MAX_N];/* stage derivatives; slots 0 and 6 alternate as k1/k7 */
    double y_old[DP45_MAX_N];   /* state at t_old */
    double y_new[DP45_MAX_N];   /* state at t_new (5th-order solution) */
    double y_stage[DP45_MAX_N]; /* stage argument / dense-output scratch */
    double g_prev[DP45_MAX_G];  /* indicators at the current point */
    double g_lo[DP45_MAX_G], g_hi[DP45_MAX_G], g_mid[DP45_MAX_G]; /* root bracket */
} dp45_t;

/* Set up a solver for n states and ng indicators. atol may be NULL (then
 * atol_j = rtol). h_max <= 0 means unlimited. Resets the statistics. */
void dp45_init(dp45_t *s, int n, int ng, double rtol, const double *atol, double h_max);

/* After any discontinuity: drop the FSAL derivative and the indicator memory.
 * The step-size proposal s->h is kept (set s->h = 0 to force a new estimate). */
void dp45_restart(dp45_t *s);

/* The right-hand side changed but neither the state nor the indicators did
 * (e.g. new piecewise-constant inputs): drop only the FSAL derivative. */
void dp45_drop_derivative(dp45_t *s);

/* Advance from *t toward t_end (>= *t). y (s->n values) is updated in place.
 * Returns
 *   DP45_REACHED  with *t == t_end exactly;
 *   DP45_ROOT     when an indicator changed sign: *t and y are at the
 *                 post-crossing side of the earliest root, located on the dense
 *                 output to within root_tol * max(1, |t|); the indicator there has
 *                 already changed sign or is exactly 0. roots[j] (s->ng values,
 *                 may be NULL when ng == 0) is +1 (rising) / -1 (falling) for every
 *                 indicator that changed sign in the final bracket, 0 otherwise;
 *   DP45_BOUND    (s->bounded) when an accepted step ended with a state outside
 *                 [y_lo, y_hi] (or NaN): *t and y are at that step's end;
 *   DP45_ERROR    on invalid arguments, step-size underflow, non-finite
 *                 state/derivative, or more than max_steps attempts. *t and y are
 *                 then the last accepted point.
 * g may be NULL (no event location). */
int dp45_advance(dp45_t *s, void *ctx, dp45_rhs_fn f, dp45_ind_fn g, double *t, double t_end,
                 double *y, int *roots);

/* Dense output (4th order, continuous, exact at both ends) of the last accepted
 * step at t in [s->t_old, s->t_new]; after DP45_ROOT that step may extend past *t.
 * Returns 0, or -1 when no step data are available or t is outside the step. */
int dp45_dense(const dp45_t *s, double t, double *y_out);

#endif /* FEEDDRIVE_SOLVER_DP45_H */
