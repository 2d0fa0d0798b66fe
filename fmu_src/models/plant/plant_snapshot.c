/* The plant's part of a saved FMU state (the glue's header and layout: fmu_src/fmi/state_format.h):
 * the call-sequence state, times and tolerance, the continuous states, the stored variables,
 * the discrete state, the per-sample scheme's carry and the solver's memory; encoded, and
 * decoded with every field checked before anything of it is used (model.h's
 * model_state_bytes / _encode / _decode). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "plant_model.h"
#include "state_format.h"

#define SOLVER_NUMS 7
#define MAX_COUNT 9007199254740992.0   /* 2^53 */
#define ST_BEFORE_INIT (ST_INSTANTIATED | ST_INIT)
#define ST_ME_STATES (ST_BEFORE_INIT | ST_EVENT | ST_CONT | ST_TERMINATED)
#define ST_CS_STATES (ST_BEFORE_INIT | ST_STEP_COMPLETE | ST_STEP_FAILED | ST_TERMINATED)
enum { F_STOP = 1, F_TOL = 2, F_PARAMS = 4, F_STROKE = 8, F_ALL = 15 };

static size_t payload_bytes(void) {
    return 2 * 4 + 5 * 8 + 8 * ((size_t)PLANT_NX + sf_n_stored() + PLANT_ND + SOLVER_NUMS + FAST_CARRY_ND);
}
size_t model_state_bytes(void) { return HEADER_BYTES + payload_bytes(); }

void model_state_encode(const model_t *m, int type, unsigned char *out) {
    wr_t w = {out, 0};
    double disc[PLANT_ND], carry[FAST_CARRY_ND];
    const double solver[SOLVER_NUMS] = {m->solver.h, m->solver.log2_facold, (double)m->solver.n_steps,
                                        (double)m->solver.n_rejected, (double)m->solver.n_rhs,
                                        (double)m->solver.n_ind, (double)m->solver.n_roots};
    int j;
    sf_put_header(&w, type, payload_bytes());
    sf_put_u32(&w, (uint32_t)m->fsm);
    sf_put_u32(&w, (uint32_t)((m->stop_defined ? F_STOP : 0) | (m->tol_defined ? F_TOL : 0) |
                           (m->params_ok ? F_PARAMS : 0) | (m->stroke_warned ? F_STROKE : 0)));
    sf_put_f64(&w, m->time);
    sf_put_f64(&w, m->t0);
    sf_put_f64(&w, m->stop_time);
    sf_put_f64(&w, m->tol);
    sf_put_f64(&w, m->tau);
    for (j = 0; j < PLANT_NX; j++) sf_put_f64(&w, m->y[j]);
    for (j = 0; j < MODEL_NVARS; j++)
        if (sf_stored(&MODEL_VARS[j])) sf_put_f64(&w, m->val[MODEL_VARS[j].vr]);
    plant_disc_pack(&m->d, disc);
    for (j = 0; j < PLANT_ND; j++) sf_put_f64(&w, disc[j]);
    fast_carry_pack(&m->carry, carry);
    for (j = 0; j < FAST_CARRY_ND; j++) sf_put_f64(&w, carry[j]);
    for (j = 0; j < SOLVER_NUMS; j++) sf_put_f64(&w, solver[j]);
    sf_seal(out, payload_bytes());
}

