/* See cs_loop.h. */
#include "cs_loop.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "model_vars.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

void pid_init(pid_ctrl_t *c) {
    memset(c, 0, sizeof *c);
    c->Ts = 5e-4;
    c->kp = 6e5;
    c->kv = 4e3;
    c->ki = 2e7;
    c->n_per_v = 78.7;
    c->alpha = exp(-2.0 * M_PI * 1000.0 * c->Ts);
    c->amplitude = 0.03;
    c->omega = 2.0 * M_PI / 6.0;
    c->centre = 0.15;
    c->quantum = 1e-7;
    c->u_max = 10.0;
}

double pid_reference(const pid_ctrl_t *c, double t) { return c->centre - c->amplitude * cos(c->omega * t); }

double pid_read(const pid_ctrl_t *c, double x) { return c->quantum > 0.0 ? round(x / c->quantum) * c->quantum : x; }

double pid_step(pid_ctrl_t *c, double xm, long k) {
    double t = (double)k * c->Ts, r = pid_reference(c, t), vr = c->amplitude * c->omega * sin(c->omega * t);
    double e, F, u;
    if (!c->started) { c->x_prev = xm; c->started = 1; }
    c->v_hat = c->alpha * c->v_hat + (1.0 - c->alpha) * (xm - c->x_prev) / c->Ts;
    c->x_prev = xm;
    e = r - xm;
    c->integral += e * c->Ts;
    F = c->kp * e + c->ki * c->integral + c->kv * (vr - c->v_hat);
    u = F / c->n_per_v;
    return u > c->u_max ? c->u_max : (u < -c->u_max ? -c->u_max : u);
}

int cs_loop_open(cs_loop_t *L, const fmi_api_t *api, const char *name, const pid_ctrl_t *ctrl, double tol,
                 int substeps) {
    return cs_loop_open_with(L, api, name, ctrl, tol, substeps, -1);
}

int cs_loop_open_with(cs_loop_t *L, const fmi_api_t *api, const char *name, const pid_ctrl_t *ctrl, double tol,
                      int substeps, int fast) {
    const fmi2ValueReference fast_vr = VR_solver_fast;
    const fmi2Boolean fast_val = fast > 0;
    const fmi2ValueReference vr[3] = {VR_x, VR_v, VR_u};
    double val[3];
    memset(L, 0, sizeof *L);
    L->api = api;
    L->substeps = substeps > 0 ? substeps : 1;
    if (ctrl) L->ctrl = *ctrl;
    else pid_init(&L->ctrl);
    L->cb = host_callbacks(&L->env);
    L->comp = api->Instantiate(name, fmi2CoSimulation, MODEL_GUID, "", &L->cb, fmi2False, fmi2False);
    if (!L->comp) { fprintf(stderr, "%s: fmi2Instantiate failed: %s\n", name, L->env.last); return -1; }
    val[0] = pid_reference(&L->ctrl, 0.0);
    val[1] = 0.0;
    val[2] = pid_step(&L->ctrl, pid_read(&L->ctrl, val[0]), 0);
    if (api->SetupExperiment(L->comp, tol > 0.0, tol, 0.0, fmi2False, 0.0) > fmi2Warning ||
        api->SetReal(L->comp, vr, 3, val) > fmi2Warning ||
        (fast >= 0 && api->SetBoolean(L->comp, &fast_vr, 1, &fast_val) > fmi2Warning) ||
        api->EnterInitializationMode(L->comp) > fmi2Warning || api->ExitInitializationMode(L->comp) > fmi2Warning) {
        fprintf(stderr, "%s: initialisation failed: %s\n", name, L->env.last);
        api->FreeInstance(L->comp);
        L->comp = NULL;
        return -1;
    }
    return 0;
}

int cs_loop_step(cs_loop_t *L, cs_sample_t *s) {
    static const fmi2ValueReference out_vr[7] = {VR_x, VR_v, VR_F_motor, VR_F_cogging, VR_F_friction, VR_i,
                                                  VR_K_f};
    const fmi2ValueReference u_vr = VR_u;
    const fmi_api_t *api = L->api;
    double out[7], u = 0.0, h = L->ctrl.Ts / L->substeps;
    int st = fmi2OK, j;
    if (L->k > 0) {
        fmi2ValueReference x_vr = VR_x;
        double x;
        int r = api->GetReal(L->comp, &x_vr, 1, &x);
        if (r > st) st = r;
        u = pid_step(&L->ctrl, pid_read(&L->ctrl, x), L->k);
        r = api->SetReal(L->comp, &u_vr, 1, &u);
        if (r > st) st = r;
    } else {
        api->GetReal(L->comp, &u_vr, 1, &u);
    }
    for (j = 0; j < L->substeps; j++) {
        /* communication points on the k-grid: t = (k * substeps + j) * h, no accumulated rounding */
        double t = ((double)L->k * L->substeps + j) * h;
        double w0 = L->dostep_wall ? host_now() : 0.0;
        int r = api->DoStep(L->comp, t, h, fmi2True);
        if (L->dostep_wall && L->n_dostep < L->cap_dostep) L->dostep_wall[L->n_dostep++] = host_now() - w0;
        if (r > st) st = r;
        if (r > fmi2Warning) return st;
    }
    L->k++;
    L->t = (double)L->k * L->ctrl.Ts;
    if (s) {
        int r = api->GetReal(L->comp, out_vr, 7, out);
        if (r > st) st = r;
        s->x = out[0]; s->v = out[1]; s->F_motor = out[2]; s->F_cogging = out[3]; s->F_friction = out[4];
        s->i = out[5]; s->K_f = out[6]; s->u = u;
    }
    return st;
}

long cs_loop_stat(cs_loop_t *L, unsigned vr) {
    fmi2ValueReference r = vr;
    fmi2Integer v = -1;
    L->api->GetInteger(L->comp, &r, 1, &v);
    return (long)v;
}

void cs_loop_close(cs_loop_t *L) {
    if (!L->comp) return;
    L->api->Terminate(L->comp);
    L->api->FreeInstance(L->comp);
    L->comp = NULL;
}
