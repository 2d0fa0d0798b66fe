/* One hour of simulated closed-loop motion (the 30 mm / 6 s sinusoid repeated 600 times, 2 kHz
 * PID, 100 nm scale, one 0.5 ms fmi2DoStep per sample) must finish, keep tracking, and keep its
 * energy balance
 *     m v(T)^2/2 - m v(0)^2/2 = W_motor - W_cogging - W_friction - W_offset,
 * W_f = integral of F_f v dt by the trapezoidal rule on each 0.5 ms sample interval, and
 * W_offset = F_off (x(T) - x(0)). The motor force jumps at the current-loop samples (taken at
 * the start of each fmi2DoStep) and is K_f(x) i with i held over the interval, so its value just
 * after t_k is K_f(x_k) i[k]: K_f(x_k) read at t_k, i[k] read at t_{k+1}.
 * Usage: hour_run LinearMotorFeedDrive.so [seconds=3600] [max_relative_residual=1e-5].
 * Prints the figures as JSON, PASS/FAIL lines and "N passed, M failed". */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "cs_loop.h"
#include "model_vars.h"

static int n_pass = 0, n_fail = 0;

static void check(int ok, const char *what) {
    printf("%s %s\n", ok ? "PASS" : "FAIL", what);
    if (ok) n_pass++; else n_fail++;
}

int main(int argc, char **argv) {
    fmi_api_t api;
    char err[512], line[256];
    double T = argc > 2 ? atof(argv[2]) : 3600.0, max_rel = argc > 3 ? atof(argv[3]) : 1e-5;
    long n = (long)(T / 5e-4 + 0.5), k, n_state, n_warn;
    cs_loop_t L;
    cs_sample_t p, s;
    double m, F_off, x0, v0, W_motor = 0.0, W_cog = 0.0, W_fric = 0.0, W_fric_abs = 0.0, W_motor_abs = 0.0;
    double W_off, dKE, resid, max_err = 0.0, max_err_last = 0.0, w0, wall, h = 5e-4;
    int finite = 1;
    if (fmi_api_load(&api, argc > 1 ? argv[1] : NULL, err, sizeof err) != 0) { fprintf(stderr, "%s\n", err); return 2; }
    if (cs_loop_open(&L, &api, "hour", NULL, 0.0, 1) != 0) return 1;
    {
        fmi2ValueReference vr[8] = {VR_m, VR_offset_F, VR_x, VR_v, VR_F_motor, VR_F_cogging, VR_F_friction, VR_K_f};
        double v[8];
        fmi2ValueReference bvr = VR_effects_offset_force;
        fmi2Boolean on = fmi2False;
        api.GetReal(L.comp, vr, 8, v);
        api.GetBoolean(L.comp, &bvr, 1, &on);
        m = v[0];
        F_off = on ? v[1] : 0.0;
        p.x = x0 = v[2];
        p.v = v0 = v[3];
        p.F_motor = v[4]; p.F_cogging = v[5]; p.F_friction = v[6]; p.K_f = v[7];
    }
    n_warn = L.env.n_msgs;
    w0 = host_now();
    for (k = 0; k < n; k++) {
        double e, Pm;
        if (cs_loop_step(&L, &s) > fmi2Warning) { fprintf(stderr, "t = %g s: %s\n", L.t, L.env.last); return 1; }
        Pm = 0.5 * h * (p.K_f * s.i * p.v + s.F_motor * s.v);
        W_motor += Pm;
        W_motor_abs += fabs(Pm);
        W_cog += 0.5 * h * (p.F_cogging * p.v + s.F_cogging * s.v);
        e = 0.5 * h * (p.F_friction * p.v + s.F_friction * s.v);
        W_fric += e;
        W_fric_abs += fabs(e);
        if (!isfinite(s.x) || !isfinite(s.v) || !isfinite(s.F_friction) || !isfinite(s.i)) { finite = 0; break; }
        p = s;
        e = fabs(s.x - pid_reference(&L.ctrl, L.t));
        if (e > max_err) max_err = e;
        if (k >= n - 12000 && e > max_err_last) max_err_last = e;
    }
    wall = host_now() - w0;
    n_state = cs_loop_stat(&L, VR_stats_n_state_events);
    n_warn = L.env.n_msgs - n_warn;
    W_off = F_off * (p.x - x0);
    dKE = 0.5 * m * (p.v * p.v - v0 * v0);
    resid = dKE - (W_motor - W_cog - W_fric - W_off);
    printf("{\"simulated_s\": %g, \"wall_s\": %.4g, \"real_time_factor\": %.4g, \"W_motor_J\": %.9g, "
           "\"W_cogging_J\": %.9g, \"W_friction_J\": %.9g, \"W_offset_J\": %.9g, \"dKE_J\": %.9g, "
           "\"residual_J\": %.6g, \"relative_residual\": %.3g, \"max_tracking_error_m\": %.4g, "
           "\"max_tracking_error_last_period_m\": %.4g, \"state_events\": %ld, \"messages\": %ld}\n",
           T, wall, T / wall, W_motor, W_cog, W_fric, W_off, dKE, resid, fabs(resid) / W_motor_abs, max_err,
           max_err_last, n_state, n_warn);
    check(finite && k == n, "the run reached its end with finite states");
    snprintf(line, sizeof line, "energy balance: |residual| %.3g J <= %g of the motor's work %.4g J", fabs(resid),
             max_rel, W_motor_abs);
    check(fabs(resid) <= max_rel * W_motor_abs, line);
    check(W_fric > 0.0, "friction dissipates (W_friction > 0)");
    snprintf(line, sizeof line, "tracking error over the last period %.3g m equals the run's worst %.3g m within "
             "a factor 1.5 (no drift)", max_err_last, max_err);
    check(max_err_last < 50e-6 && max_err < 1.5 * max_err_last + 5e-6, line);
    check(n_warn == 0, "the FMU logged nothing (no stroke or integrator warnings)");
    cs_loop_close(&L);
    fmi_api_unload(&api);
    printf("%d passed, %d failed\n", n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
}
