/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* maxisect_sweep.c - the edge-based partition of the paper: the part of an arc inside
 * each other set is one interval of its parameter, and sweeping the intervals' ends
 * gives the ownership (covered weight) of every piece and point of the arc; pieces that
 * reach the limit become candidates. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sphere/maxisect.h"

/* An arc whose great circle passes closer than asin(FAN_ARC_MIN_SIN) (~0.06 degrees) to
 * a fan's centre sweeps its bearings too fast to bound: it is clipped by every edge. */
#define FAN_ARC_MIN_SIN 1e-3

/* Intervals of a thin set's consecutive pieces closer than this in s are one (they
 * meet at the shared vertex; the gap is rounding). */
#define PIECE_JOIN 1e-12

/* Interval of edge a->b (s in [0,1]) inside polygon S; 0 when empty.  The constraint
 * x(s).n >= -tol is linear in s, but x(s) is shorter than a unit vector (down to
 * cos(L/2) mid-edge), so the slack is scaled by that: every point of the interval then
 * passes mfg_set_contains(), and boundaries within TOL cos(L/2) count as touching. */
int mfg_polygon_interval(const sset *S, const double *a, const double *b, double *lo,
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
        if (mfg_unit3(g, gu) && fabs(mfg_dot3(gu, S->ic)) > FAN_ARC_MIN_SIN) {
            int64_t ka = mfg_fan_locate(S, a), kb = mfg_fan_locate(S, b);
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
int64_t mfg_thin_intervals(const sset *S, int64_t sid, const double *a, const double *b,
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
            if (mfg_param_on_edge(a, b, p, &s))
                iv[m++] = (interval){s, s, sid};
        }
        return m;
    }
    int64_t pieces = S->closed ? S->nv : S->nv - 1;
    for (int64_t k = 0; k < pieces; k++) {
        const double *c = S->v + 3 * k, *d = S->v + 3 * ((k + 1) % S->nv);
        if (!edge_has_circle) { /* the swept "edge" is a point */
            if (mfg_set_contains(S, a))
                iv[m++] = (interval){0.0, 0.0, sid};
            return m;
        }
        if (fabs(mfg_dot3(c, neu)) <= TOL && fabs(mfg_dot3(d, neu)) <= TOL) {
            /* same great circle: overlap of the two arcs */
            double sc, sd, lo = 2.0, hi = -1.0;
            if (mfg_param_on_edge(a, b, c, &sc))
                lo = fmin(lo, sc), hi = fmax(hi, sc);
            if (mfg_param_on_edge(a, b, d, &sd))
                lo = fmin(lo, sd), hi = fmax(hi, sd);
            double nc[3], ncu[3], s;
            mfg_cross3(c, d, nc);
            mfg_unit3(nc, ncu);
            /* the edge's ends inside the piece also bound the overlap */
            if (mfg_param_on_edge(c, d, a, &s))
                lo = fmin(lo, 0.0), hi = fmax(hi, 0.0);
            if (mfg_param_on_edge(c, d, b, &s))
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
                    mfg_neg3(xu, xu);
                if (mfg_param_on_edge(a, b, xu, &s) && mfg_param_on_edge(c, d, xu, &t))
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
        if (out > 0 && iv[i].lo <= iv[out - 1].hi + PIECE_JOIN)
            iv[out - 1].hi = fmax(iv[out - 1].hi, iv[i].hi);
        else
            iv[out++] = iv[i];
    }
    return out;
}

/* The edge's bounding cap: centre and cos/sin of its half length. */
void mfg_edge_cap(const double *a, const double *b, double mc[3], double *half, double *ch,
                     double *sh)
{
    double mid[3] = {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
    *half = 0.5 * mfg_angle3(a, b);
    *ch = cos(*half);
    *sh = sin(*half);
    if (!mfg_unit3(mid, mc))
        memcpy(mc, a, 3 * sizeof(double));
}

/* Intervals of edge a->b inside the listed sets (own excluded). */
int64_t mfg_edge_intervals(work *W, int64_t own, const double *a, const double *b,
                              const int64_t *list, int64_t nlist)
{
    double mc[3], half, ch, sh;
    mfg_edge_cap(a, b, mc, &half, &ch, &sh);
    int64_t m = 0;
    for (int64_t t = 0; t < nlist; t++) {
        int64_t j = list[t];
        if (j == own)
            continue;
        const sset *S = &W->sets[j];
        if (mfg_caps_apart(mc, half, ch, sh, S))
            continue;
        if (S->kind == MFG_VM_POLYGON) {
            double lo, hi;
            if (mfg_polygon_interval(S, a, b, &lo, &hi))
                W->iv[m++] = (interval){lo, hi, j};
        } else {
            m += mfg_thin_intervals(S, j, a, b, W->iv + m);
        }
    }
    return m;
}

int mfg_cmp_event(const void *x, const void *y)
{
    const event *a = x, *b = y;
    if (a->s != b->s)
        return a->s < b->s ? -1 : 1;
    return b->start - a->start; /* starts first: closed sets touch */
}

/* Computes candidate ci's cover set (every set containing its direction) into the pool. */
mfg_status mfg_compute_cover(work *W, int64_t ci)
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
        if (mfg_set_contains(&W->sets[j], c->x)) {
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
mfg_status mfg_add_candidate(work *W, double weight, const double x[3], int degenerate)
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
    return W->mode == MODE_MIN ? mfg_compute_cover(W, W->ncands - 1) : MFG_OK;
}

/* Exact sweep of the events (already in W->ev) inside [s0, s1] of edge a->b, entering
 * with ownership depth. */
static mfg_status sweep_range(work *W, const arc_span *range, int64_t ne, double depth,
                              const sweep_goal *goal, int first_range)
{
    const double *a = range->a, *b = range->b, s0 = range->r0, s1 = range->r1;
    double threshold = goal->threshold, eps = goal->eps;
    int keep_best = goal->keep_best;
    double prev = s0;
    int point_edge = a == b;
    qsort(W->ev, (size_t)ne, sizeof(event), mfg_cmp_event);
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
            mfg_status st_ = mfg_add_candidate(W, wt_, xu_, (deg));                              \
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
mfg_status mfg_sweep_edge(work *W, int64_t own, const arc_span *span, double base,
                          const int64_t *list, int64_t nlist, const sweep_goal *goal)
{
    const double *a = span->a, *b = span->b, r0 = span->r0, r1 = span->r1;
    double threshold = goal->threshold, eps = goal->eps;
    int keep_best = goal->keep_best;
    int64_t niv = mfg_edge_intervals(W, own, a, b, list, nlist);
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
            arc_span range = {a, b, s0, s1};
            mfg_status st = sweep_range(W, &range, ne, depth, goal, bk == 0);
            if (st != MFG_OK)
                return st;
        }
        depth += bstart[bk] - bend[bk];
    }
#undef BUCKET
    return MFG_OK;
}
