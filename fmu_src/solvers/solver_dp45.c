/* Dormand-Prince 5(4) with FSAL, PI step-size control, Hairer's continuous
 * extension and Illinois root finding on it. See solver_dp45.h for the contract.
 *
 * References: Hairer, Norsett, Wanner, "Solving ODEs I", Sec. II.4-II.6 and the
 * code DOPRI5 (coefficients, initial step, PI controller with beta = 0.04,
 * continuous extension); Hiebert & Shampine / SUNDIALS CVODE for the root
 * bracketing logic (Illinois-modified secant over several indicators). */
#include "solver_dp45.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

/* C99 has no _Static_assert: a negative array size fails the build. */
typedef char dp45_struct_fits_4kib[(sizeof(dp45_t) < 4096) ? 1 : -1];

/* Butcher tableau */
#define C2 (1.0 / 5.0)
#define C3 (3.0 / 10.0)
#define C4 (4.0 / 5.0)
#define C5 (8.0 / 9.0)
#define A21 (1.0 / 5.0)
#define A31 (3.0 / 40.0)
#define A32 (9.0 / 40.0)
#define A41 (44.0 / 45.0)
#define A42 (-56.0 / 15.0)
#define A43 (32.0 / 9.0)
#define A51 (19372.0 / 6561.0)
#define A52 (-25360.0 / 2187.0)
#define A53 (64448.0 / 6561.0)
#define A54 (-212.0 / 729.0)
#define A61 (9017.0 / 3168.0)
#define A62 (-355.0 / 33.0)
#define A63 (46732.0 / 5247.0)
#define A64 (49.0 / 176.0)
#define A65 (-5103.0 / 18656.0)
#define A71 (35.0 / 384.0)
#define A73 (500.0 / 1113.0)
#define A74 (125.0 / 192.0)
#define A75 (-2187.0 / 6784.0)
#define A76 (11.0 / 84.0)
/* error estimate: 5th-order minus embedded 4th-order weights */
#define E1 (71.0 / 57600.0)
#define E3 (-71.0 / 16695.0)
#define E4 (71.0 / 1920.0)
#define E5 (-17253.0 / 339200.0)
#define E6 (22.0 / 525.0)
#define E7 (-1.0 / 40.0)
/* continuous extension (DOPRI5's CONTD5) */
#define D1 (-12715105075.0 / 11282082432.0)
#define D3 (87487479700.0 / 32700410799.0)
#define D4 (-10690763975.0 / 1880347072.0)
#define D5 (701980252875.0 / 199316789632.0)
#define D6 (-1453857185.0 / 822651844.0)
#define D7 (69997945.0 / 29380423.0)

/* step-size controller (DOPRI5 defaults), evaluated in the log2 domain */
#define FAC_GROW_MAX 10.0                    /* h_new <= 10 h */
#define EXPO1 0.17                           /* 1/5 - 0.75 * beta */
#define BETA 0.04
#define L2_FACOLD_MIN (-13.287712379549449)  /* log2(1e-4) */
#define L2_SAFE (-0.15200309344504997)       /* log2(0.9) */
#define L2_GROW_MAX 3.321928094887362        /* log2(10) */
#define L2_SHRINK_MIN (-2.321928094887362)   /* log2(0.2): h_new >= 0.2 h */
/* Below this squared error norm the growth factor saturates at 10 whatever
 * log2_facold in [log2 1e-4, 0] is: 0.17 * ln(err) <= ln(0.09) + 0.04 * ln(1e-4). */
#define ERR2_SATURATED 6.0e-15

#define NONFINITE_SHRINK 0.2
#define ROOT_MAX_ITER 200

/* log2(x) for a positive normal x, absolute error < 1.1e-3 (monotone, exact at
 * powers of 2). The step-size controller needs a few digits, not libm's 16. */
static double log2_approx(double x)
{
    uint64_t b;
    double m, u;
    int e;
    memcpy(&b, &x, sizeof b);
    e = (int)(b >> 52) - 1023;
    b = (b & 0x000FFFFFFFFFFFFFull) | 0x3FF0000000000000ull;
    memcpy(&m, &b, sizeof m);
    u = m - 1.0;
    return (double)e + u + u * (1.0 - u) * (0.42086454 - 0.15638611 * u);
}

