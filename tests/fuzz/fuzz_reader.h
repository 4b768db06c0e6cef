/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* fuzz_reader.h - the byte reader every libFuzzer target decodes its input with: reads
 * past the end give zero bytes, so every input is a complete case. */
#ifndef MFG_FUZZ_READER_H
#define MFG_FUZZ_READER_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct reader {
    const uint8_t *p;
    size_t n;
} reader;

static inline uint8_t rd_u8(reader *r)
{
    if (r->n == 0)
        return 0;
    r->n--;
    return *r->p++;
}

/* 8 bytes, least significant first */
static inline uint64_t rd_u64(reader *r)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; i++)
        v |= (uint64_t)rd_u8(r) << (8 * i);
    return v;
}

/* the bits of rd_u64 as a double (any value: NaN, Inf, subnormal) */
static inline double rd_f64(reader *r)
{
    uint64_t u = rd_u64(r);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

#endif
