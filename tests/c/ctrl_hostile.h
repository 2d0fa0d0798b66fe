/* The hostile cases of the controller FMU's C test host (ctrl_host hostile [case]): each case
 * is one function that calls the FMU as a hostile importer would and writes what the FMU
 * answered into case_answer; EXPECT fails the case (its message replaces the answer), SAY adds
 * to the answer. The cases live in ctrl_case_*.c, the table and the runner in ctrl_hostile.c. */
#ifndef CTRL_HOSTILE_H
#define CTRL_HOSTILE_H

#include <stdio.h>
#include <string.h>

#include "ctrl_host.h"

extern char case_answer[2048];
extern int case_failed;

#define EXPECT(cond, ...) do { if (!(cond)) { case_failed = 1; snprintf(case_answer, sizeof case_answer, __VA_ARGS__); return; } } while (0)
#define SAY(...) snprintf(case_answer + strlen(case_answer), sizeof case_answer - strlen(case_answer), __VA_ARGS__)

/* the name of an fmi2Status */
const char *st2(int s);

/* ctrl_case_steps.c: fmi2DoStep refused (non-finite, too many samples, coarse time), ctrl.delay */
void case_step_inf(void);
void case_step_huge(void);
void case_step_tiny_ts(void);
void case_step_coarse_time(void);
void case_delay(void);
#ifdef CTRL_FMI3
/* ctrl_case_fmi3.c: FMI 3.0 only (NULL arrays, the input clock, Boolean sizes) */
void case_get_float64_null(void);
void case_clock(void);
void case_boolean_size_max3(void);
#endif
/* ctrl_case_values.c: sizes and values refused at the set or at initialisation */
void case_boolean_size_max2(void);
void case_ref_duration(void);
void case_ref_duration_samples(void);
void case_ref_point_to_point(void);
void case_ref_p2p_samples(void);
void case_lti_full_order(void);
/* ctrl_case_unstable.c: unstable controllers refused when their states overflow */
void case_unstable_state_space(void);
void case_unstable_lti(void);

/* run the cases (all, or the one named by argv[0]); 0 only without a failure */
int hostile_main(int argc, char **argv);

#endif
