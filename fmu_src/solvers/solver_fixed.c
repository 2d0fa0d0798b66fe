/* One embedded Runge-Kutta 4(3) step over an interval of constant current, on the reduced
 * system (fast_path.h). With the discrete state fixed over the step:
 *   - a stuck element's force is F_j0 + k_j (x - x0) exactly (an RK step preserves that linear
 *     invariant), so only the sum over the stuck ones enters: F_st0 + K_st (x - x0);
 *   - the slipping elements all relax with the same rate C/S(|v|) toward nu_j dir S, so their
 *     sum F_sl = sum F_j obeys dF_sl/dt = (C/S)(nu_sl dir S - F_sl), and each one's deviation
 *     F_j - (nu_j/nu_sl) F_sl decays by exp(-L), L = integral of C/S (Eq. 11 rewritten exactly);
 *   - static friction (prerolling off) while sliding: F_f = dir S(|v|) + sigma2 v.
 * States (x, v, F_sl, L) instead of 2 + N.
 * The method: the classical 4th-order Runge-Kutta step y1, with k5 = f(y1) the embedded
 * 3rd-order solution y + h (k1 + 2 k2 + 2 k3 + k5)/6 (its order conditions hold: sum b c^2 = 1/3,
 * sum b a c = 1/6), so the error estimate is h (k5 - k4)/6; k5 is also the next step's k1
 * (first same as last): the current jumps at the sample, but the right-hand side is affine in i
 * and F_ext, so k1 = k5 + (K_f(x1) di - dF_ext)/m in the acceleration (fast_carry_t): 4
 * right-hand sides per sample. The error test maps the reduced errors back to the full state
 * and applies the DP45's own norm (fast_tol_t). Against model exchange at rtol 1e-10 on the
 * paper's 6 s loop this step per sample is as accurate as the DP45's (README, `make bench`).
 * Cheaper right-hand side, same values to rounding:
 *   - the maps: cos/sin of the fundamental at the start of the step; at a stage the rotation by
 *     d = kw0 (x - x0) from its Taylor series (|d| <= 1/16: truncation < 1e-18), then the
 *     harmonic recurrence (posmap_eval_pair's) — no sin/cos per stage;
 *   - the Stribeck level S = F_c + (F_s - F_c) exp(-w), w = (|v|/V_s)^delta: w0 = pow() and
 *     exp(-w0) at the step's start; at a stage w - w0 = w0 ((1 + eps)^delta - 1), eps = |v|/|v0| - 1,
 *     from the binomial series to degree 12 (|eps| <= 1/16, 0 < delta <= 2: relative truncation
 *     < 5e-16) and exp(-(w - w0)) from its Taylor series to degree 8 (|w - w0| <= 1/32:
 *     truncation < 1e-19) — no pow or exp per stage; outside those bounds pow() and exp(). */
#include <math.h>

#include "fast_path.h"

/* the right-hand side and the level inlined into the stages: 4 calls per sample, each a few dozen
 * floating-point operations, whose call frames cost more than their arithmetic */
#if defined(__GNUC__)
#define HOT_INLINE inline __attribute__((always_inline))
#else
#define HOT_INLINE inline
#endif

#define NQ 4          /* x, v, F_sl, L */
#define NBIN PLANT_NBIN   /* binomial series degree */
/* level_eval's unrolled Horner sum has a case per degree up to 12 (C99: no _Static_assert) */
typedef char nbin_is_12[(NBIN == 12) ? 1 : -1];
#define ROT_MAX 0.0625
#define EPS_MAX 0.0625
#define DW_MAX 0.03125
/* EPS_DEGREE[n] = 2^(-64/(n+1)): up to this |eps| the binomial series to degree n leaves out less
 * than 2^-64 of w */
static const double EPS_DEGREE[NBIN + 1] = {0.0, 0.0, 3.78465903274584e-07, 1.52587890625e-05, 0.00014022196716272393,
    0.0006151958251439813, 0.0017689915317654432, 0.00390625, 0.0072333961897444584, 0.011841535675862483,
    0.0177236331593041, 0.024803141437003122, 0.0625};

