/* The fuzz test's oracle (see fuzz_fmi.c): random generators, the modelled FMI state of each
 * instance, the legality rules for setting variables, and the per-call checks. */
#ifndef FUZZ_ORACLE_H
#define FUZZ_ORACLE_H

#include "fmi_host.h"
#include "model_vars.h"

enum { S_NONE, S_INST, S_INIT, S_EVENT, S_CONT, S_STEP, S_TERM };
#define NSLOT 4
#define NSTATE 3

typedef struct {
    fmi2Component c;
    fmi2Type type;
    int st, tainted;
    double time, stop;
    int stop_defined;
    host_env_t env;
    fmi2CallbackFunctions cb;
    fmi2FMUstate fs[NSTATE];
    int fs_st[NSTATE];
    double fs_time[NSTATE];
} inst_t;

extern fmi_api_t api;
extern inst_t slot[NSLOT];
extern long n_calls, n_ok_checks, n_fail, n_illegal_checked, n_legal_checked, n_tainted_calls;
extern long n_by_status[5], n_dostep_ok, n_me_steps_ok;
extern unsigned char fake[1 << 16];     /* zeroed: neither an instance nor an FMU state of this FMU */
extern const char *cur_fn;              /* the function under test, for messages */
extern char cur_detail[256];            /* what made the call illegal, for messages */

void fuzz_seed(unsigned long long seed);
int rint_(int n);                       /* uniform in 0..n-1 */
double runif(void);                     /* uniform in [0, 1) */
int chance(double p);
double special(void);                   /* NaN, +-Inf, huge, tiny, denormal, negative, zero */

void fail(const char *why, int status, inst_t *I);
/* illegal: 1 certainly illegal, 0 certainly legal and valid (fmi2OK required when want_ok),
 * -1 unknown; has_logger: a message can be required */
void judge(inst_t *I, int status, int illegal, int want_ok, int has_logger);

/* a value reference for a get/set of type 'R', 'I' or 'B'; *bad = 1 when certainly wrong,
 * *row_out the MODEL_VARS row or -1 */
/* no getter answers fmi2OK with a non-finite value: fails the run if one does */
void check_finite(int status, const double *v, size_t n);
fmi2ValueReference pick_vr(char type, int *bad, int *row_out);
double pick_real(int row);
int settable(int row, int st);          /* may the variable be set in modelled state st? */
int getable_state(int st);

#endif
