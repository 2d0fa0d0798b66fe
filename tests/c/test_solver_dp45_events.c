/* Tests of fmu_src/solvers/solver_dp45.c, events and dense output: bouncing ball against
 * the analytic impact times, several indicators in one step, indicators exactly
 * zero at a step start or end, indicator bookkeeping across calls, accuracy and
 * order of the continuous extension. Prints one line per check and
 * "N passed, M failed"; exits 0 only if every check passed.
 * Build: cc -std=c99 -I fmu_src -I tests/c tests/c/test_solver_dp45_events.c fmu_src/solvers/solver_dp45.c -lm */
#define _POSIX_C_SOURCE 199309L
#include "solver_dp45.h"
#include "dp45_test_util.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---------------- problems ---------------- */

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

static void grow_rhs(void *ctx, double t, const double *y, double *dy)
{
    (void)ctx;
    (void)t;
    dy[0] = y[0];
}

/* ---------------- tests ---------------- */

static void osc_ind_never(void *ctx, double t, const double *y, double *g)
{
    (void)ctx;
    (void)t;
    g[0] = 2.0 + y[0]; /* |x| <= 1: never crosses */
}

/* Indicator memory is carried across calls: one evaluation at the start, one per
 * step; a restart costs one more; roots[] is cleared on DP45_REACHED. */
static void test_indicator_bookkeeping(void)
{
    osc_ctx c = {2.0 * TEST_PI};
    dp45_t s;
    double y[2] = {1.0, 0.0}, t = 0.0;
    int roots[1] = {7}, k, rc = DP45_REACHED;
    long ind_before, rhs_before, attempts_before;

    dp45_init(&s, 2, 1, 1e-8, NULL, 0.0);
    for (k = 1; k <= 100 && rc == DP45_REACHED; ++k) {
        rc = dp45_advance(&s, &c, osc_rhs, osc_ind_never, &t, 0.01 * k, y, roots);
    }
    check(rc == DP45_REACHED && s.n_ind == s.n_steps + 1 && roots[0] == 0,
          "indicators_carried_over", "n_ind = %.0f for %.0f steps", (double)s.n_ind,
          (double)s.n_steps);
    ind_before = s.n_ind;
    rhs_before = s.n_rhs;
    attempts_before = s.n_steps + s.n_rejected;
    dp45_restart(&s);
    k = (int)s.n_steps;
    rc = dp45_advance(&s, &c, osc_rhs, osc_ind_never, &t, 1.5, y, roots);
    check(rc == DP45_REACHED && s.n_ind - ind_before == s.n_steps - k + 1,
          "indicators_reevaluated_after_restart", "%.0f evaluations for %.0f steps",
          (double)(s.n_ind - ind_before), (double)(s.n_steps - k));
    check(s.n_rhs - rhs_before == 6 * (s.n_steps + s.n_rejected - attempts_before) + 1,
          "derivative_recomputed_after_restart", "%.0f RHS calls for %.0f attempts",
          (double)(s.n_rhs - rhs_before), (double)(s.n_steps + s.n_rejected - attempts_before));
}

static void time_ind(void *ctx, double t, const double *y, double *g)
{
    (void)ctx;
    (void)y;
    g[0] = t - 0.5;
}

/* g_new == 0 exactly at a step end counts as a crossing; the returned point is
 * then exactly on the root */
static void test_exact_zero_at_step_end(void)
{
    dp45_t s;
    double y[1] = {0.0}, t = 0.0;
    int roots[1] = {0}, rc;

    dp45_init(&s, 1, 1, 1e-8, NULL, 0.0);
    rc = dp45_advance(&s, NULL, unit_rhs, time_ind, &t, 0.5, y, roots);
    check(rc == DP45_ROOT && t == 0.5 && roots[0] == 1, "zero_at_step_end_is_crossing",
          "rc = %.0f at t = %.17g", rc, t);
    rc = dp45_advance(&s, NULL, unit_rhs, time_ind, &t, 1.0, y, roots);
    check(rc == DP45_REACHED && t == 1.0 && s.n_roots == 1, "zero_at_step_end_reported_once",
          "rc = %.0f, roots total %.0f", rc, (double)s.n_roots);
}

/* Bouncing ball: x'' = -g, impact when x crosses 0, caller reflects v -> -e v and
 * sets x = 0 (the indicator is then exactly 0 at the restart: not a crossing). */
