/* Shared by the C tests of fmu_src/solvers/solver_dp45.c: a check printer, a clock and the
 * closed-form test problems used by both programs. Header-only (static inline). */
#ifndef DP45_TEST_UTIL_H
#define DP45_TEST_UTIL_H

#include <math.h>
#include <stdio.h>
#include <time.h>

#define TEST_PI 3.14159265358979323846

static int n_pass = 0, n_fail = 0;

/* Print "PASS|FAIL name: detail" (detail = fmt with up to two numbers) and count. */
static inline void check(int ok, const char *name, const char *fmt, double a, double b)
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

/* Print the summary line; the exit status of the program. */
static inline int summary(void)
{
    printf("%d passed, %d failed\n", n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
}

static inline double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* x'' = -w^2 x as (x, v) */
typedef struct {
    double w;
} osc_ctx;

static inline void osc_rhs(void *ctx, double t, const double *y, double *dy)
{
    const double w = ((const osc_ctx *)ctx)->w;
    (void)t;
    dy[0] = y[1];
    dy[1] = -w * w * y[0];
}

static inline void unit_rhs(void *ctx, double t, const double *y, double *dy)
{
    (void)ctx;
    (void)t;
    (void)y;
    dy[0] = 1.0;
}

/* y0 = t, y1 = t^3, y2 = t^4 */
static inline void poly_rhs(void *ctx, double t, const double *y, double *dy)
{
    (void)ctx;
    (void)y;
    dy[0] = 1.0;
    dy[1] = 3.0 * t * t;
    dy[2] = 4.0 * t * t * t;
}

#endif /* DP45_TEST_UTIL_H */
