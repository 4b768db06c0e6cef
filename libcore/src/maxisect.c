/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* maxisect.c - maximum (and level-k, minimum) intersection of spherical convex polygons
 * by edge-based partition (Ha 2001, seed 000 section 4). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mfg_internal.h"
#include "sphere.h"

/*
 * Edge-based partition, as in the paper: every boundary edge of every set is split by
 * the other sets and each piece gets its ownership (the weight of the sets containing
 * it); the pieces of greatest ownership bound the maximum regions, and a region of
 * maximum weight D is exactly the intersection of the sets covering it (any point of that
 * intersection covered by one more set would beat D), hence convex.
 * How it is done here:
 *  - an edge a->b is parametrised by s in [0, 1] through x(s) = a + s (b - a) (a central
 *    projection of the arc, so every half-space constraint x.n >= -tol is linear in s):
 *    the part of the edge inside another convex set is one interval, found in O(v);
 *  - the intervals are swept (closed sets: a start sorts before an end at equal s), which
 *    gives the ownership of every point and piece of the edge and its cover set;
 *  - pairs whose bounding caps are apart are skipped, and edges whose ownership bound
 *    (own weight + every set meeting the edge) cannot reach the best weight found so far
 *    are never swept, edges being visited from the highest bound down;
 *  - each distinct cover set S of maximum weight becomes one region: the intersection of
 *    S by clipping, its centre the centre of the smallest circle enclosing the poles of its
 *    edges (= the largest inscribed circle, the paper's dual construction), computed with
 *    Welzl's algorithm on the sphere.
 * Coverage is decided with the angular tolerance MFG_SPHERE_TOL (a set contains the
 * directions within that distance), so the outcome does not depend on rounding in the
 * inputs' vertices; the order of the input sets does not enter any decision.
 */

#define TOL MFG_SPHERE_TOL

/* One input set, prepared. */
typedef struct sset {
    int kind, closed;
    int64_t id, nv;
    double w;
    double *v;     /* nv unit vertices */
    double *n;     /* POLYGON: inward unit normal of edge k (v[k] -> v[k+1]) */
    double cc[3];  /* bounding cap: centre and angular radius (cos, sin kept) */
    double cr, cos_cr, sin_cr;
    double ic[3], ir;  /* POLYGON: inscribed circle (centre, radius; ir = 0 if none) */
    double cos_ir, sin_ir;
    double *fan;   /* large POLYGON: bearing of each vertex about ic (the fan of ic) */
} sset;

typedef struct interval {
    double lo, hi;
    int64_t set;
} interval;

typedef struct event {
    double s;
    int start; /* 1 = start, 0 = end */
    int64_t set;
} event;

/* A candidate region: its cover set (sorted set indices) and a sample direction. */
typedef struct cand {
    double weight;
    int64_t off, len;  /* cover set in the pool of set indices; len < 0: not computed */
    uint64_t hash;     /* of the cover set, once computed */
    double x[3];
    int degenerate;    /* found only at an isolated point of an edge */
} cand;

typedef struct work {
    sset *sets;
    int64_t nsets;
    interval *iv;
    event *ev;
    int64_t cap_iv;
    /* candidate pool */
    cand *cands;
    int64_t ncands, cap_cands;
    int64_t *pool;
    int64_t npool, cap_pool;
    double best;
    int mode; /* MODE_MAX, MODE_LEVEL or MODE_MIN */
    int scale_exp; /* weights are the caller's times 2^-scale_exp (scale_weights) */
    double eps;    /* weights closer than this are equal */
} work;

enum { MODE_MAX, MODE_LEVEL, MODE_MIN };

/* ---- Membership and edge intervals ---------------------------------------------- */

/* Parameter s of direction y (on the great circle of a->b) along x(s) = a + s (b - a);
 * returns 0 when y is outside the arc (beyond the tolerance). */
static int param_on_edge(const double *a, const double *b, const double *y, double *s)
{
    /* In the plane of the arc: y = alpha a + beta b (solve with the Gram matrix). */
    double ab = mfg_dot3(a, b), ya = mfg_dot3(y, a), yb = mfg_dot3(y, b);
    double det = 1.0 - ab * ab;
    if (det <= 1e-30) { /* a == b: a point */
        double d[3] = {y[0] - a[0], y[1] - a[1], y[2] - a[2]};
        *s = 0.0;
        return sqrt(mfg_dot3(d, d)) <= TOL;
    }
    double alpha = (ya - ab * yb) / det, beta = (yb - ab * ya) / det;
    /* x(s) is proportional to (1 - s) a + s b: s = beta / (alpha + beta). */
    if (alpha + beta <= 0.0)
        return 0;
    double t = beta / (alpha + beta);
    double len = mfg_angle3(a, b);
    double slack = TOL / fmax(len, TOL); /* tolerance as a fraction of the edge */
    if (t < -slack || t > 1.0 + slack)
        return 0;
    *s = fmin(fmax(t, 0.0), 1.0);
    return 1;
}

/* ---- The fan of a large polygon: O(log v) membership and O(log v + k) clipping ----
 *
 * A convex polygon is the union of the triangles (ic, v_k, v_k+1) about an interior
 * point ic: the lune between the half meridians from ic through v_k and v_k+1 meets the
 * polygon exactly where it meets the half-space of edge k.  The bearings of the vertices
 * about ic increase with k, so the triangle holding a direction is found by binary
 * search, and an arc, whose bearing about ic is monotone, only crosses the triangles
 * between those of its ends: only their edges can clip it.  Neighbouring edges (FAN_PAD
 * on each side) are tested too, so a direction within the tolerance of a vertex is
 * treated exactly as by the test against every edge. */
#define FAN_MIN_VERTICES 32 /* below this, testing every edge is as fast */
#define FAN_PAD 2

/* Bearing of y about ic, from v_0, in [0, 2 pi). */
static double fan_bearing(const sset *S, const double *y)
{
    double p[3], q[3], x[3];
    mfg_cross3(S->ic, S->v, p);
    mfg_cross3(S->ic, y, q);
    mfg_cross3(p, q, x);
    double t = atan2(mfg_dot3(x, S->ic), mfg_dot3(p, q));
    return t < 0.0 ? t + 2 * MFG_PI : t;
}

