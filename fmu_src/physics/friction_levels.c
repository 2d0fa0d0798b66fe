/* The sliding friction levels of Eqs. 8 and 10 per direction of motion, side 0 (v > 0, and v = 0)
 * and side 1 (v < 0): the Stribeck curve
 *     S(|v|) = F_c + (F_s - F_c) exp(-(|v| / V_s)^delta)
 * and the viscous coefficient sigma2, with the three effects that are terms of them:
 *   stribeck             the drop F_s -> F_c (off: F_s = F_c, the Coulomb level everywhere);
 *   viscous              the term sigma2 v (off: sigma2 = 0);
 *   asymmetric_friction  the levels for v < 0 shifted by asymmetry.dF and asymmetry.dsigma2.
 * One file for the three: each is one term of the same two levels, compiled in this order (the
 * asymmetry shifts the levels the other two made). The GMS elements (friction_gms.c) and the
 * static model (friction_static.c) take S, scaled by p(x) (friction_position.c), and sigma2. */
#include <math.h>
#include <stdio.h>

#include "effect.h"

double friction_level(const plant_params_t *p, double v, int side) {
    double Fs = p->Fs[side], Fc = p->Fc[side];
    if (Fs == Fc) return Fs;
    return Fc + (Fs - Fc) * exp(-pow(fabs(v) / p->Vs, p->delta));
}

static void set_range(param_range_t *r, double lo, int lo_open) {
    r->lo = lo; r->lo_open = lo_open; r->hi = HUGE_VAL; r->hi_open = 1;
}

/* ---- effect stribeck: F_s, F_c, V_s, delta (F_c is the level whether or not the drop is on) */
static bool range_stribeck(unsigned vr, param_range_t *r) {
    if (vr == VR_friction_F_s || vr == VR_friction_V_s || vr == VR_friction_delta) {
        set_range(r, 0.0, 1);
        return true;
    }
    if (vr == VR_friction_F_c) { set_range(r, 0.0, 0); return true; }
    return false;
}

static bool compile_stribeck(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    int j;
    if (val[VR_friction_F_c] > val[VR_friction_F_s]) {
        snprintf(msg, msglen, "friction.F_c = %.17g exceeds friction.F_s = %.17g: allowed friction.F_c in "
                 "[0, friction.F_s] N", val[VR_friction_F_c], val[VR_friction_F_s]);
        return false;
    }
    /* without the Stribeck drop the level is the Coulomb one everywhere (the effect catalogue: F_s = F_c) */
    p->Fs[0] = val[VR_effects_stribeck] != 0.0 ? val[VR_friction_F_s] : val[VR_friction_F_c];
    p->Fc[0] = val[VR_friction_F_c];
    p->Fs[1] = p->Fs[0];
    p->Fc[1] = p->Fc[0];
    p->Vs = val[VR_friction_V_s];
    p->delta = val[VR_friction_delta];
    p->delta_bc[0] = 1.0;
    for (j = 1; j <= PLANT_NBIN; j++) p->delta_bc[j] = p->delta_bc[j - 1] * (p->delta - (j - 1)) * (1.0 / j);
    return true;
}

const effect_t effect_stribeck = {
    "stribeck", VR_effects_stribeck, range_stribeck, compile_stribeck, NULL, NULL, NULL, NULL};

/* ---- effect viscous: sigma2 */
static bool range_viscous(unsigned vr, param_range_t *r) {
    if (vr != VR_friction_sigma2) return false;
    set_range(r, 0.0, 0);
    return true;
}

static bool compile_viscous(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    (void)msg; (void)msglen;
    p->sigma2[0] = val[VR_effects_viscous] != 0.0 ? val[VR_friction_sigma2] : 0.0;
    p->sigma2[1] = p->sigma2[0];
    return true;
}

/* the viscous rate sigma2 / m (the larger side's) */
static bool rate_viscous(const double *val, const plant_params_t *p, effect_rate_t *best, char *buf, size_t n) {
    (void)val; (void)buf; (void)n;
    effect_rate_candidate(best, VR_friction_sigma2, (p->sigma2[0] > p->sigma2[1] ? p->sigma2[0] : p->sigma2[1]) / p->m);
    return false;
}

const effect_t effect_viscous = {
    "viscous", VR_effects_viscous, range_viscous, compile_viscous, NULL, rate_viscous, NULL, NULL};

/* ---- effect asymmetric_friction: the shift of the levels for v < 0, refused where it makes a
 * level negative */
static bool compile_asymmetric_friction(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    double dF = val[VR_asymmetry_dF], ds = val[VR_asymmetry_dsigma2];
    if (val[VR_effects_asymmetric_friction] == 0.0) return true;
    if (p->Fc[0] + dF < 0.0 || p->Fs[0] + dF <= 0.0) {
        snprintf(msg, msglen, "asymmetry.dF = %.17g makes the friction level for v < 0 negative: "
                 "allowed [%.17g, inf) N", dF, -p->Fc[0]);
        return false;
    }
    if (p->sigma2[0] + ds < 0.0) {
        snprintf(msg, msglen, "asymmetry.dsigma2 = %.17g makes the viscous coefficient for v < 0 negative: "
                 "allowed [%.17g, inf) N.s/m", ds, -p->sigma2[0]);
        return false;
    }
    p->Fs[1] += dF;
    p->Fc[1] += dF;
    p->sigma2[1] += val[VR_effects_viscous] != 0.0 ? ds : 0.0;
    return true;
}

const effect_t effect_asymmetric_friction = {
    "asymmetric_friction", VR_effects_asymmetric_friction, NULL, compile_asymmetric_friction, NULL, NULL, NULL, NULL};
