/* See fuzz_oracle.h. */
#include "fuzz_oracle.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

fmi_api_t api;
inst_t slot[NSLOT];
static unsigned long long rng = 88172645463325252ull;
long n_calls, n_ok_checks, n_fail, n_illegal_checked, n_legal_checked, n_tainted_calls;
long n_by_status[5], n_dostep_ok, n_me_steps_ok;
unsigned char fake[1 << 16];
const char *cur_fn = "";
char cur_detail[256];

void fuzz_seed(unsigned long long seed) {
    rng ^= seed * 0x9E3779B97F4A7C15ull;
    if (!rng) rng = 1;
}

static unsigned long long rnd(void) {
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}
int rint_(int n) { return (int)(rnd() % (unsigned long long)n); }
double runif(void) { return (double)(rnd() >> 11) / 9007199254740992.0; }
int chance(double p) { return runif() < p; }

double special(void) {
    static const double S[] = {0.0, -0.0, -1.0, 1.0, 1e308, -1e308, 5e-324, 1e-300, -1e-300, 1e300, 2.5, -2.5};
    int k = rint_(15);
    if (k == 12) return NAN;
    if (k == 13) return INFINITY;
    if (k == 14) return -INFINITY;
    return S[k];
}

void fail(const char *why, int status, inst_t *I) {
    static const char *seen_fn[64], *seen_why[64];
    static int n_seen;
    int j;
    n_fail++;
    /* print the first occurrence of each (function, check) pair */
    for (j = 0; j < n_seen; j++)
        if (seen_fn[j] == cur_fn && seen_why[j] == why) return;
    if (n_seen < 64) { seen_fn[n_seen] = cur_fn; seen_why[n_seen] = why; n_seen++; }
    if (n_seen <= 64)
        printf("FAIL call %ld %s%s: %s (status %d, state %d%s, last message: %s)\n", n_calls, cur_fn, cur_detail, why,
               status, I ? I->st : -1, I && I->tainted ? ", tainted" : "", I ? I->env.last : "");
    cur_detail[0] = 0;
}

/* illegal: 1 certainly illegal, 0 certainly legal and valid (check OK only when want_ok), -1 unknown */
void judge(inst_t *I, int status, int illegal, int want_ok, int has_logger) {
    int bad = 0;
    n_calls++;
    if (status < fmi2OK || status > fmi2Pending) { fail("status out of range", status, I); return; }
    n_by_status[status]++;
    if (status != fmi2OK && has_logger && I && I->env.n_since_mark == 0) { fail("non-OK status without a message", status, I); bad = 1; }
    if (I && I->tainted) { n_tainted_calls++; if (!bad) n_ok_checks++; return; }
    if (illegal == 1) {
        n_illegal_checked++;
        if (status != fmi2Error && status != fmi2Discard) { fail("illegal call not answered fmi2Error/fmi2Discard", status, I); bad = 1; }
    } else if (illegal == 0 && want_ok) {
        n_legal_checked++;
        if (status != fmi2OK) { fail("legal get not answered fmi2OK", status, I); bad = 1; }
    }
    if (!bad) n_ok_checks++;
}

/* ---------------------------------------------------------------- argument generators */

static int var_row_of_type(char type) {
    int row;
    do { row = rint_(MODEL_NVARS); } while (MODEL_VARS[row].type != type);
    return row;
}

/* a value reference for a get/set of `type`; *bad set to 1 when certainly wrong */
fmi2ValueReference pick_vr(char type, int *bad, int *row_out) {
    int k = rint_(20);
    *row_out = -1;
    if (k < 15) { int r = var_row_of_type(type); *row_out = r; return MODEL_VARS[r].vr; }
    if (k < 17) {   /* a variable of another type */
        char other = type == 'R' ? (chance(0.5) ? 'I' : 'B') : 'R';
        int r = var_row_of_type(other);
        *bad = 1;
        return MODEL_VARS[r].vr;
    }
    *bad = 1;
    if (k == 17) return MODEL_NVR + (fmi2ValueReference)rint_(1000);
    if (k == 18) return 0xFFFFFFFFu;
    {   /* a hole in the table, if any */
        unsigned v;
        int tries;
        for (tries = 0; tries < 50; tries++) {
            v = (unsigned)rint_(MODEL_NVR);
            if (MODEL_VR_INDEX[v] < 0) return v;
        }
        return MODEL_NVR;
    }
}

double pick_real(int row) {
    double s = row >= 0 ? MODEL_VARS[row].start : 1.0;
    int k = rint_(10);
    if (k < 4) return s * (0.8 + 0.4 * runif());
    if (k < 6) return s;
    return special();
}

/* may the variable be set in model state st? (FMI 2.0 rules for this modelDescription) */
int settable(int row, int st) {
    const model_var_t *v = &MODEL_VARS[row];
    if (v->causality == 'i') return st == S_INST || st == S_INIT || st == S_EVENT || st == S_CONT || st == S_STEP;
    if (v->causality == 'p') {
        if (st == S_INST || st == S_INIT) return 1;
        return v->variability == 't' && (st == S_EVENT || st == S_STEP);
    }
    if (v->has_start && v->variability == 'c') return st == S_INST || st == S_INIT;
    return 0;
}

int getable_state(int st) { return st == S_INIT || st == S_EVENT || st == S_CONT || st == S_STEP || st == S_TERM; }


void check_finite(int status, const double *v, size_t n) {
    size_t j;
    if (status != fmi2OK) return;
    for (j = 0; j < n; j++)
        if (!isfinite(v[j])) {
            snprintf(cur_detail, sizeof cur_detail, "element %zu = %g", j, v[j]);
            fail("fmi2OK with a non-finite value", status, NULL);
            return;
        }
}
