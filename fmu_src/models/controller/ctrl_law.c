/* The control laws, sample k (u[k] from x_meas[k], applied over [t_k, t_k+1)):
 * state space (feeddrive.control.lti_step: u = Cc s + Dy y + Dr r + u_ff, clamp,
 * s <- Ac s + By y + Br r + Bu (u - u_ff), s[0] = y at the first sample), PID and PID with lead
 * (feeddrive.control.pid), any linear controller (feeddrive.control.lti), the ZPETC pre-filter run on the reference preview samples ahead
 * (scipy.signal.lfilter's direct form II transposed, steady at the first reference sample),
 * and the feedforward. The operations are those of the Python twins, in the same order. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "controller.h"

void ctrl_reset(const ctrl_params_t *p, ctrl_state_t *s) {
    memset(s, 0, sizeof *s);
    s->fresh = true;
    gms_track_init(&s->gms);
    (void)p;
}

static double zpetc_filter(const ctrl_params_t *p, double *z, double x) {
    int n, nb = p->nzc;
    double y;
    if (nb == 1) return x * p->zb[0];
    y = z[0] + p->zb[0] * x;
    for (n = 0; n < nb - 2; n++) z[n] = z[n + 1] + x * p->zb[n + 1] - y * p->za[n + 1];
    z[nb - 2] = x * p->zb[nb - 1] - y * p->za[nb - 1];
    return y;
}

/* reference sample j (input or generator) into the ring buffer and, with ZPETC, the filter */
static double push_reference(const ctrl_params_t *p, ctrl_state_t *s, long long j, double x, double v,
                             double a) {
    int slot = (int)(j % CTRL_RB);
    if (p->source != REF_INPUT) ref_sample(p, &s->gen, j, &x, &v, &a);
    s->rx[slot] = x;
    s->rv[slot] = v;
    s->ra[slot] = a;
    if (!p->zpetc) return x;
    if (j == 0) {
        int n;
        for (n = 0; n < p->nzc - 1; n++) s->z[n] = p->zi[n] * x;
    }
    return zpetc_filter(p, s->z, x);
}

/* the output clamp +-u_limit; NaN stays NaN (fmin/fmax would turn it into a limit), so that
 * ctrl_sample's finiteness check sees it */
static double clamp_u(double u, double lim) { return u > lim ? lim : (u < -lim ? -lim : u); }

static double state_space(const ctrl_params_t *p, ctrl_state_t *s, double y, double r, double uff) {
    double u = 0.0, w, old[CTRL_NS_MAX];
    int i, j, n = p->n;
    if (s->fresh) { s->s[0] = y; s->fresh = false; }
    for (j = 0; j < n; j++) u = u + p->Cc[j] * s->s[j];
    u = u + p->Dy * y + p->Dr * r + uff;
    s->u_law = u;
    u = clamp_u(u, p->u_limit);
    w = u - uff;
    memcpy(old, s->s, sizeof old);
    for (i = 0; i < n; i++) {
        double acc = 0.0;
        for (j = 0; j < n; j++) acc = acc + p->Ac[i][j] * old[j];
        s->s[i] = acc + p->By[i] * y + p->Br[i] * r + p->Bu[i] * w;
    }
    return u;
}

/* the general linear controller, the operations of feeddrive.control.lti.compile_lti_step in
 * its order: every term, left to right, from 0.0 */
static double lti(const ctrl_params_t *p, ctrl_state_t *s, double y, double r, double uff) {
    double v = 0.0, w, u, c, old[CTRL_NS_MAX];
    int i, j, n = p->lti_n;
    if (s->fresh) {
        for (j = 0; j < n; j++) s->s[j] = p->lti_s0[j] + p->lti_s0_r[j] * r;
        s->fresh = false;
    }
    for (j = 0; j < n; j++) v = v + p->lti_C[j] * s->s[j];
    v = v + p->lti_D[0] * r + p->lti_D[1] * y;
    w = v + uff;
    s->u_law = w;
    u = clamp_u(w, p->u_limit);
    c = u - w;
    memcpy(old, s->s, sizeof old);
    for (i = 0; i < n; i++) {
        double acc = 0.0;
        for (j = 0; j < n; j++) acc = acc + p->lti_A[i][j] * old[j];
        s->s[i] = acc + p->lti_B[i][0] * r + p->lti_B[i][1] * y + p->lti_L[i] * c;
    }
    return u;
}

