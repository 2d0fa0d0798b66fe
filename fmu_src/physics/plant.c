/* Eq. 1 assembled:  m a = K_f(x) i - F_cg(x) - F_f - F_e - F_offset (+ the compliance's
 * spring-damper force when that effect is on, compliance.c).
 * The maps are evaluated at x clamped to [stroke.x_min, stroke.x_max] (the cubic of Eq. 6
 * extrapolates badly); the motion itself is not limited. The effects' terms are called directly
 * (each is 0 or the identity where its effect is off, from the compiled parameters); the effect
 * table (effect.h) sets the states the effects own at initialisation and after a retune. */
#include <math.h>

#include "effect.h"

static double clamp(double x, double lo, double hi) { return x < lo ? lo : (x > hi ? hi : x); }

/* applied force without friction */
static double applied_force(const plant_params_t *p, const plant_out_t *o, const plant_in_t *in) {
    double F = o->F_motor - o->F_cg - in->F_ext - p->F_off;
    if (p->compliance) F += o->F_load;
    return F;
}

/* K_f and F_cg at the clamped position xc, from the memo when it holds that very position */
static void maps_at(const plant_params_t *p, double xc, plant_memo_t *memo, plant_out_t *o) {
    if (memo && memo->valid && memo->x == xc) {
        o->K_f = memo->K_f;
        o->F_cg = memo->F_cg;
        return;
    }
    posmap_eval_pair(&p->rip, &p->cog, xc, &o->K_f, &o->F_cg);
    if (memo) {
        memo->valid = 1;
        memo->x = xc;
        memo->K_f = o->K_f;
        memo->F_cg = o->F_cg;
    }
}

/* Eq. 1's forces and acceleration: every output but n_stuck (the right-hand side needs no count) */
static void plant_forces(const plant_params_t *p, const plant_disc_t *d, const double *y,
                         const plant_in_t *in, plant_memo_t *memo, plant_out_t *o) {
    double xc = clamp(y[PLANT_IX], p->x_min, p->x_max), v = y[PLANT_IV], F_app;
    int j;
    maps_at(p, xc, memo, o);
    o->i = current_loop_output(p, d, in->u);
    o->F_motor = o->K_f * o->i;
    o->F_load = compliance_force(p, y);
    F_app = applied_force(p, o, in);
    if (p->prerolling) {
        gms_element_forces(p, d, y, memo, o->F_elem);
        o->F_fric = p->sigma2[v < 0.0] * v;
        for (j = 0; j < PLANT_NE_MAX; j++) o->F_fric += o->F_elem[j];
        o->a = (F_app - o->F_fric) / p->m;
    } else {
        for (j = 0; j < PLANT_NE_MAX; j++) o->F_elem[j] = 0.0;
        o->F_fric = static_friction(p, d, y[PLANT_IX], v, F_app);
        o->a = d->st_stuck ? 0.0 : (F_app - o->F_fric) / p->m;
    }
}

void plant_outputs_memo(const plant_params_t *p, const plant_disc_t *d, const double *y,
                        const plant_in_t *in, plant_memo_t *memo, plant_out_t *o) {
    plant_forces(p, d, y, in, memo, o);
    o->n_stuck = plant_n_stuck(p, d);
    o->x_meas = compliance_x_measured(p, y);
    o->x_load = p->compliance ? y[PLANT_IX] + y[PLANT_IQ] : y[PLANT_IX];
    o->v_load = p->compliance ? y[PLANT_IV] + y[PLANT_IW] : y[PLANT_IV];
}

void plant_outputs(const plant_params_t *p, const plant_disc_t *d, const double *y,
                   const plant_in_t *in, plant_out_t *o) {
    plant_outputs_memo(p, d, y, in, NULL, o);
}

void plant_state_derivatives(const plant_params_t *p, const plant_disc_t *d, const double *y,
                             const plant_out_t *o, plant_memo_t *memo, double *dydt) {
    int j;
    dydt[PLANT_IX] = y[PLANT_IV];
    dydt[PLANT_IV] = o->a;
    if (p->prerolling) gms_derivatives(p, d, y, memo, dydt + PLANT_IF);
    else for (j = 0; j < PLANT_NE_MAX; j++) dydt[PLANT_IF + j] = 0.0;
    compliance_derivatives(p, y, o->F_load, o->a, dydt);
}

