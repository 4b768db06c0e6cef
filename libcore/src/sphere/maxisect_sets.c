/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* maxisect_sets.c - the input sets of the maximum intersection: checked (counts,
 * offsets, kinds, shapes, weights) and prepared (unit vertices, edge normals, bounding
 * caps, inscribed circles, fans), and the membership of a direction in a set. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sphere/maxisect.h"

/* Arcs shorter than sqrt(SHORT_ARC_DET) = 1e-6 rad are handled as their chord: the
 * Gram solve below divides by |a x b|^2, which for such arcs amplifies the rounding of
 * its numerators (~1e-16) beyond any use, while the chord is within len^2 / 8 < 1e-12
 * rad of the arc. */
#define SHORT_ARC_DET 1e-12

/* ---- Membership ----------------------------------------------------------------- */

/* Parameter s of direction y (on the great circle of a->b) along x(s) = a + s (b - a);
 * returns 0 when y is outside the arc (beyond the tolerance). */
int mfg_param_on_edge(const double *a, const double *b, const double *y, double *s)
{
    double ab = mfg_dot3(a, b), ya = mfg_dot3(y, a), yb = mfg_dot3(y, b), g[3];
    mfg_cross3(a, b, g);
    double det = mfg_dot3(g, g); /* = 1 - (a.b)^2, but exact 0 for a == b */
    if (det <= SHORT_ARC_DET) { /* a point, or so short an arc that its chord will do */
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, d[3];
        double uu = mfg_dot3(u, u);
        double t = uu > 0.0 ? ((y[0] - a[0]) * u[0] + (y[1] - a[1]) * u[1] + (y[2] - a[2]) * u[2]) / uu : 0.0;
        t = fmin(fmax(t, 0.0), 1.0);
        for (int i = 0; i < 3; i++)
            d[i] = y[i] - (a[i] + t * u[i]);
        *s = t;
        return sqrt(mfg_dot3(d, d)) <= TOL;
    }
    /* In the plane of the arc: y = alpha a + beta b (solve with the Gram matrix). */
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

/* Index k of the triangle (ic, v_k, v_k+1) holding direction y. */
int64_t mfg_fan_locate(const sset *S, const double *y)
{
    double t = mfg_bearing3(S->ic, S->v, y);
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
        S->fan[k] = mfg_bearing3(S->ic, S->v, S->v + 3 * k);
        if (!(S->fan[k] > S->fan[k - 1])) { /* rounding on a needle polygon: do without */
            free(S->fan);
            S->fan = NULL;
            return MFG_OK;
        }
    }
    return MFG_OK;
}

int mfg_set_contains(const sset *S, const double *y)
{
    if (mfg_dot3(S->cc, y) < S->cos_cr - CAP_SLACK_COS)
        return 0;
    if (S->kind == MFG_VM_POLYGON && S->fan) {
        int64_t k = mfg_fan_locate(S, y);
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
            if (mfg_unit3(proj, pu) && mfg_param_on_edge(a, b, pu, &s))
                return 1;
        }
    }
    return 0;
}

/* ---- Preparation ---------------------------------------------------------------- */

void mfg_sets_free(work *W)
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

/* A map takes part when it has a kind and a positive weight; every other one is
 * ignored everywhere, in the scale and the tolerance too (an ignored NULL map of weight
 * 1e200 must not make every real weight look equal). */
static int takes_part(const int32_t *kinds, const double *weights, int64_t i)
{
    return kinds[i] != MFG_VM_NULL && (weights ? weights[i] : 1.0) > 0.0;
}

/* Step 3: the weights of the maps taking part, scaled by one power of two so the
 * largest is in [0.5, 1).  A power of two scales every sum exactly, so the answer is the
 * same for weights scaled by any factor (up to rounding of the factor itself), and tiny
 * or huge weights neither underflow nor overflow in the sums; W->scale_exp maps back.
 * The tolerance for equal weights is relative to the total: sums of n weights in any
 * order differ by at most ~2 n u total, and WEIGHT_REL_EPS per set covers that with
 * room.  A weight below that tolerance is a tie: its set still covers (see load_set). */
