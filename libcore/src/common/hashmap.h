/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* hashmap.h - the open-addressing map from 4-word keys to int64 values shared by the
 * rotational sweep (sweep/: corners, leaves, lifts, welds, edges) and its planar
 * merge (planar_merge.c: directed edges).  Header-only (static inline): private to the
 * library, no symbols exported. */
#ifndef MFG_HASHMAP_H
#define MFG_HASHMAP_H

#include <stdint.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mfg_internal.h" /* mfg_huge_pages */

/* Open-addressing map from a 4-word key to an int64 value. */
typedef struct hkey {
    int64_t w[4];
} hkey;

typedef struct hmap {
    hkey *keys;
    int64_t *vals;
    int64_t cap, n; /* cap is a power of two; vals[i] < 0 marks an empty slot */
} hmap;

static inline uint64_t hkey_hash(const hkey *k)
{
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (int i = 0; i < 4; i++) {
        h ^= (uint64_t)k->w[i] + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
        h *= 0xBF58476D1CE4E5B9ull;
        h ^= h >> 31;
    }
    return h;
}

static inline int hmap_init(hmap *m, int64_t want)
{
    int64_t c = 64;
    while (c < 2 * want)
        c *= 2;
    m->keys = malloc((size_t)c * sizeof *m->keys);
    m->vals = malloc((size_t)c * sizeof *m->vals);
    if (!m->keys || !m->vals) {
        free(m->keys);
        free(m->vals);
        m->keys = NULL;
        m->vals = NULL;
        return 0;
    }
    mfg_huge_pages(m->keys, (size_t)c * sizeof *m->keys);
    mfg_huge_pages(m->vals, (size_t)c * sizeof *m->vals);
    for (int64_t i = 0; i < c; i++)
        m->vals[i] = -1;
    m->cap = c;
    m->n = 0;
    return 1;
}

static inline void hmap_free(hmap *m)
{
    free(m->keys);
    free(m->vals);
    m->keys = NULL;
    m->vals = NULL;
}

/* Slot of k: where it is, or the empty slot where it would go. */
static inline int64_t hmap_slot(const hmap *m, const hkey *k)
{
    int64_t i = (int64_t)(hkey_hash(k) & (uint64_t)(m->cap - 1));
    while (m->vals[i] >= 0 && memcmp(&m->keys[i], k, sizeof *k) != 0)
        i = (i + 1) & (m->cap - 1);
    return i;
}

static inline int64_t hmap_get(const hmap *m, const hkey *k)
{
    return m->vals[hmap_slot(m, k)];
}

/* Sets k -> v (v >= 0); 0 when out of memory. */
static inline int hmap_put(hmap *m, const hkey *k, int64_t v)
{
    if (2 * (m->n + 1) > m->cap) {
        hmap old = *m;
        if (!hmap_init(m, old.cap))
            return (*m = old, 0);
        for (int64_t i = 0; i < old.cap; i++)
            if (old.vals[i] >= 0) {
                int64_t s = hmap_slot(m, &old.keys[i]);
                m->keys[s] = old.keys[i];
                m->vals[s] = old.vals[i];
                m->n++;
            }
        hmap_free(&old);
    }
    int64_t s = hmap_slot(m, k);
    if (m->vals[s] < 0)
        m->n++;
    m->keys[s] = *k;
    m->vals[s] = v;
    return 1;
}

static inline hkey mkkey(int64_t a, int64_t b, int64_t c, int64_t d)
{
    hkey k = {{a, b, c, d}};
    return k;
}

/* The key of the cell of point p in the grid of spacing h, or of its neighbour d (0 .. 26;
 * 13: the cell itself): points within h of p lie in p's 27 cells. */
static inline hkey hmap_cell_key(const double *p, double h, int d)
{
    return mkkey((int64_t)floor(p[0] / h) + d % 3 - 1, (int64_t)floor(p[1] / h) + d / 3 % 3 - 1,
                 (int64_t)floor(p[2] / h) + d / 9 - 1, 0);
}

#endif
