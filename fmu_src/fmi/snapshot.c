/* FMU state objects, every version. A snapshot holds the serialised state (state_format.h and
 * the model's part, model.h), so every snapshot, from memory or from bytes, is loaded through
 * the one decoder that checks every field and re-derives the rest from the parameters. */
#include <math.h>
#include <string.h>

#include "state_format.h"

#define BLOB_MAGIC 0x46444253u   /* marks an fmi2FMUstate of this FMU */

typedef struct blob {
    unsigned magic;
    size_t len;
    instance_t *owner;              /* the instance that allocated it; listed in owner->states */
    struct blob *prev, *next;
    unsigned char bytes[STATE_MAX_BYTES];
} blob_t;

static blob_t *as_blob(instance_t *c, const char *fn, fmi2FMUstate state) {
    blob_t *s = (blob_t *)state;
    if (!s || s->magic != BLOB_MAGIC || s->len != model_state_bytes()) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: FMUstate is not a state of this FMU", fn);
        return NULL;
    }
    return s;
}

static blob_t *new_blob(instance_t *c, const char *fn) {
    blob_t *s = (blob_t *)c->cb.allocateMemory(1, sizeof(blob_t));
    if (!s) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: out of memory", fn); return NULL; }
    s->magic = BLOB_MAGIC;
    s->len = model_state_bytes();
    s->owner = c;
    s->prev = NULL;
    s->next = (blob_t *)c->states;
    if (s->next) s->next->prev = s;
    c->states = s;
    return s;
}

/* unlink s from its owner's list and free it with the owner's callbacks */
static void drop_blob(blob_t *s) {
    instance_t *o = s->owner;
    if (s->prev) s->prev->next = s->next;
    else o->states = s->next;
    if (s->next) s->next->prev = s->prev;
    s->magic = 0;
    o->cb.freeMemory(s);
}

void fmu_states_free_all(instance_t *c) {
    while (c->states) drop_blob((blob_t *)c->states);
}

fmi2Status fmu_state_get(instance_t *c, const char *fn, void **state) {
    blob_t *s;
    if (!c) return fmi2Error;
    if (!state) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: FMUstate pointer is NULL", fn); return fmi2Error; }
    if (model_state_bytes() > STATE_MAX_BYTES) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: a state needs %zu bytes, more than %u", fn, model_state_bytes(),
                STATE_MAX_BYTES);
        return fmi2Error;
    }
    s = *state ? as_blob(c, fn, *state) : new_blob(c, fn);
    if (!s) return fmi2Error;
    model_state_encode(&c->m, c->type, s->bytes);
    *state = s;
    return fmi2OK;
}

/* bytes checked and loaded into the instance (nothing changes when they are refused) */
static fmi2Status load(instance_t *c, const char *fn, const unsigned char *b, size_t len) {
    model_t tmp;
    if (!model_state_decode(c, fn, b, len, &tmp)) return fmi2Error;
    c->m = tmp;
    return fmi2OK;
}

fmi2Status fmu_state_set(instance_t *c, const char *fn, void *state) {
    blob_t *s;
    if (!c) return fmi2Error;
    if (!(s = as_blob(c, fn, state))) return fmi2Error;
    return load(c, fn, s->bytes, s->len);
}

fmi2Status fmu_state_free(instance_t *c, const char *fn, void **state) {
    blob_t *s;
    if (!c) return fmi2Error;
    if (!state || !*state) return fmi2OK;
    if (!(s = as_blob(c, fn, *state))) return fmi2Error;
    drop_blob(s);
    *state = NULL;
    return fmi2OK;
}

fmi2Status fmu_state_size(instance_t *c, const char *fn, void *state, size_t *size) {
    blob_t *s;
    if (!c) return fmi2Error;
    if (!size) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: size pointer is NULL", fn); return fmi2Error; }
    if (!(s = as_blob(c, fn, state))) return fmi2Error;
    *size = s->len;
    return fmi2OK;
}

fmi2Status fmu_state_serialize(instance_t *c, const char *fn, void *state, unsigned char *out, size_t size) {
    blob_t *s;
    if (!c) return fmi2Error;
    if (!(s = as_blob(c, fn, state))) return fmi2Error;
    if (!out || size < s->len) {
        fmu_log(c, fmi2Error, LOG_ERROR, "%s: invalid buffer (size %zu, need %zu)", fn, size, s->len);
        return fmi2Error;
    }
    memcpy(out, s->bytes, s->len);
    return fmi2OK;
}

fmi2Status fmu_state_deserialize(instance_t *c, const char *fn, const unsigned char *b, size_t size, void **state) {
    model_t tmp;
    blob_t *s;
    if (!c) return fmi2Error;
    if (!state) { fmu_log(c, fmi2Error, LOG_ERROR, "%s: FMUstate pointer is NULL", fn); return fmi2Error; }
    if (!model_state_decode(c, fn, b, size, &tmp)) return fmi2Error;
    s = *state ? as_blob(c, fn, *state) : new_blob(c, fn);
    if (!s) return fmi2Error;
    memcpy(s->bytes, b, size);
    *state = s;
    return fmi2OK;
}
