/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* pointclass.c - tolerance-based point classification (IN / OUT / ON) of points against
 * polygonal regions by the outcode method of Chung & Park (seed 002), made exact. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mfg_internal.h"
#include "pointclass/pointclass.h"
#include "common/predicates.h"

/*
 * The method (paper §3, with the changes noted):
 *  - Each vertex is coded against the tolerance box of the test point T, like
 *    Cohen-Sutherland: L (x < tx-e), R (x > tx+e), D (y < ty-e), U (y > ty+e).  An edge
 *    whose two codes share an L or R bit can neither touch the e-disc nor cross the
 *    vertical ray; this is the test almost every edge fails, so the L/R bits of a whole
 *    ring are computed with SIMD and only surviving edges get their U/D bits.
 *  - An edge sharing D is below the box: no ON, no crossing.  An edge sharing U is above
 *    the box: no ON, and it crosses the ray iff it straddles x = tx.
 *  - Every other edge meets the box; its exact point-segment distance decides ON.
 *
 * Change 1 (crossing line).  The paper counts crossings by code transitions (LU -> U/RU),
 * which amounts to counting on the line x = tx - e; that line is not representable in
 * floating point, so its count cannot be made exact.  We count crossings of the true ray
 * {x = tx, y > ty} with the half-open rule "one end has x < tx, the other x >= tx" (a
 * vertex on the ray is counted once by its two edges; horizontal edges never count),
 * and decide above/below exactly with an orientation predicate.  For a point that is
 * not ON the two counts have the same parity, so IN/OUT is as in the paper.
 * Change 2 (ON exactly).  The paper's "vertex in the centre box and within e" test and
 * its nearest-point test are done in floating point; here "distance <= e" is decided by
 * an exact predicate (predicates.c), so points inside the e-box but outside the e-disc,
 * and points at distance e(1 +- 2^-52), are classified by the definition.
 * The box itself is rounded outward, so the bit tests only ever reject edges that are
 * certainly farther than e.
 */

/* v moved outward by at least one ulp: covers the half-ulp error of the one rounding
 * that produced v (the additive term covers results near zero). */
#define ROUND_ULP 0x1p-52    /* one ulp of |v| (2u), relative */
#define ROUND_TINY 0x1p-1022 /* the smallest normal double: results near zero */
static inline double round_down(double v) { return v - (fabs(v) * ROUND_ULP + ROUND_TINY); }
static inline double round_up(double v) { return v + (fabs(v) * ROUND_ULP + ROUND_TINY); }

mfg_tolbox mfg_tolbox_make(double tx, double ty, double tol)
{
    mfg_tolbox b;
    b.xlo = round_down(tx - tol);
    b.xhi = round_up(tx + tol);
    b.ylo = round_down(ty - tol);
    b.yhi = round_up(ty + tol);
    return b;
}

