/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* maxisect_regions.c - regions of the best cover sets: each is the intersection of its
 * cover set (the visibility map of its members' edge normals, or an arc or point of a
 * thin member), its centre the centre of the largest inscribed circle; then the
 * result, sorted and independent of the input order. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sphere/maxisect.h"


/* A built region before output. */
typedef struct region {
    int kind, closed;
    int64_t nv;
    double *v;
    double c[3], margin;
    double weight; /* of its cover set */
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
                mfg_neg3(a, b);
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
    if (sqrt(mfg_dot3(d, d)) <= REGION_REACH) {
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

/* R's vertex storage: room for n vertices (and at least an arc's 3). */
static mfg_status region_alloc(region *R, int64_t n)
{
    R->v = malloc((size_t)(n > 3 ? n : 3) * 3 * sizeof(double));
    return R->v ? MFG_OK : mfg_fail(MFG_ERR_NOMEM, "cannot build a region");
}

/* The thin (POINT or EDGE) member of a cover set that bounds its region most: a point
 * beats an arc; -1 when every member is a polygon. */
static int64_t thinnest_member(const work *W, const int64_t *set, int64_t len)
{
    int64_t thin = -1;
    for (int64_t k = 0; k < len; k++) {
        const sset *S = &W->sets[set[k]];
        if (S->kind != MFG_VM_POLYGON && (thin < 0 || S->kind < W->sets[thin].kind))
            thin = set[k];
    }
    return thin;
}

/* Region of a cover set holding a POINT set T: the point of T nearest the sample. */
static void region_on_point(region *R, const sset *T, const double *x)
{
    int64_t best = 0;
    for (int64_t k = 1; k < T->nv; k++)
        if (mfg_dot3(T->v + 3 * k, x) > mfg_dot3(T->v + 3 * best, x))
            best = k;
    arc_region(R, T->v + 3 * best, T->v + 3 * best);
}

/* The piece of EDGE set T holding direction x (the one whose midpoint is nearest). */
static int64_t piece_holding(const sset *T, const double *x)
{
    int64_t pieces = T->closed ? T->nv : T->nv - 1, piece = 0;
    double bestd = -2.0;
    for (int64_t k = 0; k < pieces; k++) {
        const double *a = T->v + 3 * k, *b = T->v + 3 * ((k + 1) % T->nv);
        double s, mid[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]}, mu[3];
        mfg_unit3(mid, mu);
        if (mfg_param_on_edge(a, b, x, &s) && mfg_dot3(mu, x) > bestd) {
            bestd = mfg_dot3(mu, x);
            piece = k;
        }
    }
    return piece;
}

/* [lo, hi] of the arc a -> b inside every member of the cover set but thin: the
 * intersection of each member's interval (of the hull of its intervals, for a thin
 * member: the region is convex).  W->iv is free after the search and has room for any
 * thin set's pieces. */
static void clip_arc_by_cover(work *W, const int64_t *set, int64_t len, int64_t thin,
                              const double *a, const double *b, double *lo, double *hi)
{
    *lo = 0.0, *hi = 1.0;
    for (int64_t k = 0; k < len; k++) {
        if (set[k] == thin)
            continue;
        const sset *S = &W->sets[set[k]];
        double l = 2.0, h = -1.0;
        if (S->kind == MFG_VM_POLYGON) {
            if (!mfg_polygon_interval(S, a, b, &l, &h))
                l = 2.0, h = -1.0;
        } else {
            int64_t m = mfg_thin_intervals(S, set[k], a, b, W->iv);
            for (int64_t t = 0; t < m; t++)
                l = fmin(l, W->iv[t].lo), h = fmax(h, W->iv[t].hi);
        }
        if (l <= h) {
            *lo = fmax(*lo, l);
            *hi = fmin(*hi, h);
        }
    }
}

/* Region of a cover set holding an EDGE set T: the piece of T holding the sample,
 * clipped by the other members (extending over neighbouring pieces is left out: pieces
 * of a map are at most 90 degrees). */
static void region_on_arc(work *W, const cand *C, const int64_t *set, int64_t thin, region *R)
{
    const sset *T = &W->sets[thin];
    int64_t piece = piece_holding(T, C->x);
    const double *a = T->v + 3 * piece, *b = T->v + 3 * ((piece + 1) % T->nv);
    double lo, hi;
    clip_arc_by_cover(W, set, C->len, thin, a, b, &lo, &hi);
    if (lo > hi) { /* rounding disagreed with the sweep: keep the sample itself */
        arc_region(R, C->x, C->x);
        return;
    }
    double p[3], q[3];
    double xp[3] = {a[0] + lo * (b[0] - a[0]), a[1] + lo * (b[1] - a[1]), a[2] + lo * (b[2] - a[2])};
    double xq[3] = {a[0] + hi * (b[0] - a[0]), a[1] + hi * (b[1] - a[1]), a[2] + hi * (b[2] - a[2])};
    mfg_unit3(xp, p);
    mfg_unit3(xq, q);
    arc_region(R, p, q);
}

/* Centre and margin of the largest circle inscribed in the map of the normals nrm: the
 * centre of the smallest circle enclosing the poles of its edges (the dual polygon);
 * taking every normal is the same, as inner ones never bound that circle. */
static void inscribed_centre(const double *nrm, int64_t nn, region *R)
{
    double cosr, mind = 1.0;
    mfg_enclosing_cap(nrm, nn, R->c, &cosr);
    for (int64_t k = 0; k < nn; k++)
        mind = fmin(mind, mfg_dot3(R->c, nrm + 3 * k));
    R->margin = asin(fmin(fmax(mind, -1.0), 1.0));
}

/* R from the visibility map vm of the cover set's normals: a polygon with its inscribed
 * centre (or, thinner than REGION_REACH, the arc or point it thickens), an arc, a point
 * (of two antipodal ones, the sampled one), or the sample itself when the members touch
 * only there within the tolerance. */
static void region_from_map(const mfg_spoly *vm, const double *nrm, int64_t nn, const double *x,
                            region *R)
{
    if (vm->kind == MFG_VM_POLYGON) {
        inscribed_centre(nrm, nn, R);
        if (R->margin > REGION_REACH) {
            R->kind = MFG_VM_POLYGON;
            R->nv = vm->nvertices;
            memcpy(R->v, vm->vertices, (size_t)R->nv * 3 * sizeof(double));
        } else {
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
        const double *p = vm->vertices;
        if (vm->nvertices == 2 && mfg_dot3(vm->vertices + 3, x) > mfg_dot3(p, x))
            p = vm->vertices + 3;
        arc_region(R, p, p);
    } else {
        arc_region(R, x, x);
    }
}

/* Region of a cover set of polygons: every member is { x : x.n >= 0 } over its inward
 * edge normals, so their intersection is the visibility map of all those normals
 * (visibility.c: exact kinds, so two maps meeting along a circle with opposite sides give
 * an EDGE, and hemispheres, whose vertices do not span them, need no special case).
 * Normals that are equal or opposite within the tolerance are made exactly so first:
 * that is the tolerance's "boundaries this close touch". */
static mfg_status region_of_polygons(work *W, const cand *C, const int64_t *set, region *R)
{
    int64_t nn = 0;
    for (int64_t k = 0; k < C->len; k++)
        nn += W->sets[set[k]].nv;
    double *nrm = malloc((size_t)(nn + 1) * 3 * sizeof(double));
    keyed *ord = malloc((size_t)(nn + 1) * sizeof(keyed));
    mfg_status st = nrm && ord ? region_alloc(R, nn) : mfg_fail(MFG_ERR_NOMEM, "cannot build a region");
    mfg_spoly *vm = NULL;
    if (st == MFG_OK) {
        nn = 0;
        for (int64_t k = 0; k < C->len; k++) {
            const sset *S = &W->sets[set[k]];
            memcpy(nrm + 3 * nn, S->n, (size_t)S->nv * 3 * sizeof(double));
            nn += S->nv;
        }
        snap_normals(nrm, nn, ord);
        st = mfg_visibility_map(nrm, nn, 0.0, &vm);
    }
    if (st == MFG_OK)
        region_from_map(vm, nrm, nn, C->x, R); /* at most nn vertices: room made above */
    mfg_spoly_free(vm);
    free(nrm);
    free(ord);
    return st;
}

/* Builds the region of candidate ci: the intersection of its cover set.  On failure R
 * may hold storage: the caller releases it (region_release). */
static mfg_status build_region(work *W, int64_t ci, region *R)
{
    const cand *C = &W->cands[ci];
    const int64_t *set = W->pool + C->off;
    memset(R, 0, sizeof *R);
    R->cand = ci;
    int64_t thin = thinnest_member(W, set, C->len);
    if (thin < 0)
        return region_of_polygons(W, C, set, R);
    mfg_status st = region_alloc(R, 3);
    if (st != MFG_OK)
        return st;
    if (W->sets[thin].kind == MFG_VM_POINT)
        region_on_point(R, &W->sets[thin], C->x);
    else
        region_on_arc(W, C, set, thin, R);
    return MFG_OK;
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
/* Is x within reach of the large polygon region R?  Its centre is inside (margin >
 * 10 TOL), so the fan about it locates x's edge in O(log v), as for the input sets. */
static int region_fan_holds(const region *R, const double x[3], double reach)
{
    double t = mfg_bearing3(R->c, R->v, x);
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
        R->fan[k] = mfg_bearing3(R->c, R->v, R->v + 3 * k);
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
    const double reach = REGION_REACH;
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
        if (mfg_param_on_edge(R->v + 3 * i, R->v + 3 * (i + 1), x, &s))
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
        qsort(cv, (size_t)C->len, sizeof(int64_t), mfg_cmp_i64);
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
mfg_status mfg_regions_of(work *W, int maximal_only, double level, double eps,
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
            if (!mfg_prog_poll(W->prog, (double)(n - t), (double)n)) {
                st = mfg_prog_fail(W->prog);
                break;
            }
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
            if (!mfg_prog_poll(W->prog, (double)t, (double)n)) {
                st = mfg_prog_fail(W->prog);
                break;
            }
            cand *c = &W->cands[idx[t]];
            if (c->weight < (maximal_only ? level : top) - eps)
                break;
            /* only a region at least as heavy as the candidate's ownership absorbs it:
             * were the sweep and the cover set ever to disagree, a lighter region built
             * first must not hide a heavier one */
            int held = 0;
            for (int64_t r = 0; r < nr && !held; r++)
                held = R[r].weight >= c->weight - eps && region_holds(&R[r], c->x);
            if (held)
                continue;
            if ((st = mfg_compute_cover(W, idx[t])) != MFG_OK)
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
            R[nr].weight = cw;
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