#define WEIGHT_REL_EPS 0x1p-44
static mfg_status scale_weights(const int32_t *kinds, const double *weights, int64_t npolys,
                                work *W)
{
    double wmax = 0.0;
    int64_t n = 0;
    for (int64_t i = 0; i < npolys; i++)
        if (takes_part(kinds, weights, i)) {
            wmax = fmax(wmax, weights ? weights[i] : 1.0);
            n++;
        }
    int e = 0;
    if (wmax > 0.0)
        frexp(wmax, &e); /* wmax = f 2^e, f in [0.5, 1) */
    W->scale_exp = e;
    double total = 0.0;
    for (int64_t i = 0; i < npolys; i++)
        if (takes_part(kinds, weights, i))
            total += ldexp(weights ? weights[i] : 1.0, -e);
    if (!isfinite(ldexp(total, e)))
        return mfg_fail(MFG_ERR_INVALID, "the total weight overflows a double (largest weight %g)", wmax);
    W->eps = WEIGHT_REL_EPS * (double)(n + 1) * total;
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

/* How far beyond a POLYGON its tolerance reaches (radians): membership is x.n_k >= -TOL
 * for every edge k (mfg_set_contains, the sweep's intervals), the polygon with every edge
 * moved out by TOL, whose vertex k lies asin(TOL / sin(theta_k / 2)) beyond vertex k
 * (theta_k: the interior angle there; sin(theta_k / 2) = |n_k-1 + n_k| / 2).  At a sharp
 * vertex that is far more than TOL: 2.6e-8 rad at the poles of a lune 0.44 degrees wide,
 * where such a lune and its negation (and every other set through the pole) overlap.
 * Doubled against rounding; pi when the polygon is too thin to bound it. */
static double polygon_slack_reach(const sset *S)
{
    double least = 1.0;
    for (int64_t k = 0; k < S->nv; k++) {
        const double *p = S->n + 3 * ((k + S->nv - 1) % S->nv), *q = S->n + 3 * k;
        double s[3] = {p[0] + q[0], p[1] + q[1], p[2] + q[2]};
        least = fmin(least, 0.5 * sqrt(mfg_dot3(s, s)));
    }
    return least > 4 * TOL ? 2.0 * asin(TOL / least) : MFG_PI;
}

/* The set's bounding cap (centre cc, radius cr): it must hold every direction the set
 * contains with the tolerance, since the float tests that skip sets and cells by their
 * caps (mfg_set_contains, mfg_caps_apart) must agree with the membership tests.  It is
 * the smallest cap of the vertices, widened by how far the tolerance reaches beyond them
 * (polygon_slack_reach: the moved-out polygon is the hull of its moved-out vertices) and
 * by CAP_WIDEN against rounding.  A cap of radius >= pi/2 is not convex: containing the
 * vertices no longer means containing the set.  A polygon lies in the hemisphere around
 * the sum s of its inward edge normals (x.n_k >= -TOL for all k gives x.s >= -nv TOL, so
 * the moved-out polygon lies within asin(nv TOL / |s|) beyond it); an arc this large
 * gets no cap at all (radius pi). */
static void bounding_cap(sset *S)
{
    double cosr;
    mfg_enclosing_cap(S->v, S->nv, S->cc, &cosr);
    S->cr = acos(fmin(fmax(cosr, -1.0), 1.0));
    for (int64_t k = 0; k < S->nv; k++)
        S->cr = fmax(S->cr, mfg_angle3(S->cc, S->v + 3 * k));
    double reach = S->kind == MFG_VM_POLYGON ? polygon_slack_reach(S) : 0.0;
    if (S->cr + reach >= MFG_PI / 2 - CAP_HEMI_MARGIN) {
        double sum[3] = {0, 0, 0};
        S->cr = MFG_PI;
        if (S->kind == MFG_VM_POLYGON) {
            for (int64_t k = 0; k < S->nv; k++)
                for (int d = 0; d < 3; d++)
                    sum[d] += S->n[3 * k + d];
            double len = sqrt(mfg_dot3(sum, sum)), f = len > 0.0 ? (double)S->nv * TOL / len : 2.0;
            if (f < 0.5 && mfg_unit3(sum, S->cc))
                S->cr = MFG_PI / 2 + CAP_HEMI_MARGIN + 2.0 * asin(f);
        }
    } else {
        S->cr += reach;
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
    if (!takes_part(kinds, weights, i))
        return MFG_OK; /* contributes nothing anywhere */
    /* A weight more than 2^1074 times lighter than the heaviest underflows when scaled;
     * it is a tie like any weight below the tolerance, and its set still covers (whether
     * a set counts must not depend on the scale of the weights), so it keeps the least
     * positive weight. */
    double w = fmax(ldexp(weights ? weights[i] : 1.0, -W->scale_exp), DBL_TRUE_MIN);
    int64_t nv = offsets[i + 1] - offsets[i];
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

mfg_status mfg_sets_prepare(const ms_input *in, work *W)
{
    const double *vertices = in->vertices, *weights = in->weights;
    const int64_t *offsets = in->offsets;
    const int32_t *kinds = in->kinds, *closed = in->closed;
    int64_t npolys = in->npolys;
    memset(W, 0, sizeof *W);
    mfg_status st = check_layout(offsets, kinds, closed, npolys, weights);
    if (st == MFG_OK)
        st = check_vertices(vertices, offsets, kinds, npolys);
    if (st == MFG_OK)
        st = scale_weights(kinds, weights, npolys, W);
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