typedef struct {
    const plant_params_t *p;
    double i, F_const;               /* current; -F_ext - F_off */
    int gms, lag, dir, side;         /* dir: slip direction (GMS) or sliding direction (static) */
    double x0, K_st, F_st0, nu_sl;
    int rot;                         /* maps by rotation from xc0 */
    double xc0, c0, s0;
    int series;                      /* Stribeck level by the binomial series about |v0| */
    double inv_v0, w0, E0;
    const double *bc;                /* p->delta_bc */
    /* what the last evaluation computed: cos/sin at its position, w and exp(-w) at its speed */
    double l_c1, l_s1, l_w, l_E, l_S;
    int l_w_ok, l_S_ok;              /* l_S_ok: the last right-hand side evaluated the level, l_S */
} rctx_t;

static double clamp(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }

static HOT_INLINE void maps(rctx_t *c, double x, double *Kf, double *Fcg) {
    const posmap_t *m1 = &c->p->rip, *m2 = &c->p->cog;
    double xc = clamp(x, c->p->x_min, c->p->x_max), d, d2, cd, sd, c1, s1;
    if (!c->rot) {
        posmap_eval_pair(m1, m2, xc, Kf, Fcg);
        return;
    }
    d = m1->kw0 * (xc - c->xc0);
    if (fabs(d) <= ROT_MAX) {
        d2 = d * d;
        cd = 1.0 - d2 * 0.5 * (1.0 - d2 * (1.0 / 12.0) * (1.0 - d2 * (1.0 / 30.0) * (1.0 - d2 * (1.0 / 56.0))));
        sd = d * (1.0 - d2 * (1.0 / 6.0) * (1.0 - d2 * (1.0 / 20.0) * (1.0 - d2 * (1.0 / 42.0) * (1.0 - d2 * (1.0 / 72.0)))));
    } else {
        cd = cos(d);
        sd = sin(d);
    }
    c1 = c->c0 * cd - c->s0 * sd;
    s1 = c->s0 * cd + c->c0 * sd;
    c->l_c1 = c1;
    c->l_s1 = s1;
    posmap_sum_pair(m1, m2, xc, c1, s1, Kf, Fcg);    /* the rotated fundamental, one recurrence */
}

/* S(|v|) on the side of the motion (friction_level's value) */
static HOT_INLINE double level_eval(rctx_t *c, double v) {
    const plant_params_t *p = c->p;
    double Fs = p->Fs[c->side], Fc = p->Fc[c->side], av = fabs(v), w;
    c->l_w_ok = 0;
    if (Fs == Fc) return Fs;
    if (c->series && av > 0.0) {
        double eps = av * c->inv_v0 - 1.0;
        if (fabs(eps) <= EPS_MAX) {
            double dw, x;
            double ae = fabs(eps);
            int top = 2;
            /* the degree this |eps| needs: the lowest (at least 2) whose terms left out are below
             * 2^-64 of w (|C(delta, j)| <= 1); EPS_DEGREE rises, so the search goes up from 2 */
            while (top < NBIN && ae > EPS_DEGREE[top]) top++;
            w = c->bc[top];
            switch (top) {   /* Horner from bc[top - 1] down to bc[1], unrolled (top <= NBIN = 12) */
            case 12: w = w * eps + c->bc[11]; /* fall through */
            case 11: w = w * eps + c->bc[10]; /* fall through */
            case 10: w = w * eps + c->bc[9]; /* fall through */
            case 9: w = w * eps + c->bc[8]; /* fall through */
            case 8: w = w * eps + c->bc[7]; /* fall through */
            case 7: w = w * eps + c->bc[6]; /* fall through */
            case 6: w = w * eps + c->bc[5]; /* fall through */
            case 5: w = w * eps + c->bc[4]; /* fall through */
            case 4: w = w * eps + c->bc[3]; /* fall through */
            case 3: w = w * eps + c->bc[2]; /* fall through */
            case 2: w = w * eps + c->bc[1]; /* fall through */
            default: break;
            }
            dw = c->w0 * (w * eps);
            if (fabs(dw) <= DW_MAX) {
                x = -dw;
                x = 1.0 + x * (1.0 + x * 0.5 * (1.0 + x * (1.0 / 3) * (1.0 + x * 0.25 * (1.0 + x * (1.0 / 5) *
                    (1.0 + x * (1.0 / 6) * (1.0 + x * (1.0 / 7) * (1.0 + x * 0.125)))))));
                c->l_w_ok = 1;
                c->l_w = c->w0 + dw;
                c->l_E = c->E0 * x;
                return Fc + (Fs - Fc) * c->l_E;
            }
            return Fc + (Fs - Fc) * exp(-(c->w0 + dw));
        }
    }
    return Fc + (Fs - Fc) * exp(-pow(av / p->Vs, p->delta));
}

