/* The glue's part of the serialised FMU state (layout in state_format.h): the little-endian
 * numbers, the CRC-32, the variables a state stores and the header, written and checked (magic,
 * version, sizes, GUID, interface, structure, checksum) before anything of the payload is used. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "state_format.h"

#define GUID_BYTES 48


void sf_put_u32(wr_t *w, uint32_t v) {
    int j;
    for (j = 0; j < 4; j++) w->b[w->n++] = (unsigned char)(v >> (8 * j));
}
void sf_put_f64(wr_t *w, double v) {
    uint64_t u;
    int j;
    memcpy(&u, &v, sizeof u);
    for (j = 0; j < 8; j++) w->b[w->n++] = (unsigned char)(u >> (8 * j));
}
uint32_t sf_get_u32(rd_t *r) {
    uint32_t v = 0;
    int j;
    for (j = 0; j < 4; j++) v |= (uint32_t)r->b[r->n++] << (8 * j);
    return v;
}
double sf_get_f64(rd_t *r) {
    union { uint64_t u; double d; } bits = {0};   /* the double's pattern (C99 TC3 6.5.2.3) */
    int j;
    for (j = 0; j < 8; j++) bits.u |= (uint64_t)r->b[r->n++] << (8 * j);
    return bits.d;
}

static uint32_t crc32(uint32_t crc, const unsigned char *b, size_t n) {
    size_t i;
    int k;
    crc = ~crc;
    for (i = 0; i < n; i++) {
        crc ^= b[i];
        for (k = 0; k < 8; k++) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
}

/* the variables a state stores: parameters, inputs and the start values of the states */
int sf_stored(const glue_var_t *v) {
    return v->causality == 'p' || v->causality == 'i' || (v->has_start && v->variability == 'c');
}
uint32_t sf_n_stored(void) {
    uint32_t n = 0;
    int j;
    for (j = 0; j < GLUE_NVARS; j++) n += (uint32_t)sf_stored(&GLUE_VARS[j]);
    return n;
}
static uint32_t layout_crc(void) {
    uint32_t crc = 0;
    int j;
    for (j = 0; j < GLUE_NVARS; j++)
        if (sf_stored(&GLUE_VARS[j])) crc = crc32(crc, (const unsigned char *)GLUE_VARS[j].name,
                                                strlen(GLUE_VARS[j].name) + 1);
    return crc;
}
void sf_put_header(wr_t *w, int type, size_t payload) {
    unsigned char guid[GUID_BYTES] = {0};
    memcpy(guid, MODEL_TOKEN, strlen(MODEL_TOKEN) < GUID_BYTES ? strlen(MODEL_TOKEN) : GUID_BYTES - 1);
    sf_put_u32(w, STATE_MAGIC);
    sf_put_u32(w, STATE_VERSION);
    sf_put_u32(w, HEADER_BYTES);
    sf_put_u32(w, (uint32_t)payload);
    memcpy(w->b + w->n, guid, GUID_BYTES);
    w->n += GUID_BYTES;
    sf_put_u32(w, (uint32_t)type);
    sf_put_u32(w, GLUE_NVR);
    sf_put_u32(w, sf_n_stored());
    sf_put_u32(w, GLUE_NX);
    sf_put_u32(w, GLUE_NZ);
    sf_put_u32(w, MODEL_ND);
    sf_put_u32(w, layout_crc());
    sf_put_u32(w, 0u);   /* the payload's CRC, written last */
}

void sf_seal(unsigned char *out, size_t payload) {
    wr_t w = {out, CRC_AT};
    sf_put_u32(&w, crc32(0, out + HEADER_BYTES, payload));
}


int sf_header_ok(instance_t *c, const char *fn, const unsigned char *b, size_t len, size_t payload) {
    static const char *const STRUCT[] = {"value references", "stored variables", "continuous states",
                                         "event indicators", "discrete-state numbers", "variable layout (CRC)"};
    const uint32_t mine[6] = {GLUE_NVR, sf_n_stored(), GLUE_NX, GLUE_NZ, MODEL_ND, layout_crc()};
    static const char *const IFACE[] = {"model exchange", "co-simulation"};
    rd_t r = {b, 0};
    char guid[GUID_BYTES + 1];
    unsigned char mine_guid[GUID_BYTES];
    uint32_t magic, version, hb, pb, type, crc;
    int j;
    if (len < HEADER_BYTES) BAD("%s: %zu bytes are no FMU state: the header alone has %d", fn, len, HEADER_BYTES);
    magic = sf_get_u32(&r); version = sf_get_u32(&r); hb = sf_get_u32(&r); pb = sf_get_u32(&r);
    if (magic != STATE_MAGIC) BAD("%s: not a state of this FMU (magic 0x%08x, expected 0x%08x)", fn,
                                  (unsigned)magic, STATE_MAGIC);
    if (version != STATE_VERSION) BAD("%s: state format version %u, this FMU reads version %u only (a state saved by another build of the FMU)", fn,
                                      (unsigned)version, STATE_VERSION);
    if (hb != HEADER_BYTES || pb != payload || len != HEADER_BYTES + payload)
        BAD("%s: state of %zu bytes (header %u + payload %u), a state of this FMU has %zu (%d + %zu)", fn, len,
            (unsigned)hb, (unsigned)pb, HEADER_BYTES + payload, HEADER_BYTES, payload);
    memcpy(guid, b + r.n, GUID_BYTES);
    guid[GUID_BYTES] = 0;
    r.n += GUID_BYTES;
    memset(mine_guid, 0, sizeof mine_guid);
    memcpy(mine_guid, MODEL_TOKEN, strlen(MODEL_TOKEN) < GUID_BYTES ? strlen(MODEL_TOKEN) : GUID_BYTES - 1);
    if (memcmp(b + 16, mine_guid, GUID_BYTES) != 0)
        BAD("%s: the state's GUID %.48s differs from this FMU's %s", fn, guid, MODEL_TOKEN);
    type = sf_get_u32(&r);
    if (type != (uint32_t)c->type)
        BAD("%s: the state is of %s (interface %u), this instance is %s", fn, type <= 1 ? IFACE[type] : "no interface",
            (unsigned)type, IFACE[c->type == fmi2CoSimulation]);
    for (j = 0; j < 6; j++) {
        uint32_t v = sf_get_u32(&r);
        if (v != mine[j]) BAD("%s: the state's structure differs: %s %u, this FMU has %u", fn, STRUCT[j],
                              (unsigned)v, (unsigned)mine[j]);
    }
    crc = sf_get_u32(&r);
    if (crc != crc32(0, b + HEADER_BYTES, payload))
        BAD("%s: checksum 0x%08x does not match the payload's 0x%08x: the state is corrupted", fn, (unsigned)crc,
            (unsigned)crc32(0, b + HEADER_BYTES, payload));
    return 1;
}