/* the call-sequence state, flags, times and tolerance */
static int read_scalars(instance_t *c, const char *fn, rd_t *r, model_t *m) {
    uint32_t fsm = sf_get_u32(r), flags = sf_get_u32(r);
    /* an FMI 3.0 co-simulation instance may also be saved in Event Mode */
    const int allowed = c->type == fmi2CoSimulation ? (ST_CS_STATES | (c->fmi3 ? ST_EVENT : 0)) : ST_ME_STATES;
    if (fsm == 0 || (fsm & (fsm - 1)) != 0 || !(fsm & (uint32_t)allowed))
        BAD("%s: call-sequence state 0x%x is not one a state of this interface is saved in", fn, (unsigned)fsm);
    if (flags & ~(uint32_t)F_ALL) BAD("%s: flags 0x%x: allowed bits 0x%x", fn, (unsigned)flags, (unsigned)F_ALL);
    m->fsm = (int)fsm;
    m->stop_defined = (flags & F_STOP) != 0;
    m->tol_defined = (flags & F_TOL) != 0;
    m->params_ok = (flags & F_PARAMS) != 0;
    m->stroke_warned = (flags & F_STROKE) != 0;
    m->time = sf_get_f64(r);
    m->t0 = sf_get_f64(r);
    m->stop_time = sf_get_f64(r);
    m->tol = sf_get_f64(r);
    m->tau = sf_get_f64(r);
    if (!isfinite(m->time) || !isfinite(m->t0) || !isfinite(m->stop_time) || !(m->tol > 0.0 && m->tol <= TOL_MAX) ||
        (m->stop_defined && m->stop_time < m->t0))
        BAD("%s: time %g, startTime %g, stopTime %g, tolerance %g: allowed finite times, stopTime >= "
            "startTime, tolerance in (0, %g]", fn, m->time, m->t0, m->stop_time, m->tol, TOL_MAX);
    /* time = startTime + tau up to the rounding of that sum (and of an importer's times) */
    if (!(fabs(m->t0 + m->tau - m->time) <= fmu_ulp_slack(m->time) + fmu_ulp_slack(m->t0)))
        BAD("%s: the integrator's time since startTime %.17g s does not match time %.17g s - startTime %.17g s",
            fn, m->tau, m->time, m->t0);
    if ((m->fsm & ST_INSTANTIATED) ? m->params_ok : (!(m->fsm & ST_INIT) && !m->params_ok))
        BAD("%s: parameters-compiled flag %d contradicts the call-sequence state 0x%x", fn, m->params_ok, m->fsm);
    return 1;
}

/* continuous states and the stored variables, each through the setter's checks */
static int read_values(instance_t *c, const char *fn, rd_t *r, model_t *m) {
    char msg[512];
    int j;
    for (j = 0; j < PLANT_NX; j++) {
        m->y[j] = sf_get_f64(r);
        if (!isfinite(m->y[j])) BAD("%s: state %s = %g is not finite", fn,
                                    MODEL_VARS[MODEL_VR_INDEX[MODEL_STATE_VR[j]]].name, m->y[j]);
        /* the range fmi2SetContinuousStates enforces (the XML's min/max) */
        if (!params_check_value(MODEL_STATE_VR[j], m->y[j], msg, sizeof msg)) BAD("%s: state %s", fn, msg);
    }
    for (j = 0; j < MODEL_NVARS; j++) {
        const model_var_t *v = &MODEL_VARS[j];
        double x;
        if (!sf_stored(v)) continue;
        x = sf_get_f64(r);
        if (!params_check_value(v->vr, x, msg, sizeof msg)) BAD("%s: %s", fn, msg);
        if ((v->type == 'B' && x != 0.0 && x != 1.0) || (v->type == 'I' && x != floor(x)) ||
            (v->vr == VR_solver_tol && !(x > 0.0 && x <= TOL_MAX)))
            BAD("%s: %s = %g is not a valid %s value", fn, v->name, x, v->type == 'B' ? "Boolean" :
                (v->type == 'I' ? "Integer" : "Real"));
        m->val[v->vr] = x;
    }
    return 1;
}