/* the same, kept as the last evaluation's level (the end point's, after the last stage) */
static HOT_INLINE double level(rctx_t *c, double v) {
    c->l_S = level_eval(c, v);
    c->l_S_ok = 1;
    return c->l_S;
}

/* dq = f(q); the maps' values there into *Kf, *Fcg */
static HOT_INLINE void rhs(rctx_t *c, const double *q, double *dq, double *Kf_out, double *Fcg_out) {
    const plant_params_t *p = c->p;
    double Kf, Fcg, v = q[1], Ff, S = 1.0;
    c->l_S_ok = 0;
    maps(c, q[0], &Kf, &Fcg);
    *Kf_out = Kf;
    *Fcg_out = Fcg;
    dq[0] = v;
    dq[2] = dq[3] = 0.0;
    if (c->gms) {
        Ff = p->sigma2[v < 0.0] * v + c->F_st0 + c->K_st * (q[0] - c->x0);
        if (c->dir != 0) {
            S = level(c, v);
            if (c->lag) {
                double rate = p->C / S;
                Ff += q[2];
                dq[2] = rate * (c->nu_sl * c->dir * S - q[2]);
                dq[3] = rate;
            } else {
                Ff += c->nu_sl * c->dir * S;
            }
        }
    } else {
        Ff = c->dir * level(c, v) + p->sigma2[v < 0.0] * v;
    }
    dq[1] = (Kf * c->i - Fcg + c->F_const - Ff) / p->m;
}

/* the bases of the cheap maps and level at y: carried over from the last step (cr) or from libm */
static void setup_bases(rctx_t *c, const plant_params_t *p, const double *y, const fast_carry_t *cr) {
    double av = fabs(y[PLANT_IV]);
    c->rot = p->rip.harmonic && p->cog.harmonic && p->rip.kw0 == p->cog.kw0 && p->rip.kmax >= 1 &&
             p->cog.kmax >= 1;
    if (c->rot) {
        c->xc0 = clamp(y[PLANT_IX], p->x_min, p->x_max);
        if (cr && cr->rot_ok) {
            c->c0 = cr->c1;
            c->s0 = cr->s1;
        } else {
            c->c0 = cos(p->rip.kw0 * c->xc0);
            c->s0 = sin(p->rip.kw0 * c->xc0);
        }
    }
    c->series = av > 0.0 && p->delta > 0.0 && p->delta <= 2.0 && p->Fs[c->side] != p->Fc[c->side] &&
                c->dir != 0;
    if (c->series) {
        c->inv_v0 = 1.0 / av;
        if (cr && cr->w_ok) {
            c->w0 = cr->w1;
            c->E0 = cr->E1;
        } else {
            c->w0 = pow(av / p->Vs, p->delta);
            c->E0 = exp(-c->w0);
        }
    }
}