mfg_status mfg_ringset_build(mfg_ringset *rs, const double *xy, const int64_t *ring_offsets,
                             int64_t nrings, double tol)
{
    memset(rs, 0, sizeof *rs);
    if (nrings < 0)
        return mfg_fail(MFG_ERR_INVALID, "nrings must be >= 0 (got %lld)", (long long)nrings);
    if (!ring_offsets)
        return mfg_fail(MFG_ERR_NULL, "ring_offsets is NULL");
    if (nrings == 0)
        return mfg_fail(MFG_ERR_DEGENERATE, "no rings: a region needs at least one ring (nrings = %lld)",
                        (long long)nrings);
    /* Every ring has 3 vertices or more: a larger nrings can only be a wrong count, and
     * walking ring_offsets that far would read past the caller's array. */
    if (nrings > MFG_MAX_COUNT / 3)
        return mfg_fail(MFG_ERR_INVALID, "nrings = %lld is more than %lld rings of 3 vertices",
                        (long long)nrings, (long long)(MFG_MAX_COUNT / 3));
    if (!(tol >= 0.0) || !mfg_coord_ok(tol))
        return mfg_fail(MFG_ERR_INVALID, "tolerance must be 0 or between 2^-200 and 2^200 (got %g)", tol);
    if (ring_offsets[0] != 0)
        return mfg_fail(MFG_ERR_INVALID, "ring_offsets[0] must be 0 (got %lld)",
                        (long long)ring_offsets[0]);
    /* Compared before subtracted: with ring_offsets[r] in [0, MFG_MAX_COUNT] (by
     * induction from ring_offsets[0] = 0) and ring_offsets[r + 1] checked against both
     * ends, the difference cannot overflow ({0, 4, INT64_MIN + 2} once wrapped to a
     * positive ring size and a too-small allocation). */
    for (int64_t r = 0; r < nrings; r++) {
        int64_t k0 = ring_offsets[r], k1 = ring_offsets[r + 1];
        if (k1 < k0)
            return mfg_fail(MFG_ERR_INVALID,
                            "ring_offsets must be non-decreasing (ring %lld: %lld after %lld)",
                            (long long)r, (long long)k1, (long long)k0);
        if (k1 > MFG_MAX_COUNT)
            return mfg_fail(MFG_ERR_INVALID,
                            "ring_offsets[%lld] = %lld: more than %lld vertices in all",
                            (long long)(r + 1), (long long)k1, (long long)MFG_MAX_COUNT);
        if (k1 - k0 < 3)
            return mfg_fail(MFG_ERR_DEGENERATE,
                            "ring %lld has %lld vertices; a ring needs at least 3",
                            (long long)r, (long long)(k1 - k0));
    }
    int64_t total = ring_offsets[nrings];
    if (!xy)
        return mfg_fail(MFG_ERR_NULL, "xy (ring vertices) is NULL");
    for (int64_t k = 0; k < 2 * total; k++)
        if (!mfg_coord_ok(xy[k]))
            return mfg_fail(MFG_ERR_INVALID,
                            "vertex %lld has a NaN, infinite or out-of-range coordinate (allowed: 0 or 2^-200 <= |x| <= 2^200) (%g)",
                            (long long)(k / 2), xy[k]);

    int64_t nslots = total + nrings;
    if ((uint64_t)nslots > SIZE_MAX / sizeof(double)) /* only on 32-bit targets */
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate %lld ring vertices", (long long)nslots);
    rs->x = malloc((size_t)nslots * sizeof(double));
    rs->y = malloc((size_t)nslots * sizeof(double));
    rs->ring_first = malloc((size_t)nrings * sizeof(int64_t));
    rs->ring_edges = malloc((size_t)nrings * sizeof(int64_t));
    if (!rs->x || !rs->y || !rs->ring_first || !rs->ring_edges) {
        mfg_ringset_free(rs);
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate %lld ring vertices", (long long)nslots);
    }
    rs->nrings = nrings;
    rs->nedges = total;
    rs->nslots = nslots;
    rs->minx = rs->miny = INFINITY;
    rs->maxx = rs->maxy = -INFINITY;
    int64_t s = 0;
    for (int64_t r = 0; r < nrings; r++) {
        int64_t k0 = ring_offsets[r], k1 = ring_offsets[r + 1];
        rs->ring_first[r] = s;
        rs->ring_edges[r] = k1 - k0;
        for (int64_t k = k0; k < k1; k++, s++) {
            double x = xy[2 * k], y = xy[2 * k + 1];
            rs->x[s] = x;
            rs->y[s] = y;
            rs->minx = fmin(rs->minx, x);
            rs->maxx = fmax(rs->maxx, x);
            rs->miny = fmin(rs->miny, y);
            rs->maxy = fmax(rs->maxy, y);
        }
        rs->x[s] = xy[2 * k0]; /* closing copy: edge k1-1 -> k0 */
        rs->y[s] = xy[2 * k0 + 1];
        s++;
    }
    return MFG_OK;
}

/* Float conversions rounded toward -inf / +inf (out-of-range values saturate to an
 * infinity on the safe side instead of the undefined plain conversion). */
static float float_down(double v)
{
    if (v > FLT_MAX)
        return FLT_MAX;
    if (v < -FLT_MAX)
        return -INFINITY;
    float f = (float)v;
    return (double)f > v ? nextafterf(f, -INFINITY) : f;
}

static float float_up(double v)
{
    if (v < -FLT_MAX)
        return -FLT_MAX;
    if (v > FLT_MAX)
        return INFINITY;
    float f = (float)v;
    return (double)f < v ? nextafterf(f, INFINITY) : f;
}

