/* Compliance (effect `compliance`, beyond the paper): a second mass m2 (table, workpiece, frame)
 * on a spring k2 and damper c2 attached to the motor slide,
 *     m a = F_slide + k2 (x2 - x) + c2 (v2 - v),     m2 a2 = -k2 (x2 - x) - c2 (v2 - v),
 * with F_slide the motor force less cogging, friction, load and offset (plant.c). The states are
 * the deflection q = x2 - x and its rate w = v2 - v (small numbers with their own nominals, so
 * the integrator resolves the vibration however far the slide has travelled):
 *     dq/dt = w,   dw/dt = a2 - a = -(k2 q + c2 w) / m2 - a.
 * k2 = m2 (2 pi f)^2 and c2 = 2 zeta m2 (2 pi f) are compiled from compliance.f and
 * compliance.zeta (params.c): f is the load's natural frequency on its spring with the slide
 * held. The friction (stick/slip of the slide) is untouched: it is about v alone. */
#include "plant.h"

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