/* the context of a step from y: what the discrete state fixes, the bases of the cheap maps/level */
static int setup(rctx_t *c, const plant_params_t *p, const plant_disc_t *d, const plant_in_t *in,
                 const double *y, double *q, const fast_carry_t *cr) {
    int j;
    c->p = p;
    c->l_w_ok = c->l_S_ok = 0;
    c->l_c1 = c->l_s1 = c->l_w = c->l_E = c->l_S = 0.0;
    c->xc0 = c->c0 = c->s0 = c->inv_v0 = c->w0 = c->E0 = 0.0;   /* set by setup_bases where used */
    c->bc = p->delta_bc;
    c->i = current_loop_output(p, d, in->u);
    c->F_const = -in->F_ext - p->F_off;
    c->gms = p->prerolling;
    c->lag = p->lag;
    c->x0 = y[PLANT_IX];
    c->K_st = c->F_st0 = c->nu_sl = 0.0;
    q[0] = y[PLANT_IX];
    q[1] = y[PLANT_IV];
    q[2] = q[3] = 0.0;
    if (c->gms) {
        c->dir = d->dir;
        for (j = 0; j < p->N; j++) {
            if (!p->active[j]) continue;
            if (d->stuck[j]) {
                c->K_st += p->k[j];
                c->F_st0 += y[PLANT_IF + j];
            } else {
                c->nu_sl += p->nu[j];
                q[2] += y[PLANT_IF + j];
            }
        }
    } else {
        if (d->st_stuck) return 0;   /* nothing moves: the caller's business */
        c->dir = d->st_dir;
    }
    c->side = c->dir < 0;
    setup_bases(c, p, y, cr);
    return 1;
}

/* the indicators at the end of the step (gms_indicators / static_indicator) still positive;
 * S_end >= 0: the level there on side 1 (v < 0) when side_end, else side 0 (the last stage's) */
static int end_ok(const plant_params_t *p, const plant_disc_t *d, const double *y, double S_end, int side_end) {
    double v = y[PLANT_IV];
    int j, sg;
    if (!p->prerolling) return d->st_dir * v + PLANT_V_HYS > 0.0;
    if (d->dir != 0 && !(d->dir * v + PLANT_V_HYS > 0.0)) return 0;
    sg = friction_sign(v);
    {
        double S = -1.0;
        for (j = 0; j < p->N; j++) {   /* active[j] implies j < N */
            if (!p->active[j] || !d->stuck[j]) continue;
            if (S < 0.0) S = S_end >= 0.0 && side_end == (sg < 0) ? S_end : friction_level(p, v, sg < 0);
            if (!(p->nu[j] * S - sg * y[PLANT_IF + j] > 0.0)) return 0;
        }
    }
    return 1;
}

static double sq_err(double e, double a, double b, double atol, double rtol) {
    double q = e / (atol + rtol * (fabs(a) > fabs(b) ? fabs(a) : fabs(b)));
    return q * q;
}

/* the carried derivative belongs to (d, y)? Only x, v and the N elements in use enter the
 * right-hand side (fast_path_ok refuses the compliance's two states) */
static int carry_ok(const fast_carry_t *cr, int N, const plant_disc_t *d, const double *y) {
    int j;
    if (!cr || !cr->valid || cr->dir != d->dir || cr->st_dir != d->st_dir || cr->st_stuck != d->st_stuck) return 0;
    for (j = 0; j < PLANT_IF + N; j++)
        if (cr->y[j] != y[j]) return 0;
    for (j = 0; j < N; j++)
        if (cr->stuck[j] != d->stuck[j]) return 0;
    return 1;
}

