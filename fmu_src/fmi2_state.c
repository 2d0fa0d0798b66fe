/* FMI 2.0 FMU state: snapshots are copies of the instance's one plain-data struct, so get/set
 * and serialisation are byte copies guarded by a magic number and the struct size. */
#include <math.h>
#include <string.h>

#include "fmi2_instance.h"

/* ---------------------------------------------------------------- FMU state */

fmi2Status fmi2GetFMUstate(fmi2Component comp, fmi2FMUstate *state) {
    instance_t *c = FMU_ENTER(comp, fmi2GetFMUstate);
    model_t *s;
    if (!c) return fmi2Error;
    if (!state) { fmu_log(c, fmi2Error, LOG_ERROR, "fmi2GetFMUstate: FMUstate pointer is NULL"); return fmi2Error; }
    s = (model_t *)*state;
    if (!s) {
        s = (model_t *)c->cb.allocateMemory(1, sizeof(model_t));
        if (!s) { fmu_log(c, fmi2Error, LOG_ERROR, "fmi2GetFMUstate: out of memory"); return fmi2Error; }
    } else if (s->magic != MODEL_MAGIC || s->size != sizeof(model_t)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2GetFMUstate: *FMUstate is not a state of this FMU");
        return fmi2Error;
    }
    memcpy(s, &c->m, sizeof(model_t));
    *state = s;
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component comp, fmi2FMUstate state) {
    instance_t *c = FMU_ENTER(comp, fmi2SetFMUstate);
    const model_t *s = (const model_t *)state;
    if (!c) return fmi2Error;
    if (!s || s->magic != MODEL_MAGIC || s->size != sizeof(model_t)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SetFMUstate: not a state of this FMU");
        return fmi2Error;
    }
    memcpy(&c->m, s, sizeof(model_t));
    c->m.solver_restart = 1;
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component comp, fmi2FMUstate *state) {
    instance_t *c = FMU_ENTER(comp, fmi2FreeFMUstate);
    model_t *s;
    if (!c) return fmi2Error;
    if (!state || !*state) return fmi2OK;
    s = (model_t *)*state;
    if (s->magic != MODEL_MAGIC) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2FreeFMUstate: not a state of this FMU");
        return fmi2Error;
    }
    s->magic = 0;
    c->cb.freeMemory(s);
    *state = NULL;
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component comp, fmi2FMUstate state, size_t *size) {
    instance_t *c = FMU_ENTER(comp, fmi2SerializedFMUstateSize);
    if (!c) return fmi2Error;
    if (!state || !size || ((const model_t *)state)->magic != MODEL_MAGIC) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SerializedFMUstateSize: %s", !size ? "size pointer is NULL"
                : "FMUstate is not a state of this FMU");
        return fmi2Error;
    }
    *size = sizeof(model_t);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component comp, fmi2FMUstate state, fmi2Byte serializedState[], size_t size) {
    instance_t *c = FMU_ENTER(comp, fmi2SerializeFMUstate);
    const model_t *s = (const model_t *)state;
    if (!c) return fmi2Error;
    if (!s || s->magic != MODEL_MAGIC || !serializedState || size < sizeof(model_t)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2SerializeFMUstate: invalid state or buffer (size %zu, need %zu)",
                size, sizeof(model_t));
        return fmi2Error;
    }
    memcpy(serializedState, s, sizeof(model_t));
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component comp, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *state) {
    instance_t *c = FMU_ENTER(comp, fmi2DeSerializeFMUstate);
    model_t tmp;
    if (!c) return fmi2Error;
    if (!serializedState || !state || size != sizeof(model_t)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2DeSerializeFMUstate: size %zu, expected %zu", size, sizeof(model_t));
        return fmi2Error;
    }
    memcpy(&tmp, serializedState, sizeof tmp);
    if (tmp.magic != MODEL_MAGIC || tmp.size != sizeof(model_t)) {
        fmu_log(c, fmi2Error, LOG_ERROR, "fmi2DeSerializeFMUstate: bytes are not a serialized state of this FMU");
        return fmi2Error;
    }
    if (!*state) {
        *state = c->cb.allocateMemory(1, sizeof(model_t));
        if (!*state) { fmu_log(c, fmi2Error, LOG_ERROR, "fmi2DeSerializeFMUstate: out of memory"); return fmi2Error; }
    }
    memcpy(*state, &tmp, sizeof tmp);
    return fmi2OK;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component comp, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[]) {
    instance_t *c = FMU_ENTER(comp, fmi2GetDirectionalDerivative);
    (void)vUnknown_ref; (void)nUnknown; (void)vKnown_ref; (void)nKnown; (void)dvKnown; (void)dvUnknown;
    if (!c) return fmi2Error;
    fmu_log(c, fmi2Error, LOG_ERROR, "fmi2GetDirectionalDerivative: not provided "
            "(providesDirectionalDerivative is false)");
    return fmi2Error;
}
