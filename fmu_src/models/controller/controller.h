/* The drive controller of feeddrive's harness (python/feeddrive/control, harness/controllers.py)
 * as plain data and pure functions: compiled parameters, the per-sample state, the reference
 * generator, the feedforward on a nominal plant (the plant FMU's own C physics: position_maps.c,
 * friction_gms.c, params.c) and the control laws. Knows nothing of FMI. All quantities SI. */
#ifndef CONTROLLER_H
#define CONTROLLER_H

#include <stdbool.h>
#include <stddef.h>

#include "plant.h"

#define CTRL_NS_MAX 8        /* state-space controller states */
#define CTRL_NZ_MAX 16       /* ZPETC coefficients (order + 1) */
#define CTRL_PREVIEW_MAX 64  /* ZPETC preview [samples] */
#define CTRL_RB (CTRL_PREVIEW_MAX + 1)
/* the most samples a reference may last: an exact double and a long long (sample indices) */
#define REF_MAX_SAMPLES 1e15

enum { CTRL_STATE_SPACE = 1, CTRL_PID = 2, CTRL_PID_LEAD = 3, CTRL_LTI = 4 };
enum { REF_INPUT = 0, REF_SINUSOID = 1, REF_POINT_TO_POINT = 2 };
enum { FF_FRICTION_NONE = 0, FF_FRICTION_STATIC = 1, FF_FRICTION_GMS = 2 };

/* Compiled parameters. */
typedef struct {
    double Ts, u_limit, quantum;
    int type, source;
    int delay;                        /* computation delay [samples], 0 or 1 (ctrl.delay) */
    /* state space: u = Cc s + Dy y + Dr r + u_ff;  s <- Ac s + By y + Br r + Bu (u - u_ff) */
    int n;
    double Ac[CTRL_NS_MAX][CTRL_NS_MAX], By[CTRL_NS_MAX], Br[CTRL_NS_MAX], Bu[CTRL_NS_MAX],
        Cc[CTRL_NS_MAX], Dy, Dr;
    /* any linear controller (feeddrive.control.lti), inputs e = (r, y):
     * v = C s + D e; u = clamp(v + u_ff); s <- A s + B e + L (u - v - u_ff); first s = s0 + s0_r r */
    int lti_n;
    double lti_A[CTRL_NS_MAX][CTRL_NS_MAX], lti_B[CTRL_NS_MAX][2], lti_C[CTRL_NS_MAX], lti_D[2],
        lti_L[CTRL_NS_MAX], lti_s0[CTRL_NS_MAX], lti_s0_r[CTRL_NS_MAX];
    /* PID (force equivalent) and lead (Tustin of (1 + s/w_z)/(1 + s/w_p)) */
    double Kp, Kv, Ki, fpv, tf, pid_a, pid_b;
    bool anti_windup, lead;
    double lead_b0, lead_b1, lead_a1;
    /* ZPETC pre-filter (direct form II transposed, as scipy.signal.lfilter) */
    bool zpetc;
    int preview, nzc;                 /* nzc = order + 1 coefficients */
    double zb[CTRL_NZ_MAX], za[CTRL_NZ_MAX], zi[CTRL_NZ_MAX];
    /* reference generator */
    double amp, w, centre, phase;     /* sinusoid */
    long long n_sin;
    double x_start, sgn, speed, accel, dwell, t_acc, t_cruise;   /* point to point */
    double p2p_samples;               /* ceil(duration of the move / Ts), checked before n_p2p */
    long long n_p2p;
    /* feedforward */
    bool ff, ff_inertia, ff_cogging, ff_ripple, ff_offset;
    int ff_friction;
    double v_eps;
    plant_params_t plant;             /* the nominal plant, compiled by params.c */
} ctrl_params_t;

/* The reference stream: sample j of the internal generator (sequential j). */
typedef struct { long long j; double cs; } ref_gen_t;

/* Everything that changes from sample to sample. */
typedef struct {
    long long k;                           /* index of the next sample */
    double y_prev;                    /* x_meas of the last sample (ctrl.delay 1 reads it) */
    double s[CTRL_NS_MAX];
    bool fresh;
    double q, D, e_prev, F_prev, L_prev;
    bool has_e_prev;
    double z[CTRL_NZ_MAX];            /* ZPETC filter state */
    double rx[CTRL_RB], rv[CTRL_RB], ra[CTRL_RB];   /* reference samples k..k+preview */
    ref_gen_t gen;
    gms_track_t gms;
    double u, x_cmd, u_ff, r_x;       /* outputs of the last sample */
    double u_law;                     /* u of the last sample before the clamp */
} ctrl_state_t;

typedef struct { double x_ref, v_ref, a_ref, x_meas; } ctrl_in_t;

/* ctrl_reference.c: sample j of the internal reference (x, v, a) */
/* derived constants; n_sin only for a sinusoid (duration checked first), n_p2p left to ctrl_compile */
void ref_prepare(ctrl_params_t *p, double duration, double x_end);
void ref_sample(const ctrl_params_t *p, ref_gen_t *g, long long j, double *x, double *v, double *a);

/* ctrl_feedforward.c: u_ff [V] at the reference (x, v, a); advances the GMS along the reference */
double feedforward_sample(const ctrl_params_t *p, gms_track_t *g, double x, double v, double a);

/* ctrl_law.c */
void ctrl_reset(const ctrl_params_t *p, ctrl_state_t *s);
/* one sample: u (and x_cmd, u_ff, r_x) from the inputs of this instant (with ctrl.delay 1, from
 * the x_meas of the previous sample, the first sample's own at k = 0); advances the state.
 * false when a number it produced or keeps is not finite (a diverging controller or filter,
 * inputs out of scale), with `why` naming it; the state is then unusable */
bool ctrl_sample(const ctrl_params_t *p, ctrl_state_t *s, const ctrl_in_t *in, char *why, size_t whylen);

#endif