mfg_status mfg_ringset_build_extents(mfg_ringset *rs)
{
    rs->fxmin = malloc((size_t)rs->nslots * sizeof(float));
    rs->fxmax = malloc((size_t)rs->nslots * sizeof(float));
    if (!rs->fxmin || !rs->fxmax)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate edge extents for %lld edges",
                        (long long)rs->nedges);
    for (int64_t i = 0; i + 1 < rs->nslots; i++) {
        rs->fxmin[i] = float_down(fmin(rs->x[i], rs->x[i + 1]));
        rs->fxmax[i] = float_up(fmax(rs->x[i], rs->x[i + 1]));
    }
    for (int64_t r = 0; r < rs->nrings; r++) {
        int64_t closing = rs->ring_first[r] + rs->ring_edges[r];
        rs->fxmin[closing] = INFINITY;
        rs->fxmax[closing] = -INFINITY;
    }
    return MFG_OK;
}

void mfg_ringset_free(mfg_ringset *rs)
{
    free(rs->fxmin);
    free(rs->fxmax);
    free(rs->x);
    free(rs->y);
    free(rs->ring_first);
    free(rs->ring_edges);
    memset(rs, 0, sizeof *rs);
}

mfg_status mfg_check_points(const double *pts, int64_t npoints, const void *out)
{
    if (npoints < 0)
        return mfg_fail(MFG_ERR_INVALID, "npoints must be >= 0 (got %lld)", (long long)npoints);
    if (npoints > MFG_MAX_COUNT) /* also keeps 2 * npoints below overflow */
        return mfg_fail(MFG_ERR_INVALID, "npoints = %lld is more than %lld points",
                        (long long)npoints, (long long)MFG_MAX_COUNT);
    if (npoints == 0)
        return MFG_OK;
    if (!pts)
        return mfg_fail(MFG_ERR_NULL, "pts is NULL");
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "out is NULL");
    /* Blocks without an early exit vectorise; the culprit is searched only on failure. */
    for (int64_t b = 0; b < 2 * npoints; b += 256) {
        int64_t e = b + 256 < 2 * npoints ? b + 256 : 2 * npoints;
        int ok = 1;
        for (int64_t k = b; k < e; k++)
            ok &= mfg_coord_ok(pts[k]);
        if (ok)
            continue;
        for (int64_t k = b; k < e; k++)
            if (!mfg_coord_ok(pts[k]))
                return mfg_fail(MFG_ERR_INVALID,
                                "point %lld has a NaN, infinite or out-of-range coordinate (allowed: 0 or 2^-200 <= |x| <= 2^200) (%g)",
                                (long long)(k / 2), pts[k]);
    }
    return MFG_OK;
}

/* State of one test point while its rings are walked. */
typedef struct probe {
    double tx, ty, tol;
    mfg_tolbox box;
    int crossings;
} probe;

/* An edge that survived the L/R bit test: finish its outcode and decide it.
 * Returns 1 when T is ON (within tol of this edge). */
static inline int visit_edge(const mfg_ringset *rs, int64_t i, probe *p)
{
    double ax = rs->x[i], ay = rs->y[i], bx = rs->x[i + 1], by = rs->y[i + 1];
    int straddle = (ax < p->tx) != (bx < p->tx);
    if (ay > p->box.yhi && by > p->box.yhi) { /* shared U bit */
        p->crossings += straddle;
        return 0;
    }
    if (ay < p->box.ylo && by < p->box.ylo) /* shared D bit */
        return 0;
    if (!mfg_far_from_line(p->tx, p->ty, ax, ay, bx, by, p->tol) &&
        mfg_segment_within(p->tx, p->ty, ax, ay, bx, by, p->tol))
        return 1;
    if (straddle) {
        if (ay > p->ty && by > p->ty) {
            p->crossings++;
        } else if (!(ay < p->ty && by < p->ty)) {
            /* Above iff T is right of the edge directed from its left end: never 0 here,
             * since T on the edge would have been ON. */
            int o = ax < bx ? mfg_orient2d(ax, ay, bx, by, p->tx, p->ty)
                            : mfg_orient2d(bx, by, ax, ay, p->tx, p->ty);
            p->crossings += o < 0;
        }
    }
    return 0;
}

/* Walks edges (slots) [first, first + count); returns 1 as soon as T is ON.  An edge
 * survives the L/R bit test when its x-extent meets [xlo, xhi]. */
