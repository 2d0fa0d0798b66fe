/* Model-based feedforward on the nominal plant (feeddrive.control.feedforward, current_loop "dc"):
 *   F_ff = [m a_ref] + [F_cg(x_ref)] + [F_offset] + [F_f(x_ref, v_ref)],  u_ff = F_ff / (K_f G(1))
 * with K_f = K_f(x_ref) (ripple) or K_f0, the maps at x clamped to the stroke (position_maps.c),
 * the friction the regularised Eq. 12 (friction_level_at of friction_position.c: the level at x_ref)
 * or the GMS along the reference (gms_track_step of friction_gms.c): the plant FMU's own physics. */
#include <math.h>

#include "controller.h"

double feedforward_sample(const ctrl_params_t *p, gms_track_t *g, double x, double v, double a) {
    const plant_params_t *pp = &p->plant;
    double total = 0.0, K_f, xc = fmin(fmax(x, pp->x_min), pp->x_max);
    double F_fric = 0.0;
    /* the GMS follows the whole reference, whatever the other switches */
    if (p->ff_friction == FF_FRICTION_GMS) F_fric = gms_track_step(pp, g, x, v, p->Ts);
    else if (p->ff_friction == FF_FRICTION_STATIC)
        F_fric = friction_level_at(pp, v, x, v < 0.0) * tanh(v / p->v_eps) + pp->sigma2[v < 0.0] * v;
    if (p->ff_inertia) total = total + pp->m * a;
    if (p->ff_cogging) total = total + posmap_eval(&pp->cog, xc);
    if (p->ff_offset && pp->F_off != 0.0) total = total + pp->F_off;
    if (p->ff_friction != FF_FRICTION_NONE) total = total + F_fric;
    K_f = p->ff_ripple ? posmap_eval(&pp->rip, xc) : pp->rip.c[0];
    return total / (K_f * pp->G1);
}
