/* The serialised FMU state (format version 4): a self-describing little-endian byte string.
 * The glue writes and checks the header (state_format.c); the payload is the model's
 * (model.h; the plant's: models/plant/plant_snapshot.c).
 *
 *   header (u32 unless noted)
 *     magic 0x53524446 ("FDRS"), format version, header bytes, payload bytes,
 *     GUID (48 bytes, NUL-padded), interface (0 model exchange, 1 co-simulation),
 *     structure: value references, stored variables, continuous states, event indicators,
 *     discrete-state numbers (MODEL_ND), CRC-32 of the stored variables' names (the variable layout),
 *     CRC-32 (IEEE) of the payload
 *   payload (the plant's)
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
#ifndef STATE_FORMAT_H
#define STATE_FORMAT_H

#include <stdint.h>

#include "instance.h"

#define STATE_MAGIC 0x53524446u
#define STATE_VERSION 4u   /* 2: + compliance (14 continuous states, its parameters);
                              3: + the per-sample scheme's carry;
                              4: + the integrator's time since startTime */
#define STATE_MAX_BYTES 4096u
#define GUID_BYTES 48
#define HEADER_BYTES (4 * 4 + GUID_BYTES + 4 + 6 * 4 + 4)
#define CRC_AT (HEADER_BYTES - 4)

typedef struct { unsigned char *b; size_t n; } wr_t;
typedef struct { const unsigned char *b; size_t n; } rd_t;

/* little-endian numbers, written at w->n / read from r->n (which advance) */
void sf_put_u32(wr_t *w, uint32_t v);
void sf_put_f64(wr_t *w, double v);
uint32_t sf_get_u32(rd_t *r);
double sf_get_f64(rd_t *r);
/* the variables a state stores: parameters, inputs and the start values of the states */
int sf_stored(const glue_var_t *v);
uint32_t sf_n_stored(void);
/* the header of a state of interface type with a payload of `payload` bytes (its CRC 0) */
void sf_put_header(wr_t *w, int type, size_t payload);
/* the payload's CRC-32 into the header of the state at out */
void sf_seal(unsigned char *out, size_t payload);
/* magic, version, sizes, GUID, interface, structure and checksum, each against this FMU's;
 * 0 with "<fn>: <what differs>" logged on c */
int sf_header_ok(instance_t *c, const char *fn, const unsigned char *b, size_t len, size_t payload);

/* a refused field: "<fn>: ..." logged on c, 0 returned */
#define BAD(...) do { fmu_log(c, fmi2Error, LOG_ERROR, __VA_ARGS__); return 0; } while (0)

#endif