/* the RK4 stages from q (k1 given) to qn, the error estimate e, k5 = f(qn), the maps at qn */
static void stages(rctx_t *c, double h, const double *q, const double *k1, double *qn, double *e,
                   double *k5, double *Kf, double *Fcg) {
    double k2[NQ], k3[NQ], k4[NQ], s[NQ];
    int j;
    for (j = 0; j < NQ; j++) s[j] = q[j] + 0.5 * h * k1[j];
    rhs(c, s, k2, Kf, Fcg);
    for (j = 0; j < NQ; j++) s[j] = q[j] + 0.5 * h * k2[j];
    rhs(c, s, k3, Kf, Fcg);
    for (j = 0; j < NQ; j++) s[j] = q[j] + h * k3[j];
    rhs(c, s, k4, Kf, Fcg);
    for (j = 0; j < NQ; j++) qn[j] = q[j] + h / 6.0 * (k1[j] + 2.0 * (k2[j] + k3[j]) + k4[j]);
    rhs(c, qn, k5, Kf, Fcg);
    for (j = 0; j < NQ; j++) e[j] = h / 6.0 * (k5[j] - k4[j]);
}

/* The error test without the divisions, where it can: with w_j = atol_j + rtol max(|y0_j|, |y1_j|)
 * >= atol_j > 0, the test's sum S = sum_j (e_j / w_j)^2 is at most B = sum_j (e_j / atol_j)^2. In
 * floating point B is taken as sum_j (e_j ia_j)^2 with ia_j = fl(1 / atol_j): each of its at most
 * 12 terms is within 3 roundings of the real one and the sum within 11 more, so the real B is at most
 * B_fl (1 + 15u) / (1 - 3u) (u = 2^-53); S in floating point (5 roundings per term, 13 in the sum)
 * exceeds the real S by at most 18u relative. So B_fl <= ERR_BOUND_MAX n_norm gives
 * S_fl / n_norm <= 0.9 (1 + 40u) < 1: the exact test would accept the step too, and is computed
 * (in the same order as ever) only when the bound does not settle it. A NaN error fails the bound
 * and goes to the exact test; a non-finite y1 (which the exact test may pass) is refused before
 * either test. */
#define ERR_BOUND_MAX 0.9

/* the full state y1 at the end from the reduced qn (x, v and the N elements' forces: the other
 * states keep y's values, the caller copies only these); 1 when every one of these is finite
 * (0 x y1_j summed: NaN as soon as one is not) and the step passes the error test (the squared RMS
 * of the weighted errors at most 1, also no NaN) */
static int full_state(const rctx_t *c, const plant_disc_t *d, const fast_tol_t *tol, const double *y,
                      const double *q, const double *qn, const double *e, double *y1) {
    const plant_params_t *p = c->p;
    const double *ia = tol->inv_atol;
    double sum, bound, dec = 1.0, ej[PLANT_NE_MAX], nonfinite;
    int j;
    y1[PLANT_IX] = qn[0];
    y1[PLANT_IV] = qn[1];
    nonfinite = 0.0 * qn[0] + 0.0 * qn[1];
    bound = (e[0] * ia[PLANT_IX]) * (e[0] * ia[PLANT_IX]) + (e[1] * ia[PLANT_IV]) * (e[1] * ia[PLANT_IV]);
    if (c->gms && c->lag && c->nu_sl > 0.0) dec = exp(-qn[3]);
    for (j = 0; j < p->N; j++) {   /* active[j] implies j < N */
        double F0 = y[PLANT_IF + j], F1 = F0;
        ej[j] = 0.0;
        if (c->gms && p->active[j]) {
            if (d->stuck[j]) {
                F1 = F0 + p->k[j] * (qn[0] - c->x0);
                ej[j] = p->k[j] * e[0];
            } else if (c->lag && c->nu_sl > 0.0) {
                double f = p->nu[j] / c->nu_sl, dev = F0 - f * q[2];
                F1 = f * qn[2] + dev * dec;
                ej[j] = f * e[2] - dev * dec * e[3];
            }
            bound += (ej[j] * ia[PLANT_IF + j]) * (ej[j] * ia[PLANT_IF + j]);
        }
        y1[PLANT_IF + j] = F1;
        nonfinite += 0.0 * F1;
    }
    if (nonfinite != 0.0) return 0;
    if (bound <= ERR_BOUND_MAX * tol->n_norm) return 1;
    sum = sq_err(e[0], y[PLANT_IX], qn[0], tol->atol[PLANT_IX], tol->rtol) +
          sq_err(e[1], y[PLANT_IV], qn[1], tol->atol[PLANT_IV], tol->rtol);
    for (j = 0; c->gms && j < p->N; j++)
        if (p->active[j])
            sum += sq_err(ej[j], y[PLANT_IF + j], y1[PLANT_IF + j], tol->atol[PLANT_IF + j], tol->rtol);
    return sum / tol->n_norm <= 1.0;
}

