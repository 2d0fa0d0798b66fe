/* The serialised FMU state (format version 4): a self-describing little-endian byte string.
 *
 *   header (u32 unless noted)
 *     magic 0x53524446 ("FDRS"), format version, header bytes, payload bytes,
 *     GUID (48 bytes, NUL-padded), interface (0 model exchange, 1 co-simulation),
 *     structure: value references, stored variables, continuous states, event indicators,
 *     discrete-state numbers, CRC-32 of the stored variables' names (the variable layout),
 *     CRC-32 (IEEE) of the payload
 *   payload
 *     u32 call-sequence state, u32 flags (1 stopTime defined, 2 tolerance defined,
 *     4 parameters compiled, 8 stroke warning given), f64 time, startTime, stopTime, tolerance,
 *     the integrator's time since startTime (time = startTime + it, rounded),
 *     f64 continuous states (x, v, friction.F[1..10], compliance.dx, compliance.dv),
 *     f64 value of every parameter, input and state start (table order),
 *     f64 discrete state (plant_disc_pack), f64 the per-sample scheme's carry (fast_carry_pack:
 *     the derivative and bases the next step reuses), f64 solver: step proposal, step-controller
 *     memory, accepted, rejected steps, right-hand sides, indicator evaluations, roots.
 *
 * Only the state is stored: compiled parameters, solver configuration, indices and pointers are
 * re-derived on load (params_compile, dp45_init) and every field is checked first. */
#ifndef FMI2_STATE_FORMAT_H
#define FMI2_STATE_FORMAT_H

#include "fmi2_instance.h"

#define STATE_MAGIC 0x53524446u
#define STATE_VERSION 4u   /* 2: + compliance (14 continuous states, its parameters);
                              3: + the per-sample scheme's carry;
                              4: + the integrator's time since startTime */
#define STATE_MAX_BYTES 4096u

/* the serialised size of a state of this FMU */
size_t state_bytes(void);
/* m (an instance of interface type) into out (state_bytes() long) */
void state_encode(const model_t *m, int type, unsigned char *out);
/* bytes into *out after checking every field; on failure logs "<fn>: <what differs>" on c
 * and returns 0 (out is then garbage) */
int state_decode(instance_t *c, const char *fn, const unsigned char *b, size_t len, model_t *out);

#endif
