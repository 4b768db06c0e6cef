/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* mfg_internal.h - private helpers shared by every algorithm family (errors, limits). */
#ifndef MFG_INTERNAL_H
#define MFG_INTERNAL_H

#include <math.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
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

/* Progress of one call of a long entry point (mfg_progress in mfgeom.h): lives on the
 * caller's stack, so the library keeps no state between calls.  Only the calling thread
 * reports (mfg_prog_stage, mfg_prog_poll, mfg_prog_report); worker threads only read
 * mfg_prog_stopped.  The fraction of a stage runs from lo to lo + span; every is the
 * number of work units (mfg_prog_poll calls) between two reports in that stage. */
typedef struct mfg_prog {
    mfg_progress_fn fn;   /* NULL: inactive (every function below is then a no-op) */
    void *user;
    const char *call;     /* the entry point, for the detail message */
    const char *stage;    /* the current stage (static string) */
    double lo, span;      /* the stage's part of [0, 1] */
    double last;          /* the last fraction reported: reports never go back */
    int64_t left, every;  /* units until the next report; units between reports */
    int64_t reports;      /* callbacks made (for the tests of the interval) */
    atomic_int stop;      /* set once the callback returned nonzero */
} mfg_prog;

/* Starts the progress of a call named call (e.g. "mfg_rotational_sweep"); progress may be
 * NULL. */
void mfg_prog_init(mfg_prog *p, const mfg_progress *progress, const char *call);
/* Enters stage (a static string) spanning fractions lo .. hi, reporting every `every` work
 * units, and reports its start.  Returns 1 to go on, 0 when the call must stop. */
int mfg_prog_stage(mfg_prog *p, const char *stage, double lo, double hi, int64_t every);
/* Reports the fraction done / total of the current stage now.  Returns 1 / 0 as above. */
int mfg_prog_report(mfg_prog *p, double done, double total);
/* True once the callback has asked to stop (any thread may ask). */
static inline int mfg_prog_stopped(const mfg_prog *p)
{
    return p->fn && atomic_load_explicit(&p->stop, memory_order_relaxed);
}
/* One work unit of the current stage, done of total done: reports every p->every units.
 * Returns 1 to go on, 0 when the call must stop.  Calling thread only. */
static inline int mfg_prog_poll(mfg_prog *p, double done, double total)
{
    if (!p->fn)
        return 1;
    if (--p->left > 0)
        return !atomic_load_explicit(&p->stop, memory_order_relaxed);
    return mfg_prog_report(p, done, total);
}
/* For the workers of a parallel stage (p may be NULL): the caller's own thread
 * (is_caller) polls as mfg_prog_poll; the other threads only see whether to stop. */
static inline int mfg_prog_poll_mt(mfg_prog *p, int is_caller, double done, double total)
{
    if (!p || !p->fn)
        return 1;
    return is_caller ? mfg_prog_poll(p, done, total) : !mfg_prog_stopped(p);
}
/* Records the detail "<call>: cancelled in stage \"<stage>\"" and returns MFG_ERR_CANCELLED. */
mfg_status mfg_prog_fail(const mfg_prog *p);

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
 * closed-mesh check (fans, components), the arrangement and the sweep. */
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

/* Advises the system to back a large table (bytes of it from p) by huge pages, where it can
 * (common/memory.c); small tables and other systems: nothing. */
void mfg_huge_pages(void *p, size_t bytes);

/* The capacity for need items: cap (or first, when cap is 0) doubled until it holds them
 * (need itself once doubling would overflow).  The one doubling rule of the growable
 * buffers, including those that grow several arrays together (mfg_resize). */
static inline int64_t mfg_grown_cap(int64_t cap, int64_t need, int64_t first)
{
    int64_t c = cap > 0 ? cap : first;
    while (c < need)
        c = c > INT64_MAX / 2 ? need : 2 * c;
    return c;
}

/* Grows the array *p (items of size bytes, capacity *cap) to hold need items, doubling from
 * 16.  Returns 1, or 0 when memory runs out or the size would not fit in a size_t (then
 * *p and *cap are untouched and still valid).  The one growable-buffer helper. */
static inline int mfg_grow(void **p, int64_t *cap, int64_t need, size_t size)
{
    if (need <= *cap)
        return 1;
    if (need > (int64_t)(PTRDIFF_MAX / (ptrdiff_t)size))
        return 0;
    int64_t c = mfg_grown_cap(*cap, need, 16);
    void *q = realloc(*p, (size_t)c * size);
    if (!q)
        return 0;
    mfg_huge_pages(q, (size_t)c * size);
    *p = q;
    *cap = c;
    return 1;
}

/* Moves the block *p to one of n items of size bytes (realloc): 1, or 0 when memory runs
 * out (then *p is untouched and still valid).  For arrays that share one capacity, grown
 * together (mfg_grow keeps a capacity per array). */
static inline int mfg_resize(void **p, int64_t n, size_t size)
{
    void *q = realloc(*p, (size_t)n * size);
    if (!q)
        return 0;
    *p = q;
    return 1;
}

/* The index of the first entry >= v in the ascending a[0 .. n) (n if none). */
static inline int64_t mfg_lower_bound_i64(const int64_t *a, int64_t n, int64_t v)
{
    int64_t lo = 0, hi = n;
    while (lo < hi) {
        int64_t mid = lo + (hi - lo) / 2;
        if (a[mid] < v)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The thinning of a polyline into chords (the medial seams, the medial sheets' boundary
 * loops): the farthest j in (a, end] for which holds(ctx, a, j) - "the chord from point a
 * to point j stands for every point between" - is true, given that it is for a + 1.
 * Found by doubling the span from a, then halving between the last span that held and
 * the first that did not, so a run of k points that all hold costs O(k log k) point
 * checks (extending the chord one point at a time rechecks every point: O(k^2)).  Where
 * holds is not monotone in j this may reach past a j that fails: every chord returned
 * holds all the same. */
static inline int64_t mfg_farthest_chord(int64_t a, int64_t end,
                                         int (*holds)(const void *ctx, int64_t a, int64_t j),
                                         const void *ctx)
{
    int64_t good = a + 1, bad = end + 1, span = 2;
    while (a + span <= end) {
        if (!holds(ctx, a, a + span)) {
            bad = a + span;
            break;
        }
        good = a + span;
        span *= 2;
    }
    if (bad == end + 1 && good < end) {
        if (holds(ctx, a, end))
            good = end;
        else
            bad = end;
    }
    while (bad - good > 1) {
        int64_t mid = good + (bad - good) / 2;
        if (holds(ctx, a, mid))
            good = mid;
        else
            bad = mid;
    }
    return good;
}

/* qsort comparator of int64_t in ascending order. */
static inline int mfg_cmp_i64(const void *pa, const void *pb)
{
    int64_t a = *(const int64_t *)pa, b = *(const int64_t *)pb;
    return (a > b) - (a < b);
}

#endif