/* 2^y for |y| < 1000, relative error < 1.2e-4 (monotone, exact at integers). */
static double exp2_approx(double y)
{
    int i = (int)y;
    uint64_t b;
    double scale, f;
    if ((double)i > y) --i;
    f = y - (double)i;
    b = (uint64_t)(i + 1023) << 52;
    memcpy(&scale, &b, sizeof scale);
    return scale * (1.0 + f + f * (1.0 - f) * (-0.30449799 - 0.07822817 * f));
}

/* Element-wise copy. A plain loop: for the few doubles copied per step, gcc's
 * inline expansion of a variable-size memcpy (rep movsq) costs more than the step. */
static void copy_n(double *dst, const double *src, int n)
{
    int j;
    for (j = 0; j < n; ++j) dst[j] = src[j];
}

static int crossed(double g_ref, double g_now)
{
    return (g_ref > 0.0 && g_now <= 0.0) || (g_ref < 0.0 && g_now >= 0.0);
}

void dp45_init(dp45_t *s, int n, int ng, double rtol, const double *atol, double h_max)
{
    int j;
    memset(s, 0, sizeof *s);
    s->n = n;
    s->n_norm = n;
    s->ng = ng;
    s->rtol = rtol;
    for (j = 0; j < n && j < DP45_MAX_N; ++j) {
        s->atol[j] = (atol != NULL) ? atol[j] : rtol;
    }
    s->h = 0.0;
    s->h_max = (h_max > 0.0) ? h_max : HUGE_VAL;
    s->h_min = 0.0;
    s->root_tol = DP45_DEFAULT_ROOT_TOL;
    s->max_steps = DP45_DEFAULT_MAX_STEPS;
    s->log2_facold = L2_FACOLD_MIN;
    s->i_k1 = 0;
}

void dp45_restart(dp45_t *s)
{
    s->fsal_ok = 0;
    s->g_ok = 0;
    s->reject_prev = 0;
}

void dp45_drop_derivative(dp45_t *s)
{
    s->fsal_ok = 0;
}

/* Hairer's continuous extension of the last accepted step at theta in [0, 1]. */
static void dense_eval(const dp45_t *s, double theta, double *out)
{
    const int n = s->n;
    const double h = s->h_last;
    const double th1 = 1.0 - theta;
    const double *k1 = s->k[s->dense_k1], *k3 = s->k[2], *k4 = s->k[3], *k5 = s->k[4],
                 *k6 = s->k[5], *k7 = s->k[6 - s->dense_k1];
    int j;
    for (j = 0; j < n; ++j) {
        const double y0 = s->y_old[j];
        const double ydiff = s->y_new[j] - y0;
        const double bspl = h * k1[j] - ydiff;
        const double r4 = ydiff - h * k7[j] - bspl;
        const double r5 =
            h * (D1 * k1[j] + D3 * k3[j] + D4 * k4[j] + D5 * k5[j] + D6 * k6[j] + D7 * k7[j]);
        out[j] = y0 + theta * (ydiff + th1 * (bspl + theta * (r4 + th1 * r5)));
    }
}

int dp45_dense(const dp45_t *s, double t, double *y_out)
{
    if (!s->dense_ok || !(t >= s->t_old && t <= s->t_new) || !(s->h_last > 0.0)) {
        return -1;
    }
    if (t == s->t_new) {
        memcpy(y_out, s->y_new, (size_t)s->n * sizeof(double));
    } else {
        dense_eval(s, (t - s->t_old) / s->h_last, y_out);
    }
    return 0;
}

/* RMS of v_j / sk_j with sk_j = atol_j + rtol |y_j|. */
static double scaled_rms(const dp45_t *s, const double *y, const double *v)
{
    double sum = 0.0;
    int j;
    for (j = 0; j < s->n; ++j) {
        const double q = v[j] / (s->atol[j] + s->rtol * fabs(y[j]));
        sum += q * q;
    }
    return sqrt(sum / s->n_norm);
}

/* Initial step-size estimate (Hairer, HINIT in DOPRI5), capped by h_max and by
 * the distance to t_end. Uses k1 = f(t, y); costs one RHS evaluation. */