static int scan_scalar(const mfg_ringset *rs, int64_t first, int64_t count, probe *p)
{
    const double *X = rs->x;
    double lo = p->box.xlo, hi = p->box.xhi;
    for (int64_t i = first; i < first + count; i++) {
        double a = X[i], b = X[i + 1];
        if ((a < lo && b < lo) || (a > hi && b > hi))
            continue;
        if (visit_edge(rs, i, p))
            return 1;
    }
    return 0;
}

/* The same test on the float extents (rounded outward, and the box rounded outward
 * again, so a rejection is still certain).  Works over all slots at once: closing slots
 * carry empty extents. */
static inline int scan_extents_tail(const mfg_ringset *rs, int64_t i, int64_t end, float lo,
                                    float hi, probe *p)
{
    for (; i < end; i++)
        if (rs->fxmax[i] >= lo && rs->fxmin[i] <= hi && visit_edge(rs, i, p))
            return 1;
    return 0;
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#include <immintrin.h>
#define MFG_HAVE_SIMD 1

/* Visits the edges base + k for the set bits k of mask (candidates of a SIMD block). */
static inline int visit_mask(const mfg_ringset *rs, int64_t base, uint32_t mask, probe *p)
{
    while (mask) {
        int k = __builtin_ctz(mask);
        mask &= mask - 1;
        if (visit_edge(rs, base + k, p))
            return 1;
    }
    return 0;
}

__attribute__((target("avx2"))) static int scan_extents_avx2(const mfg_ringset *rs, float lo,
                                                              float hi, probe *p)
{
    const __m256 vlo = _mm256_set1_ps(lo), vhi = _mm256_set1_ps(hi);
    const float *mn = rs->fxmin, *mx = rs->fxmax;
    int64_t n = rs->nslots - 1, i = 0;
    for (; i + 16 <= n; i += 16) {
        __m256 k0 = _mm256_and_ps(_mm256_cmp_ps(_mm256_loadu_ps(mx + i), vlo, _CMP_GE_OQ),
                                  _mm256_cmp_ps(_mm256_loadu_ps(mn + i), vhi, _CMP_LE_OQ));
        __m256 k1 = _mm256_and_ps(_mm256_cmp_ps(_mm256_loadu_ps(mx + i + 8), vlo, _CMP_GE_OQ),
                                  _mm256_cmp_ps(_mm256_loadu_ps(mn + i + 8), vhi, _CMP_LE_OQ));
        uint32_t m = (uint32_t)_mm256_movemask_ps(k0) | ((uint32_t)_mm256_movemask_ps(k1) << 8);
        if (m && visit_mask(rs, i, m, p))
            return 1;
    }
    return scan_extents_tail(rs, i, n, lo, hi, p);
}

__attribute__((target("avx512f"))) static int scan_extents_avx512(const mfg_ringset *rs,
                                                                   float lo, float hi, probe *p)
{
    const __m512 vlo = _mm512_set1_ps(lo), vhi = _mm512_set1_ps(hi);
    const float *mn = rs->fxmin, *mx = rs->fxmax;
    int64_t n = rs->nslots - 1, i = 0;
    for (; i + 32 <= n; i += 32) {
        __mmask16 k0 = _mm512_mask_cmp_ps_mask(_mm512_cmp_ps_mask(_mm512_loadu_ps(mx + i), vlo, _CMP_GE_OQ),
                                               _mm512_loadu_ps(mn + i), vhi, _CMP_LE_OQ);
        __mmask16 k1 = _mm512_mask_cmp_ps_mask(_mm512_cmp_ps_mask(_mm512_loadu_ps(mx + i + 16), vlo, _CMP_GE_OQ),
                                               _mm512_loadu_ps(mn + i + 16), vhi, _CMP_LE_OQ);
        uint32_t m = (uint32_t)k0 | ((uint32_t)k1 << 16);
        if (m && visit_mask(rs, i, m, p))
            return 1;
    }
    return scan_extents_tail(rs, i, n, lo, hi, p);
}
#endif

static int scan_extents_plain(const mfg_ringset *rs, float lo, float hi, probe *p)
{
    return scan_extents_tail(rs, 0, rs->nslots - 1, lo, hi, p);
}

typedef int (*scan_fn)(const mfg_ringset *, float, float, probe *);

static scan_fn pick_scan(void)
{
#ifdef MFG_HAVE_SIMD
    if (__builtin_cpu_supports("avx512f"))
        return scan_extents_avx512;
    if (__builtin_cpu_supports("avx2"))
        return scan_extents_avx2;
#endif
    return scan_extents_plain;
}

static inline int box_misses_bbox(const mfg_ringset *rs, const mfg_tolbox *b)
{
    /* A box apart from the region's bounding box: farther than tol from every edge and
     * outside every ring, so OUT without a walk. */
    return b->xhi < rs->minx || b->xlo > rs->maxx || b->yhi < rs->miny || b->ylo > rs->maxy;
}

static void probe_init(probe *p, double tx, double ty, double tol)
{
    p->tx = tx;
    p->ty = ty;
    p->tol = tol;
    p->box = mfg_tolbox_make(tx, ty, tol);
    p->crossings = 0;
}

uint8_t mfg_classify_one(const mfg_ringset *rs, double tx, double ty, double tol)
{
    probe p;
    probe_init(&p, tx, ty, tol);
    if (box_misses_bbox(rs, &p.box))
        return MFG_OUT;
    for (int64_t r = 0; r < rs->nrings; r++)
        if (scan_scalar(rs, rs->ring_first[r], rs->ring_edges[r], &p))
            return MFG_ON;
    return (p.crossings & 1) ? MFG_IN : MFG_OUT;
}

mfg_status mfg_classify_points(const double *xy, const int64_t *ring_offsets, int64_t nrings,
                               const double *pts, int64_t npoints, double tol, uint8_t *out)
{
    mfg_ringset rs;
    mfg_status st = mfg_check_points(pts, npoints, out);
    if (st != MFG_OK)
        return st;
    st = mfg_ringset_build(&rs, xy, ring_offsets, nrings, tol);
    if (st != MFG_OK)
        return st;
    st = mfg_ringset_build_extents(&rs);
    if (st != MFG_OK) {
        mfg_ringset_free(&rs);
        return st;
    }
    scan_fn scan = pick_scan();
    for (int64_t k = 0; k < npoints; k++) {
        probe p;
        probe_init(&p, pts[2 * k], pts[2 * k + 1], tol);
        if (box_misses_bbox(&rs, &p.box)) {
            out[k] = MFG_OUT;
            continue;
        }
        /* Clamped to finite floats: the closing slots' empty extents (+inf, -inf) must
         * fail the test even for a box reaching beyond the float range. */
        float lo = fmaxf(float_down(p.box.xlo), -FLT_MAX), hi = fminf(float_up(p.box.xhi), FLT_MAX);
        if (scan(&rs, lo, hi, &p))
            out[k] = MFG_ON;
        else
            out[k] = (p.crossings & 1) ? MFG_IN : MFG_OUT;
    }
    mfg_ringset_free(&rs);
    mfg_clear_error();
    return MFG_OK;
}

int mfg_edge_crosses_segment(double rx, double ry, double tx, double ty, double ax,
                             double ay, double bx, double by)
{
    /* Edges whose boxes are strictly apart from the segment's cannot cross it. */
    if (mfg_segment_boxes_apart(rx, ry, tx, ty, ax, ay, bx, by))
        return 0;
    /* Symbolic perturbation: a vertex exactly on the line r-t is taken to lie on its
     * left (positive) side, i.e. the line is shifted infinitesimally to the right.  The
     * shifted segment meets no vertex, so each edge crosses it 0 or 1 times and the sum
     * over the boundary has the parity of the change of inside-ness from r to t. */
    int sa = mfg_orient2d(rx, ry, tx, ty, ax, ay);
    int sb = mfg_orient2d(rx, ry, tx, ty, bx, by);
    if ((sa >= 0) == (sb >= 0))
        return 0;
    if (sa != 0 && sb != 0) {
        /* A proper crossing of the line: inside the segment iff r and t are on opposite
         * sides of the edge's line (neither is on it: both are off the boundary). */
        int o_r = mfg_orient2d(ax, ay, bx, by, rx, ry);
        int o_t = mfg_orient2d(ax, ay, bx, by, tx, ty);
        return o_r * o_t < 0;
    }
    /* One end v lies on the line: the shifted line crosses the edge next to v, inside
     * the segment iff v is strictly between r and t. */
    double vx = sa == 0 ? ax : bx, vy = sa == 0 ? ay : by;
    return mfg_dot2d(rx, ry, tx, ty, vx, vy) > 0 && mfg_dot2d(tx, ty, rx, ry, vx, vy) > 0;
}
