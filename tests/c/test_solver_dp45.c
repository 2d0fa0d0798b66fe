/* Tests of fmu_src/solvers/solver_dp45.c, integration: accuracy against closed-form
 * solutions, step-size bookkeeping (FSAL, h_max, h kept across calls, inputs
 * changing per call), error paths, and the cost per step. Prints one line per
 * check and "N passed, M failed"; exits 0 only if every check passed.
 * Build: cc -std=c99 -I fmu_src -I tests/c tests/c/test_solver_dp45.c fmu_src/solvers/solver_dp45.c -lm
 * Events and dense output: test_solver_dp45_events.c. */
#define _POSIX_C_SOURCE 199309L
#include "solver_dp45.h"
#include "dp45_test_util.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* ---------------- problems ---------------- */

static void decay_rhs(void *ctx, double t, const double *y, double *dy)
{
    const double *lam = (const double *)ctx;
    (void)t;
    dy[0] = -lam[0] * y[0];
    dy[1] = -lam[1] * y[1];
    dy[2] = -lam[2] * y[2];
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
    osc_ctx c = {2.0 * TEST_PI};
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
    osc_ctx c = {2.0 * TEST_PI};
    dp45_t s;
    double y[2] = {1.0, 0.0}, t = 0.0, dt = 1e-3, h_natural;
    long k, calls = 2000, bad = 0, multi = 0;

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
        const long before = s.n_steps;
        if (dp45_advance(&s, &c, osc_rhs, NULL, &t, (double)k * dt, y, NULL) != DP45_REACHED ||
            t != (double)k * dt) {
            ++bad;
        }
        /* after the first call (initial-step ramp-up) every call is one step */
        if (k > 1 && s.n_steps - before != 1) ++multi;
    }
    check(bad == 0, "grid_all_reached_exactly", "%.0f calls failed of %.0f", (double)bad,
          (double)calls);
    check(multi == 0 && s.n_rejected == 0, "grid_one_step_per_call",
          "%.0f later calls took more than one step; %.0f steps in all", (double)multi,
          (double)s.n_steps);
    check(s.n_rhs == 6 * s.n_steps + 2, "grid_fsal_across_calls", "n_rhs = %.0f, expected %.0f",
          (double)s.n_rhs, (double)(6 * s.n_steps + 2));
    check(s.h > 5.0 * dt, "grid_h_kept", "proposal h = %g after calls of %g", s.h, dt);
    check(h_natural > 5.0 * dt, "grid_natural_h_larger_than_grid", "natural h = %g, dt = %g",
          h_natural, dt);
    check(fabs(y[0] - cos(c.w * t)) < 1e-8, "grid_accuracy", "|x err| = %.3g at t = %g",
          fabs(y[0] - cos(c.w * t)), t);
}

/* y' = u with u piecewise constant per call: dp45_drop_derivative makes the
 * result exact; the FSAL derivative from the old u would not be. */
static void input_rhs(void *ctx, double t, const double *y, double *dy)
{
    (void)t;
    (void)y;
    dy[0] = *(const double *)ctx;
}

static void test_drop_derivative(void)
{
    dp45_t s;
    double y[1] = {0.0}, t = 0.0, u = 0.0, exact = 0.0;
    int k, bad = 0;

    dp45_init(&s, 1, 0, 1e-8, NULL, 0.0);
    for (k = 1; k <= 200; ++k) {
        u = (k % 3 == 0) ? -2.0 : 1.0 + 0.01 * k;
        dp45_drop_derivative(&s);
        if (dp45_advance(&s, &u, input_rhs, NULL, &t, 1e-3 * k, y, NULL) != DP45_REACHED) ++bad;
        exact += u * 1e-3;
    }
    check(bad == 0 && fabs(y[0] - exact) < 1e-12, "drop_derivative_piecewise_input",
          "|y - exact| = %.3g, n_rhs = %.0f", fabs(y[0] - exact), (double)s.n_rhs);
}

static void test_decay(void)
{
    double lam[3] = {1.0, 4.0, 0.1};
    double atol[3] = {1e-14, 1e-14, 1e-14}; /* far below |y(3)| >= 1.2e-5: relative control */
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
    check(rc == DP45_ERROR && fabs(t - 1.0) < 1e-6, "blowup_error", "rc = %.0f at t = %.12f", rc,
          t);

    /* step cap */
    {
        osc_ctx c = {2.0 * TEST_PI};
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
    {
        const double bad_atol[1] = {0.0};
        dp45_init(&s, 1, 0, 1e-8, bad_atol, 0.0);
        rc = dp45_advance(&s, NULL, unit_rhs, NULL, &t, 2.0, y, NULL);
        check(rc == DP45_ERROR && t == 1.0, "zero_atol_error", "rc = %.0f, t = %g", rc, t);
    }
    dp45_init(&s, DP45_MAX_N + 1, 0, 1e-8, NULL, 0.0);
    rc = dp45_advance(&s, NULL, unit_rhs, NULL, &t, 2.0, y, NULL);
    check(rc == DP45_ERROR, "too_many_states_error", "rc = %.0f (n = %.0f)", rc,
          (double)(DP45_MAX_N + 1));
}

static void report_cost(void)
{
    osc_ctx c = {2.0 * TEST_PI};
    dp45_t s;
    double t0, el, y[2], t, best = 1e9;
    long r, rounds, steps = 0;

    /* best of 10 rounds of 20 runs: other processes share the cores */
    for (rounds = 0; rounds < 10; ++rounds) {
        steps = 0;
        t0 = now_s();
        for (r = 0; r < 20; ++r) {
            y[0] = 1.0;
            y[1] = 0.0;
            t = 0.0;
            dp45_init(&s, 2, 0, 1e-8, NULL, 0.0);
            s.atol[0] = s.atol[1] = 1e-10;
            dp45_advance(&s, &c, osc_rhs, NULL, &t, 10.0, y, NULL);
            steps += s.n_steps;
        }
        el = (now_s() - t0) / (double)steps;
        if (el < best) best = el;
    }
    printf("INFO cost_oscillator: %.1f ns per step (2 states, rtol 1e-8, %ld steps per round)\n",
           1e9 * best, steps);

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
                    sc.u = 30.0 * sin(2.0 * TEST_PI * 2.0 * t);
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
    test_drop_derivative();
    test_decay();
    test_h_max();
    test_errors();
    report_cost();
    return summary();
}
