/* The plant's effect table (effect.h): its entries, generated from modelDescription.xml's
 * `effects.*` switches (model_effects.h), and the helpers the entries share. */
#include <stdio.h>
#include <stdlib.h>

#include "effect.h"

#define EFFECT_ENTRY(id) &effect_##id,
const effect_t *const PLANT_EFFECTS[MODEL_NEFFECTS] = {MODEL_EFFECTS(EFFECT_ENTRY)};
#undef EFFECT_ENTRY

const char *effect_num(char *buf, size_t n, double v) {
    snprintf(buf, n, "%.15g", v);
    if (strtod(buf, NULL) != v) snprintf(buf, n, "%.17g", v);
    return buf;
}

void effect_rate_candidate(effect_rate_t *best, unsigned vr, double rate) {
    if (rate > best->rate) {
        best->rate = rate;
        best->vr = vr;
    }
}
