/* The internal reference generator, sample for sample what feeddrive.harness.references makes:
 *   sinusoid:       x = centre - A cos(w t + phase), v = A w sin(..), a = A w^2 cos(..), t = j Ts,
 *                   n = round(duration / Ts) samples, held at sample n afterwards (v = a = 0);
 *   point to point: trapezoidal velocity with rest (dwell) before and after; x is the running
 *                   trapezoidal sum of v, a the central difference of v (numpy.gradient). */
#include <math.h>

#include "controller.h"

void ref_prepare(ctrl_params_t *p, double duration, double x_end) {
    double d = x_end - p->x_start, L, T;
    /* the sample counts as doubles first: ctrl_compile converts them to long long only when they are
     * at most REF_MAX_SAMPLES (a larger double to long long is undefined) */
    p->n_sin = p->source == REF_SINUSOID ? (long long)nearbyint(duration / p->Ts) : 0;
    if (p->source == REF_POINT_TO_POINT) {
        p->sgn = (double)((d > 0.0) - (d < 0.0));
        L = fabs(d);
        p->t_acc = p->speed / p->accel;
        if (p->accel * (p->t_acc * p->t_acc) > L) {   /* triangular profile */
            p->t_acc = sqrt(L / p->accel);
            p->speed = p->accel * p->t_acc;
        }
        p->t_cruise = (L - p->accel * (p->t_acc * p->t_acc)) / p->speed;
        T = p->dwell + 2 * p->t_acc + p->t_cruise + p->dwell;
        p->p2p_samples = ceil(T / p->Ts);
    }
}

/* velocity magnitude of the trapezoid at sample j (0 outside 0..n) */
static double p2p_speed(const ctrl_params_t *p, long long j) {
    double t, v;
    if (j < 0 || j > p->n_p2p) return 0.0;
    t = (double)j * p->Ts - p->dwell;
    if (t < 0.0) return 0.0;
    v = fmin(p->accel * t, p->accel * (2 * p->t_acc + p->t_cruise - t));
    return fmin(fmax(v, 0.0), p->speed);
}

static double p2p_accel(const ctrl_params_t *p, long long j) {
    if (j == 0) return (p2p_speed(p, 1) - p2p_speed(p, 0)) / p->Ts;
    if (j == p->n_p2p) return (p2p_speed(p, j) - p2p_speed(p, j - 1)) / p->Ts;
    return (p2p_speed(p, j + 1) - p2p_speed(p, j - 1)) / (2. * p->Ts);
}

void ref_sample(const ctrl_params_t *p, ref_gen_t *g, long long j, double *x, double *v, double *a) {
    if (p->source == REF_SINUSOID) {
        long long jj = j < p->n_sin ? j : p->n_sin;
        double th = p->w * ((double)jj * p->Ts) + p->phase;
        *x = p->centre - p->amp * cos(th);
        *v = j > p->n_sin ? 0.0 : p->amp * p->w * sin(th);
        *a = j > p->n_sin ? 0.0 : p->amp * (p->w * p->w) * cos(th);
        return;
    }
    /* point to point: j runs 0, 1, 2, ... (the running sum needs every sample once) */
    while (g->j < j && g->j < p->n_p2p) {
        g->j++;
        g->cs += (p2p_speed(p, g->j) + p2p_speed(p, g->j - 1)) / 2 * p->Ts;
    }
    *x = p->x_start + p->sgn * g->cs;
    if (j > p->n_p2p) { *v = *a = 0.0; return; }
    *v = p->sgn * p2p_speed(p, j);
    *a = p->sgn * p2p_accel(p, j);
}