static void run_ball(const char *tag, double grid, double h_max, double max_evals)
{
    ball_ctx c = {9.81};
    const double e = 0.8, x0 = 1.0;
    const double t1 = sqrt(2.0 * x0 / c.grav), v1 = c.grav * t1;
    double y[2] = {x0, 0.0}, t = 0.0, t_next = 0.0, worst_dt = 0.0, worst_v = 0.0;
    double t_exact = t1, v_exact = v1, t_pred = t1, worst_local = 0.0, worst_excess = 0.0;
    int roots[1], bounce = 0, post_ok = 1, dir_ok = 1, rc = DP45_REACHED;
    long calls = 0;
    dp45_t s;
    char name[64];

    dp45_init(&s, 2, 1, 1e-10, NULL, h_max);
    s.atol[0] = s.atol[1] = 1e-12;
    while (bounce < 6 && calls < 1000000) {
        ++calls;
        if (grid > 0.0 && rc == DP45_REACHED) t_next += grid;
        rc = dp45_advance(&s, &c, ball_rhs, ball_ind, &t, grid > 0.0 ? t_next : 100.0, y, roots);
        if (rc == DP45_ERROR) break;
        if (rc == DP45_ROOT) {
            const double dt = fabs(t - t_exact), dv = fabs(y[1] + v_exact);
            /* impact predicted from the state the caller restarted from: isolates
             * the root location of this flight from the caller's resets */
            const double dl = t - t_pred, tol = s.root_tol * (t > 1.0 ? t : 1.0);
            if (fabs(dl) > worst_local) worst_local = fabs(dl);
            if (fabs(dl) - tol > worst_excess) worst_excess = fabs(dl) - tol;
            if (dt > worst_dt) worst_dt = dt;
            if (dv > worst_v) worst_v = dv;
            if (!(y[0] <= 0.0)) post_ok = 0;
            if (roots[0] != -1) dir_ok = 0;
            y[0] = 0.0;
            y[1] = -e * y[1];
            t_pred = t + 2.0 * y[1] / c.grav;
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
    snprintf(name, sizeof name, "ball_%s_root_within_root_tol", tag);
    check(worst_excess <= 1e-14, name, "max |t_root - t_predicted| = %.3g s (root_tol %.0e)",
          worst_local, s.root_tol);
    /* evaluations: 1 at init, 1 per restart, 1 per step, 1 zero-start probe per
     * flight (x = 0 at restart), the rest locate roots. Illinois converges
     * superlinearly: from a bracket of one step to 1e-12 s in ~10 evaluations
     * (plain regula falsi: 18 and 14 here, bisection ~35) */
    {
        const double per_root =
            (double)(s.n_ind - s.n_steps - 1 - 2 * bounce) / (bounce > 0 ? bounce : 1);
        snprintf(name, sizeof name, "ball_%s_root_finding_cost", tag);
        check(bounce > 0 && per_root < max_evals, name,
              "%.1f indicator evaluations per root location (%.0f roots)", per_root, bounce);
    }
    snprintf(name, sizeof name, "ball_%s_impact_speeds", tag);
    check(worst_v < 1e-8, name, "max |v_impact - analytic| = %.3g m/s (%.0f)", worst_v, bounce);
    snprintf(name, sizeof name, "ball_%s_post_crossing_falling", tag);
    check(post_ok && dir_ok, name, "x <= 0 at every returned root: %.0f, roots[0] == -1: %.0f",
          post_ok, dir_ok);
}

static void test_bouncing_ball(void)
{
    /* A quadratic is integrated exactly, so without h_max the step grows to ~100 s
     * and the interpolant's rounding (|y| ~ g h^2 / 2 ~ 5e4) exceeds 1e-10: a
     * caller sets h_max to the time scale of its events. */
    run_ball("free", 0.0, 0.05, 15.0);
    run_ball("grid", 5e-4, 0.0, 11.0);
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
    /* the same within ONE step of 1 s: the zero at the start is not a crossing,
     * the root at 0.5 of the indicator that left 0 downwards is still found */
    y[0] = 0.0;
    t = 0.0;
    dp45_init(&s, 1, 3, 1e-8, NULL, 2.0);
    s.h = 1.0;
    rc = dp45_advance(&s, NULL, unit_rhs, zero_start_ind, &t, 1.0, y, roots);
    check(rc == DP45_ROOT && fabs(t - 0.5) < 1e-12 && roots[0] == 0 && roots[1] == 0 &&
              roots[2] == 1 && s.n_steps == 1,
          "zero_start_one_step_later_root_found", "root at t = %.15f in %.0f step(s)", t,
          (double)s.n_steps);
    rc = dp45_advance(&s, NULL, unit_rhs, zero_start_ind, &t, 1.0, y, roots);
    /* restart exactly on the root of indicator 0 (value 0): not reported again */
    y[0] = 0.0;
    t = 2.0;
    dp45_restart(&s);
    rc = dp45_advance(&s, NULL, unit_rhs, zero_start_ind, &t, 2.3, y, roots);
    check(rc == DP45_REACHED && s.n_roots == 1, "zero_after_restart_not_reported",
          "rc = %.0f, roots total %.0f", rc, (double)s.n_roots);
}

static void test_dense(void)
{
    osc_ctx c = {2.0 * TEST_PI};
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

    /* order: on y' = y from exact data the interpolant's error at mid-step is a
     * local error O(h^5): halving h divides it by ~32 */
    {
        double errs[2];
        int i;
        for (i = 0; i < 2; ++i) {
            const double hh = (i == 0) ? 0.2 : 0.1;
            double ye[1] = {1.0}, te = 0.0, ym[1];
            dp45_init(&s, 1, 0, 1e-3, NULL, hh);
            s.h = hh;
            dp45_advance(&s, NULL, grow_rhs, NULL, &te, hh, ye, NULL);
            dp45_dense(&s, 0.5 * hh, ym);
            errs[i] = fabs(ym[0] - exp(0.5 * hh));
        }
        check(errs[0] / errs[1] > 22.0 && errs[0] / errs[1] < 45.0, "dense_local_order_5",
              "error ratio for h 0.2 -> 0.1: %.1f (32 expected), error at h = 0.1: %.3g",
              errs[0] / errs[1], errs[1]);
    }

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

int main(void)
{
    test_indicator_bookkeeping();
    test_exact_zero_at_step_end();
    test_bouncing_ball();
    test_multi_indicator();
    test_zero_at_start();
    test_dense();
    return summary();
}