static double initial_step(dp45_t *s, void *ctx, dp45_rhs_fn f, double t, const double *y,
                           double rem)
{
    const int n = s->n;
    const double *k1 = s->k[s->i_k1];
    double *kt = s->k[1];
    double *d = s->y_stage;
    double d0 = scaled_rms(s, y, y);
    double d1 = scaled_rms(s, y, k1);
    double h, h1, d2, der12;
    int j;

    h = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    if (h > s->h_max) h = s->h_max;
    if (h > rem) h = rem;
    for (j = 0; j < n; ++j) d[j] = y[j] + h * k1[j];
    f(ctx, t + h, d, kt);
    s->n_rhs++;
    for (j = 0; j < n; ++j) d[j] = kt[j] - k1[j];
    d2 = scaled_rms(s, y, d) / h;
    der12 = (d2 > d1) ? d2 : d1;
    if (!(der12 == der12)) {
        h1 = 0.1 * h; /* non-finite probe: stay small, the error test sorts it out */
    } else if (der12 <= 1e-15) {
        h1 = (h * 1e-3 > 1e-6) ? h * 1e-3 : 1e-6;
    } else {
        h1 = pow(0.01 / der12, 0.2);
    }
    h = (100.0 * h < h1) ? 100.0 * h : h1;
    if (h > s->h_max) h = s->h_max;
    if (h > rem) h = rem;
    return h;
}

/* Index of the indicator whose secant root estimate in [t_lo, t_hi] is earliest
 * (largest |g_hi / (g_hi - g_lo)|) among those with a strict sign change, or -1
 * when every crossed indicator is exactly 0 at t_hi. */
static int earliest_secant(const dp45_t *s, const double *glo, const double *ghi)
{
    int j, imax = -1;
    double fmax = -1.0;
    for (j = 0; j < s->ng; ++j) {
        if (crossed(s->g_prev[j], ghi[j]) && ghi[j] != 0.0) {
            const double frac = fabs(ghi[j] / (ghi[j] - glo[j]));
            if (frac > fmax) {
                fmax = frac;
                imax = j;
            }
        }
    }
    return imax;
}

/* Indicators exactly 0 at the start of the last accepted step but not at its
 * end: take as reference the sign they have just after the start (dense output
 * at t_old + min(root_tol * max(1, |t|), h / 2)). A zero at the start is thus
 * never a crossing, but a later one in the same step is not missed (e.g. a ball
 * released at height 0 that rises and falls back within one step). */
static void probe_zero_start(dp45_t *s, void *ctx, dp45_ind_fn g)
{
    const double t0 = s->t_old;
    double dt = s->root_tol * ((fabs(t0) > 1.0) ? fabs(t0) : 1.0);
    int j;
    if (dt > 0.5 * s->h_last) dt = 0.5 * s->h_last;
    dense_eval(s, dt / s->h_last, s->y_stage);
    g(ctx, t0 + dt, s->y_stage, s->g_mid);
    s->n_ind++;
    for (j = 0; j < s->ng; ++j) {
        if (s->g_prev[j] == 0.0) s->g_prev[j] = s->g_mid[j];
    }
}

/* Locate the earliest sign change in (t0, t1] of the last accepted step, g_hi
 * holding the indicators at t1 and g_prev those at t0. Returns the post-crossing
 * bracket end; writes the state there to y_out, the indicators there to g_prev
 * (after filling roots[]). */