static double pid(const ctrl_params_t *p, ctrl_state_t *s, double y, double r, double uff) {
    double e = r - y, D, q_before, F, u;
    if (p->tf == 0.0) {
        double de = s->has_e_prev ? (e - s->e_prev) / p->Ts : 0.0;
        D = p->Kv * de;
    } else {
        D = p->pid_a * s->D + (s->has_e_prev ? p->pid_b * (e - s->e_prev) : 0.0);
        s->D = D;
    }
    s->e_prev = e;
    s->has_e_prev = true;
    q_before = s->q;
    s->q += e * p->Ts;
    F = p->Kp * e + p->Ki * s->q + D;
    if (p->lead) {
        double L = p->lead_b0 * F + p->lead_b1 * s->F_prev - p->lead_a1 * s->L_prev;
        s->F_prev = F;
        s->L_prev = L;
        F = L;
    }
    u = F / p->fpv;
    if (p->ff) u += uff;
    s->u_law = u;
    if (p->anti_windup && fabs(u) > p->u_limit && u * e > 0) s->q = q_before;
    return clamp_u(u, p->u_limit);
}

/* every number the sample produced or keeps is finite, else false with the first one named */
static bool finite_or_why(const char *what, int idx, double v, char *why, size_t n) {
    if (isfinite(v)) return true;
    if (idx >= 0) snprintf(why, n, "%s[%d] = %g is not finite", what, idx + 1, v);
    else snprintf(why, n, "%s = %g is not finite", what, v);
    return false;
}

static bool sample_finite(const ctrl_params_t *p, const ctrl_state_t *s, double y, char *why, size_t n) {
    int j;
    if (!finite_or_why("x_meas after the scale quantisation", -1, y, why, n)) return false;
    if (!finite_or_why("the reference r_x", -1, s->r_x, why, n) ||
        !finite_or_why("the command x_cmd (ZPETC output)", -1, s->x_cmd, why, n))
        return false;
    for (j = 0; p->zpetc && j < p->nzc - 1; j++)
        if (!finite_or_why("the ZPETC filter state", j, s->z[j], why, n)) return false;
    if (!finite_or_why("the feedforward u_ff", -1, s->u_ff, why, n)) return false;
    if (p->type == CTRL_STATE_SPACE) {
        if (!finite_or_why("the state-space output before the clamp", -1, s->u_law, why, n)) return false;
        for (j = 0; j < p->n; j++)
            if (!finite_or_why("the state-space state s", j, s->s[j], why, n)) return false;
    } else if (p->type == CTRL_LTI) {
        if (!finite_or_why("the linear controller's output before the clamp", -1, s->u_law, why, n)) return false;
        for (j = 0; j < p->lti_n; j++)
            if (!finite_or_why("the linear controller's state lti.s", j, s->s[j], why, n)) return false;
    } else {
        if (!finite_or_why("the PID output before the clamp", -1, s->u_law, why, n) ||
            !finite_or_why("the PID integral", -1, s->q, why, n) ||
            !finite_or_why("the PID derivative", -1, s->D, why, n) ||
            !finite_or_why("the PID error", -1, s->e_prev, why, n) ||
            !finite_or_why("the lead filter input", -1, s->F_prev, why, n) ||
            !finite_or_why("the lead filter output", -1, s->L_prev, why, n))
            return false;
    }
    return finite_or_why("u", -1, s->u, why, n);
}

bool ctrl_sample(const ctrl_params_t *p, ctrl_state_t *s, const ctrl_in_t *in, char *why, size_t whylen) {
    long long k = s->k, j;
    int slot = (int)(k % CTRL_RB);
    double y = (p->delay && k > 0) ? s->y_prev : in->x_meas, r, uff = 0.0;
    s->y_prev = in->x_meas;
    if (p->quantum > 0.0) y = nearbyint(y / p->quantum) * p->quantum;
    if (k == 0)   /* the samples before the first input: the reference at rest at its first value */
        for (j = 0; j < p->preview; j++) push_reference(p, s, j, in->x_ref, 0.0, 0.0);
    r = push_reference(p, s, k + p->preview, in->x_ref, in->v_ref, in->a_ref);
    if (!p->zpetc) r = s->rx[slot];
    if (p->ff) uff = feedforward_sample(p, &s->gms, s->rx[slot], s->rv[slot], s->ra[slot]);
    s->x_cmd = r;
    s->u_ff = uff;
    s->r_x = s->rx[slot];
    s->u = p->type == CTRL_STATE_SPACE ? state_space(p, s, y, r, uff)
         : p->type == CTRL_LTI ? lti(p, s, y, r, uff) : pid(p, s, y, r, uff);
    s->k = k + 1;
    return sample_finite(p, s, y, why, whylen);
}
