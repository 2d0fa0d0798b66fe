/* Tests of fmu_src/solver_dp45.c: accuracy against closed-form solutions, step-size
 * bookkeeping (FSAL, h_max, kept h across calls), event location, dense output and
 * error paths. Prints one line per check and "N passed, M failed"; exits 0 only if
 * every check passed. Build: cc -std=c99 -I fmu_src tests/c/test_solver_dp45.c
 * fmu_src/solver_dp45.c -lm */
#define _POSIX_C_SOURCE 199309L
#include "solver_dp45.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static const double PI = 3.14159265358979323846;
static int n_pass = 0, n_fail = 0;

static void check(int ok, const char *name, const char *fmt, double a, double b)
{
    char detail[160];
    snprintf(detail, sizeof detail, fmt, a, b);
    printf("%s %s: %s\n", ok ? "PASS" : "FAIL", name, detail);
    if (ok) {
        ++n_pass;
    } else {
        ++n_fail;
    }
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ---------------- problems ---------------- */

typedef struct {
    double w;
} osc_ctx;

static void osc_rhs(void *ctx, double t, const double *y, double *dy)
{
    const double w = ((const osc_ctx *)ctx)->w;
    (void)t;
    dy[0] = y[1];
    dy[1] = -w * w * y[0];
}

static void decay_rhs(void *ctx, double t, const double *y, double *dy)
{
    const double *lam = (const double *)ctx;
    (void)t;
    dy[0] = -lam[0] * y[0];
    dy[1] = -lam[1] * y[1];
    dy[2] = -lam[2] * y[2];
}

static void unit_rhs(void *ctx, double t, const double *y, double *dy)
{
    (void)ctx;
    (void)t;
    (void)y;
    dy[0] = 1.0;
}

/* y0 = t, y1 = t^3, y2 = t^4 */
static void poly_rhs(void *ctx, double t, const double *y, double *dy)
{
    (void)ctx;
    (void)y;
    dy[0] = 1.0;
    dy[1] = 3.0 * t * t;
    dy[2] = 4.0 * t * t * t;
}

static void poly_ind(void *ctx, double t, const double *y, double *g)
{
    (void)ctx;
    (void)t;
    g[0] = y[0] - 0.3;   /* rising at 0.3 */
    g[1] = 0.3 - y[0];   /* falling at 0.3 */
    g[2] = y[1] - 0.125; /* rising at 0.5 */
    g[3] = y[0] - 0.7;   /* rising at 0.7 */
    g[4] = 1.0;          /* never */
}

typedef struct {
    double grav;
} ball_ctx;

static void ball_rhs(void *ctx, double t, const double *y, double *dy)
{
    (void)t;
    dy[0] = y[1];
    dy[1] = -((const ball_ctx *)ctx)->grav;
}

static void ball_ind(void *ctx, double t, const double *y, double *g)
{
    (void)ctx;
    (void)t;
    g[0] = y[0];
}

static void zero_start_ind(void *ctx, double t, const double *y, double *g)
{
    (void)ctx;
    (void)t;
    g[0] = y[0];                 /* 0 at start, then positive */
    g[1] = -y[0];                /* 0 at start, then negative */
    g[2] = y[0] * (y[0] - 0.5);  /* 0 at start, negative, rises through 0 at 0.5 */
}

static void nan_rhs(void *ctx, double t, const double *y, double *dy)
{
    (void)ctx;
    (void)t;
    (void)y;
    dy[0] = NAN;
}

static void nan_late_rhs(void *ctx, double t, const double *y, double *dy)
{
    long *calls = (long *)ctx;
    (void)y;
    ++*calls;
    dy[0] = (t > 0.5) ? NAN : 1.0;
}

static void blowup_rhs(void *ctx, double t, const double *y, double *dy)
{
    (void)ctx;
    (void)t;
    dy[0] = y[0] * y[0];
}

/* 7 states of a stage on five stuck GMS springs: x, v, F_1..F_5, driven by u(t). */
typedef struct {
    double m, sigma2, k[5], u;
} stage_ctx;

static void stage_rhs(void *ctx, double t, const double *y, double *dy)
{
    const stage_ctx *c = (const stage_ctx *)ctx;
    const double v = y[1];
    double ff = c->sigma2 * v;
    int i;
    (void)t;
    for (i = 0; i < 5; ++i) {
        ff += y[2 + i];
        dy[2 + i] = c->k[i] * v;
    }
    dy[0] = v;
    dy[1] = (c->u - ff) / c->m;
}

/* ---------------- tests ---------------- */

static void test_struct_size(void)
{
    check(sizeof(dp45_t) < 4096, "struct_size", "sizeof(dp45_t) = %.0f bytes (< %.0f)",
          (double)sizeof(dp45_t), 4096.0);
}

static void test_oscillator(void)
{
    osc_ctx c = {2.0 * PI};
    dp45_t s;
    double atol[2] = {1e-10, 1e-10};
    double y[2] = {1.0, 0.0}, t = 0.0, ex, ev;
    int rc;

    dp45_init(&s, 2, 0, 1e-8, atol, 0.0);
    rc = dp45_advance(&s, &c, osc_rhs, NULL, &t, 10.0, y, NULL);
    ex = fabs(y[0] - 1.0);
    ev = fabs(y[1] - 0.0) / c.w;
    check(rc == DP45_REACHED && t == 10.0, "osc_reached", "rc = %.0f, t - 10 = %g", rc, t - 10.0);
    check(ex < 1e-6 && ev < 1e-6, "osc_error_10_periods", "|x err| = %.3g, |v err|/w = %.3g", ex,
          ev);
    /* DP5 at rtol 1e-8 on a sinusoid: of the order of 50-150 steps per period */
    check(s.n_steps > 200 && s.n_steps < 1500, "osc_step_count", "%.0f steps, %.0f rejected",
          (double)s.n_steps, (double)s.n_rejected);
    check(s.n_rejected * 10 <= s.n_steps, "osc_few_rejections", "%.0f rejected of %.0f",
          (double)s.n_rejected, (double)s.n_steps);
    /* FSAL: 6 new RHS per attempt, + 1 initial derivative + 1 for the initial step estimate */
    check(s.n_rhs == 6 * (s.n_steps + s.n_rejected) + 2, "osc_fsal_rhs_count",
          "n_rhs = %.0f, 6*(steps+rejected)+2 = %.0f", (double)s.n_rhs,
          (double)(6 * (s.n_steps + s.n_rejected) + 2));
}

/* Successive calls on a grid finer than the natural step: one step per call,
 * FSAL carried across calls, the natural step size kept. */
static void test_grid_calls_keep_h(void)
{
    osc_ctx c = {2.0 * PI};
    dp45_t s;
    double y[2] = {1.0, 0.0}, t = 0.0, dt = 1e-3, h_natural;
    long k, calls = 2000, bad = 0;

    dp45_init(&s, 2, 0, 1e-8, NULL, 0.0);
    s.atol[0] = s.atol[1] = 1e-10;
    {
        /* natural step of this problem at this tolerance */
        dp45_t probe;
        double yp[2] = {1.0, 0.0}, tp = 0.0;
        dp45_init(&probe, 2, 0, 1e-8, s.atol, 0.0);
        dp45_advance(&probe, &c, osc_rhs, NULL, &tp, 2.0, yp, NULL);
        h_natural = 2.0 / (double)probe.n_steps;
    }
    for (k = 1; k <= calls; ++k) {
        if (dp45_advance(&s, &c, osc_rhs, NULL, &t, (double)k * dt, y, NULL) != DP45_REACHED ||
            t != (double)k * dt) {
            ++bad;
        }
    }
    check(bad == 0, "grid_all_reached_exactly", "%.0f calls failed of %.0f", (double)bad,
          (double)calls);
    check(s.n_steps == calls && s.n_rejected == 0, "grid_one_step_per_call",
          "%.0f steps for %.0f calls", (double)s.n_steps, (double)calls);
    check(s.n_rhs == 6 * s.n_steps + 2, "grid_fsal_across_calls", "n_rhs = %.0f, expected %.0f",
          (double)s.n_rhs, (double)(6 * s.n_steps + 2));
    check(s.h > 5.0 * dt, "grid_h_kept", "proposal h = %g after calls of %g", s.h, dt);
    check(h_natural > 5.0 * dt, "grid_natural_h_larger_than_grid", "natural h = %g, dt = %g",
          h_natural, dt);
    check(fabs(y[0] - cos(c.w * t)) < 1e-8, "grid_accuracy", "|x err| = %.3g at t = %g",
          fabs(y[0] - cos(c.w * t)), t);
}

static void test_decay(void)
{
    double lam[3] = {1.0, 10.0, 0.1};
    double atol[3] = {1e-14, 1e-14, 1e-14};
    double y[3] = {1.0, 2.0, -3.0}, t = 0.0, worst = 0.0;
    double y0[3] = {1.0, 2.0, -3.0};
    dp45_t s;
    int j, rc;

    dp45_init(&s, 3, 0, 1e-9, atol, 0.0);
    rc = dp45_advance(&s, lam, decay_rhs, NULL, &t, 3.0, y, NULL);
    for (j = 0; j < 3; ++j) {
        const double ex = y0[j] * exp(-lam[j] * 3.0);
        const double rel = fabs(y[j] - ex) / fabs(ex);
        if (rel > worst) worst = rel;
    }
    /* rtol 1e-9 per step; the global relative error of a decay stays of that order */
    check(rc == DP45_REACHED && worst < 1e-7, "decay_relative_error",
          "max relative error = %.3g (rc %.0f)", worst, rc);
    check(s.n_steps < 400, "decay_step_count", "%.0f steps, %.0f rejected", (double)s.n_steps,
          (double)s.n_rejected);
}

static void test_h_max(void)
{
    dp45_t s, free_s;
    double y[1] = {0.0}, t = 0.0, yf[1] = {0.0}, tf = 0.0, hmax = 0.01, worst_h = 0.0;
    int k, bad = 0;

    /* y' = 1 is integrated exactly, so without h_max the step grows 10x per step */
    dp45_init(&free_s, 1, 0, 1e-6, NULL, 0.0);
    dp45_advance(&free_s, NULL, unit_rhs, NULL, &tf, 1.0, yf, NULL);
    dp45_init(&s, 1, 0, 1e-6, NULL, hmax);
    for (k = 1; k <= 27; ++k) {
        const double te = (k == 27) ? 1.0 : 0.037 * k;
        if (dp45_advance(&s, NULL, unit_rhs, NULL, &t, te, y, NULL) != DP45_REACHED) ++bad;
        if (s.h_last > worst_h) worst_h = s.h_last;
    }
    check(free_s.n_steps < 15, "hmax_unlimited_reference", "%.0f steps without h_max",
          (double)free_s.n_steps, 0.0);
    check(bad == 0 && worst_h <= hmax * (1.0 + 1e-9), "hmax_respected",
          "largest step %.17g (h_max %g)", worst_h, hmax);
    /* 1/0.01 = 100 steps plus one partial step per grid point that cuts a step */
    check(s.n_steps >= 100 && s.n_steps <= 127, "hmax_step_count", "%.0f steps, y(1) - 1 = %g",
          (double)s.n_steps, y[0] - 1.0);
}

/* Bouncing ball: x'' = -g, impact when x crosses 0, caller reflects v -> -e v and
 * sets x = 0 (the indicator is then exactly 0 at the restart: not a crossing). */
static void run_ball(const char *tag, double grid)
{
    ball_ctx c = {9.81};
    const double e = 0.8, x0 = 1.0;
    const double t1 = sqrt(2.0 * x0 / c.grav), v1 = c.grav * t1;
    double y[2] = {x0, 0.0}, t = 0.0, t_next = 0.0, worst_dt = 0.0, worst_v = 0.0;
    double t_exact = t1, v_exact = v1;
    int roots[1], bounce = 0, post_ok = 1, dir_ok = 1, rc = DP45_REACHED;
    long calls = 0;
    dp45_t s;
    char name[64];

    dp45_init(&s, 2, 1, 1e-10, NULL, 0.0);
    s.atol[0] = s.atol[1] = 1e-12;
    while (bounce < 6 && calls < 1000000) {
        ++calls;
        if (grid > 0.0 && rc == DP45_REACHED) t_next += grid;
        rc = dp45_advance(&s, &c, ball_rhs, ball_ind, &t, grid > 0.0 ? t_next : 100.0, y, roots);
        if (rc == DP45_ERROR) break;
        if (rc == DP45_ROOT) {
            const double dt = fabs(t - t_exact), dv = fabs(y[1] + v_exact);
            if (dt > worst_dt) worst_dt = dt;
            if (dv > worst_v) worst_v = dv;
            if (!(y[0] <= 0.0)) post_ok = 0;
            if (roots[0] != -1) dir_ok = 0;
            y[0] = 0.0;
            y[1] = -e * y[1];
            dp45_restart(&s);
            ++bounce;
            t_exact += 2.0 * e * v_exact / c.grav;
            v_exact *= e;
        }
    }
    snprintf(name, sizeof name, "ball_%s_six_impacts", tag);
    check(bounce == 6 && rc != DP45_ERROR, name, "%.0f impacts found (last rc %.0f)", bounce, rc);
    snprintf(name, sizeof name, "ball_%s_impact_times", tag);
    check(worst_dt < 1e-10, name, "max |t_impact - analytic| = %.3g s over %.0f bounces",
          worst_dt, bounce);
    snprintf(name, sizeof name, "ball_%s_impact_speeds", tag);
    check(worst_v < 1e-8, name, "max |v_impact - analytic| = %.3g m/s (%.0f)", worst_v, bounce);
    snprintf(name, sizeof name, "ball_%s_post_crossing_falling", tag);
    check(post_ok && dir_ok, name, "x <= 0 at every returned root: %.0f, roots[0] == -1: %.0f",
          post_ok, dir_ok);
}

static void test_bouncing_ball(void)
{
    run_ball("free", 0.0);
    run_ball("grid", 5e-4);
}

/* Several indicators in one step (y' = 1, y'' = 3t^2: integrated exactly, so one
 * step of 1 s is accepted): the earliest root is reported, roots[] flags both
 * indicators that cross there, and later roots follow on the next calls. */
static void test_multi_indicator(void)
{
    dp45_t s;
    double y[3] = {0.0, 0.0, 0.0}, t = 0.0;
    int roots[5], rc;
    const double expect_t[3] = {0.3, 0.5, 0.7};
    const int expect_r[3][5] = {{1, -1, 0, 0, 0}, {0, 0, 1, 0, 0}, {0, 0, 0, 1, 0}};
    int k, j, roots_ok, one_step;

    dp45_init(&s, 3, 5, 1e-8, NULL, 2.0);
    s.h = 1.0;
    for (k = 0; k < 3; ++k) {
        char name[64];
        rc = dp45_advance(&s, NULL, poly_rhs, poly_ind, &t, 1.0, y, roots);
        roots_ok = (rc == DP45_ROOT);
        for (j = 0; j < 5; ++j) roots_ok = roots_ok && (roots[j] == expect_r[k][j]);
        snprintf(name, sizeof name, "multi_root%d_time", k + 1);
        check(rc == DP45_ROOT && fabs(t - expect_t[k]) < 1e-12 && t >= expect_t[k] - 1e-15, name,
              "t = %.15f, error %.3g", t, t - expect_t[k]);
        snprintf(name, sizeof name, "multi_root%d_flags", k + 1);
        check(roots_ok, name, "roots = {%.0f, %.0f, ...} as expected", roots[0], roots[1]);
        if (k == 0) {
            one_step = (s.n_steps == 1 && s.n_roots == 1);
            check(one_step, "multi_all_in_one_step", "%.0f accepted step(s) before first root",
                  (double)s.n_steps, 0.0);
            check(y[0] >= 0.3 && fabs(y[1] - t * t * t) < 1e-14, "multi_state_at_root",
                  "y0 - 0.3 = %.3g, y1 - t^3 = %.3g", y[0] - 0.3, y[1] - t * t * t);
        }
    }
    rc = dp45_advance(&s, NULL, poly_rhs, poly_ind, &t, 1.0, y, roots);
    check(rc == DP45_REACHED && t == 1.0 && s.n_roots == 3, "multi_then_reached",
          "rc = %.0f, roots total %.0f", rc, (double)s.n_roots);
}

static void test_zero_at_start(void)
{
    dp45_t s;
    double y[1] = {0.0}, t = 0.0;
    int roots[3], rc;

    dp45_init(&s, 1, 3, 1e-8, NULL, 0.1);
    rc = dp45_advance(&s, NULL, unit_rhs, zero_start_ind, &t, 1.0, y, roots);
    check(rc == DP45_ROOT && fabs(t - 0.5) < 1e-12 && roots[0] == 0 && roots[1] == 0 &&
              roots[2] == 1,
          "zero_start_not_reported", "first root at t = %.15f (expected 0.5), roots[2] = %.0f", t,
          roots[2]);
    rc = dp45_advance(&s, NULL, unit_rhs, zero_start_ind, &t, 1.0, y, roots);
    check(rc == DP45_REACHED && s.n_roots == 1, "zero_start_then_reached", "rc = %.0f, roots %.0f",
          rc, (double)s.n_roots);
    /* restart exactly on the root of indicator 0 (value 0): not reported again */
    y[0] = 0.0;
    t = 2.0;
    dp45_restart(&s);
    rc = dp45_advance(&s, NULL, unit_rhs, zero_start_ind, &t, 2.3, y, roots);
    check(rc == DP45_REACHED && s.n_roots == 1, "zero_after_restart_not_reported",
          "rc = %.0f, roots total %.0f", rc, (double)s.n_roots);
}

static void test_errors(void)
{
    dp45_t s;
    double y[1] = {1.0}, t = 0.0;
    long calls = 0;
    int rc;

    dp45_init(&s, 1, 0, 1e-8, NULL, 0.0);
    rc = dp45_advance(&s, NULL, nan_rhs, NULL, &t, 1.0, y, NULL);
    check(rc == DP45_ERROR && t == 0.0 && s.n_rhs <= 2, "nan_rhs_error_immediately",
          "rc = %.0f after %.0f RHS calls", rc, (double)s.n_rhs);

    y[0] = 0.0;
    t = 0.0;
    dp45_init(&s, 1, 0, 1e-8, NULL, 0.0);
    rc = dp45_advance(&s, &calls, nan_late_rhs, NULL, &t, 1.0, y, NULL);
    check(rc == DP45_ERROR && t <= 0.5 && t > 0.49 && isfinite(y[0]) && fabs(y[0] - t) < 1e-12,
          "nan_later_error_not_hang", "stopped at t = %.15f with y finite, %.0f RHS calls", t,
          (double)calls);
    check(calls < 20000, "nan_later_bounded_work", "%.0f RHS calls, %.0f rejected", (double)calls,
          (double)s.n_rejected);

    y[0] = NAN;
    t = 0.0;
    dp45_init(&s, 1, 0, 1e-8, NULL, 0.0);
    rc = dp45_advance(&s, NULL, unit_rhs, NULL, &t, 1.0, y, NULL);
    check(rc == DP45_ERROR && s.n_rhs == 0, "nan_state_error", "rc = %.0f, RHS calls %.0f", rc,
          (double)s.n_rhs);

    /* y' = y^2, y(0) = 1 blows up at t = 1 */
    y[0] = 1.0;
    t = 0.0;
    dp45_init(&s, 1, 0, 1e-8, NULL, 0.0);
    rc = dp45_advance(&s, NULL, blowup_rhs, NULL, &t, 2.0, y, NULL);
    check(rc == DP45_ERROR && t < 1.0 && t > 0.999, "blowup_error", "rc = %.0f at t = %.9f", rc,
          t);

    /* step cap */
    {
        osc_ctx c = {2.0 * PI};
        double yo[2] = {1.0, 0.0};
        t = 0.0;
        dp45_init(&s, 2, 0, 1e-10, NULL, 0.0);
        s.max_steps = 10;
        rc = dp45_advance(&s, &c, osc_rhs, NULL, &t, 10.0, yo, NULL);
        check(rc == DP45_ERROR && t > 0.0 && t < 10.0 && s.n_steps + s.n_rejected == 10,
              "max_steps_error", "rc = %.0f at t = %g", rc, t);
    }

    /* invalid arguments */
    y[0] = 1.0;
    t = 1.0;
    dp45_init(&s, 1, 0, 1e-8, NULL, 0.0);
    rc = dp45_advance(&s, NULL, unit_rhs, NULL, &t, 0.5, y, NULL);
    check(rc == DP45_ERROR && t == 1.0, "backward_t_end_error", "rc = %.0f, t = %g", rc, t);
    rc = dp45_advance(&s, NULL, unit_rhs, NULL, &t, 1.0, y, NULL);
    check(rc == DP45_REACHED && t == 1.0 && s.n_rhs == 0, "zero_length_call", "rc = %.0f, t = %g",
          rc, t);
    dp45_init(&s, DP45_MAX_N + 1, 0, 1e-8, NULL, 0.0);
    rc = dp45_advance(&s, NULL, unit_rhs, NULL, &t, 2.0, y, NULL);
    check(rc == DP45_ERROR, "too_many_states_error", "rc = %.0f (n = %.0f)", rc,
          (double)(DP45_MAX_N + 1));
}

static void test_dense(void)
{
    osc_ctx c = {2.0 * PI};
    dp45_t s;
    double y[2] = {1.0, 0.0}, t = 0.0, yd[3], worst_dense = 0.0, worst_node = 0.0;
    int k, end_ok = 1, bad_calls = 0;

    /* one call per natural step (t_end = t + proposal), dense output inside each */
    dp45_init(&s, 2, 0, 1e-6, NULL, 0.0);
    s.atol[0] = s.atol[1] = 1e-8;
    while (t < 5.0) {
        const double proposal = (s.h > 0.0) ? s.h : 1e-3;
        const double te = (t + proposal < 5.0) ? t + proposal : 5.0;
        if (dp45_advance(&s, &c, osc_rhs, NULL, &t, te, y, NULL) != DP45_REACHED) {
            ++bad_calls;
            break;
        }
        if (fabs(y[0] - cos(c.w * t)) > worst_node) worst_node = fabs(y[0] - cos(c.w * t));
        for (k = 1; k < 10; ++k) {
            const double tq = s.t_old + 0.1 * k * (s.t_new - s.t_old);
            double ex, ev;
            if (dp45_dense(&s, tq, yd) != 0) ++bad_calls;
            ex = fabs(yd[0] - cos(c.w * tq));
            ev = fabs(yd[1] + c.w * sin(c.w * tq)) / c.w;
            if (ex > worst_dense) worst_dense = ex;
            if (ev > worst_dense) worst_dense = ev;
        }
        if (dp45_dense(&s, s.t_old, yd) != 0 || fabs(yd[0] - s.y_old[0]) > 1e-15) end_ok = 0;
        if (dp45_dense(&s, s.t_new, yd) != 0 || yd[0] != y[0] || yd[1] != y[1]) end_ok = 0;
    }
    check(bad_calls == 0 && end_ok, "dense_endpoints", "bad calls %.0f, endpoints match %.0f",
          bad_calls, end_ok);
    /* the 4th-order interpolant adds an O(h^5) error of the size of the local
     * error, so inside steps it stays within a small multiple of the node error */
    check(worst_dense < 3.0 * worst_node + 1e-6, "dense_oscillator_accuracy",
          "max interior error %.3g vs max node error %.3g", worst_dense, worst_node);
    check(dp45_dense(&s, s.t_new + 1e-3, yd) == -1 && dp45_dense(&s, s.t_old - 1e-3, yd) == -1,
          "dense_outside_step_rejected", "%.0f %.0f", 0.0, 0.0);

    /* quartic solution: the continuous extension is exact on a 1 s step */
    {
        double yp[3] = {0.0, 0.0, 0.0}, tp = 0.0, worst = 0.0;
        dp45_init(&s, 3, 0, 1e-8, NULL, 0.0);
        s.h = 1.0;
        dp45_advance(&s, NULL, poly_rhs, NULL, &tp, 1.0, yp, NULL);
        for (k = 0; k <= 20; ++k) {
            const double tq = 0.05 * k;
            double d;
            dp45_dense(&s, tq, yd);
            d = fabs(yd[0] - tq) + fabs(yd[1] - tq * tq * tq) + fabs(yd[2] - tq * tq * tq * tq);
            if (d > worst) worst = d;
        }
        check(s.n_steps == 1 && worst < 1e-14, "dense_exact_for_quartic",
              "one step: %.0f, max error %.3g", (double)(s.n_steps == 1), worst);
    }
}

static void report_cost(void)
{
    osc_ctx c = {2.0 * PI};
    dp45_t s;
    double t0 = now_s(), el, y[2], t;
    long reps = 200, r, steps = 0;

    for (r = 0; r < reps; ++r) {
        y[0] = 1.0;
        y[1] = 0.0;
        t = 0.0;
        dp45_init(&s, 2, 0, 1e-8, NULL, 0.0);
        s.atol[0] = s.atol[1] = 1e-10;
        if (r == 1) t0 = now_s(); /* first run warms up */
        dp45_advance(&s, &c, osc_rhs, NULL, &t, 10.0, y, NULL);
        if (r >= 1) steps += s.n_steps;
    }
    el = now_s() - t0;
    printf("INFO cost_oscillator: %.1f ns per step (%ld steps, rtol 1e-8)\n", 1e9 * el / steps,
           steps);

    /* the FMU's pattern: 12000 communication steps of 0.5 ms, new input each time */
    {
        stage_ctx sc = {16.1, 54.0, {1152.07e3, 377.23e3, 215.33e3, 9.39e3, 87.66e3}, 0.0};
        double ys[7];
        const double rtols[2] = {1e-6, 1e-8};
        int ir, rep, k;
        for (ir = 0; ir < 2; ++ir) {
            double best = 1e9;
            for (rep = 0; rep < 5; ++rep) {
                memset(ys, 0, sizeof ys);
                t = 0.0;
                dp45_init(&s, 7, 0, rtols[ir], NULL, 5e-4);
                for (k = 0; k < 7; ++k) s.atol[k] = (k < 2) ? 1e-12 : 1e-6;
                t0 = now_s();
                for (k = 1; k <= 12000; ++k) {
                    sc.u = 30.0 * sin(2.0 * PI * 2.0 * t);
                    dp45_drop_derivative(&s);
                    dp45_advance(&s, &sc, stage_rhs, NULL, &t, k * 5e-4, ys, NULL);
                }
                el = now_s() - t0;
                if (el < best) best = el;
            }
            printf("INFO cost_fmu_pattern: rtol %g, 7 states, 12000 x 0.5 ms: %.3f ms total, "
                   "%.2f steps/call, %.2f RHS/call\n",
                   rtols[ir], 1e3 * best, (double)s.n_steps / 12000.0, (double)s.n_rhs / 12000.0);
        }
    }
}

int main(void)
{
    test_struct_size();
    test_oscillator();
    test_grid_calls_keep_h();
    test_decay();
    test_h_max();
    test_bouncing_ball();
    test_multi_indicator();
    test_zero_at_start();
    test_errors();
    test_dense();
    report_cost();
    printf("%d passed, %d failed\n", n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
}
