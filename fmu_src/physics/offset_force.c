/* Effect offset_force (beyond the paper): a constant force offset.F along the axis (a tilted axis'
 * weight, a cable carrier, a bellows preload), a term of Eq. 1: m a = ... - F_offset. Compiled
 * into plant_params_t's F_off (0 N when off), which plant.c subtracts from the applied force. */
#include "effect.h"

static bool compile_offset_force(const double *val, plant_params_t *p, char *msg, size_t msglen) {
    (void)msg; (void)msglen;
    p->F_off = val[VR_effects_offset_force] != 0.0 ? val[VR_offset_F] : 0.0;
    return true;
}

const effect_t effect_offset_force = {
    "offset_force", VR_effects_offset_force, NULL, compile_offset_force, NULL, NULL, NULL, NULL};