static double locate_root(dp45_t *s, void *ctx, dp45_ind_fn g, double t0, double t1,
                          double *y_out, int *roots)
{
    const int ng = s->ng;
    double *glo = s->g_lo, *ghi = s->g_hi, *gmid = s->g_mid, *tmp;
    double tlo = t0, thi = t1;
    double ttol = s->root_tol * ((fabs(t1) > 1.0) ? fabs(t1) : 1.0);
    double alpha = 1.0;
    int side = 0, sideprev = -1, imax, it, j;
    const double ulp_floor = 8.0 * DBL_EPSILON * fabs(t1);

    if (ttol < ulp_floor) ttol = ulp_floor;
    memcpy(glo, s->g_prev, (size_t)ng * sizeof(double));
    imax = earliest_secant(s, glo, ghi);

    for (it = 0; it < ROOT_MAX_ITER && imax >= 0 && thi - tlo > ttol; ++it) {
        double tmid, width = thi - tlo;
        int any = 0;
        if (side == sideprev) {
            alpha = (side == 2) ? 2.0 * alpha : 0.5 * alpha;
        } else {
            alpha = 1.0;
        }
        tmid = thi - width * ghi[imax] / (ghi[imax] - alpha * glo[imax]);
        if (!(tmid > tlo && tmid < thi)) tmid = tlo + 0.5 * width;
        if (tmid - tlo < 0.5 * ttol) {
            const double fracint = width / ttol;
            tmid = tlo + ((fracint > 5.0) ? 0.1 : 0.5 / fracint) * width;
        } else if (thi - tmid < 0.5 * ttol) {
            const double fracint = width / ttol;
            tmid = thi - ((fracint > 5.0) ? 0.1 : 0.5 / fracint) * width;
        }
        dense_eval(s, (tmid - s->t_old) / s->h_last, s->y_stage);
        g(ctx, tmid, s->y_stage, gmid);
        s->n_ind++;
        sideprev = side;
        for (j = 0; j < ng; ++j) any |= crossed(s->g_prev[j], gmid[j]);
        if (any) {
            thi = tmid;
            tmp = ghi; ghi = gmid; gmid = tmp;
            side = 1;
        } else {
            tlo = tmid;
            tmp = glo; glo = gmid; gmid = tmp;
            side = 2;
        }
        imax = earliest_secant(s, glo, ghi);
    }

    for (j = 0; j < ng; ++j) {
        roots[j] = crossed(s->g_prev[j], ghi[j]) ? ((s->g_prev[j] < 0.0) ? 1 : -1) : 0;
    }
    memcpy(s->g_prev, ghi, (size_t)ng * sizeof(double));
    if (thi == t1) {
        memcpy(y_out, s->y_new, (size_t)s->n * sizeof(double));
    } else {
        dense_eval(s, (thi - s->t_old) / s->h_last, y_out);
    }
    return thi;
}

/* Arguments and tolerances valid for an advance from tc to t_end (ng: indicators in use)? */
static int advance_args_ok(const dp45_t *s, dp45_rhs_fn f, int ng, const int *roots, double tc,
                           double t_end)
{
    int j;
    if (s->n < 1 || s->n > DP45_MAX_N || s->n_norm < s->n || s->ng < 0 || s->ng > DP45_MAX_G || f == NULL ||
        (ng > 0 && roots == NULL) || !(t_end >= tc) || !(t_end - tc < HUGE_VAL)) {
        return 0;
    }
    if (!(s->rtol >= 0.0)) return 0;
    for (j = 0; j < s->n; ++j) {
        if (!(s->atol[j] > 0.0)) return 0;
    }
    return 1;
}

/* Make what is carried over valid at tc: k1 = f(tc, y) (FSAL), the indicators at tc and a
 * step-size proposal. Returns 0 when y or f(tc, y) is not finite. */
static int prepare_start(dp45_t *s, void *ctx, dp45_rhs_fn f, dp45_ind_fn g, int ng, double tc,
                         double t_end, const double *y)
{
    const int n = s->n;
    int j;
    if (s->t_cur != tc) {
        /* the caller moved time: nothing carried over is valid */
        s->fsal_ok = 0;
        s->g_ok = 0;
    }
    if (!s->fsal_ok) {
        double chk = 0.0;
        for (j = 0; j < n; ++j) chk += y[j] * 0.0; /* NaN iff some y_j is not finite */
        if (chk != 0.0) return 0;
        f(ctx, tc, y, s->k[s->i_k1]);
        s->n_rhs++;
        for (j = 0; j < n; ++j) chk += s->k[s->i_k1][j] * 0.0;
        if (chk != 0.0) return 0;
        s->fsal_ok = 1;
        s->t_cur = tc;
    }
    if (ng > 0 && !s->g_ok) {
        g(ctx, tc, y, s->g_prev);
        s->n_ind++;
        s->g_ok = 1;
        s->t_cur = tc;
    }
    if (!(s->h > 0.0)) {
        s->h = initial_step(s, ctx, f, tc, y, t_end - tc);
    }
    return 1;
}

/* Step size from tc with proposal hp: land exactly on t_end, stretching by <= 1 % (never
 * beyond h_max, up to rounding); split a remainder below 2 hp into two halves. Returns 1 when
 * the step ends on t_end. */
static int choose_step(const dp45_t *s, double tc, double t_end, double tiny, double hp, double *h,
                       double *t1)
{
    const double rem = t_end - tc;
    double lim = 1.01 * s->h;
    if (lim > s->h_max + tiny) lim = s->h_max + tiny;
    if (rem <= lim) {
        *h = rem;
        *t1 = t_end;
        return 1;
    }
    *h = (rem < 2.0 * hp) ? 0.5 * rem : hp;
    *t1 = tc + *h;
    return 0;
}

