/* The plant of docs/model.md (paper Eqs. 1-12): data and pure functions of state and parameters.
 * Knows nothing of FMI and nothing of any solver. All quantities SI. */
#ifndef PLANT_H
#define PLANT_H

#include <stdbool.h>
#include <stddef.h>

#define PLANT_NE_MAX 10      /* GMS element slots */
#define PLANT_NH_MAX 8       /* Fourier slots per position map */
#define PLANT_NA_MAX 5       /* current loop: i[k-1..k-5] */
#define PLANT_NB_MAX 6       /* current loop: u[k..k-5] */
#define PLANT_NPF_MAX 16     /* knots of the friction-level profile (position_friction) */
#define PLANT_NBIN 12        /* degree of the binomial series of (1 + eps)^delta (solver_fixed.c) */
#define PLANT_NMULT 24       /* highest multiple of the fundamental evaluated by recurrence */
#define PLANT_NX_BASE (2 + PLANT_NE_MAX)      /* x, v, F_1..F_10 */
#define PLANT_NX (PLANT_NX_BASE + 2)          /* + the compliance's deflection and its rate */
#define PLANT_NZ (PLANT_NE_MAX + 1)   /* one per element + one for the motion direction */
#define PLANT_IX 0
#define PLANT_IV 1
#define PLANT_IF 2
#define PLANT_IQ PLANT_NX_BASE        /* compliance: deflection x_load - x [m] */
#define PLANT_IW (PLANT_NX_BASE + 1)  /* compliance: its rate v_load - v [m/s] */
/* Hysteresis of the velocity zero-crossing indicator [m/s]: the crossing is taken at
 * dir*v = -PLANT_V_HYS, so no indicator is left at exactly 0 after an event. */
#define PLANT_V_HYS 1e-9

/* A position map: polynomial (aperiodic) + Fourier terms each with its own wavelength. */
typedef struct {
    int npoly;                       /* number of polynomial coefficients */
    double c[4];
    int nh;                          /* Fourier terms in use (nonzero amplitude) */
    double kw[PLANT_NH_MAX];         /* 2*pi/lambda [1/m] */
    double a[PLANT_NH_MAX], b[PLANT_NH_MAX];
    /* fast path: every term a harmonic of kw0 -> amplitudes summed per multiple (1..PLANT_NMULT) */
    int harmonic, kmax;
    double kw0, ha[PLANT_NMULT + 1], hb[PLANT_NMULT + 1];
} posmap_t;

/* Compiled parameters (from the FMU's values, effects applied). */
typedef struct {
    double m, Ts;
    bool current_dynamics;
    double ca[PLANT_NA_MAX], cb[PLANT_NB_MAX];
    double G1;                        /* DC gain of the current loop [A/V] */
    posmap_t cog, rip;
    double x_min, x_max;
    /* friction */
    bool prerolling, lag;
    double Fs[2], Fc[2], sigma2[2];   /* [0]: v > 0 (and v = 0), [1]: v < 0 */
    double Vs, delta, C;
    double delta_bc[PLANT_NBIN + 1];  /* binomial coefficients C(delta, j), j = 0..PLANT_NBIN */
    int N;                            /* elements in use */
    double nu[PLANT_NE_MAX], k[PLANT_NE_MAX];
    bool active[PLANT_NE_MAX];        /* i < N and nu_i > 0 */
    double F_off;
    /* position_friction: level factor p(x), a uniform cubic B-spline (friction_position.c) */
    bool posfric;
    int pf_n;                         /* knots in use (2..PLANT_NPF_MAX) */
    double pf_x0, pf_h;               /* first knot [m], knot spacing [m] */
    double pf_c[PLANT_NPF_MAX];       /* relative level change at the knots [-] */
    /* compliance (compliance.c): load m2 on a spring k2 and damper c2 on the slide */
    bool compliance;
    double m2, k2, c2;
    int sensor_side;                  /* 0: encoder on the motor slide, 1: on the load */
} plant_params_t;

/* Discrete state. */
typedef struct {
    /* current loop */
    double i;                         /* held current [A] */
    double ih[PLANT_NA_MAX];          /* i[k-1], i[k-2], ... */
    double uh[PLANT_NB_MAX];          /* u[k-1], u[k-2], ... (uh[0] = u[k-1]) */
    long long k;                           /* index of the last processed sample */
    /* GMS */
    bool stuck[PLANT_NE_MAX];
    int dir;                          /* direction of the slipping elements (+1/-1), 0: none slips */
    /* static friction (prerolling off): Karnopp stick/slide */
    bool st_stuck;
    int st_dir;
    /* statistics */
    long long n_stick, n_slip, n_time_events, n_state_events;
} plant_disc_t;