/* discrete state and solver memory; then the parameters compiled and the solver set up again */
static int read_rest(instance_t *c, const char *fn, rd_t *r, model_t *m) {
    double disc[PLANT_ND], s[SOLVER_NUMS], cw[FAST_CARRY_ND];
    fast_carry_t carry;
    char msg[512];
    int j;
    for (j = 0; j < PLANT_ND; j++) disc[j] = sf_get_f64(r);
    for (j = 0; j < FAST_CARRY_ND; j++) cw[j] = sf_get_f64(r);
    for (j = 0; j < SOLVER_NUMS; j++) s[j] = sf_get_f64(r);
    if (!plant_disc_unpack(disc, &m->d, msg, sizeof msg)) BAD("%s: %s", fn, msg);
    if (!fast_carry_unpack(cw, &carry, msg, sizeof msg)) BAD("%s: %s", fn, msg);
    if (!(s[0] >= 0.0 && s[0] < HUGE_VAL) || !(s[1] >= -14.0 && s[1] <= 0.0))
        BAD("%s: solver step proposal %g, controller memory %g: allowed a finite step >= 0, memory in "
            "[-14, 0]", fn, s[0], s[1]);
    for (j = 2; j < SOLVER_NUMS; j++)
        if (!(s[j] >= 0.0 && s[j] <= MAX_COUNT && s[j] == floor(s[j])))
            BAD("%s: solver count %d = %g: allowed an integer in [0, 2^53]", fn, j - 2, s[j]);
    if (!m->params_ok) return 1;
    if (!params_compile(m->val, &m->p, msg, sizeof msg)) BAD("%s: %s", fn, msg);
    if (m->d.k > 0 && (double)m->d.k > (m->time - m->t0) / m->p.Ts + 2.0)
        BAD("%s: current-loop sample %lld lies after the state's time %.17g s (startTime %.17g s, Ts %g s)", fn,
            m->d.k, m->time, m->t0, m->p.Ts);
    plant_solver_setup(m);
    m->solver.h = s[0] < m->solver.h_max ? s[0] : m->solver.h_max;
    m->solver.log2_facold = s[1];
    m->solver.n_steps = (long long)s[2]; m->solver.n_rejected = (long long)s[3]; m->solver.n_rhs = (long long)s[4];
    m->solver.n_ind = (long long)s[5]; m->solver.n_roots = (long long)s[6];
    m->carry = carry;   /* after plant_solver_setup, which clears it */
    return 1;
}

/* what the instance was made with and cannot change by a state: an FMI 3.0 instance's number of
 * continuous states 2 + friction.N (a structural parameter, set only in Configuration Mode), and
 * a co-simulation instance's eventModeUsed (Event Mode exists only with it) */
static int structure_ok(instance_t *c, const char *fn, const model_t *m) {
    double n_state = m->val[VR_friction_N], n_inst = c->m.val[VR_friction_N];
    if (c->fmi3 && n_state != n_inst)
        BAD("%s: the state has friction.N = %g, this instance %g: friction.N is a structural parameter (it sets "
            "the number of continuous states, 2 + friction.N); allowed: a state of the same friction.N (set it "
            "in Configuration Mode before loading)", fn, n_state, n_inst);
    if (c->type == fmi2CoSimulation && (m->fsm & ST_EVENT) && !c->event_mode_used)
        BAD("%s: the state was saved in Event Mode; this co-simulation instance was instantiated with "
            "eventModeUsed = false (allowed: a state saved in Step Mode, or an instance with eventModeUsed = true)",
            fn);
    return 1;
}

int model_state_decode(instance_t *c, const char *fn, const unsigned char *b, size_t len, model_t *out) {
    rd_t r = {b, HEADER_BYTES};
    if (!b) BAD("%s: the state is NULL", fn);
    if (!sf_header_ok(c, fn, b, len, payload_bytes())) return 0;
    model_defaults(out);
    if (!read_scalars(c, fn, &r, out) || !read_values(c, fn, &r, out) || !structure_ok(c, fn, out) ||
        !read_rest(c, fn, &r, out))
        return 0;
    params_inputs(out->val, &out->in);
    out->out_valid = 0;
    out->solver_restart = 1;
    return 1;
}
