/* The controller's value table (ctrl_vars.h, generated from fmu_src/models/controller/modelDescription.xml
 * with the plant's parameters imported as plant.*) compiled into ctrl_params_t: the rules of single
 * values and of their combination, each refusal a message naming the variable, its value and the
 * allowed range. The nominal plant is compiled by the plant FMU's own params.c. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "ctrl_params.h"

/* value reference of plant.<name> = this offset + the plant's own */
#define PLANT_VR_OFFSET (CVR_plant_m - VR_m)
#define COMPILE_CHECK(name, cond) typedef char compile_check_##name[(cond) ? 1 : -1]
#define COUNT(a) (sizeof(a) / sizeof((a)[0]))
COMPILE_CHECK(ss_sizes_match_xml, COUNT(CVRA_ss_Cc) == CTRL_NS_MAX + 1 && COUNT(CVRA2_ss_Ac) == CTRL_NS_MAX + 1);
COMPILE_CHECK(lti_sizes_match_xml, COUNT(CVRA2_lti_A) == CTRL_NS_MAX + 1 && COUNT(CVRA2_lti_A[0]) == CTRL_NS_MAX + 1 &&
              COUNT(CVRA2_lti_B) == CTRL_NS_MAX + 1 && COUNT(CVRA2_lti_B[0]) == 3 && COUNT(CVRA_lti_C) == CTRL_NS_MAX + 1 &&
              COUNT(CVRA_lti_L) == CTRL_NS_MAX + 1 && COUNT(CVRA_lti_s0) == CTRL_NS_MAX + 1 &&
              COUNT(CVRA_lti_s0_r) == CTRL_NS_MAX + 1 && COUNT(CVRA_lti_D) == 3);
COMPILE_CHECK(zpetc_sizes_match_xml, COUNT(CVRA_zpetc_b) == CTRL_NZ_MAX + 1 && COUNT(CVRA_zpetc_zi) == CTRL_NZ_MAX);
COMPILE_CHECK(plant_offset_consistent, CVR_plant_friction_F_s - VR_friction_F_s == PLANT_VR_OFFSET);

const char *ctrl_var_name(unsigned vr) {
    return (vr < CTRL_NVR && CTRL_VR_INDEX[vr] >= 0) ? CTRL_VARS[CTRL_VR_INDEX[vr]].name : "?";
}

int ctrl_is_plant_vr(unsigned vr) {
    return vr >= PLANT_VR_OFFSET && vr - PLANT_VR_OFFSET < MODEL_NVR &&
           MODEL_VR_INDEX[vr - PLANT_VR_OFFSET] >= 0;
}

void ctrl_defaults(double *val) {
    int n;
    for (n = 0; n < CTRL_NVARS; n++) val[CTRL_VARS[n].vr] = CTRL_VARS[n].start;
}

bool ctrl_check_value(unsigned vr, double value, char *msg, size_t msglen) {
    if (!isfinite(value)) {
        snprintf(msg, msglen, "%s = %g is not a finite number: allowed values are finite", ctrl_var_name(vr), value);
        return false;
    }
    if (ctrl_is_plant_vr(vr)) {
        char m[480];
        if (params_check_value(vr - PLANT_VR_OFFSET, value, m, sizeof m)) return true;
        snprintf(msg, msglen, "plant.%s", m);
        return false;
    }
    return true;
}

#define FAIL(...) do { snprintf(msg, msglen, __VA_ARGS__); return false; } while (0)

static bool compile_plant(const double *val, ctrl_params_t *p, char *msg, size_t msglen) {
    double pv[MODEL_NVR];
    char m[480];
    unsigned vr;
    params_defaults(pv);
    for (vr = 0; vr < MODEL_NVR; vr++)
        if (MODEL_VR_INDEX[vr] >= 0 && MODEL_VARS[MODEL_VR_INDEX[vr]].causality == 'p')
            pv[vr] = val[vr + PLANT_VR_OFFSET];
    if (!params_compile(pv, &p->plant, m, sizeof m)) FAIL("plant.%s", m);
    return true;
}

