/* Compliance (effect `compliance`, beyond the paper): a second mass m2 (table, workpiece, frame)
 * on a spring k2 and damper c2 attached to the motor slide,
 *     m a = F_slide + k2 (x2 - x) + c2 (v2 - v),     m2 a2 = -k2 (x2 - x) - c2 (v2 - v),
 * with F_slide the motor force less cogging, friction, load and offset (plant.c). The states are
 * the deflection q = x2 - x and its rate w = v2 - v (small numbers with their own nominals, so
 * the integrator resolves the vibration however far the slide has travelled):
 *     dq/dt = w,   dw/dt = a2 - a = -(k2 q + c2 w) / m2 - a.
 * k2 = m2 (2 pi f)^2 and c2 = 2 zeta m2 (2 pi f) are compiled from compliance.f and
 * compliance.zeta (the effect's entry at the end): f is the load's natural frequency on its
 * spring with the slide held. The friction (stick/slip of the slide) is untouched: it is about v
 * alone. */
#include <math.h>

#include "effect.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

double compliance_force(const plant_params_t *p, const double *y) {
    return p->compliance ? p->k2 * y[PLANT_IQ] + p->c2 * y[PLANT_IW] : 0.0;
}

void compliance_derivatives(const plant_params_t *p, const double *y, double F_load, double a,
                            double *dydt) {
    if (!p->compliance) {
        dydt[PLANT_IQ] = 0.0;
        dydt[PLANT_IW] = 0.0;
        return;
    }
    dydt[PLANT_IQ] = y[PLANT_IW];
    dydt[PLANT_IW] = -F_load / p->m2 - a;
}

double compliance_x_measured(const plant_params_t *p, const double *y) {
    return (p->compliance && p->sensor_side == 1) ? y[PLANT_IX] + y[PLANT_IQ] : y[PLANT_IX];
}

double compliance_v_measured(const plant_params_t *p, const double *y) {
    return (p->compliance && p->sensor_side == 1) ? y[PLANT_IV] + y[PLANT_IW] : y[PLANT_IV];
}

void compliance_velocity_jump(const plant_params_t *p, double v_old, double *y) {
    if (p->compliance) y[PLANT_IW] += v_old - y[PLANT_IV];
}

/* ---- effect compliance: k2 = m2 w^2, c2 = 2 zeta m2 w, w = 2 pi f */
static bool compile_compliance(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    double w = 2.0 * M_PI * val[VR_compliance_f];
    (void)msg; (void)msglen;
    p->compliance = val[VR_effects_compliance] != 0.0;
    p->m2 = val[VR_compliance_m2];
    p->k2 = p->m2 * w * w;
    p->c2 = 2.0 * val[VR_compliance_zeta] * p->m2 * w;
    p->sensor_side = (int)val[VR_compliance_sensor_side];
    return true;
}

/* the coupled mode w sqrt(1 + m2/m) when on */
static bool rate_compliance(const double *val, const plant_params_t *p, effect_rate_t *best, char *buf, size_t n) {
    (void)val; (void)buf; (void)n;
    if (p->compliance) effect_rate_candidate(best, VR_compliance_f, sqrt(p->k2 / p->m2 * (1.0 + p->m2 / p->m)));
    return false;
}

/* no deflection when off */
static void init_compliance(const plant_params_t *p, double *y) {
    if (!p->compliance) y[PLANT_IQ] = y[PLANT_IW] = 0.0;
}

const effect_t effect_compliance = {
    "compliance", VR_effects_compliance, NULL, compile_compliance, NULL, rate_compliance, init_compliance, NULL};
