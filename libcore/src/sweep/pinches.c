/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sweep/pinches.c - Pinches: edges shared by more than two output triangles, paired round
 * the edge.  Overview and file map: sweep/sweep.h. */
#include "sweep/sweep.h"

typedef struct sw_he {
    int64_t lo, hi; /* undirected edge */
    int64_t tri;    /* triangle using it */
    int dir;        /* +1: lo -> hi in the triangle, -1: hi -> lo */
    double ang;     /* angle of the triangle's third corner round the edge */
} sw_he;

static int cmp_he(const void *pa, const void *pb)
{
    const sw_he *a = pa, *b = pb;
    if (a->lo != b->lo)
        return (a->lo > b->lo) - (a->lo < b->lo);
    if (a->hi != b->hi)
        return (a->hi > b->hi) - (a->hi < b->hi);
    return (a->ang > b->ang) - (a->ang < b->ang);
}

/* Joins the corners at the edge's two ends of triangles h and g (paired across it). */
static void join_across(const sw_ctx *c, const sw_he *h, const sw_he *g, int64_t *parent)
{
    int64_t t1 = h->tri / 3, t2 = g->tri / 3;
    for (int k = 0; k < 3; k++)
        for (int m = 0; m < 3; m++) {
            int64_t v1 = c->otri[3 * t1 + k], v2 = c->otri[3 * t2 + m];
            if (v1 == v2 && (v1 == h->lo || v1 == h->hi))
                mfg_uf_union(parent, 3 * t1 + k, 3 * t2 + m);
        }
}

/* Do the n triangles round an edge (sorted by angle) alternate in direction? */
static int alternates(const sw_he *e, int64_t n)
{
    if (n % 2)
        return 0;
    for (int64_t q = 0; q < n; q++)
        if (e[q].dir == e[(q + 1) % n].dir)
            return 0;
    return 1;
}

/* Where the directions round an edge do not alternate (rounding swapped two nearly
 * coincident pieces), the triangles are read in decreasing angle as a cyclic bracket
 * sequence (+1 opens, -1 closes) and each +1 is paired with its matching -1: every
 * triangle gets a partner, where pairing with the next one round would leave some
 * unpaired and the edge open once the vertices are split.  An edge with unequal counts
 * of the two directions is left as it is (the closedness check reports it). */
static int pair_round_edge(sw_ctx *c, const sw_he *e, int64_t n, int64_t *parent,
                           int64_t **stack, int64_t *capstack)
{
    int64_t sum = 0, low = 0, start = 0;
    for (int64_t k = 0; k < n; k++) {
        sum += e[n - 1 - k].dir;
        if (sum < low) {
            low = sum;
            start = k + 1;
        }
    }
    if (sum != 0)
        return 1;
    if (!mfg_grow((void **)stack, capstack, n, sizeof **stack))
        return ctx_nomem(c);
    int64_t depth = 0;
    for (int64_t k = 0; k < n; k++) {
        int64_t idx = n - 1 - (start + k) % n;
        if (e[idx].dir == 1)
            (*stack)[depth++] = idx;
        else if (depth > 0)
            join_across(c, &e[(*stack)[--depth]], &e[idx], parent);
    }
    return 1;
}

/*
 * The boundary of a union of prisms may touch itself: where two covered regions meet
 * across a corner of the decomposition, four pieces share an arc (a pinch), and a vertex
 * may join two separate fans.  Each such edge is resolved by pairing its triangles round
 * it (each with the next one of the opposite direction), and each vertex gets one copy per
 * fan of triangles joined through paired edges: the surface stays closed and becomes a
 * 2-manifold that touches itself there, as the true boundary does.
 */
