/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* mfg_internal.h - private helpers shared by every algorithm family (errors, limits). */
#ifndef MFG_INTERNAL_H
#define MFG_INTERNAL_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "mfgeom.h"

/* Records the detail text for the calling thread and returns status, so that a
 * failure path reads `return mfg_fail(MFG_ERR_INVALID, "...", ...);`. */
mfg_status mfg_fail(mfg_status status, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* Clears the thread's detail text (called on success paths of public entry points). */
void mfg_clear_error(void);

/* Largest count (of vertices, points, rings, polygons, normals) any entry point accepts:
 * 2^40, far beyond real inputs, yet every size derived from it (times 3 doubles, plus a
 * slot per ring, in bytes) stays far below INT64_MAX, so no size computation can wrap.
 * A larger count cannot describe memory the caller owns: it is rejected before anything
 * is read through it. */
#define MFG_MAX_COUNT ((int64_t)1 << 40)

/* True when v is 0 or MFG_MIN_COORD <= |v| <= MFG_MAX_COORD (false for NaN and Inf).
 * Inside that range every coordinate is a multiple of 2^-252, so every exact
 * intermediate of a degree-4 predicate is a multiple of 2^-1008: representable, never
 * flushed to zero, and below 2^810: the expansion arithmetic stays exact. */
static inline int mfg_coord_ok(double v)
{
    /* On the bit pattern with the sign cleared, integer order is the order of |v| (NaN
     * and Inf sort above every finite value): integer compares, no branch on the sign
     * (which random inputs mispredict), and loops over many values vectorise. */
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    u &= 0x7fffffffffffffffULL;
    return (u == 0) | ((u >= 0x3370000000000000ULL) & (u <= 0x4c70000000000000ULL));
}

/* Union-find over 0 .. n-1 (parent[i] = i initially) with path halving; the smaller index
 * becomes the root, so results do not depend on the order of the unions.  Shared by the
 * closed-mesh check (fans, components) and the sweep's pinch resolution. */
static inline int64_t mfg_uf_find(int64_t *parent, int64_t x)
{
    while (parent[x] != x) {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    return x;
}

static inline void mfg_uf_union(int64_t *parent, int64_t a, int64_t b)
{
    a = mfg_uf_find(parent, a);
    b = mfg_uf_find(parent, b);
    if (a < b)
        parent[b] = a;
    else if (b < a)
        parent[a] = b;
}

#endif