static bool compile_pid(const double *val, ctrl_params_t *p, char *msg, size_t msglen) {
    double nyq = 0.5 / p->Ts;
    p->Kp = val[CVR_pid_Kp];
    p->Kv = val[CVR_pid_Kv];
    p->Ki = val[CVR_pid_Ki];
    p->fpv = val[CVR_pid_force_per_volt];
    p->tf = val[CVR_pid_tf];
    p->anti_windup = val[CVR_pid_anti_windup] != 0.0;
    /* u = F / force_per_volt: at least 1e-9 N/V keeps u finite for every force a finite gain gives */
    if (!(p->fpv >= 1e-9)) FAIL("pid.force_per_volt = %.17g: allowed [1e-9, 1e15] N/V", p->fpv);
    p->pid_a = p->tf / (p->tf + p->Ts);
    p->pid_b = p->Kv / (p->tf + p->Ts);
    p->lead = p->type == CTRL_PID_LEAD;
    if (p->lead) {
        double fz = val[CVR_lead_zero_hz], fp = val[CVR_lead_pole_hz], K = 2.0 / p->Ts, wz, wp, a0;
        if (!(fz > 0.0 && fz < fp))
            FAIL("lead.zero_hz = %.17g: allowed (0, lead.pole_hz = %.17g) Hz", fz, fp);
        if (!(fp < nyq)) FAIL("lead.pole_hz = %.17g: allowed (lead.zero_hz = %.17g, %.17g) Hz (Nyquist)", fp, fz, nyq);
        /* Tustin (s = 2/Ts (z - 1)/(z + 1)) of (1 + s/w_z)/(1 + s/w_p), normalised a0 = 1 */
        wz = 2 * M_PI * fz;
        wp = 2 * M_PI * fp;
        a0 = 1.0 + K / wp;
        p->lead_b0 = (1.0 + K / wz) / a0;
        p->lead_b1 = (1.0 - K / wz) / a0;
        p->lead_a1 = (1.0 - K / wp) / a0;
        if (!(isfinite(p->lead_b0) && isfinite(p->lead_b1) && isfinite(p->lead_a1)))
            FAIL("lead.zero_hz = %.17g Hz, lead.pole_hz = %.17g Hz: the lead's Tustin coefficients at Ts = %g s are "
                 "not finite (allowed: 2/(Ts 2 pi lead.zero_hz) a finite number)", fz, fp, p->Ts);
    }
    return true;
}

static bool compile_state_space(const double *val, ctrl_params_t *p, char *msg, size_t msglen) {
    int i, j;
    p->n = (int)val[CVR_ss_n];
    if (p->n < 1 || p->n > CTRL_NS_MAX) FAIL("ss.n = %d: allowed [1, %d]", p->n, CTRL_NS_MAX);
    for (i = 0; i < CTRL_NS_MAX; i++) {
        p->By[i] = val[CVRA_ss_By[i + 1]];
        p->Br[i] = val[CVRA_ss_Br[i + 1]];
        p->Bu[i] = val[CVRA_ss_Bu[i + 1]];
        p->Cc[i] = val[CVRA_ss_Cc[i + 1]];
        for (j = 0; j < CTRL_NS_MAX; j++) p->Ac[i][j] = val[CVRA2_ss_Ac[i + 1][j + 1]];
    }
    p->Dy = val[CVR_ss_Dy];
    p->Dr = val[CVR_ss_Dr];
    return true;
}

/* the linear controller: every element is a finite value of its declared range (checked at the
 * set); the order is the one rule of the combination */