/* Index k of the triangle (ic, v_k, v_k+1) holding direction y. */
static int64_t fan_locate(const sset *S, const double *y)
{
    double t = fan_bearing(S, y);
    int64_t lo = 0, hi = S->nv; /* fan[lo] <= t < fan[hi] (fan[nv] = 2 pi) */
    while (hi - lo > 1) {
        int64_t mid = lo + (hi - lo) / 2;
        if (S->fan[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* The fan's bearings (S->fan, nv entries); S->fan stays NULL (every edge tested) for
 * small polygons or when no inscribed circle was found. */
static mfg_status fan_build(sset *S)
{
    if (S->nv < FAN_MIN_VERTICES || !(S->ir > 0.0))
        return MFG_OK;
    S->fan = malloc((size_t)S->nv * sizeof(double));
    if (!S->fan)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate the fan of map %lld", (long long)S->id);
    S->fan[0] = 0.0;
    for (int64_t k = 1; k < S->nv; k++) {
        S->fan[k] = fan_bearing(S, S->v + 3 * k);
        if (!(S->fan[k] > S->fan[k - 1])) { /* rounding on a needle polygon: do without */
            free(S->fan);
            S->fan = NULL;
            return MFG_OK;
        }
    }
    return MFG_OK;
}

static int set_contains(const sset *S, const double *y)
{
    if (mfg_dot3(S->cc, y) < S->cos_cr - 1e-12)
        return 0;
    if (S->kind == MFG_VM_POLYGON && S->fan) {
        int64_t k = fan_locate(S, y);
        for (int64_t j = k - FAN_PAD; j <= k + FAN_PAD; j++)
            if (mfg_dot3(y, S->n + 3 * ((j + S->nv) % S->nv)) < -TOL)
                return 0;
        return 1;
    }
    if (S->kind == MFG_VM_POLYGON) {
        for (int64_t k = 0; k < S->nv; k++)
            if (mfg_dot3(y, S->n + 3 * k) < -TOL)
                return 0;
        return 1;
    }
    if (S->kind == MFG_VM_POINT) {
        for (int64_t k = 0; k < S->nv; k++) {
            const double *p = S->v + 3 * k;
            double d[3] = {y[0] - p[0], y[1] - p[1], y[2] - p[2]};
            if (sqrt(mfg_dot3(d, d)) <= TOL)
                return 1;
        }
        return 0;
    }
    /* EDGE: within tolerance of one of its pieces */
    int64_t pieces = S->closed ? S->nv : S->nv - 1;
    for (int64_t k = 0; k < pieces; k++) {
        const double *a = S->v + 3 * k, *b = S->v + 3 * ((k + 1) % S->nv);
        double n[3], nu[3], s;
        mfg_cross3(a, b, n);
        if (!mfg_unit3(n, nu))
            continue;
        if (fabs(mfg_dot3(y, nu)) <= TOL) {
            double proj[3] = {y[0] - mfg_dot3(y, nu) * nu[0], y[1] - mfg_dot3(y, nu) * nu[1],
                              y[2] - mfg_dot3(y, nu) * nu[2]}, pu[3];
            if (mfg_unit3(proj, pu) && param_on_edge(a, b, pu, &s))
                return 1;
        }
    }
    return 0;
}

/* Interval of edge a->b (s in [0,1]) inside polygon S; 0 when empty.  The constraint
 * x(s).n >= -tol is linear in s, but x(s) is shorter than a unit vector (down to
 * cos(L/2) mid-edge), so the slack is scaled by that: every point of the interval then
 * passes set_contains(), and boundaries within TOL cos(L/2) count as touching. */
static int polygon_interval(const sset *S, const double *a, const double *b, double *lo,
                            double *hi)
{
    double l = 0.0, h = 1.0;
    double m[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
    double tol = TOL * 0.5 * sqrt(mfg_dot3(m, m));
    /* Edges to test: all, or (fan) those of the triangles the arc crosses, padded. */
    int64_t first = 0, count = S->nv;
    if (S->fan) {
        double g[3], gu[3];
        mfg_cross3(a, b, g);
        /* an arc whose circle passes near ic sweeps bearings too fast: test all */
        if (mfg_unit3(g, gu) && fabs(mfg_dot3(gu, S->ic)) > 1e-3) {
            int64_t ka = fan_locate(S, a), kb = fan_locate(S, b);
            int64_t from = mfg_dot3(gu, S->ic) > 0.0 ? ka : kb, to = from == ka ? kb : ka;
            int64_t span = ((to - from) % S->nv + S->nv) % S->nv + 1 + 2 * FAN_PAD;
            if (span < S->nv) {
                first = from - FAN_PAD + S->nv;
                count = span;
            }
        }
    }
    for (int64_t t = 0; t < count; t++) {
        int64_t k = S->fan ? (first + t) % S->nv : t;
        const double *n = S->n + 3 * k;
        double fa = mfg_dot3(a, n) + tol, fb = mfg_dot3(b, n) + tol;
        if (fa >= 0.0 && fb >= 0.0)
            continue;
        if (fa < 0.0 && fb < 0.0)
            return 0;
        double s = fa / (fa - fb);
        if (fa < 0.0)
            l = s > l ? s : l;
        else
            h = s < h ? s : h;
        if (l > h)
            return 0;
    }
    *lo = l;
    *hi = h;
    return 1;
}

/* Intervals of edge a->b inside an EDGE or POINT set: appended to iv, returns count. */
static int64_t thin_intervals(const sset *S, int64_t sid, const double *a, const double *b,
                              interval *iv)
{
    int64_t m = 0;
    double ne[3], neu[3];
    mfg_cross3(a, b, ne);
    int edge_has_circle = mfg_unit3(ne, neu);
    if (S->kind == MFG_VM_POINT) {
        for (int64_t k = 0; k < S->nv; k++) {
            double s;
            const double *p = S->v + 3 * k;
            if (edge_has_circle && fabs(mfg_dot3(p, neu)) > TOL)
                continue;
            if (param_on_edge(a, b, p, &s))
                iv[m++] = (interval){s, s, sid};
        }
        return m;
    }
    int64_t pieces = S->closed ? S->nv : S->nv - 1;
    for (int64_t k = 0; k < pieces; k++) {
        const double *c = S->v + 3 * k, *d = S->v + 3 * ((k + 1) % S->nv);
        if (!edge_has_circle) { /* the swept "edge" is a point */
            if (set_contains(S, a))
                iv[m++] = (interval){0.0, 0.0, sid};
            return m;
        }
        if (fabs(mfg_dot3(c, neu)) <= TOL && fabs(mfg_dot3(d, neu)) <= TOL) {
            /* same great circle: overlap of the two arcs */
            double sc, sd, lo = 2.0, hi = -1.0;
            if (param_on_edge(a, b, c, &sc))
                lo = fmin(lo, sc), hi = fmax(hi, sc);
            if (param_on_edge(a, b, d, &sd))
                lo = fmin(lo, sd), hi = fmax(hi, sd);
            double nc[3], ncu[3], s;
            mfg_cross3(c, d, nc);
            mfg_unit3(nc, ncu);
            /* the edge's ends inside the piece also bound the overlap */
            if (param_on_edge(c, d, a, &s))
                lo = fmin(lo, 0.0), hi = fmax(hi, 0.0);
            if (param_on_edge(c, d, b, &s))
                lo = fmin(lo, 1.0), hi = fmax(hi, 1.0);
            if (lo <= hi)
                iv[m++] = (interval){lo, hi, sid};
        } else {
            double nc[3], x[3], xu[3], s, t;
            mfg_cross3(c, d, nc);
            mfg_cross3(ne, nc, x);
            if (!mfg_unit3(x, xu))
                continue;
            for (int sign = 0; sign < 2; sign++) {
                if (sign)
                    xu[0] = -xu[0], xu[1] = -xu[1], xu[2] = -xu[2];
                if (param_on_edge(a, b, xu, &s) && param_on_edge(c, d, xu, &t))
                    iv[m++] = (interval){s, s, sid};
            }
        }
    }
    /* merge the pieces' intervals so the set counts once at shared piece ends */
    for (int64_t i = 1; i < m; i++)
        for (int64_t j = i; j > 0 && iv[j].lo < iv[j - 1].lo; j--) {
            interval t = iv[j];
            iv[j] = iv[j - 1];
            iv[j - 1] = t;
        }
    int64_t out = 0;
    for (int64_t i = 0; i < m; i++) {
        if (out > 0 && iv[i].lo <= iv[out - 1].hi + 1e-12)
            iv[out - 1].hi = fmax(iv[out - 1].hi, iv[i].hi);
        else
            iv[out++] = iv[i];
    }
    return out;
}

/* ---- Preparation --------------------------------------------------------------------- */

static void free_work(work *W)
{
    for (int64_t i = 0; i < W->nsets; i++) {
        free(W->sets[i].v);
        free(W->sets[i].n);
        free(W->sets[i].fan);
    }
    free(W->sets);
    free(W->iv);
    free(W->ev);
    free(W->cands);
    free(W->pool);
    memset(W, 0, sizeof *W);
}

/* Vertices must be unit vectors within this relative length error: a map's vertices are
 * directions, and a vector far from unit length (a point of a mesh, an unnormalised
 * normal) signals a mix-up rather than rounding.  Float data normalised in single
 * precision (error ~6e-8) passes. */
#define UNIT_LENGTH_TOL 1e-6

/* How far a vertex may be off the shape its map's kind claims (radians): off the great
 * circle of an EDGE, right of a POLYGON's edge, away from antipodal for a two-vertex
 * POINT.  Loose enough for maps computed in double from rounded data, tight enough that
 * a visibly wrong shape (a kinked "edge", a reflex corner) is refused. */
#define SHAPE_TOL 1e-9

/* A POLYGON's bounding cap of radius >= pi/2 - CAP_HEMI_MARGIN is replaced by the
 * hemisphere about its normals' sum (a cap this large no longer bounds the set). */
#define CAP_HEMI_MARGIN 1e-9

/* Caps are widened by this much (radians) so the float tests that skip far sets never
 * skip one within the coverage tolerance. */
#define CAP_WIDEN 1e-9

/* Step 1: counts, offsets, kinds, closed flags and weights, each read once, checked
 * without integer overflow (offsets are bounded before any difference is taken). */
static mfg_status check_layout(const int64_t *offsets, const int32_t *kinds,
                               const int32_t *closed, int64_t npolys, const double *weights)
{
    if (npolys == 0)
        return mfg_fail(MFG_ERR_DEGENERATE, "no maps (npolys = 0)");
    if (npolys < 0 || npolys > MFG_MAX_COUNT)
        return mfg_fail(MFG_ERR_INVALID, "npolys = %lld is not a count (allowed: 1 .. 2^40)",
                        (long long)npolys);
    if (!offsets || !kinds)
        return mfg_fail(MFG_ERR_NULL, "offsets or kinds is NULL");
    if (offsets[0] != 0)
        return mfg_fail(MFG_ERR_INVALID, "offsets[0] must be 0 (got %lld)", (long long)offsets[0]);
    for (int64_t i = 0; i < npolys; i++) {
        int64_t o0 = offsets[i], o1 = offsets[i + 1];
        if (o1 < o0)
            return mfg_fail(MFG_ERR_INVALID, "offsets must be non-decreasing (offsets[%lld] = %lld < offsets[%lld] = %lld)",
                            (long long)(i + 1), (long long)o1, (long long)i, (long long)o0);
        if (o1 > MFG_MAX_COUNT)
            return mfg_fail(MFG_ERR_INVALID, "offsets[%lld] = %lld is beyond the accepted count (2^40)",
                            (long long)(i + 1), (long long)o1);
        int64_t nv = o1 - o0; /* both in [0, 2^40]: no overflow */
        int k = kinds[i], cl = closed ? closed[i] : 0;
        if (k < MFG_VM_NULL || k > MFG_VM_POLYGON)
            return mfg_fail(MFG_ERR_INVALID, "map %lld has unknown kind %d (allowed: 0 null, 1 point, 2 edge, 3 polygon)",
                            (long long)i, k);
        if (cl != 0 && cl != 1)
            return mfg_fail(MFG_ERR_INVALID, "map %lld: closed must be 0 or 1 (got %d)", (long long)i, cl);
        if (cl && k != MFG_VM_EDGE)
            return mfg_fail(MFG_ERR_INVALID, "map %lld: closed = 1 is only for an EDGE (a whole great circle)",
                            (long long)i);
        int ok = k == MFG_VM_NULL || (k == MFG_VM_POINT && (nv == 1 || nv == 2)) ||
                 (k == MFG_VM_EDGE && nv >= (cl ? 3 : 2)) || (k == MFG_VM_POLYGON && nv >= 3);
        if (!ok)
            return mfg_fail(MFG_ERR_DEGENERATE, "map %lld: %lld vertices do not make a %s%s", (long long)i,
                            (long long)nv, k == MFG_VM_POINT ? "point (1 or 2 antipodal)" : k == MFG_VM_EDGE ? "edge" : "polygon",
                            k == MFG_VM_EDGE ? (cl ? " (closed: >= 3)" : " (>= 2)") : k == MFG_VM_POLYGON ? " (>= 3)" : "");
        if (nv > INT32_MAX)
            return mfg_fail(MFG_ERR_INVALID, "map %lld has %lld vertices (at most 2^31 - 1 per map)",
                            (long long)i, (long long)nv);
        if (weights && !(weights[i] >= 0.0 && weights[i] <= DBL_MAX))
            return mfg_fail(MFG_ERR_INVALID, "weight %lld must be finite and >= 0 (got %g)", (long long)i, weights[i]);
    }
    return MFG_OK;
}

/* Step 2: every coordinate in range, every vertex of a non-NULL map a unit vector. */
static mfg_status check_vertices(const double *vertices, const int64_t *offsets,
                                 const int32_t *kinds, int64_t npolys)
{
    if (offsets[npolys] > 0 && !vertices)
        return mfg_fail(MFG_ERR_NULL, "vertices is NULL");
    for (int64_t i = 0; i < npolys; i++) {
        for (int64_t k = offsets[i]; k < offsets[i + 1]; k++) {
            const double *p = vertices + 3 * k;
            if (!mfg_coord_ok(p[0]) || !mfg_coord_ok(p[1]) || !mfg_coord_ok(p[2]))
                return mfg_fail(MFG_ERR_INVALID, "map %lld, vertex %lld has a NaN, infinite or out-of-range coordinate (allowed: 0 or 2^-200 <= |x| <= 2^200)",
                                (long long)i, (long long)(k - offsets[i]));
            if (kinds[i] == MFG_VM_NULL)
                continue;
            double len = sqrt(mfg_dot3(p, p));
            if (!(fabs(len - 1.0) <= UNIT_LENGTH_TOL))
                return mfg_fail(MFG_ERR_INVALID, "map %lld, vertex %lld is not a unit vector (length %.17g; allowed: 1 +- %g)",
                                (long long)i, (long long)(k - offsets[i]), len, UNIT_LENGTH_TOL);
        }
    }
    return MFG_OK;
}

/* Step 3: the weights, scaled by one power of two so the largest is in [0.5, 1).  A
 * power of two scales every sum exactly, so the answer is the same for weights scaled by
 * any factor (up to rounding of the factor itself), and tiny or huge weights neither
 * underflow nor overflow in the sums; W->scale maps back.  The tolerance for equal
 * weights is relative to the total: sums of n weights in any order differ by at most
 * ~2 n u total, and WEIGHT_REL_EPS per set covers that with room. */
#define WEIGHT_REL_EPS 0x1p-44
static mfg_status scale_weights(const double *weights, int64_t npolys, work *W)
{
    double wmax = 0.0;
    for (int64_t i = 0; i < npolys; i++)
        wmax = fmax(wmax, weights ? weights[i] : 1.0);
    int e = 0;
    if (wmax > 0.0)
        frexp(wmax, &e); /* wmax = f 2^e, f in [0.5, 1) */
    W->scale_exp = e;
    double total = 0.0;
    for (int64_t i = 0; i < npolys; i++)
        total += ldexp(weights ? weights[i] : 1.0, -e);
    if (!isfinite(ldexp(total, e)))
        return mfg_fail(MFG_ERR_INVALID, "the total weight overflows a double (largest weight %g)", wmax);
    W->eps = WEIGHT_REL_EPS * (double)(npolys + 1) * total;
    return MFG_OK;
}

/* A POINT: one direction, or two antipodal ones. */
static mfg_status check_point_map(const sset *S)
{
    if (S->nv == 2) {
        double s[3] = {S->v[0] + S->v[3], S->v[1] + S->v[4], S->v[2] + S->v[5]};
        double off = sqrt(mfg_dot3(s, s)); /* chord to the antipode of v[0] */
        if (off > SHAPE_TOL)
            return mfg_fail(MFG_ERR_INVALID, "map %lld: a POINT with two vertices must have them antipodal (they are %.3g rad from antipodal)",
                            (long long)S->id, 2 * asin(fmin(off / 2, 1.0)));
    }
    return MFG_OK;
}

/* An EDGE: consecutive vertices less than pi apart, all on one great circle, every piece
 * turning the same way about it, and the pieces adding up to less than a whole turn (or,
 * closed, to exactly one). */
static mfg_status check_edge_map(const sset *S)
{
    int64_t pieces = S->closed ? S->nv : S->nv - 1;
    double g[3] = {0, 0, 0}, gu[3];
    for (int64_t k = 0; k < pieces; k++) {
        const double *a = S->v + 3 * k, *b = S->v + 3 * ((k + 1) % S->nv);
        double c[3], s[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
        if (sqrt(mfg_dot3(s, s)) <= SHAPE_TOL)
            return mfg_fail(MFG_ERR_INVALID, "map %lld: EDGE vertices %lld and %lld are antipodal, so the arc between them is ambiguous (give its midpoint as a vertex too)",
                            (long long)S->id, (long long)k, (long long)((k + 1) % S->nv));
        mfg_cross3(a, b, c);
        if (sqrt(mfg_dot3(c, c)) <= SHAPE_TOL)
            return mfg_fail(MFG_ERR_INVALID, "map %lld: EDGE vertices %lld and %lld coincide",
                            (long long)S->id, (long long)k, (long long)((k + 1) % S->nv));
        g[0] += c[0], g[1] += c[1], g[2] += c[2];
    }
    if (!mfg_unit3(g, gu))
        return mfg_fail(MFG_ERR_INVALID, "map %lld: the EDGE's pieces turn both ways (not one arc of a great circle)",
                        (long long)S->id);
    for (int64_t k = 0; k < S->nv; k++)
        if (fabs(mfg_dot3(S->v + 3 * k, gu)) > SHAPE_TOL)
            return mfg_fail(MFG_ERR_INVALID, "map %lld: EDGE vertex %lld is %.3g rad off the great circle of the others",
                            (long long)S->id, (long long)k, asin(fmin(fabs(mfg_dot3(S->v + 3 * k, gu)), 1.0)));
    double turn = 0.0;
    for (int64_t k = 0; k < pieces; k++) {
        const double *a = S->v + 3 * k, *b = S->v + 3 * ((k + 1) % S->nv);
        double c[3];
        mfg_cross3(a, b, c);
        if (mfg_dot3(c, gu) <= 0.0)
            return mfg_fail(MFG_ERR_INVALID, "map %lld: EDGE piece %lld runs backwards along the great circle",
                            (long long)S->id, (long long)k);
        turn += mfg_angle3(a, b);
    }
    /* pieces all turning one way add up to a whole multiple of 2 pi when closed */
    if (S->closed ? fabs(turn - 2 * MFG_PI) > MFG_PI : turn > 2 * MFG_PI + SHAPE_TOL)
        return mfg_fail(MFG_ERR_INVALID, "map %lld: the EDGE's pieces go %.6g times round the circle (%s)",
                        (long long)S->id, turn / (2 * MFG_PI), S->closed ? "closed: exactly once" : "open: less than once");
    return MFG_OK;
}

/* A POLYGON: the inward normal of every edge (consecutive vertices neither equal nor
 * antipodal), every turn to the left (v[k+2] not right of edge k, within SHAPE_TOL), and
 * the vertices going once round an interior point, counter-clockwise.  Left turns and
 * one monotone turn round a point make a convex polygon: O(nv), not the O(nv^2)
 * all-vertices-against-all-edges test. */
static mfg_status check_polygon_map(sset *S)
{
    int64_t nv = S->nv;
    for (int64_t k = 0; k < nv; k++) {
        double c[3];
        mfg_cross3(S->v + 3 * k, S->v + 3 * ((k + 1) % nv), c);
        if (!mfg_unit3(c, S->n + 3 * k) || sqrt(mfg_dot3(c, c)) <= SHAPE_TOL)
            return mfg_fail(MFG_ERR_DEGENERATE, "map %lld: POLYGON vertices %lld and %lld coincide or are antipodal",
                            (long long)S->id, (long long)k, (long long)((k + 1) % nv));
    }
    for (int64_t k = 0; k < nv; k++)
        if (mfg_dot3(S->v + 3 * ((k + 2) % nv), S->n + 3 * k) < -SHAPE_TOL)
            return mfg_fail(MFG_ERR_INVALID, "map %lld: POLYGON is not convex and counter-clockwise (vertex %lld is right of edge %lld)",
                            (long long)S->id, (long long)((k + 2) % nv), (long long)k);
    /* The round: about the vertices' sum (inside a convex polygon smaller than a
     * hemisphere), else about the normals' sum (a hemisphere: every normal is its pole). */
    double sv[3] = {0, 0, 0}, sn[3] = {0, 0, 0}, c[3];
    for (int64_t k = 0; k < nv; k++)
        for (int d = 0; d < 3; d++)
            sv[d] += S->v[3 * k + d], sn[d] += S->n[3 * k + d];
    for (int attempt = 0; attempt < 2; attempt++) {
        if (!mfg_unit3(attempt ? sn : sv, c))
            continue;
        double turn = 0.0;
        int forward = 1;
        for (int64_t k = 0; k < nv && forward; k++) {
            const double *a = S->v + 3 * k, *b = S->v + 3 * ((k + 1) % nv);
            double ca[3], cb[3], x[3];
            mfg_cross3(c, a, ca);
            mfg_cross3(c, b, cb);
            mfg_cross3(ca, cb, x);
            double sn_ = mfg_dot3(x, c), cs = mfg_dot3(ca, cb);
            forward = sn_ > 0.0;
            turn += atan2(sn_, cs);
        }
        if (forward && fabs(turn - 2 * MFG_PI) < MFG_PI)
            return MFG_OK;
    }
    return mfg_fail(MFG_ERR_INVALID, "map %lld: POLYGON is not convex and counter-clockwise (its vertices do not go once round its interior)",
                    (long long)S->id);
}

/* The set's bounding cap (centre cc, radius cr): the smallest cap of its vertices,
 * widened to hold every vertex despite rounding.  A cap of radius >= pi/2 is not convex:
 * containing the vertices no longer means containing the set.  A polygon lies in the
 * hemisphere around the sum of its inward edge normals (x.n_k >= 0 for all k gives
 * x.sum >= 0); an arc this large gets no cap at all (radius pi). */
static void bounding_cap(sset *S)
{
    double cosr;
    mfg_enclosing_cap(S->v, S->nv, S->cc, &cosr);
    S->cr = acos(fmin(fmax(cosr, -1.0), 1.0));
    for (int64_t k = 0; k < S->nv; k++)
        S->cr = fmax(S->cr, mfg_angle3(S->cc, S->v + 3 * k));
    if (S->cr >= MFG_PI / 2 - CAP_HEMI_MARGIN) {
        double sum[3] = {0, 0, 0};
        S->cr = MFG_PI;
        if (S->kind == MFG_VM_POLYGON) {
            for (int64_t k = 0; k < S->nv; k++)
                for (int d = 0; d < 3; d++)
                    sum[d] += S->n[3 * k + d];
            if (mfg_unit3(sum, S->cc))
                S->cr = MFG_PI / 2 + CAP_HEMI_MARGIN;
        }
    }
    S->cr = fmin(S->cr + CAP_WIDEN, MFG_PI);
    S->cos_cr = cos(S->cr);
    S->sin_cr = sin(S->cr);
}

/* A POLYGON's inscribed circle (the smallest cap of its edge normals, dual), shrunk a
 * little: it is only ever used to claim that a cell lies inside the set. */
static void inscribed_circle(sset *S)
{
    double cosr, mind = 1.0;
    mfg_enclosing_cap(S->n, S->nv, S->ic, &cosr);
    for (int64_t k = 0; k < S->nv; k++)
        mind = fmin(mind, mfg_dot3(S->ic, S->n + 3 * k));
    S->ir = mind > 0.0 ? fmax(asin(fmin(mind, 1.0)) - CAP_WIDEN, 0.0) : 0.0;
    S->cos_ir = cos(S->ir);
    S->sin_ir = sin(S->ir);
}

/* Step 4: one prepared set per non-empty map of positive weight: unit vertices, its
 * shape checked, normals, caps. */
static mfg_status load_set(work *W, const double *vertices, const int64_t *offsets,
                           const int32_t *kinds, const int32_t *closed, const double *weights,
                           int64_t i)
{
    double w = ldexp(weights ? weights[i] : 1.0, -W->scale_exp);
    int64_t nv = offsets[i + 1] - offsets[i];
    if (kinds[i] == MFG_VM_NULL || w <= 0.0)
        return MFG_OK; /* contributes nothing anywhere */
    sset *S = &W->sets[W->nsets++];
    S->kind = kinds[i];
    S->closed = kinds[i] == MFG_VM_EDGE && closed && closed[i];
    S->id = i;
    S->nv = nv;
    S->w = w;
    S->v = malloc((size_t)nv * 3 * sizeof(double));
    if (S->kind == MFG_VM_POLYGON)
        S->n = malloc((size_t)nv * 3 * sizeof(double));
    if (!S->v || (S->kind == MFG_VM_POLYGON && !S->n))
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate map %lld", (long long)i);
    for (int64_t k = 0; k < nv; k++)
        mfg_unit3(vertices + 3 * (offsets[i] + k), S->v + 3 * k); /* unit within 1e-6 */
    mfg_status st = S->kind == MFG_VM_POINT ? check_point_map(S)
                    : S->kind == MFG_VM_EDGE ? check_edge_map(S)
                                             : check_polygon_map(S);
    if (st != MFG_OK)
        return st;
    bounding_cap(S);
    if (S->kind == MFG_VM_POLYGON) {
        inscribed_circle(S);
        return fan_build(S);
    }
    return MFG_OK;
}

/* Step 5: the sweep's buffers: an interval per set, two per thin-set piece. */
static mfg_status alloc_sweep(work *W)
{
    W->cap_iv = 2 * W->nsets + 16;
    for (int64_t i = 0; i < W->nsets; i++)
        if (W->sets[i].kind != MFG_VM_POLYGON)
            W->cap_iv += W->sets[i].nv * 2;
    W->iv = malloc((size_t)W->cap_iv * sizeof(interval));
    W->ev = malloc((size_t)W->cap_iv * 2 * sizeof(event));
    if (!W->iv || !W->ev)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate the sweep");
    return MFG_OK;
}

static mfg_status prepare(const double *vertices, const int64_t *offsets, const int32_t *kinds,
                          const int32_t *closed, int64_t npolys, const double *weights,
                          work *W)
{
    memset(W, 0, sizeof *W);
    mfg_status st = check_layout(offsets, kinds, closed, npolys, weights);
    if (st == MFG_OK)
        st = check_vertices(vertices, offsets, kinds, npolys);
    if (st == MFG_OK)
        st = scale_weights(weights, npolys, W);
    if (st != MFG_OK)
        return st;
    W->sets = calloc((size_t)npolys, sizeof(sset));
    if (!W->sets)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate %lld sets", (long long)npolys);
    for (int64_t i = 0; i < npolys && st == MFG_OK; i++)
        st = load_set(W, vertices, offsets, kinds, closed, weights, i);
    if (st == MFG_OK && W->nsets == 0)
        st = mfg_fail(MFG_ERR_DEGENERATE, "every map is empty or has zero weight");
    if (st == MFG_OK)
        st = alloc_sweep(W);
    return st;
}

/* The edge's bounding cap: centre and cos/sin of its half length. */
static void edge_cap(const double *a, const double *b, double mc[3], double *half, double *ch,
                     double *sh)
{
    double mid[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
    *half = 0.5 * mfg_angle3(a, b);
    *ch = cos(*half);
    *sh = sin(*half);
    if (!mfg_unit3(mid, mc))
        memcpy(mc, a, 3 * sizeof(double));
}

/* Caps apart: angle(mc, cc) > half + cr, compared through cosines. */
static inline int caps_apart(const double mc[3], double half, double ch, double sh,
                             const sset *S)
{
    return half + S->cr < MFG_PI && mfg_dot3(mc, S->cc) < ch * S->cos_cr - sh * S->sin_cr - 1e-12;
}

/* Intervals of edge a->b inside the listed sets (own excluded). */
static int64_t edge_intervals(work *W, int64_t own, const double *a, const double *b,
                              const int64_t *list, int64_t nlist)
{
    double mc[3], half, ch, sh;
    edge_cap(a, b, mc, &half, &ch, &sh);
    int64_t m = 0;
    for (int64_t t = 0; t < nlist; t++) {
        int64_t j = list[t];
        if (j == own)
            continue;
        const sset *S = &W->sets[j];
        if (caps_apart(mc, half, ch, sh, S))
            continue;
        if (S->kind == MFG_VM_POLYGON) {
            double lo, hi;
            if (polygon_interval(S, a, b, &lo, &hi))
                W->iv[m++] = (interval){lo, hi, j};
        } else {
            m += thin_intervals(S, j, a, b, W->iv + m);
        }
    }
    return m;
}

static int cmp_event(const void *x, const void *y)
{
    const event *a = x, *b = y;
    if (a->s != b->s)
        return a->s < b->s ? -1 : 1;
    return b->start - a->start; /* starts first: closed sets touch */
}

static int cmp_i64(const void *x, const void *y)
{
    int64_t a = *(const int64_t *)x, b = *(const int64_t *)y;
    return (a > b) - (a < b);
}

/* Computes candidate ci's cover set (every set containing its direction) into the pool. */
static mfg_status compute_cover(work *W, int64_t ci)
{
    if (W->npool + W->nsets + 1 > W->cap_pool) {
        int64_t cap = W->cap_pool ? 2 * W->cap_pool : 1024;
        while (cap < W->npool + W->nsets + 1)
            cap *= 2;
        int64_t *p = realloc(W->pool, (size_t)cap * sizeof(int64_t));
        if (!p)
            return mfg_fail(MFG_ERR_NOMEM, "cannot store cover sets");
        W->pool = p;
        W->cap_pool = cap;
    }
    cand *c = &W->cands[ci];
    int64_t len = 0;
    uint64_t h = 1469598103934665603ULL; /* FNV-1a over the sorted indices */
    for (int64_t j = 0; j < W->nsets; j++)
        if (set_contains(&W->sets[j], c->x)) {
            W->pool[W->npool + len++] = j;
            h = (h ^ (uint64_t)j) * 1099511628211ULL;
        }
    c->off = W->npool;
    c->len = len;
    c->hash = h;
    W->npool += len;
    return MFG_OK;
}

/* Records a candidate direction.  Its cover set is computed later, and only for the
 * few candidates that are not inside a region already built (minimum: at once). */
static mfg_status add_candidate(work *W, double weight, const double x[3], int degenerate)
{
    if (W->ncands == W->cap_cands) {
        int64_t cap = W->cap_cands ? 2 * W->cap_cands : 64;
        cand *c = realloc(W->cands, (size_t)cap * sizeof(cand));
        if (!c)
            return mfg_fail(MFG_ERR_NOMEM, "cannot store candidates");
        W->cands = c;
        W->cap_cands = cap;
    }
    cand *c = &W->cands[W->ncands++];
    c->weight = weight;
    c->off = 0;
    c->len = -1;
    c->hash = 0;
    c->degenerate = degenerate;
    memcpy(c->x, x, sizeof c->x);
    return W->mode == MODE_MIN ? compute_cover(W, W->ncands - 1) : MFG_OK;
}

/* Exact sweep of the events (already in W->ev) inside [s0, s1] of edge a->b, entering
 * with ownership depth. */
static mfg_status sweep_range(work *W, const double *a, const double *b, int64_t ne, double s0,
                              double s1, double depth, double threshold, int keep_best,
                              double eps, int first_range)
{
    double prev = s0;
    int point_edge = a == b;
    qsort(W->ev, (size_t)ne, sizeof(event), cmp_event);
#define CONSIDER(wt, lo, hi, deg)                                                            \
    do {                                                                                     \
        double wt_ = (wt), lim_ = keep_best ? W->best : threshold;                           \
        if (keep_best && wt_ > W->best + eps) {                                              \
            W->best = wt_;                                                                   \
            W->ncands = 0;                                                                   \
            W->npool = 0;                                                                    \
            lim_ = wt_;                                                                      \
        }                                                                                    \
        if (wt_ >= lim_ - eps) {                                                             \
            double sm_ = 0.5 * ((lo) + (hi)), x_[3], xu_[3];                                 \
            x_[0] = a[0] + sm_ * (b[0] - a[0]);                                              \
            x_[1] = a[1] + sm_ * (b[1] - a[1]);                                              \
            x_[2] = a[2] + sm_ * (b[2] - a[2]);                                              \
            mfg_unit3(x_, xu_);                                                              \
            mfg_status st_ = add_candidate(W, wt_, xu_, (deg));                              \
            if (st_ != MFG_OK)                                                               \
                return st_;                                                                  \
        }                                                                                    \
    } while (0)
    /* A point is recorded only when no piece next to it has its cover set: a piece
     * before it where no set starts, or a piece after it where none ends, would build the
     * same region (this keeps the candidates to about one per piece). */
    if (first_range && (ne == 0 || W->ev[0].s > s0) && (point_edge || (ne == 0 && s1 <= s0)))
        CONSIDER(depth, s0, s0, 1);
    for (int64_t i = 0; i < ne;) {
        double s = W->ev[i].s, starts = 0.0, ends = 0.0;
        int piece_before = s > prev && !point_edge;
        if (piece_before)
            CONSIDER(depth, prev, s, 0);
        int64_t j = i, nstarts = 0, nends = 0;
        for (; j < ne && W->ev[j].s == s; j++) {
            if (W->ev[j].start)
                starts += W->sets[W->ev[j].set].w, nstarts++;
            else
                ends += W->sets[W->ev[j].set].w, nends++;
        }
        int piece_after = !point_edge && (j < ne || s < s1);
        if (!((nstarts == 0 && piece_before) || (nends == 0 && piece_after)))
            CONSIDER(depth + starts, s, s, 1);
        depth = depth + starts - ends;
        prev = s;
        i = j;
    }
    if (prev < s1 && !point_edge)
        CONSIDER(depth, prev, s1, 0);
#undef CONSIDER
    return MFG_OK;
}

#define NBUCKET 16
#define BUCKET_MIN_INTERVALS 64

/* Sweeps the part [r0, r1] of edge a->b: base is the ownership every point there has
 * anyway (the sets containing the whole cell, and the edge's own set); the listed sets
 * add their intervals.  Records pieces and points whose ownership reaches the limit
 * (the running best when keep_best).  The range is cut into buckets first, and a bucket
 * whose bound (depth on entry + everything starting inside it) cannot reach the limit
 * is never sorted. */
static mfg_status sweep_edge(work *W, int64_t own, const double *a, const double *b, double r0,
                             double r1, double base, const int64_t *list, int64_t nlist,
                             double threshold, int keep_best, double eps)
{
    int64_t niv = edge_intervals(W, own, a, b, list, nlist);
    double ebound = base;
    int64_t kept = 0;
    for (int64_t k = 0; k < niv; k++) { /* keep the intervals meeting [r0, r1] */
        if (W->iv[k].hi < r0 || W->iv[k].lo > r1)
            continue;
        W->iv[kept] = W->iv[k];
        W->iv[kept].lo = W->iv[k].lo > r0 ? W->iv[k].lo : r0;
        W->iv[kept].hi = W->iv[k].hi < r1 ? W->iv[k].hi : r1;
        ebound += W->sets[W->iv[k].set].w;
        kept++;
    }
    niv = kept;
    if (ebound < (keep_best ? W->best : threshold) - eps)
        return MFG_OK;
    /* buckets pay off only with many intervals; each bucket records its own pieces */
    int nb = (a == b || r1 <= r0 || niv <= BUCKET_MIN_INTERVALS) ? 1 : NBUCKET;
    double bstart[NBUCKET], bend[NBUCKET], width = r1 > r0 ? r1 - r0 : 1.0;
    for (int k = 0; k < nb; k++)
        bstart[k] = bend[k] = 0.0;
#define BUCKET(s) ((int)fmin(fmax(floor(((s) - r0) / width * nb), 0.0), (double)(nb - 1)))
    for (int64_t k = 0; k < niv; k++) {
        double w = W->sets[W->iv[k].set].w;
        bstart[BUCKET(W->iv[k].lo)] += w;
        bend[BUCKET(W->iv[k].hi)] += w;
    }
    double depth = base;
    for (int bk = 0; bk < nb; bk++) {
        double lim = keep_best ? W->best : threshold;
        if (depth + bstart[bk] >= lim - eps) {
            int64_t ne = 0;
            for (int64_t k = 0; k < niv; k++) {
                if (BUCKET(W->iv[k].lo) == bk)
                    W->ev[ne++] = (event){W->iv[k].lo, 1, W->iv[k].set};
                if (BUCKET(W->iv[k].hi) == bk)
                    W->ev[ne++] = (event){W->iv[k].hi, 0, W->iv[k].set};
            }
            double s0 = r0 + width * bk / nb, s1 = bk == nb - 1 ? r1 : r0 + width * (bk + 1) / nb;
            mfg_status st = sweep_range(W, a, b, ne, s0, s1, depth, threshold, keep_best, eps, bk == 0);
            if (st != MFG_OK)
                return st;
        }
        depth += bstart[bk] - bend[bk];
    }
#undef BUCKET
    return MFG_OK;
}

/* ---- Regions ------------------------------------------------------------------------- */

/* A built region before output. */
typedef struct region {
    int kind, closed;
    int64_t nv;
    double *v;
    double c[3], margin;
    int64_t cand;
    double *fan; /* large POLYGON: bearings of its vertices about c (region_holds) */
} region;

static void region_release(region *R)
{
    free(R->v);
    free(R->fan);
    R->v = NULL;
    R->fan = NULL;
}

/* Normals closer than this (in each coordinate) are made equal, or opposite: the
 * tolerance's "boundaries this close touch", in normal space (~10 TOL). */
#define SNAP_NORMAL 1e-9

typedef struct keyed {
    double x;
    int64_t i;
} keyed;

static int cmp_keyed(const void *p, const void *q)
{
    const keyed *a = p, *b = q;
    return (a->x > b->x) - (a->x < b->x);
}

/* Makes normals that are equal or opposite within SNAP_NORMAL exactly so (sorted by x, a
 * partner can only be among the neighbours in x).  ord is scratch of nn entries. */
static void snap_normals(double *n, int64_t nn, keyed *ord)
{
    const double snap = SNAP_NORMAL;
    for (int64_t i = 0; i < nn; i++)
        ord[i] = (keyed){n[3 * i], i};
    qsort(ord, (size_t)nn, sizeof *ord, cmp_keyed);
    for (int64_t i = 0; i < nn; i++) {
        double *a = n + 3 * ord[i].i;
        /* same direction: neighbours above in x */
        for (int64_t j = i + 1; j < nn && ord[j].x - a[0] <= snap; j++) {
            double *b = n + 3 * ord[j].i;
            if (fabs(b[1] - a[1]) <= snap && fabs(b[2] - a[2]) <= snap)
                memcpy(b, a, 3 * sizeof(double));
        }
        /* opposite direction: binary search for x near -a[0] */
        int64_t lo = 0, hi = nn;
        while (lo < hi) {
            int64_t mid = (lo + hi) / 2;
            if (ord[mid].x < -a[0] - snap)
                lo = mid + 1;
            else
                hi = mid;
        }
        for (int64_t j = lo; j < nn && ord[j].x <= -a[0] + snap; j++) {
            double *b = n + 3 * ord[j].i;
            if (b != a && fabs(b[1] + a[1]) <= snap && fabs(b[2] + a[2]) <= snap)
                b[0] = -a[0], b[1] = -a[1], b[2] = -a[2];
        }
    }
}

/* The vertex of v[0..n) farthest from p: twice (from v[0], then from the answer) it
 * gives the two ends of a polygon no thicker than the tolerance, in O(n). */
static int64_t farthest_vertex(const double *v, int64_t n, const double *p)
{
    int64_t best = 0;
    for (int64_t i = 1; i < n; i++)
        if (mfg_dot3(v + 3 * i, p) < mfg_dot3(v + 3 * best, p))
            best = i;
    return best;
}

static void arc_region(region *R, const double *p, const double *q)
{
    double d[3] = {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    if (sqrt(mfg_dot3(d, d)) <= 10 * TOL) {
        double m[3] = {p[0] + q[0], p[1] + q[1], p[2] + q[2]};
        R->kind = MFG_VM_POINT;
        R->nv = 1;
        mfg_unit3(m, R->v);
        memcpy(R->c, R->v, sizeof R->c);
    } else {
        double m[3] = {p[0] + q[0], p[1] + q[1], p[2] + q[2]};
        R->kind = MFG_VM_EDGE;
        R->nv = 3;
        memcpy(R->v, p, 3 * sizeof(double));
        mfg_unit3(m, R->v + 3);
        memcpy(R->v + 6, q, 3 * sizeof(double));
        memcpy(R->c, R->v + 3, sizeof R->c);
    }
    R->margin = 0.0;
}

/* Builds the region of candidate c: the intersection of its cover set. */
static mfg_status build_region(work *W, int64_t ci, region *R)
{
    const cand *C = &W->cands[ci];
    const int64_t *set = W->pool + C->off;
    memset(R, 0, sizeof *R);
    R->cand = ci;
    int64_t thin = -1, cap = 0;
    for (int64_t k = 0; k < C->len; k++) {
        const sset *S = &W->sets[set[k]];
        if (S->kind != MFG_VM_POLYGON && (thin < 0 || S->kind < W->sets[thin].kind))
            thin = set[k]; /* a point beats an arc */
        cap += S->nv + 1;
    }
    R->v = malloc((size_t)(2 * cap + 24) * 3 * sizeof(double));
    if (!R->v)
        return mfg_fail(MFG_ERR_NOMEM, "cannot build a region");
    if (thin >= 0) {
        const sset *T = &W->sets[thin];
        if (T->kind == MFG_VM_POINT) { /* the point of it nearest the sample */
            int64_t best = 0;
            for (int64_t k = 1; k < T->nv; k++)
                if (mfg_dot3(T->v + 3 * k, C->x) > mfg_dot3(T->v + 3 * best, C->x))
                    best = k;
            arc_region(R, T->v + 3 * best, T->v + 3 * best);
            return MFG_OK;
        }
        /* An arc: clip the piece holding the sample by the other sets; extending over
         * neighbouring pieces is left out (pieces of a map are at most 90 degrees). */
        int64_t pieces = T->closed ? T->nv : T->nv - 1, piece = 0;
        double bestd = -2.0;
        for (int64_t k = 0; k < pieces; k++) {
            const double *a = T->v + 3 * k, *b = T->v + 3 * ((k + 1) % T->nv);
            double s;
            double mid[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]}, mu[3];
            mfg_unit3(mid, mu);
            if (param_on_edge(a, b, C->x, &s) && mfg_dot3(mu, C->x) > bestd) {
                bestd = mfg_dot3(mu, C->x);
                piece = k;
            }
        }
        const double *a = T->v + 3 * piece, *b = T->v + 3 * ((piece + 1) % T->nv);
        double lo = 0.0, hi = 1.0;
        for (int64_t k = 0; k < C->len; k++) {
            if (set[k] == thin)
                continue;
            const sset *S = &W->sets[set[k]];
            double l = 2.0, h = -1.0;
            if (S->kind == MFG_VM_POLYGON) {
                if (!polygon_interval(S, a, b, &l, &h))
                    l = 2.0, h = -1.0;
            } else { /* W->iv (free after the search) has room for any thin set's pieces */
                int64_t m = thin_intervals(S, set[k], a, b, W->iv);
                for (int64_t t = 0; t < m; t++)
                    l = fmin(l, W->iv[t].lo), h = fmax(h, W->iv[t].hi);
            }
            if (l <= h) {
                lo = fmax(lo, l);
                hi = fmin(hi, h);
            }
        }
        if (lo > hi) /* rounding disagreed with the sweep: keep the sample itself */
            arc_region(R, C->x, C->x);
        else {
            double p[3], q[3];
            double xp[3] = {a[0] + lo * (b[0] - a[0]), a[1] + lo * (b[1] - a[1]), a[2] + lo * (b[2] - a[2])};
            double xq[3] = {a[0] + hi * (b[0] - a[0]), a[1] + hi * (b[1] - a[1]), a[2] + hi * (b[2] - a[2])};
            mfg_unit3(xp, p);
            mfg_unit3(xq, q);
            arc_region(R, p, q);
        }
        return MFG_OK;
    }
    /* All polygons: every member is { x : x.n >= 0 } over its inward edge normals, so
     * their intersection is the visibility map of all those normals (visibility.c:
     * exact kinds, so two maps meeting along a circle with opposite sides give an EDGE,
     * and hemispheres, whose vertices do not span them, need no special case).  Normals
     * that are equal or opposite within the tolerance are made exactly so first: that
     * is the tolerance's "boundaries this close touch". */
    int64_t nn = 0;
    for (int64_t k = 0; k < C->len; k++)
        nn += W->sets[set[k]].nv;
    double *nrm = malloc((size_t)(nn + 1) * 3 * sizeof(double));
    keyed *ord = malloc((size_t)(nn + 1) * sizeof(keyed));
    if (!nrm || !ord) {
        free(nrm), free(ord);
        return mfg_fail(MFG_ERR_NOMEM, "cannot build a region");
    }
    nn = 0;
    for (int64_t k = 0; k < C->len; k++) {
        const sset *S = &W->sets[set[k]];
        memcpy(nrm + 3 * nn, S->n, (size_t)S->nv * 3 * sizeof(double));
        nn += S->nv;
    }
    snap_normals(nrm, nn, ord);
    mfg_spoly *vm = NULL;
    mfg_status st = mfg_visibility_map(nrm, nn, 0.0, &vm);
    if (st != MFG_OK) {
        free(nrm), free(ord);
        return st;
    }
    if (vm->kind == MFG_VM_POLYGON) {
        /* centre of the largest inscribed circle = centre of the smallest circle
         * enclosing the poles of the edges (the dual polygon); taking every normal is
         * the same, as inner ones never bound that circle.  Scrambled order keeps
         * Welzl's algorithm linear. */
        double cosr, mind = 1.0;
        mfg_enclosing_cap(nrm, nn, R->c, &cosr);
        for (int64_t k = 0; k < nn; k++)
            mind = fmin(mind, mfg_dot3(R->c, nrm + 3 * k));
        R->margin = asin(fmin(fmax(mind, -1.0), 1.0));
        if (R->margin > 10 * TOL) {
            R->kind = MFG_VM_POLYGON;
            R->nv = vm->nvertices;
            memcpy(R->v, vm->vertices, (size_t)R->nv * 3 * sizeof(double));
        } else { /* a sliver of the tolerance: the arc (or point) it thickens */
            const double *va = vm->vertices;
            int64_t bi = farthest_vertex(va, vm->nvertices, va);
            int64_t bj = farthest_vertex(va, vm->nvertices, va + 3 * bi);
            arc_region(R, va + 3 * bi, va + 3 * bj);
        }
    } else if (vm->kind == MFG_VM_EDGE) {
        R->kind = MFG_VM_EDGE;
        R->closed = vm->closed;
        R->nv = vm->nvertices;
        memcpy(R->v, vm->vertices, (size_t)R->nv * 3 * sizeof(double));
        memcpy(R->c, vm->vertices + 3 * (vm->closed ? 0 : vm->nvertices / 2), sizeof R->c);
        R->margin = 0.0;
    } else if (vm->kind == MFG_VM_POINT) {
        const double *p = vm->vertices; /* of two antipodal points, the sampled one */
        if (vm->nvertices == 2 && mfg_dot3(vm->vertices + 3, C->x) > mfg_dot3(p, C->x))
            p = vm->vertices + 3;
        arc_region(R, p, p);
    } else { /* touching within the tolerance only at the sample: keep the sample */
        arc_region(R, C->x, C->x);
    }
    mfg_spoly_free(vm);
    free(nrm);
    free(ord);
    return MFG_OK;
}

/* ---- Drivers ----------------------------------------------------------------------- */

/* ---- Branch and bound over cells of the sphere ------------------------------------ */

/* A cell: a spherical quadrilateral bounded by great circles (a cube face, quartered
 * again and again), kept as an sset so the interval code clips edges to it. */
typedef struct cell {
    sset q;             /* kind POLYGON, 4 vertices, inward normals, bounding cap */
    double vbuf[12], nbuf[12];
    double full;        /* weight of the sets containing the whole cell */
    int64_t *part;      /* sets meeting it only partly */
    int64_t npart;
    /* For partial set t, the pieces whose circle still crosses the cell are
     * eidx[eoff[t] .. eoff[t+1]): every other edge's half-space holds the whole cell
     * (decided at an ancestor), so descendants never look at it again. */
    int32_t *eidx;
    int64_t *eoff;
    double ub;          /* full + weight of the partial sets */
    double key;         /* heap priority: ub (max, level) or -full (min) */
    int depth;
} cell;

static void cell_init(cell *c, const double q[4][3])
{
    c->q.kind = MFG_VM_POLYGON;
    c->q.nv = 4;
    c->q.v = c->vbuf;
    c->q.n = c->nbuf;
    for (int k = 0; k < 4; k++)
        mfg_unit3(q[k], c->vbuf + 3 * k);
    for (int k = 0; k < 4; k++) {
        double n[3];
        mfg_cross3(c->vbuf + 3 * k, c->vbuf + 3 * ((k + 1) % 4), n);
        mfg_unit3(n, c->nbuf + 3 * k);
    }
    double s[3] = {0, 0, 0};
    for (int k = 0; k < 4; k++)
        for (int i = 0; i < 3; i++)
            s[i] += c->vbuf[3 * k + i];
    mfg_unit3(s, c->q.cc);
    c->q.cr = 0.0;
    for (int k = 0; k < 4; k++)
        c->q.cr = fmax(c->q.cr, mfg_angle3(c->q.cc, c->vbuf + 3 * k));
    c->q.cr += 1e-9;
    c->q.cos_cr = cos(c->q.cr);
    c->q.sin_cr = sin(c->q.cr);
}

/* 0: the set misses the cell, 1: meets it partly, 2: contains it (with the tolerance).
 * Only the pieces ein[0..nin) of S can still decide; the ones that stay undecided for
 * this cell are written to eout (for POLYGON sets; thin sets keep all of theirs). */
static int classify_cell(const sset *S, const cell *c, const int32_t *ein, int64_t nin,
                         int32_t *eout, int64_t *nout)
{
    const double *q = c->q.v;
    *nout = 0;
    if (caps_apart(c->q.cc, c->q.cr, c->q.cos_cr, c->q.sin_cr, S))
        return 0;
    if (S->kind != MFG_VM_POLYGON) {
        memcpy(eout, ein, (size_t)nin * sizeof(int32_t));
        *nout = nin;
        return 1;
    }
    if (S->ir > c->q.cr &&
        mfg_dot3(c->q.cc, S->ic) >= S->cos_ir * c->q.cos_cr + S->sin_ir * c->q.sin_cr + 1e-12)
        return 2; /* the cell's cap lies in the set's inscribed circle */
    /* Against each edge's half-space the cell's cap decides at once unless the edge's
     * circle passes through the cap: then its four corners decide (the cell is the cone
     * of its corners). */
    const double band = c->q.sin_cr + TOL;
    int64_t m = 0;
    for (int64_t t = 0; t < nin; t++) {
        const double *n = S->n + 3 * ein[t];
        double d = mfg_dot3(c->q.cc, n);
        if (d >= band)
            continue; /* cell inside this half-space */
        if (d < -band)
            return 0; /* cell outside it: disjoint */
        int out = 0;
        for (int k = 0; k < 4; k++)
            out += mfg_dot3(q + 3 * k, n) < -TOL;
        if (out == 4)
            return 0; /* an edge of S separates */
        if (out)
            eout[m++] = ein[t];
    }
    *nout = m;
    return m ? 1 : 2;
}

/* Max-heap of cells by upper bound. */
typedef struct heap {
    cell **a;
    int64_t n, cap;
} heap;

static mfg_status heap_push(heap *h, cell *c)
{
    if (h->n == h->cap) {
        int64_t cap = h->cap ? 2 * h->cap : 64;
        cell **a = realloc(h->a, (size_t)cap * sizeof(cell *));
        if (!a)
            return mfg_fail(MFG_ERR_NOMEM, "cannot grow the cell queue");
        h->a = a;
        h->cap = cap;
    }
    int64_t i = h->n++;
    while (i > 0 && h->a[(i - 1) / 2]->key < c->key) {
        h->a[i] = h->a[(i - 1) / 2];
        i = (i - 1) / 2;
    }
    h->a[i] = c;
    return MFG_OK;
}

static cell *heap_pop(heap *h)
{
    cell *top = h->a[0], *last = h->a[--h->n];
    int64_t i = 0;
    for (;;) {
        int64_t l = 2 * i + 1, r = l + 1, big = i;
        double bu = last->key;
        if (l < h->n && h->a[l]->key > bu)
            big = l, bu = h->a[l]->key;
        if (r < h->n && h->a[r]->key > bu)
            big = r;
        if (big == i)
            break;
        h->a[i] = h->a[big];
        i = big;
    }
    if (h->n > 0)
        h->a[i] = last;
    return top;
}

static void cell_free(cell *c)
{
    if (c) {
        free(c->part);
        free(c->eidx);
        free(c->eoff);
        free(c);
    }
}

/* A child cell of parent p with corners q, classifying the parent's partial sets. */
static mfg_status make_child(work *W, const cell *p, const double q[4][3], cell **out)
{
    cell *c = calloc(1, sizeof *c);
    int64_t *part = malloc((size_t)(p->npart + 1) * sizeof(int64_t));
    int64_t *eoff = malloc((size_t)(p->npart + 1) * sizeof(int64_t));
    int32_t *eidx = malloc((size_t)(p->eoff[p->npart] + 1) * sizeof(int32_t));
    if (!c || !part || !eoff || !eidx) {
        free(c), free(part), free(eoff), free(eidx);
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate a cell");
    }
    cell_init(c, q);
    c->part = part;
    c->eoff = eoff;
    c->eidx = eidx;
    c->full = p->full;
    c->depth = p->depth + 1;
    c->eoff[0] = 0;
    double partial_w = 0.0;
    for (int64_t t = 0; t < p->npart; t++) {
        const sset *S = &W->sets[p->part[t]];
        int64_t nout = 0, at = c->eoff[c->npart];
        int k = classify_cell(S, c, p->eidx + p->eoff[t], p->eoff[t + 1] - p->eoff[t],
                              c->eidx + at, &nout);
        if (k == 2) {
            c->full += S->w;
        } else if (k == 1) {
            c->part[c->npart++] = p->part[t];
            c->eoff[c->npart] = at + nout;
            partial_w += S->w;
        }
    }
    c->ub = c->full + partial_w;
    c->key = W->mode == MODE_MIN ? -c->full : c->ub;
    *out = c;
    return MFG_OK;
}

/* Piece k of set S as an arc a -> b (a point when S is a POINT set). */
static void piece(const sset *S, int64_t k, const double **a, const double **b)
{
    *a = S->v + 3 * k;
    *b = S->kind == MFG_VM_POINT ? *a : S->v + 3 * ((k + 1) % S->nv);
}

static int64_t piece_count(const sset *S)
{
    return S->kind == MFG_VM_EDGE && !S->closed ? S->nv - 1 : S->nv;
}

/* The exact work in a small cell: sweep the partial sets' edges clipped to the cell, and
 * the cell's own edges (a face of the arrangement may have no other boundary here). */
static mfg_status leaf(work *W, const cell *c, double threshold, int keep_best, double eps)
{
    mfg_status st = MFG_OK;
    for (int k = 0; k < 4 && st == MFG_OK; k++)
        st = sweep_edge(W, -1, c->q.v + 3 * k, c->q.v + 3 * ((k + 1) % 4), 0.0, 1.0, c->full,
                        c->part, c->npart, threshold, keep_best, eps);
    for (int64_t t = 0; t < c->npart && st == MFG_OK; t++) {
        int64_t j = c->part[t];
        const sset *S = &W->sets[j];
        for (int64_t u = c->eoff[t]; u < c->eoff[t + 1] && st == MFG_OK; u++) {
            const double *a, *b;
            piece(S, c->eidx[u], &a, &b);
            double r0 = 0.0, r1 = 1.0;
            if (!polygon_interval(&c->q, a, b, &r0, &r1))
                continue;
            st = sweep_edge(W, j, a, b, r0, r1, c->full + S->w, c->part, c->npart, threshold,
                            keep_best, eps);
        }
    }
    return st;
}

static mfg_status consider_min(work *W, double wt, const double x[3], double eps)
{
    if (wt < W->best - eps) {
        W->best = wt;
        W->ncands = 0;
        W->npool = 0;
    }
    return wt <= W->best + eps ? add_candidate(W, wt, x, 0) : MFG_OK;
}

/* Minimum in a small cell: every face of the arrangement here borders the cell's edges
 * or an edge of a partial set from outside; sample the pieces of those edges (pushed
 * 1e-7 rad off a set's edge, to its outer side). */
static mfg_status leaf_min(work *W, const cell *c, double eps)
{
    mfg_status st = MFG_OK;
    /* the cell's 4 edges, then the polygon pieces still crossing the cell */
    int64_t total = 4 + c->eoff[c->npart];
    int64_t t = 0;
    for (int64_t e = 0; e < total && st == MFG_OK; e++) {
        int64_t own = -1;
        const double *a, *b, *n = NULL;
        if (e < 4) {
            a = c->q.v + 3 * e;
            b = c->q.v + 3 * ((e + 1) % 4);
        } else {
            int64_t u = e - 4;
            while (c->eoff[t + 1] <= u)
                t++;
            own = c->part[t];
            const sset *S = &W->sets[own];
            if (S->kind != MFG_VM_POLYGON)
                continue;
            int64_t k = c->eidx[u];
            a = S->v + 3 * k;
            b = S->v + 3 * ((k + 1) % S->nv);
            n = S->n + 3 * k;
        }
        double r0 = 0.0, r1 = 1.0;
        if (own >= 0 && !polygon_interval(&c->q, a, b, &r0, &r1))
            continue;
        int64_t niv = edge_intervals(W, own, a, b, c->part, c->npart), ne = 0;
        for (int64_t i = 0; i < niv; i++) {
            if (W->iv[i].hi < r0 || W->iv[i].lo > r1)
                continue;
            W->ev[ne++] = (event){fmax(W->iv[i].lo, r0), 1, W->iv[i].set};
            W->ev[ne++] = (event){fmin(W->iv[i].hi, r1), 0, W->iv[i].set};
        }
        qsort(W->ev, (size_t)ne, sizeof(event), cmp_event);
        double depth = c->full, prev = r0;
        for (int64_t i = 0; i <= ne && st == MFG_OK; i++) {
            double s = i < ne ? W->ev[i].s : r1;
            if (s > prev) { /* an open piece: one face on each side */
                double sm = 0.5 * (prev + s), x[3], xu[3];
                for (int d = 0; d < 3; d++)
                    x[d] = a[d] + sm * (b[d] - a[d]);
                mfg_unit3(x, xu);
                if (n) {
                    for (int d = 0; d < 3; d++)
                        x[d] = xu[d] - 1e-7 * n[d];
                    mfg_unit3(x, xu);
                }
                st = consider_min(W, depth, xu, eps);
            }
            if (i < ne)
                depth += (W->ev[i].start ? 1.0 : -1.0) * W->sets[W->ev[i].set].w;
            prev = s;
        }
    }
    return st;
}

#define LEAF_SETS 16
#define MAX_DEPTH 16

static mfg_status search(work *W, int mode, double threshold, double eps)
{
    heap h = {NULL, 0, 0};
    mfg_status st = MFG_OK;
    int keep_best = mode == MODE_MAX;
    W->mode = mode;
    W->best = mode == MODE_MIN ? INFINITY : -INFINITY;
    /* The six cube faces, each counter-clockwise seen from outside. */
    int64_t *all = malloc((size_t)W->nsets * sizeof(int64_t));
    if (!all)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate the search");
    for (int64_t j = 0; j < W->nsets; j++)
        all[j] = j;
    cell root;
    memset(&root, 0, sizeof root);
    root.part = all;
    root.npart = W->nsets;
    root.depth = -1;
    int64_t npieces = 0;
    for (int64_t j = 0; j < W->nsets; j++)
        npieces += piece_count(&W->sets[j]);
    root.eoff = malloc((size_t)(W->nsets + 1) * sizeof(int64_t));
    root.eidx = malloc((size_t)(npieces + 1) * sizeof(int32_t));
    if (!root.eoff || !root.eidx) {
        free(all), free(root.eoff), free(root.eidx);
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate the search");
    }
    root.eoff[0] = 0;
    for (int64_t j = 0, u = 0; j < W->nsets; j++) {
        for (int64_t k = 0; k < piece_count(&W->sets[j]); k++)
            root.eidx[u++] = (int32_t)k;
        root.eoff[j + 1] = root.eoff[j] + piece_count(&W->sets[j]);
    }
    for (int axis = 0; axis < 3 && st == MFG_OK; axis++)
        for (int sgn = -1; sgn <= 1 && st == MFG_OK; sgn += 2) {
            double u[3] = {0, 0, 0}, v[3] = {0, 0, 0}, w[3] = {0, 0, 0}, q[4][3];
            w[axis] = sgn;
            u[(axis + 1) % 3] = 1;
            v[(axis + 2) % 3] = 1;
            if (sgn < 0) { /* keep u x v = w */
                double t[3];
                memcpy(t, u, sizeof t), memcpy(u, v, sizeof u), memcpy(v, t, sizeof v);
            }
            const double cu[4] = {-1, 1, 1, -1}, cv[4] = {-1, -1, 1, 1};
            for (int k = 0; k < 4; k++)
                for (int i = 0; i < 3; i++)
                    q[k][i] = w[i] + cu[k] * u[i] + cv[k] * v[i];
            cell *c = NULL;
            st = make_child(W, &root, q, &c);
            if (st == MFG_OK && (st = heap_push(&h, c)) != MFG_OK)
                cell_free(c);
        }
    free(all);
    free(root.eoff);
    free(root.eidx);
    while (st == MFG_OK && h.n > 0) {
        cell *c = heap_pop(&h);
        double lim = keep_best ? W->best : threshold;
        if (mode == MODE_MIN ? c->full > W->best + eps : c->ub < lim - eps) {
            cell_free(c); /* nothing left can reach the limit */
            break;
        }
        if (mode != MODE_LEVEL) { /* the cell's centre: a bound that sharpens pruning */
            double d = c->full;
            for (int64_t t = 0; t < c->npart; t++)
                if (set_contains(&W->sets[c->part[t]], c->q.cc))
                    d += W->sets[c->part[t]].w;
            if (mode == MODE_MIN) {
                st = consider_min(W, d, c->q.cc, eps);
            } else if (d > W->best + eps) {
                W->best = d;
                W->ncands = 0;
                W->npool = 0;
            }
        }
        if (st != MFG_OK) {
            cell_free(c);
            break;
        }
        if (c->npart <= LEAF_SETS || c->depth >= MAX_DEPTH) {
            st = mode == MODE_MIN ? leaf_min(W, c, eps) : leaf(W, c, threshold, keep_best, eps);
        } else {
            const double *p = c->q.v;
            double m[4][3], ctr[3], kids[4][4][3];
            for (int k = 0; k < 4; k++) {
                const double *a = p + 3 * k, *b = p + 3 * ((k + 1) % 4);
                double s[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
                mfg_unit3(s, m[k]);
            }
            memcpy(ctr, c->q.cc, sizeof ctr);
            /* corners: p0 p1 p2 p3, edge midpoints m0 (p0p1) .. m3 (p3p0) */
            for (int k = 0; k < 4; k++) {
                memcpy(kids[k][0], p + 3 * k, sizeof ctr);
                memcpy(kids[k][1], m[k], sizeof ctr);
                memcpy(kids[k][2], ctr, sizeof ctr);
                memcpy(kids[k][3], m[(k + 3) % 4], sizeof ctr);
            }
            for (int k = 0; k < 4 && st == MFG_OK; k++) {
                cell *kid = NULL;
                if ((st = make_child(W, c, kids[k], &kid)) != MFG_OK)
                    break; /* kid stays NULL: nothing to free */
                int useful = mode == MODE_MIN ? kid->full <= W->best + eps
                                              : kid->ub >= (keep_best ? W->best : threshold) - eps;
                if (useful) {
                    if ((st = heap_push(&h, kid)) != MFG_OK)
                        cell_free(kid);
                } else {
                    cell_free(kid);
                }
            }
        }
        cell_free(c);
    }
    while (h.n > 0)
        cell_free(heap_pop(&h));
    free(h.a);
    return st;
}

static int same_set(const work *W, const cand *a, const cand *b)
{
    if (a->len != b->len || a->hash != b->hash)
        return 0;
    for (int64_t k = 0; k < a->len; k++)
        if (W->pool[a->off + k] != W->pool[b->off + k])
            return 0;
    return 1;
}

/* Is a's cover set inside b's?  (Both sorted.) */
static int subset_of(const work *W, const cand *a, const cand *b)
{
    int64_t p = 0, q = 0;
    while (p < a->len && q < b->len) {
        int64_t x = W->pool[a->off + p], y = W->pool[b->off + q];
        if (x == y)
            p++, q++;
        else if (x > y)
            q++;
        else
            return 0;
    }
    return p == a->len;
}

/* Within reach (10 TOL) of a built region? */
/* Bearing of y about c, from v, in [0, 2 pi). */
static double bearing_about(const double *c, const double *v, const double *y)
{
    double p[3], q[3], x[3];
    mfg_cross3(c, v, p);
    mfg_cross3(c, y, q);
    mfg_cross3(p, q, x);
    double t = atan2(mfg_dot3(x, c), mfg_dot3(p, q));
    return t < 0.0 ? t + 2 * MFG_PI : t;
}

/* Is x within reach of the large polygon region R?  Its centre is inside (margin >
 * 10 TOL), so the fan about it locates x's edge in O(log v), as for the input sets. */
static int region_fan_holds(const region *R, const double x[3], double reach)
{
    double t = bearing_about(R->c, R->v, x);
    int64_t lo = 0, hi = R->nv;
    while (hi - lo > 1) {
        int64_t mid = lo + (hi - lo) / 2;
        if (R->fan[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    for (int64_t j = lo - FAN_PAD; j <= lo + FAN_PAD; j++) {
        int64_t i = (j + R->nv) % R->nv;
        double n[3], nu[3];
        mfg_cross3(R->v + 3 * i, R->v + 3 * ((i + 1) % R->nv), n);
        if (mfg_unit3(n, nu) && mfg_dot3(x, nu) < -reach)
            return 0;
    }
    return 1;
}

/* The fan of a large POLYGON region (its centre is inside: margin > 10 TOL); left NULL
 * (every edge tested) for small ones or if rounding breaks the order of the bearings. */
static mfg_status region_fan_build(region *R)
{
    if (R->kind != MFG_VM_POLYGON || R->nv < FAN_MIN_VERTICES)
        return MFG_OK;
    R->fan = malloc((size_t)R->nv * sizeof(double));
    if (!R->fan)
        return mfg_fail(MFG_ERR_NOMEM, "cannot build a region");
    R->fan[0] = 0.0;
    for (int64_t k = 1; k < R->nv; k++) {
        R->fan[k] = bearing_about(R->c, R->v, R->v + 3 * k);
        if (!(R->fan[k] > R->fan[k - 1])) {
            free(R->fan);
            R->fan = NULL;
            break;
        }
    }
    return MFG_OK;
}

static int region_holds(const region *R, const double x[3])
{
    const double reach = 10 * TOL;
    if (R->kind == MFG_VM_POLYGON && R->fan)
        return region_fan_holds(R, x, reach);
    if (R->kind == MFG_VM_POLYGON) {
        for (int64_t i = 0; i < R->nv; i++) {
            double n[3], nu[3];
            mfg_cross3(R->v + 3 * i, R->v + 3 * ((i + 1) % R->nv), n);
            if (mfg_unit3(n, nu) && mfg_dot3(x, nu) < -reach)
                return 0;
        }
        return 1;
    }
    const double *p = R->v, *q = R->v + 3 * (R->nv - 1);
    if (R->kind == MFG_VM_POINT) {
        double d[3] = {x[0] - p[0], x[1] - p[1], x[2] - p[2]};
        return sqrt(mfg_dot3(d, d)) <= reach;
    }
    double n[3], nu[3], s;
    mfg_cross3(p, q, n);
    if (!mfg_unit3(n, nu)) { /* a half circle: use its midpoint to get the circle */
        mfg_cross3(p, R->v + 3, n);
        mfg_unit3(n, nu);
    }
    if (fabs(mfg_dot3(x, nu)) > reach)
        return 0;
    for (int64_t i = 0; i + 1 < R->nv; i++)
        if (param_on_edge(R->v + 3 * i, R->v + 3 * (i + 1), x, &s))
            return 1;
    return 0;
}

static int cmp_region(const void *x, const void *y)
{
    const region *a = x, *b = y;
    if (a->margin != b->margin)
        return a->margin > b->margin ? -1 : 1;
    for (int k = 0; k < 3; k++)
        if (a->c[k] != b->c[k])
            return a->c[k] < b->c[k] ? -1 : 1;
    return 0;
}

static mfg_status emit(work *W, region *R, int64_t nr, double weight, mfg_regions **out)
{
    qsort(R, (size_t)nr, sizeof(region), cmp_region);
    mfg_regions *res = calloc(1, sizeof *res);
    int64_t tv = 0, tc = 0;
    for (int64_t r = 0; r < nr; r++) {
        tv += R[r].nv;
        tc += W->cands[R[r].cand].len;
    }
    if (res) {
        res->kinds = malloc((size_t)(nr + 1) * sizeof(int32_t));
        res->closed = malloc((size_t)(nr + 1) * sizeof(int32_t));
        res->vertex_offsets = malloc((size_t)(nr + 1) * sizeof(int64_t));
        res->vertices = malloc((size_t)(tv + 1) * 3 * sizeof(double));
        res->cover_offsets = malloc((size_t)(nr + 1) * sizeof(int64_t));
        res->cover = malloc((size_t)(tc + 1) * sizeof(int64_t));
        res->centres = malloc((size_t)(nr + 1) * 3 * sizeof(double));
        res->margins = malloc((size_t)(nr + 1) * sizeof(double));
    }
    if (!res || !res->kinds || !res->closed || !res->vertex_offsets || !res->vertices || !res->cover_offsets ||
        !res->cover || !res->centres || !res->margins) {
        mfg_regions_free(res);
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate the result");
    }
    res->weight = ldexp(weight, W->scale_exp); /* back to the caller's scale */
    res->nregions = nr;
    res->vertex_offsets[0] = res->cover_offsets[0] = 0;
    for (int64_t r = 0; r < nr; r++) {
        const cand *C = &W->cands[R[r].cand];
        res->kinds[r] = R[r].kind;
        res->closed[r] = R[r].closed;
        if (R[r].nv > 0)
            memcpy(res->vertices + 3 * res->vertex_offsets[r], R[r].v, (size_t)R[r].nv * 3 * sizeof(double));
        res->vertex_offsets[r + 1] = res->vertex_offsets[r] + R[r].nv;
        int64_t *cv = res->cover + res->cover_offsets[r];
        for (int64_t k = 0; k < C->len; k++)
            cv[k] = W->sets[W->pool[C->off + k]].id;
        qsort(cv, (size_t)C->len, sizeof(int64_t), cmp_i64);
        res->cover_offsets[r + 1] = res->cover_offsets[r] + C->len;
        memcpy(res->centres + 3 * r, R[r].c, 3 * sizeof(double));
        res->margins[r] = R[r].margin;
    }
    *out = res;
    return MFG_OK;
}

/* Candidate order for building regions: heavier first, pieces before isolated points,
 * then by direction, so the result does not depend on the search order. */
static int cand_before(const cand *a, const cand *b)
{
    if (a->weight != b->weight)
        return a->weight > b->weight;
    if (a->degenerate != b->degenerate)
        return a->degenerate < b->degenerate;
    for (int k = 0; k < 3; k++)
        if (a->x[k] != b->x[k])
            return a->x[k] < b->x[k];
    return 0;
}

static void sort_candidates(const work *W, int64_t *idx, int64_t n, int64_t *tmp)
{
    if (n < 2)
        return;
    int64_t h = n / 2;
    sort_candidates(W, idx, h, tmp);
    sort_candidates(W, idx + h, n - h, tmp);
    int64_t i = 0, j = h, k = 0;
    while (i < h && j < n)
        tmp[k++] = cand_before(&W->cands[idx[j]], &W->cands[idx[i]]) ? idx[j++] : idx[i++];
    while (i < h)
        tmp[k++] = idx[i++];
    while (j < n)
        tmp[k++] = idx[j++];
    memcpy(idx, tmp, (size_t)n * sizeof(int64_t));
}

static double cover_weight(const work *W, const cand *c)
{
    double w = 0.0;
    for (int64_t k = 0; k < c->len; k++)
        w += W->sets[W->pool[c->off + k]].w;
    return w;
}

/* Turns candidates into regions.  Maximum and levels: candidates are visited heaviest
 * first; one inside a region already built adds nothing, any other gets its cover set
 * computed and, if its weight qualifies and (levels) its set is not inside a kept one,
 * becomes a region: the intersection of that set.  Minimum: one region per distinct cover
 * set of least weight, represented by its sample direction.  The reported weight is
 * recomputed from the cover sets, so count and covers always agree. */
static mfg_status regions_of(work *W, int maximal_only, double level, double eps,
                             mfg_regions **out)
{
    int64_t n = W->ncands;
    int64_t *idx = malloc((size_t)(n + 1) * sizeof(int64_t));
    int64_t *tmp = malloc((size_t)(n + 1) * sizeof(int64_t));
    region *R = calloc((size_t)(n + 1), sizeof(region));
    if (!idx || !tmp || !R) {
        free(idx), free(tmp), free(R);
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate regions");
    }
    for (int64_t i = 0; i < n; i++)
        idx[i] = i;
    sort_candidates(W, idx, n, tmp);
    mfg_status st = MFG_OK;
    int64_t nr = 0;
    double weight = 0.0;
    if (W->mode == MODE_MIN) {
        double bottom = INFINITY;
        for (int64_t i = 0; i < n; i++)
            bottom = fmin(bottom, cover_weight(W, &W->cands[i]));
        for (int64_t t = n - 1; t >= 0; t--) { /* lightest first */
            const cand *c = &W->cands[idx[t]];
            if (cover_weight(W, c) > bottom + eps)
                continue;
            int dup = 0;
            for (int64_t r = 0; r < nr && !dup; r++)
                dup = same_set(W, &W->cands[R[r].cand], c);
            if (dup)
                continue;
            R[nr].kind = MFG_VM_FACE; /* a face, not convex: only its direction */
            R[nr].cand = idx[t];
            memcpy(R[nr].c, c->x, sizeof R[nr].c);
            nr++;
        }
        weight = bottom;
    } else {
        double top = -INFINITY;
        for (int64_t t = 0; t < n && st == MFG_OK; t++) {
            cand *c = &W->cands[idx[t]];
            if (c->weight < (maximal_only ? level : top) - eps)
                break;
            int held = 0;
            for (int64_t r = 0; r < nr && !held; r++)
                held = region_holds(&R[r], c->x);
            if (held)
                continue;
            if ((st = compute_cover(W, idx[t])) != MFG_OK)
                break;
            c = &W->cands[idx[t]];
            double cw = cover_weight(W, c);
            if (!maximal_only && cw > top + eps) { /* a heavier set: start again */
                for (int64_t r = 0; r < nr; r++)
                    region_release(&R[r]);
                nr = 0;
                top = cw;
            }
            if (cw < (maximal_only ? level : top) - eps)
                continue;
            int dominated = 0;
            for (int64_t r = 0; r < nr && !dominated; r++)
                dominated = subset_of(W, c, &W->cands[R[r].cand]);
            if (dominated)
                continue;
            st = build_region(W, idx[t], &R[nr]);
            if (st == MFG_OK)
                st = region_fan_build(&R[nr]);
            if (st == MFG_OK) {
                nr++;
            } else { /* a region half built: release it */
                region_release(&R[nr]);
            }
        }
        weight = maximal_only ? level : (nr ? top : 0.0);
    }
    if (st == MFG_OK)
        st = emit(W, R, nr, weight, out);
    for (int64_t r = 0; r < nr; r++)
        region_release(&R[r]);
    free(R);
    free(idx);
    free(tmp);
    return st;
}

/* The three entry points differ only in the search mode and the region rule. */
static mfg_status run(int mode, const double *vertices, const int64_t *offsets,
                      const int32_t *kinds, const int32_t *closed, int64_t npolys,
                      const double *weights, double level, mfg_regions **out)
{
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "out is NULL");
    work W;
    mfg_status st = prepare(vertices, offsets, kinds, closed, npolys, weights, &W);
    double eps = W.eps, lev = mode == MODE_LEVEL ? ldexp(level, -W.scale_exp) : 0.0;
    if (st == MFG_OK)
        st = search(&W, mode, lev, eps);
    if (st == MFG_OK)
        st = regions_of(&W, mode == MODE_LEVEL, mode == MODE_LEVEL ? lev : W.best, eps, out);
    free_work(&W);
    if (st == MFG_OK)
        mfg_clear_error();
    return st;
}

mfg_status mfg_max_intersection(const double *vertices, const int64_t *offsets,
                                const int32_t *kinds, const int32_t *closed, int64_t npolys,
                                const double *weights, mfg_regions **out)
{
    return run(MODE_MAX, vertices, offsets, kinds, closed, npolys, weights, 0.0, out);
}

mfg_status mfg_level_regions(const double *vertices, const int64_t *offsets,
                             const int32_t *kinds, const int32_t *closed, int64_t npolys,
                             const double *weights, double level, mfg_regions **out)
{
    if (!(level > -1e300 && level < 1e300))
        return mfg_fail(MFG_ERR_INVALID, "level must be finite (got %g)", level);
    return run(MODE_LEVEL, vertices, offsets, kinds, closed, npolys, weights, level, out);
}

mfg_status mfg_min_intersection(const double *vertices, const int64_t *offsets,
                                const int32_t *kinds, const int32_t *closed, int64_t npolys,
                                const double *weights, mfg_regions **out)
{
    return run(MODE_MIN, vertices, offsets, kinds, closed, npolys, weights, 0.0, out);
}

void mfg_regions_free(mfg_regions *r)
{
    if (!r)
        return;
    free(r->kinds);
    free(r->closed);
    free(r->vertex_offsets);
    free(r->vertices);
    free(r->cover_offsets);
    free(r->cover);
    free(r->centres);
    free(r->margins);
    free(r);
}