void plant_derivatives_memo(const plant_params_t *p, const plant_disc_t *d, const double *y,
                            const plant_in_t *in, plant_memo_t *memo, double *dydt) {
    plant_out_t o;
    plant_forces(p, d, y, in, memo, &o);
    plant_state_derivatives(p, d, y, &o, memo, dydt);
}

void plant_derivatives(const plant_params_t *p, const plant_disc_t *d, const double *y,
                       const plant_in_t *in, double *dydt) {
    plant_derivatives_memo(p, d, y, in, NULL, dydt);
}

void plant_indicators(const plant_params_t *p, const plant_disc_t *d, const double *y,
                      const plant_in_t *in, double *z) {
    int j;
    if (p->prerolling) { gms_indicators(p, d, y, z); return; }
    for (j = 0; j < PLANT_NE_MAX; j++) z[j] = 1.0;
    {
        plant_out_t o;
        plant_forces(p, d, y, in, NULL, &o);
        z[PLANT_NE_MAX] = static_indicator(p, d, y[PLANT_IX], y[PLANT_IV], applied_force(p, &o, in));
    }
}

void plant_init(const plant_params_t *p, plant_disc_t *d, double *y, const plant_in_t *in) {
    plant_out_t o;
    bool changed = false;
    int j;
    current_loop_init(p, d, in->u);
    d->n_stick = d->n_slip = d->n_time_events = d->n_state_events = 0;
    d->st_stuck = false;
    d->st_dir = 0;
    for (j = 0; j < MODEL_NEFFECTS; j++) if (PLANT_EFFECTS[j]->init) PLANT_EFFECTS[j]->init(p, y);
    if (p->prerolling) {
        gms_init(p, d, y);
        gms_update(p, d, y, NULL, &changed);
    } else {
        for (j = 0; j < PLANT_NE_MAX; j++) d->stuck[j] = false;
        d->dir = 0;
        plant_outputs(p, d, y, in, &o);
        static_init(p, d, y, applied_force(p, &o, in));
    }
    d->n_stick = d->n_slip = 0;
}

int plant_event_update(const plant_params_t *p, plant_disc_t *d, double *y, const plant_in_t *in,
                       bool sample_due, plant_memo_t *memo, bool *y_changed) {
    int n = 0, pass;
    if (sample_due) {
        current_loop_sample(p, d, in->u);
        d->n_time_events++;
    }
    for (pass = 0; pass < 4; pass++) {   /* a switch may enable another (stick then break away) */
        int m;
        double v_old = y[PLANT_IV];
        if (p->prerolling) {
            m = gms_update(p, d, y, memo, y_changed);
        } else {
            plant_out_t o;
            plant_outputs(p, d, y, in, &o);
            m = static_update(p, d, y, applied_force(p, &o, in), y_changed);
        }
        if (y[PLANT_IV] != v_old) compliance_velocity_jump(p, v_old, y);
        if (m == 0) break;
        n += m;
    }
    if (n > 0) d->n_state_events++;
    return n;
}

bool plant_indicators_of_state(const plant_params_t *p) { return p->prerolling; }

void plant_sample_update(const plant_params_t *p, plant_disc_t *d, const plant_in_t *in) {
    current_loop_sample(p, d, in->u);
    d->n_time_events++;
}

int plant_n_stuck(const plant_params_t *p, const plant_disc_t *d) {
    return p->prerolling ? gms_n_stuck(p, d) : d->st_stuck;
}

void plant_retune(const plant_params_t *old, const plant_params_t *p, plant_disc_t *d, double *y) {
    int j;
    for (j = 0; j < MODEL_NEFFECTS; j++) if (PLANT_EFFECTS[j]->retune) PLANT_EFFECTS[j]->retune(old, p, d, y);
}