/* Inputs. */
typedef struct { double u, F_ext; } plant_in_t;

/* Everything derived from (params, discrete state, continuous state, inputs). */
typedef struct {
    double i, K_f, F_cg, F_motor, F_fric, F_elem[PLANT_NE_MAX], a;
    double F_load;                    /* compliance: force of the load's spring-damper on the slide */
    double x_meas, x_load, v_load;    /* the encoder's position, the load's position and velocity */
    int n_stuck;
} plant_out_t;

/* The last evaluation of both position maps (K_f, F_cg at a clamped position) and of the scaled
 * Stribeck level (friction_level_at at v, x, side), owned by the caller: a step's last stage, the
 * outputs read there and the event update at the next step's start share the point, so each is
 * computed once. The caller calls plant_memo_reset whenever the parameters are compiled again. */
typedef struct {
    int valid;
    double x, K_f, F_cg;
    int lv_valid, lv_side;
    double lv_v, lv_x, lv_S;
} plant_memo_t;
void plant_memo_reset(plant_memo_t *memo);
/* friction_level_at(p, v, x, side), from the memo (may be NULL) when it holds that very point */
double friction_level_memo(const plant_params_t *p, plant_memo_t *memo, double v, double x, int side);

/* position_maps.c */
double posmap_eval(const posmap_t *m, double x);
void posmap_prepare(posmap_t *m);   /* fill the fast-path fields from kw, a, b */
void posmap_eval_pair(const posmap_t *m1, const posmap_t *m2, double x, double *f1, double *f2);
/* the polynomial part of a map at x: Horner from c[npoly - 1] down to c[0], unrolled (npoly <= 4) */
static inline double posmap_poly(const posmap_t *m, double x) {
    double a = 0.0;
    switch (m->npoly) {
    case 4: a = a * x + m->c[3]; /* fall through */
    case 3: a = a * x + m->c[2]; /* fall through */
    case 2: a = a * x + m->c[1]; /* fall through */
    case 1: a = a * x + m->c[0]; /* fall through */
    default: break;
    }
    return a;
}

/* Both maps of a shared fundamental at x, given c1 = cos(kw0 x) and s1 = sin(kw0 x) (however
 * the caller got them): the polynomials and one recurrence for every harmonic. Inline: the
 * per-sample scheme evaluates it at each of its 4 stages. */
static inline void posmap_sum_pair(const posmap_t *m1, const posmap_t *m2, double x, double c1, double s1,
                                   double *f1, double *f2) {
    double ck = c1, sk = s1, t, a = posmap_poly(m1, x), b = posmap_poly(m2, x);
    int k, kmax = m1->kmax > m2->kmax ? m1->kmax : m2->kmax;
    for (k = 1;; k++) {
        a += m1->ha[k] * ck + m1->hb[k] * sk;
        b += m2->ha[k] * ck + m2->hb[k] * sk;
        if (k == kmax) break;
        t = ck * c1 - sk * s1;
        sk = sk * c1 + ck * s1;
        ck = t;
    }
    *f1 = a;
    *f2 = b;
}

/* current_loop.c */
void current_loop_init(const plant_params_t *p, plant_disc_t *d, double u0);
void current_loop_sample(const plant_params_t *p, plant_disc_t *d, double u);
double current_loop_output(const plant_params_t *p, const plant_disc_t *d, double u);

/* friction_levels.c: the Stribeck level S(|v|) for side 0 (+) / 1 (-) */
double friction_level(const plant_params_t *p, double v, int side);

/* friction_gms.c */
int friction_sign(double v);
/* memo (may be NULL): the Stribeck level's (plant_memo_t) */
void gms_element_forces(const plant_params_t *p, const plant_disc_t *d, const double *y, plant_memo_t *memo,
                        double *Fe);
void gms_derivatives(const plant_params_t *p, const plant_disc_t *d, const double *y, plant_memo_t *memo,
                     double *dF);
void gms_indicators(const plant_params_t *p, const plant_disc_t *d, const double *y, double *z);
void gms_init(const plant_params_t *p, plant_disc_t *d, const double *y);
int gms_update(const plant_params_t *p, plant_disc_t *d, double *y, plant_memo_t *memo, bool *y_changed);
int gms_n_stuck(const plant_params_t *p, const plant_disc_t *d);
/* elements switched on or off by a parameter change (old -> p) start stuck at zero force */
void gms_retune(const plant_params_t *old, const plant_params_t *p, plant_disc_t *d, double *y);

/* GMS along a sampled motion (the controller's feedforward; Python twin
 * feeddrive.physics.friction_gms.gms_force): the velocity is linear between samples, an
 * interval where it changes sign is split at the crossing, each piece is exact. */