/* One Dormand-Prince step of size h from (tc, y) to t1: stages k2..k7 into s->k (k1 is
 * s->k[s->i_k1]), the 5th-order solution into s->y_new. Returns the mean squared scaled error,
 * or HUGE_VAL when the new state or derivative is not finite. */
static double dopri_step(dp45_t *s, void *ctx, dp45_rhs_fn f, double tc, double h, double t1,
                         const double *y)
{
    const int n = s->n;
    const double *k1 = s->k[s->i_k1];
    double *k2 = s->k[1], *k3 = s->k[2], *k4 = s->k[3], *k5 = s->k[4], *k6 = s->k[5];
    double *k7 = s->k[6 - s->i_k1];
    double *ys = s->y_stage, *yn = s->y_new;
    double sum = 0.0, chk = 0.0;
    int j;

    for (j = 0; j < n; ++j) ys[j] = y[j] + h * (A21 * k1[j]);
    f(ctx, tc + C2 * h, ys, k2);
    for (j = 0; j < n; ++j) ys[j] = y[j] + h * (A31 * k1[j] + A32 * k2[j]);
    f(ctx, tc + C3 * h, ys, k3);
    for (j = 0; j < n; ++j) ys[j] = y[j] + h * (A41 * k1[j] + A42 * k2[j] + A43 * k3[j]);
    f(ctx, tc + C4 * h, ys, k4);
    for (j = 0; j < n; ++j)
        ys[j] = y[j] + h * (A51 * k1[j] + A52 * k2[j] + A53 * k3[j] + A54 * k4[j]);
    f(ctx, tc + C5 * h, ys, k5);
    for (j = 0; j < n; ++j)
        ys[j] = y[j] +
                h * (A61 * k1[j] + A62 * k2[j] + A63 * k3[j] + A64 * k4[j] + A65 * k5[j]);
    f(ctx, t1, ys, k6);
    for (j = 0; j < n; ++j)
        yn[j] = y[j] +
                h * (A71 * k1[j] + A73 * k3[j] + A74 * k4[j] + A75 * k5[j] + A76 * k6[j]);
    f(ctx, t1, yn, k7);
    s->n_rhs += 6;

    for (j = 0; j < n; ++j) {
        const double e =
            h * (E1 * k1[j] + E3 * k3[j] + E4 * k4[j] + E5 * k5[j] + E6 * k6[j] + E7 * k7[j]);
        const double a = fabs(y[j]), b = fabs(yn[j]);
        const double q = e / (s->atol[j] + s->rtol * ((a > b) ? a : b));
        sum += q * q;
        chk += yn[j] * 0.0 + k7[j] * 0.0;
    }
    return (chk != 0.0) ? HUGE_VAL : sum / s->n_norm;
}

/* Factor by which a rejected step shrinks: hard for non-finite values, else 0.9 err^-0.17
 * (at least 0.2). */
static double shrink_factor(double err2)
{
    double lf;
    if (!(err2 <= DBL_MAX)) return NONFINITE_SHRINK;
    lf = L2_SAFE - EXPO1 * 0.5 * log2_approx(err2); /* log2(0.9 err^-0.17) */
    if (lf < L2_SHRINK_MIN) lf = L2_SHRINK_MIN;
    return exp2_approx(lf);
}

/* After an accepted step of size h (proposal hp): the next proposal from the PI controller
 * h_new = h * 0.9 * err^-0.17 * errold^0.04, no growth right after a rejection. */
static void next_step_size(dp45_t *s, double h, double hp, double err2)
{
    double grow;
    if (err2 < ERR2_SATURATED) {
        grow = FAC_GROW_MAX;
        s->log2_facold = L2_FACOLD_MIN;
    } else {
        const double l2_err = 0.5 * log2_approx(err2);
        double lf = L2_SAFE - EXPO1 * l2_err + BETA * s->log2_facold;
        if (lf > L2_GROW_MAX) lf = L2_GROW_MAX;
        if (lf < L2_SHRINK_MIN) lf = L2_SHRINK_MIN;
        grow = exp2_approx(lf);
        s->log2_facold = (l2_err > L2_FACOLD_MIN) ? l2_err : L2_FACOLD_MIN;
    }
    if (s->reject_prev && grow > 1.0) grow = 1.0;
    s->reject_prev = 0;
    if (h < hp) {
        /* limited by t_end, not by accuracy: keep the earlier proposal when the
         * error allows growth */
        const double hg = h * grow;
        s->h = (grow >= 1.0 && s->h > hg) ? s->h : hg;
    } else {
        s->h = h * grow;
    }
    if (s->h > s->h_max) s->h = s->h_max;
}

