/* The paper's Sec. 3 closed loop driven from C through fmi2DoStep: a 2 kHz discrete PID on the
 * 100 nm-quantised position following x_ref = centre - A cos(2 pi t / P) (starts at rest at the
 * bottom reversal). Force-equivalent gains, output u = F / (K_f0 G(1)) = F / 78.7 N/V, |u| <= 10 V,
 * velocity by backward difference of the reading low-passed at 1 kHz. The same controller as
 * tests/test_cs_agreement.py's PID. */
#ifndef CS_LOOP_H
#define CS_LOOP_H

#include "fmi_host.h"

typedef struct {
    double Ts, kp, kv, ki, n_per_v, alpha, amplitude, omega, centre, quantum, u_max;
    double integral, x_prev, v_hat;
    int started;
} pid_ctrl_t;

/* defaults: Ts 0.5 ms, Kp 6e5 N/m, Kv 4e3 N s/m, Ki 2e7 N/(m s), 78.7 N/V, 1 kHz velocity filter,
 * 30 mm / 6 s / 150 mm, 100 nm */
void pid_init(pid_ctrl_t *c);
double pid_reference(const pid_ctrl_t *c, double t);
double pid_read(const pid_ctrl_t *c, double x);     /* the scale's reading of x */
double pid_step(pid_ctrl_t *c, double x_meas, long k);

/* One CS instance of the FMU at x0 with the controller's first output as u. */
typedef struct {
    const fmi_api_t *api;
    fmi2Component comp;
    host_env_t env;
    fmi2CallbackFunctions cb;
    pid_ctrl_t ctrl;
    long k;                 /* controller samples done */
    double t;
    int substeps;           /* communication steps per controller sample */
    double *dostep_wall;    /* if set: wall time of each fmi2DoStep call is stored here */
    long n_dostep, cap_dostep;
} cs_loop_t;

/* Signals read after each controller sample. */
typedef struct { double x, v, F_motor, F_cogging, F_friction, i, K_f, u; } cs_sample_t;

/* instantiate + setup + initialise, at rest at the reference's start; ctrl NULL: pid_init's
 * controller; tol <= 0 keeps the FMU's default. Returns 0 or -1 (message
 * on stderr). */
int cs_loop_open(cs_loop_t *L, const fmi_api_t *api, const char *name, const pid_ctrl_t *ctrl, double tol,
                 int substeps);
/* the same with solver.fast set to fast (0/1; < 0: the FMU's default) */
int cs_loop_open_with(cs_loop_t *L, const fmi_api_t *api, const char *name, const pid_ctrl_t *ctrl, double tol,
                      int substeps, int fast);
/* one controller sample: read x, compute u, set it, fmi2DoStep(s) over Ts; fills *s (may be NULL)
 * with the values at the end of the sample. Returns the worst fmi2Status of the calls. */
int cs_loop_step(cs_loop_t *L, cs_sample_t *s);
void cs_loop_close(cs_loop_t *L);
/* read an Integer statistic (e.g. VR_stats_n_state_events) */
long cs_loop_stat(cs_loop_t *L, unsigned vr);

#endif