static bool compile_lti(const double *val, ctrl_params_t *p, char *msg, size_t msglen) {
    int i, j;
    p->lti_n = (int)val[CVR_lti_n];
    if (p->lti_n < 0 || p->lti_n > CTRL_NS_MAX) FAIL("lti.n = %d: allowed [0, %d]", p->lti_n, CTRL_NS_MAX);
    for (i = 0; i < CTRL_NS_MAX; i++) {
        p->lti_B[i][0] = val[CVRA2_lti_B[i + 1][1]];
        p->lti_B[i][1] = val[CVRA2_lti_B[i + 1][2]];
        p->lti_C[i] = val[CVRA_lti_C[i + 1]];
        p->lti_L[i] = val[CVRA_lti_L[i + 1]];
        p->lti_s0[i] = val[CVRA_lti_s0[i + 1]];
        p->lti_s0_r[i] = val[CVRA_lti_s0_r[i + 1]];
        for (j = 0; j < CTRL_NS_MAX; j++) p->lti_A[i][j] = val[CVRA2_lti_A[i + 1][j + 1]];
    }
    p->lti_D[0] = val[CVRA_lti_D[1]];
    p->lti_D[1] = val[CVRA_lti_D[2]];
    return true;
}

static bool compile_zpetc(const double *val, ctrl_params_t *p, char *msg, size_t msglen) {
    int j;
    p->zpetc = val[CVR_zpetc_on] != 0.0;
    p->preview = p->zpetc ? (int)val[CVR_zpetc_preview] : 0;
    if (p->preview < 0 || p->preview > CTRL_PREVIEW_MAX)
        FAIL("zpetc.preview = %d: allowed [0, %d] samples", p->preview, CTRL_PREVIEW_MAX);
    p->nzc = (int)val[CVR_zpetc_order] + 1;
    if (p->nzc < 2 || p->nzc > CTRL_NZ_MAX) FAIL("zpetc.order = %d: allowed [1, %d]", p->nzc - 1, CTRL_NZ_MAX - 1);
    for (j = 0; j < CTRL_NZ_MAX; j++) {
        p->zb[j] = val[CVRA_zpetc_b[j + 1]];
        p->za[j] = val[CVRA_zpetc_a[j + 1]];
        p->zi[j] = j < CTRL_NZ_MAX - 1 ? val[CVRA_zpetc_zi[j + 1]] : 0.0;
    }
    if (p->zpetc && p->za[0] != 1.0) FAIL("zpetc.a[1] = %.17g: allowed 1 (a normalised denominator)", p->za[0]);
    return true;
}

static bool compile_reference(const double *val, ctrl_params_t *p, char *msg, size_t msglen) {
    double dur = val[CVR_ref_duration], x_end = val[CVR_ref_x_end];
    p->amp = val[CVR_ref_amplitude];
    p->centre = val[CVR_ref_centre];
    p->phase = val[CVR_ref_phase];
    p->x_start = val[CVR_ref_x_start];
    p->speed = val[CVR_ref_speed];
    p->accel = val[CVR_ref_accel];
    p->dwell = val[CVR_ref_dwell];
    if (p->source == REF_SINUSOID) {
        double T = val[CVR_ref_period];
        if (!(T > 0.0)) FAIL("ref.period = %.17g: allowed (0, inf) s", T);
        if (!(dur >= 0.0 && dur / p->Ts <= REF_MAX_SAMPLES))
            FAIL("ref.duration = %.17g s is %g samples of Ts = %g s: allowed at most %g samples, ref.duration <= "
                 "%g s", dur, dur / p->Ts, p->Ts, REF_MAX_SAMPLES, REF_MAX_SAMPLES * p->Ts);
        p->w = 2 * M_PI / T;
    }
    if (p->source == REF_POINT_TO_POINT) {
        if (!(p->speed > 0.0)) FAIL("ref.speed = %.17g: allowed (0, inf) m/s", p->speed);
        if (!(p->accel > 0.0)) FAIL("ref.accel = %.17g: allowed (0, inf) m/s2", p->accel);
        if (!(x_end != p->x_start)) FAIL("ref.x_end = %.17g: allowed any position but ref.x_start = %.17g m", x_end, p->x_start);
    }
    ref_prepare(p, dur, x_end);
    if (p->source == REF_POINT_TO_POINT && !(p->p2p_samples <= REF_MAX_SAMPLES))
        FAIL("ref.x_start = %.17g m, ref.x_end = %.17g m, ref.speed = %.17g m/s, ref.accel = %.17g m/s2, ref.dwell = "
             "%.17g s: the move lasts %g s, %g samples of Ts = %g s: allowed at most %g samples", p->x_start,
             x_end, val[CVR_ref_speed], p->accel, p->dwell, p->p2p_samples * p->Ts, p->p2p_samples, p->Ts,
             REF_MAX_SAMPLES);
    if (p->source == REF_POINT_TO_POINT) p->n_p2p = (long long)p->p2p_samples;
    return true;
}