typedef struct {
    double F[PLANT_NE_MAX];
    bool stuck[PLANT_NE_MAX];
    double x, v, last_dir;
    bool started;
} gms_track_t;
void gms_track_init(gms_track_t *g);
/* advance to (x, v) a time dt after the previous sample; returns F_f there [N] */
double gms_track_step(const plant_params_t *p, gms_track_t *g, double x, double v, double dt);

/* friction_position.c: p(x) (1 when position_friction is off), the scaled level p(x) S(|v|) of
 * side 0 (+) / 1 (-), and the scaled break-away level p(x) F_s of a side */
double friction_profile(const plant_params_t *p, double x);
double friction_level_at(const plant_params_t *p, double v, double x, int side);
double friction_break_away(const plant_params_t *p, double x, int side);

/* friction_static.c */
double static_friction(const plant_params_t *p, const plant_disc_t *d, double x, double v, double F_app);
double static_indicator(const plant_params_t *p, const plant_disc_t *d, double x, double v, double F_app);
void static_init(const plant_params_t *p, plant_disc_t *d, double *y, double F_app);
int static_update(const plant_params_t *p, plant_disc_t *d, double *y, double F_app, bool *y_changed);

/* compliance.c: the load m2 on a spring-damper (k2, c2) attached to the slide, states
 * q = x_load - x and w = v_load - v (y[PLANT_IQ], y[PLANT_IW]); everything 0 when off */
double compliance_force(const plant_params_t *p, const double *y);   /* k2 q + c2 w [N] on the slide */
void compliance_derivatives(const plant_params_t *p, const double *y, double F_load, double a,
                            double *dydt);                           /* dq, dw from the slide's a */
double compliance_x_measured(const plant_params_t *p, const double *y);   /* the encoder's position */
double compliance_v_measured(const plant_params_t *p, const double *y);
/* the slide's velocity set from v_old to y[PLANT_IV] by an event: the load keeps its velocity */
void compliance_velocity_jump(const plant_params_t *p, double v_old, double *y);

/* plant_state.c: the discrete state as PLANT_ND numbers (saved FMU states); unpack checks every
 * field (flags, directions, finite values, exact counts) and names the first bad one in msg */
#define PLANT_ND (1 + PLANT_NA_MAX + PLANT_NB_MAX + 1 + PLANT_NE_MAX + 3 + 4)
void plant_disc_pack(const plant_disc_t *d, double *w);
bool plant_disc_unpack(const double *w, plant_disc_t *d, char *msg, size_t msglen);

/* plant.c: Eq. 1 assembled */
void plant_init(const plant_params_t *p, plant_disc_t *d, double *y, const plant_in_t *in);
void plant_outputs(const plant_params_t *p, const plant_disc_t *d, const double *y,
                   const plant_in_t *in, plant_out_t *o);
void plant_derivatives(const plant_params_t *p, const plant_disc_t *d, const double *y,
                       const plant_in_t *in, double *dydt);
/* the same with the maps' memo (may be NULL) */
void plant_outputs_memo(const plant_params_t *p, const plant_disc_t *d, const double *y,
                        const plant_in_t *in, plant_memo_t *memo, plant_out_t *o);
void plant_derivatives_memo(const plant_params_t *p, const plant_disc_t *d, const double *y,
                            const plant_in_t *in, plant_memo_t *memo, double *dydt);
/* the same derivatives from outputs o already computed at (d, y) (no second evaluation; memo may
 * be NULL) */
void plant_state_derivatives(const plant_params_t *p, const plant_disc_t *d, const double *y,
                             const plant_out_t *o, plant_memo_t *memo, double *dydt);
void plant_indicators(const plant_params_t *p, const plant_disc_t *d, const double *y,
                      const plant_in_t *in, double *z);
/* Event update at time t: processes the current-loop sample when sample_due, then every
 * stick/slip switch the state calls for. Returns the number of friction switches. */
int plant_event_update(const plant_params_t *p, plant_disc_t *d, double *y, const plant_in_t *in,
                       bool sample_due, plant_memo_t *memo, bool *y_changed);
/* the event indicators are functions of (d, y) alone, not of the inputs (GMS; the static model's
 * depend on the applied force) */
bool plant_indicators_of_state(const plant_params_t *p);
/* the event update where every event indicator is known to be > 0 (no friction switch is due):
 * the current-loop sample alone */
void plant_sample_update(const plant_params_t *p, plant_disc_t *d, const plant_in_t *in);
/* friction elements stuck (GMS), or 1/0 for the static model stuck/sliding */
int plant_n_stuck(const plant_params_t *p, const plant_disc_t *d);
/* after tunable parameters changed from old to p: the discrete and continuous state to match */
void plant_retune(const plant_params_t *old, const plant_params_t *p, plant_disc_t *d, double *y);

#endif
