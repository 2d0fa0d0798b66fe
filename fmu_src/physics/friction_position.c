/* Effect position_friction: the friction level varying along the stroke (guideway wear,
 * lubrication, preload).  The whole Stribeck level of either side is scaled,
 *     S(|v|, x) = p(x) S(|v|),    p(x) = 1 + sum_j c_j B_j(x),
 * with B_j a uniform cubic B-spline on n knots x_j = x_start + (j - 1) h, h = (x_end -
 * x_start) / (n - 1); the control values beyond the ends are mirrored (c_0 = c_2,
 * c_{n+1} = c_{n-1}) so p'(x_start) = p'(x_end) = 0, and p is held constant outside
 * [x_start, x_end]: p is C1 everywhere (C2 inside), linear in c, and lies within
 * [1 + min c_j, 1 + max c_j] (the B-spline's convex hull), so c_j >= -0.9 keeps p >= 0.1
 * without a further rule.  The viscous term is not scaled.  p(x) is smooth, so the stick/slip
 * indicators, which use the scaled level, need no new event.  Python twin:
 * feeddrive.physics.friction_position. */
#include <math.h>
#include <stdio.h>

#include "effect.h"

/* mirrored control value: index i of 0..n-1, i = -1 -> 1, i = n -> n - 2 */
static double ctrl(const plant_params_t *p, int i) {
    if (i < 0) i = -i;
    if (i > p->pf_n - 1) i = 2 * (p->pf_n - 1) - i;
    return p->pf_c[i];
}

double friction_profile(const plant_params_t *p, double x) {
    double u, t, s, w0, w1, w2, w3;
    int k;
    if (!p->posfric) return 1.0;
    u = (x - p->pf_x0) / p->pf_h;
    if (!(u > 0.0)) u = 0.0;                          /* also a NaN position: p(x_start) */
    if (u > (double)(p->pf_n - 1)) u = (double)(p->pf_n - 1);
    k = (int)floor(u);
    if (k > p->pf_n - 2) k = p->pf_n - 2;
    t = u - (double)k;
    w0 = (1.0 - t) * (1.0 - t) * (1.0 - t) / 6.0;
    w1 = (3.0 * t * t * t - 6.0 * t * t + 4.0) / 6.0;
    w2 = (-3.0 * t * t * t + 3.0 * t * t + 3.0 * t + 1.0) / 6.0;
    w3 = t * t * t / 6.0;
    s = w0 * ctrl(p, k - 1) + w1 * ctrl(p, k) + w2 * ctrl(p, k + 1) + w3 * ctrl(p, k + 2);
    return 1.0 + s;
}

double friction_level_at(const plant_params_t *p, double v, double x, int side) {
    return friction_profile(p, x) * friction_level(p, v, side);
}

void plant_memo_reset(plant_memo_t *memo) {
    memo->valid = 0;
    memo->lv_valid = 0;
}

double friction_level_memo(const plant_params_t *p, plant_memo_t *memo, double v, double x, int side) {
    double S;
    if (!memo) return friction_level_at(p, v, x, side);
    if (memo->lv_valid && memo->lv_v == v && memo->lv_x == x && memo->lv_side == side) return memo->lv_S;
    S = friction_level_at(p, v, x, side);
    memo->lv_valid = 1;
    memo->lv_v = v;
    memo->lv_x = x;
    memo->lv_side = side;
    memo->lv_S = S;
    return S;
}

double friction_break_away(const plant_params_t *p, double x, int side) {
    return friction_profile(p, x) * p->Fs[side];
}

/* ---- effect position_friction: the knots and their spacing (friction_profile.*); its rules are
 * checked whether it is on or off, like the stroke's, so a model's profile is valid either way */
static bool compile_position_friction(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    double x0 = val[VR_friction_profile_x_start], x1 = val[VR_friction_profile_x_end];
    int j;
    (void)msg; (void)msglen;
    p->posfric = val[VR_effects_position_friction] != 0.0;
    p->pf_n = (int)val[VR_friction_profile_n];
    p->pf_x0 = x0;
    p->pf_h = (x1 - x0) / (double)(p->pf_n - 1);
    for (j = 0; j < PLANT_NPF_MAX; j++) p->pf_c[j] = j < p->pf_n ? val[VRA_friction_profile_c[j + 1]] : 0.0;
    return true;
}

static bool check_position_friction(const double *val, const plant_params_t *p, char *msg, size_t msglen) {
    double x0 = val[VR_friction_profile_x_start], x1 = val[VR_friction_profile_x_end];
    double n = val[VR_friction_profile_n];
    (void)p;
    if (!(x1 > x0)) {
        snprintf(msg, msglen, "friction_profile.x_end = %.17g must exceed friction_profile.x_start = %.17g: "
                 "allowed friction_profile.x_end in (%.17g, inf) m", x1, x0, x0);
        return false;
    }
    if ((double)(int)n != n) {
        snprintf(msg, msglen, "friction_profile.n = %.17g is not an integer: allowed 2..%d", n, PLANT_NPF_MAX);
        return false;
    }
    return true;
}

const effect_t effect_position_friction = {
    "position_friction", VR_effects_position_friction, NULL, compile_position_friction, check_position_friction,
    NULL, NULL, NULL};