bool ctrl_compile(const double *val, ctrl_params_t *p, char *msg, size_t msglen) {
    memset(p, 0, sizeof *p);
    p->Ts = val[CVR_Ts];
    p->type = (int)val[CVR_ctrl_type];
    p->source = (int)val[CVR_ref_source];
    p->u_limit = val[CVR_u_limit];
    p->quantum = val[CVR_scale_quantum];
    p->delay = (int)val[CVR_ctrl_delay];
    if (!(p->Ts > 0.0)) FAIL("Ts = %.17g: allowed (0, inf) s", p->Ts);
    if (p->type < CTRL_STATE_SPACE || p->type > CTRL_LTI)
        FAIL("ctrl.type = %d: allowed 1 (state_space), 2 (pid), 3 (pid_lead), 4 (lti)", p->type);
    if (p->delay < 0 || p->delay > 1) FAIL("ctrl.delay = %d: allowed 0 or 1 sample", p->delay);
    if (p->source < REF_INPUT || p->source > REF_POINT_TO_POINT)
        FAIL("ref.source = %d: allowed 0 (inputs), 1 (sinusoid), 2 (point to point)", p->source);
    if (!(p->u_limit > 0.0)) FAIL("u_limit = %.17g: allowed (0, 1e6] V", p->u_limit);
    /* x_meas / quantum stays finite for any position of the declared ranges from 1 pm up */
    if (!(p->quantum == 0.0 || p->quantum >= 1e-12))
        FAIL("scale.quantum = %.17g m: allowed 0 (no quantisation) or [1e-12, 1] m", p->quantum);
    if (p->type == CTRL_STATE_SPACE) { if (!compile_state_space(val, p, msg, msglen)) return false; }
    else if (p->type == CTRL_LTI) { if (!compile_lti(val, p, msg, msglen)) return false; }
    else if (!compile_pid(val, p, msg, msglen)) return false;
    if (!compile_zpetc(val, p, msg, msglen) || !compile_reference(val, p, msg, msglen)) return false;
    p->ff = val[CVR_ff_on] != 0.0;
    p->ff_inertia = val[CVR_ff_inertia] != 0.0;
    p->ff_cogging = val[CVR_ff_cogging] != 0.0;
    p->ff_ripple = val[CVR_ff_ripple] != 0.0;
    p->ff_offset = val[CVR_ff_offset] != 0.0;
    p->ff_friction = (int)val[CVR_ff_friction];
    p->v_eps = val[CVR_ff_v_eps];
    if (p->ff_friction < FF_FRICTION_NONE || p->ff_friction > FF_FRICTION_GMS)
        FAIL("ff.friction = %d: allowed 0 (none), 1 (static), 2 (gms)", p->ff_friction);
    if (p->ff && p->ff_friction == FF_FRICTION_STATIC && !(p->v_eps > 0.0))
        FAIL("ff.v_eps = %.17g: allowed (0, 1000] m/s", p->v_eps);
    if (p->ff && !compile_plant(val, p, msg, msglen)) return false;
    return true;
}
