/* The plant's effect table: one entry per effect of the catalogue (the `effects.*` switches of
 * modelDescription.xml), each defined in the effect's own C file under physics/ with what is the
 * effect's own: the single-value rules of its parameters, what its switch does to the compiled
 * parameters, its rules of combination, its candidate for the fastest rate and its states when
 * off. The list of entries, MODEL_EFFECTS(X), is generated from the XML (model_effects.h, by
 * gen_vars.py) in the XML's order; params.c and plant.c iterate PLANT_EFFECTS instead of naming
 * effects. The per-sample equations do not go through the table: plant.c, the solvers and the
 * per-sample scheme call the effects' force and state terms directly. */
#ifndef EFFECT_H
#define EFFECT_H

#include <stdbool.h>
#include <stddef.h>

#include "model_effects.h"
#include "model_vars.h"
#include "plant.h"

/* a single-value rule: lo/hi with open (1) or closed (0) ends */
typedef struct { double lo; int lo_open; double hi; int hi_open; } param_range_t;

/* the fastest rate the solver must resolve: the largest candidate [1/s] and the parameter it comes
 * from (its value reference) */
typedef struct { double rate; unsigned vr; } effect_rate_t;

typedef struct {
    const char *id;      /* the catalogue's id (its switch is effects.<id>) */
    unsigned vr;         /* value reference of the switch */
    /* the single-value rule of one of the effect's parameters: true and *r when vr is one */
    bool (*range)(unsigned vr, param_range_t *r);
    /* what the switch does to p: the effect's compiled fields from the values val (switch on or
     * off), refusing values they cannot be compiled from (false and a message naming the
     * variable, its value and the allowed range); entries compile in table order */
    bool (*compile)(const double *val, plant_params_t *p, char *msg, size_t msglen);
    /* the rules of combination over every compiled parameter (after every entry compiled) */
    bool (*check)(const double *val, const plant_params_t *p, char *msg, size_t msglen);
    /* the effect's candidates for the fastest rate into *best (the larger wins, the first of
     * equals stays); true when the rate has no bound, with the whole message written into buf */
    bool (*rate)(const double *val, const plant_params_t *p, effect_rate_t *best, char *buf, size_t n);
    /* the continuous states the effect owns, set to their rest values where it is off */
    void (*init)(const plant_params_t *p, double *y);
    /* after tunable parameters changed from old to p: its discrete and continuous states */
    void (*retune)(const plant_params_t *old, const plant_params_t *p, plant_disc_t *d, double *y);
} effect_t;

#define EFFECT_DECLARE(id) extern const effect_t effect_##id;
MODEL_EFFECTS(EFFECT_DECLARE)
#undef EFFECT_DECLARE

/* every effect, in the order of modelDescription.xml (effects.c) */
extern const effect_t *const PLANT_EFFECTS[MODEL_NEFFECTS];

/* the shortest decimal form of v that reads back exactly (%.15g when enough, else %.17g) */
const char *effect_num(char *buf, size_t n, double v);
/* one candidate of an effect's rate: rate [1/s] from the parameter vr */
void effect_rate_candidate(effect_rate_t *best, unsigned vr, double rate);

#endif
