/* The hostile cases' table and runner (see ctrl_hostile.h). */
#include "ctrl_hostile.h"

#include <stdio.h>
#include <string.h>

char case_answer[2048];
int case_failed;

static const char *ST2[] = {"fmi2OK", "fmi2Warning", "fmi2Discard", "fmi2Error", "fmi2Fatal", "fmi2Pending"};
const char *st2(int s) { return s >= 0 && s <= 5 ? ST2[s] : "?"; }

typedef struct { const char *name; void (*run)(void); } case_t;
static const case_t CASES[] = {
    {"step_inf", case_step_inf},
    {"step_huge", case_step_huge},
    {"step_tiny_ts", case_step_tiny_ts},
    {"step_coarse_time", case_step_coarse_time},
#ifdef CTRL_FMI3
    {"get_float64_null", case_get_float64_null},
    {"boolean_size_max3", case_boolean_size_max3},
    {"clock", case_clock},
#endif
    {"boolean_size_max2", case_boolean_size_max2},
    {"unstable_state_space", case_unstable_state_space},
    {"unstable_lti", case_unstable_lti},
    {"lti_full_order", case_lti_full_order},
    {"ref_duration", case_ref_duration},
    {"ref_duration_samples", case_ref_duration_samples},
    {"ref_point_to_point", case_ref_point_to_point},
    {"ref_p2p_samples", case_ref_p2p_samples},
    {"delay", case_delay},
};

int hostile_main(int argc, char **argv) {
    size_t k;
    int n_pass = 0, n_fail = 0;
    long live0 = host_live_allocations();
    for (k = 0; k < sizeof CASES / sizeof CASES[0]; k++) {
        if (argc > 0 && strcmp(argv[0], CASES[k].name) != 0) continue;
        case_answer[0] = 0;
        case_failed = 0;
        CASES[k].run();
        printf("%s %s: %s\n", case_failed ? "FAIL" : "PASS", CASES[k].name, case_answer);
        fflush(stdout);
        if (case_failed) n_fail++; else n_pass++;
    }
    if (n_pass + n_fail == 0) { fprintf(stderr, "no case %s\n", argc > 0 ? argv[0] : ""); return 2; }
    if (host_live_allocations() != live0) {
        printf("FAIL leak: %ld callback allocations left\n", host_live_allocations() - live0);
        n_fail++;
    }
    printf("%d passed, %d failed\n", n_pass, n_fail);
    return n_fail == 0 ? 0 : 1;
}