/* is a state of y outside the bounds (a NaN is)? */
static int out_of_bounds(const dp45_t *s, const double *y)
{
    int j;
    for (j = 0; j < s->n; ++j)
        if (!(y[j] >= s->y_lo[j] && y[j] <= s->y_hi[j])) return 1;
    return 0;
}

/* Keep the accepted step [tc, t1] for dense output; k7 becomes the next k1 (FSAL). */
static void record_step(dp45_t *s, const double *y, double tc, double t1, double h)
{
    s->n_steps++;
    copy_n(s->y_old, y, s->n);
    s->t_old = tc;
    s->t_new = t1;
    s->h_last = h;
    s->dense_k1 = s->i_k1;
    s->dense_ok = 1;
    s->i_k1 = 6 - s->i_k1;
}

/* Indicators at the end t1 of the last accepted step (into g_hi): did one change sign? */
static int step_has_crossing(dp45_t *s, void *ctx, dp45_ind_fn g, int ng, double t1)
{
    int any = 0, zero_start = 0, j;
    g(ctx, t1, s->y_new, s->g_hi);
    s->n_ind++;
    for (j = 0; j < ng; ++j) {
        any |= crossed(s->g_prev[j], s->g_hi[j]);
        zero_start |= (s->g_prev[j] == 0.0 && s->g_hi[j] != 0.0);
    }
    if (zero_start) {
        probe_zero_start(s, ctx, g);
        for (j = 0; j < ng; ++j) any |= crossed(s->g_prev[j], s->g_hi[j]);
    }
    return any;
}

int dp45_advance(dp45_t *s, void *ctx, dp45_rhs_fn f, dp45_ind_fn g, double *t, double t_end,
                 double *y, int *roots)
{
    const int ng = (g != NULL) ? s->ng : 0;
    double tc = *t;
    long long attempts = 0;
    int j;

    if (!advance_args_ok(s, f, ng, roots, tc, t_end)) return DP45_ERROR;
    for (j = 0; j < ng; ++j) roots[j] = 0;
    if (t_end == tc) return DP45_REACHED;
    if (!prepare_start(s, ctx, f, g, ng, tc, t_end, y)) return DP45_ERROR;

    for (;;) {
        const double tiny = 16.0 * DBL_EPSILON * (fabs(tc) + fabs(t_end));
        const double hp = (s->h < s->h_max) ? s->h : s->h_max;
        double h, t1, err2;
        int last;

        if (attempts++ >= s->max_steps) break;
        last = choose_step(s, tc, t_end, tiny, hp, &h, &t1);
        s->dense_ok = 0; /* the stage slots are about to be overwritten */
        err2 = dopri_step(s, ctx, f, tc, h, t1, y);
        if (!(err2 <= 1.0)) {
            /* rejected (error test or non-finite stage values): shrink and retry */
            s->n_rejected++;
            s->reject_prev = 1;
            s->h = h * shrink_factor(err2);
            if (s->h < s->h_min || s->h < tiny) break;
            continue;
        }
        next_step_size(s, h, hp, err2);
        record_step(s, y, tc, t1, h);
        if (ng > 0) {
            if (step_has_crossing(s, ctx, g, ng, t1)) {
                tc = locate_root(s, ctx, g, s->t_old, t1, y, roots);
                s->fsal_ok = (tc == t1);
                s->t_cur = tc;
                s->n_roots++;
                *t = tc;
                return DP45_ROOT;
            }
            memcpy(s->g_prev, s->g_hi, sizeof s->g_prev); /* fixed size: inlined */
        }
        copy_n(y, s->y_new, s->n);
        tc = t1;
        s->t_cur = tc;
        if (s->bounded && out_of_bounds(s, y)) {
            *t = tc;
            return DP45_BOUND;
        }
        if (last) {
            *t = t_end;
            return DP45_REACHED;
        }
    }
    *t = tc;
    return DP45_ERROR;
}