int sw_resolve_pinches(sw_ctx *c, sw_out *o)
{
    int64_t nt = c->notri, ne = 3 * nt;
    sw_he *he = malloc((size_t)(ne + 1) * sizeof *he);
    int64_t *parent = malloc((size_t)(ne + 1) * sizeof *parent);
    if (!he || !parent) {
        free(he);
        free(parent);
        return ctx_nomem(c);
    }
    for (int64_t t = 0; t < nt; t++)
        for (int k = 0; k < 3; k++) {
            int64_t a = c->otri[3 * t + k], b = c->otri[3 * t + (k + 1) % 3];
            int64_t d = c->otri[3 * t + (k + 2) % 3];
            sw_he *h = &he[3 * t + k];
            h->lo = a < b ? a : b;
            h->hi = a < b ? b : a;
            h->tri = 3 * t + k;
            h->dir = a < b ? 1 : -1;
            /* angle of corner d round the axis lo -> hi */
            const double *P = c->ox + 3 * h->lo, *Q = c->ox + 3 * h->hi, *D = c->ox + 3 * d;
            double ax[3] = {Q[0] - P[0], Q[1] - P[1], Q[2] - P[2]};
            double w[3] = {D[0] - P[0], D[1] - P[1], D[2] - P[2]};
            double l2 = ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2];
            double pr = l2 > 0 ? (w[0] * ax[0] + w[1] * ax[1] + w[2] * ax[2]) / l2 : 0;
            double u[3] = {w[0] - pr * ax[0], w[1] - pr * ax[1], w[2] - pr * ax[2]};
            /* a fixed frame perpendicular to the edge */
            double ref[3] = {1, 0, 0};
            if (fabs(ax[0]) > fabs(ax[1]) && fabs(ax[0]) > fabs(ax[2]))
                ref[0] = 0, ref[1] = 1;
            double e1[3] = {ax[1] * ref[2] - ax[2] * ref[1], ax[2] * ref[0] - ax[0] * ref[2],
                            ax[0] * ref[1] - ax[1] * ref[0]};
            double e2[3] = {ax[1] * e1[2] - ax[2] * e1[1], ax[2] * e1[0] - ax[0] * e1[2],
                            ax[0] * e1[1] - ax[1] * e1[0]};
            h->ang = atan2(u[0] * e2[0] + u[1] * e2[1] + u[2] * e2[2],
                           u[0] * e1[0] + u[1] * e1[1] + u[2] * e1[2]);
            /* an edge along a circle (a chord between two ring vertices): the pieces leave
             * it in the directions of their 2-D edges, which the circle's own sag would
             * hide; measure the third corner's direction in the meridian plane */
            double rp = v_r(P[0], P[1]), rq = v_r(Q[0], Q[1]);
            int64_t r0 = c->oring[2 * t], r1 = c->oring[2 * t + 1];
            if ((r0 == a && r1 == b) || (r0 == b && r1 == a)) {
                double dr = cos(c->odir[t]), dz = sin(c->odir[t]);
                (void)rp;
                (void)rq;
                double turn = angle_diff(atan2(Q[1], Q[0]), atan2(P[1], P[0]));
                h->ang = turn > 0 ? atan2(dr, dz) : atan2(dz, dr);
            }
        }
    for (int64_t i = 0; i < ne; i++)
        parent[i] = i;
    if (!sw_report(c, 0.84)) {
        free(he);
        free(parent);
        return 0;
    }
    qsort(he, (size_t)ne, sizeof *he, cmp_he);
    if (!sw_report(c, 0.88)) {
        free(he);
        free(parent);
        return 0;
    }
    int64_t *stack = NULL, capstack = 0;
    /* corners: 3t + k is the corner at otri[3t + k] */
    for (int64_t i = 0; i < ne;) {
        int64_t j = i;
        while (j < ne && he[j].lo == he[i].lo && he[j].hi == he[i].hi)
            j++;
        int64_t n = j - i;
        /* pair each triangle with the next one round the edge of the other direction
         * (going round in decreasing angle): where the directions alternate, each pair
         * bounds a consistently oriented wedge */
        if (n >= 2 && alternates(he + i, n)) {
            for (int64_t q = 0; q < n; q++)
                if (he[i + q].dir == 1)
                    join_across(c, &he[i + q], &he[i + (q + n - 1) % n], parent);
        } else if (n >= 2 && !pair_round_edge(c, he + i, n, parent, &stack, &capstack)) {
            free(he);
            free(parent);
            free(stack);
            return 0;
        }
        i = j;
    }
    if (!sw_report(c, 0.92)) {
        free(he);
        free(parent);
        free(stack);
        return 0;
    }
    /* one vertex per class of corners */
    hmap seen;
    if (!hmap_init(&seen, ne + 16)) {
        free(he);
        free(parent);
        return ctx_nomem(c);
    }
    int ok = 1;
    for (int64_t cr = 0; cr < ne && ok; cr++) {
        if ((cr & 63) == 0 && !sw_poll(c, 0.92 * ne + 0.08 * cr, ne)) {
            ok = 0;
            break;
        }
        int64_t root = mfg_uf_find(parent, cr);
        int64_t v = c->otri[cr];
        hkey k = mkkey(root, 0, 0, 0);
        int64_t nv = hmap_get(&seen, &k);
        if (nv < 0) {
            /* the first class of a vertex keeps it; later ones get a copy */
            hkey kv = mkkey(-1 - v, 0, 0, 0);
            if (hmap_get(&seen, &kv) < 0) {
                nv = v;
                ok = hmap_put(&seen, &kv, 1);
            } else {
                if (!mfg_grow((void **)&c->ox, &c->capout, c->nout + 1, 3 * sizeof *c->ox) ||
                    !mfg_grow((void **)&o->phi, &o->capphi, c->nout + 1, sizeof *o->phi)) {
                    ok = ctx_nomem(c);
                    break;
                }
                memcpy(c->ox + 3 * c->nout, c->ox + 3 * v, 3 * sizeof *c->ox);
                o->phi[c->nout] = o->phi[v];
                nv = c->nout++;
            }
            ok = ok && hmap_put(&seen, &k, nv);
        }
        c->otri[cr] = nv;
    }
    if (!ok)
        ctx_nomem(c); /* keeps a cancel's status: ctx_nomem sets only an empty one */
    hmap_free(&seen);
    free(he);
    free(parent);
    free(stack);
    return ok;
}