/* what the next step may reuse: the derivative at y1 and the bases there */
static void carry_save(fast_carry_t *cr, const rctx_t *c, const plant_disc_t *d, const plant_in_t *in,
                       const double *y1, const double *k5, double Kf, int carried) {
    int j;
    cr->valid = 1;
    for (j = 0; j < PLANT_NX; j++) cr->y[j] = y1[j];
    for (j = 0; j < PLANT_NE_MAX; j++) cr->stuck[j] = d->stuck[j];
    cr->dir = d->dir;
    cr->st_dir = d->st_dir;
    cr->st_stuck = d->st_stuck;
    cr->i = c->i;
    cr->F_ext = in->F_ext;
    cr->Kf = Kf;
    for (j = 0; j < NQ; j++) cr->k[j] = k5[j];
    /* the bases of the next step, from the last stage (re-anchored by libm every FAST_REANCHOR) */
    cr->age = carried && cr->age < FAST_REANCHOR ? cr->age + 1 : 0;
    cr->rot_ok = c->rot;
    cr->c1 = c->l_c1;
    cr->s1 = c->l_s1;
    cr->w_ok = c->series && c->l_w_ok && c->dir != 0;
    cr->w1 = c->l_w;
    cr->E1 = c->l_E;
}

int fixed_step(const plant_params_t *p, const plant_disc_t *d, const plant_in_t *in, double h,
               const fast_tol_t *tol, double *y, long long *n_rhs, fast_carry_t *carry, plant_memo_t *memo) {
    rctx_t c;
    double q[NQ], k1[NQ], k5[NQ], qn[NQ], e[NQ], y1[PLANT_NX], Kf, Fcg;
    int j;
    const int carried = carry_ok(carry, p->N, d, y);
    if (!(h > 0.0) || !setup(&c, p, d, in, y, q, carried && carry->age < FAST_REANCHOR ? carry : NULL)) return 0;
    if (carried) {
        for (j = 0; j < NQ; j++) k1[j] = carry->k[j];
        k1[1] += (carry->Kf * (c.i - carry->i) - (in->F_ext - carry->F_ext)) / p->m;
    } else {
        rhs(&c, q, k1, &Kf, &Fcg);
        ++*n_rhs;
    }
    stages(&c, h, q, k1, qn, e, k5, &Kf, &Fcg);
    *n_rhs += 4;
    if (!full_state(&c, d, tol, y, q, qn, e, y1)) return 0;
    if (!end_ok(p, d, y1, c.l_S_ok ? c.l_S : -1.0, c.side)) return 0;
    for (j = 0; j < PLANT_IF + p->N; j++) y[j] = y1[j];
    if (carry) carry_save(carry, &c, d, in, y, k5, Kf, carried);
    if (memo) {
        memo->valid = 1;
        memo->x = clamp(y1[PLANT_IX], p->x_min, p->x_max);
        memo->K_f = Kf;
        memo->F_cg = Fcg;
        if (c.l_S_ok) {   /* the level at the end point: the outputs and the event update take it */
            memo->lv_valid = 1;
            memo->lv_v = y1[PLANT_IV];
            memo->lv_x = y1[PLANT_IX];
            memo->lv_side = c.side;
            memo->lv_S = c.l_S;
        }
    }
    return 1;
}
