/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* maxisect_search.c - branch and bound over cells of the sphere: a cell (a cube face,
 * quartered again and again) knows the weight of the sets containing it and the sets
 * meeting it partly; cells whose bound cannot reach the limit are dropped, small ones
 * are swept exactly (maxisect_sweep.c). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sphere/maxisect.h"

/* A minimum's sample on a set's edge is pushed this far (radians) to the edge's outer
 * side: well beyond the coverage tolerance, so the set does not cover it, and far below
 * the size of any face worth reporting. */
#define FACE_SAMPLE_OFFSET 1e-7


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
    int stall;          /* levels in a row whose split changed nothing (STALL_LEVELS) */
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
    c->q.cr += CAP_WIDEN;
    c->q.cos_cr = cos(c->q.cr);
    c->q.sin_cr = sin(c->q.cr);
}

/* Slack (radians, 10 TOL) of the test whether a thin set's piece reaches a cell: a
 * direction of the cell (or of an arc clipped to it by mfg_polygon_interval, within TOL
 * of it) is within TOL of the piece only if the piece comes within 2 TOL of the cell, so
 * a piece farther than this holds no direction the cell's sweep looks at. */
#define THIN_CELL_SLACK (10 * TOL)

/* Does piece k of thin set S (an arc a -> b, or a point) come within THIN_CELL_SLACK of
 * cell c?  x(s) = a + s (b - a), s in [0, 1], covers the arc; a direction x(s)/|x(s)|
 * at angle delta or less outside edge j of the cell has x(s).n_j >= -delta |x(s)|
 * >= -delta (|x(s)| <= 1), so asking x(s).n_j >= -slack of all four edges for one s,
 * a linear program in s, keeps every piece that may matter (and perhaps a few more). */
static int thin_piece_meets(const sset *S, int64_t k, const cell *c)
{
    const double *a = S->v + 3 * k;
    const double *b = S->kind == MFG_VM_POINT ? a : S->v + 3 * ((k + 1) % S->nv);
    double lo = 0.0, hi = 1.0;
    for (int j = 0; j < 4; j++) {
        const double *n = c->q.n + 3 * j;
        double fa = mfg_dot3(a, n) + THIN_CELL_SLACK, fb = mfg_dot3(b, n) + THIN_CELL_SLACK;
        if (fa >= 0.0 && fb >= 0.0)
            continue;
        if (fa < 0.0 && fb < 0.0)
            return 0;
        double s = fa / (fa - fb); /* fa - fb != 0: the signs differ */
        if (fa < 0.0)
            lo = fmax(lo, s);
        else
            hi = fmin(hi, s);
        if (lo > hi)
            return 0;
    }
    return 1;
}

/* 0: the set misses the cell, 1: meets it partly, 2: contains it (with the tolerance).
 * Only the pieces ein[0..nin) of S can still decide; the ones that stay undecided for
 * this cell are written to eout (for POLYGON sets; thin sets keep all of theirs). */
static int classify_cell(const sset *S, const cell *c, const int32_t *ein, int64_t nin,
                         int32_t *eout, int64_t *nout)
{
    const double *q = c->q.v;
    *nout = 0;
    if (mfg_caps_apart(c->q.cc, c->q.cr, c->q.cos_cr, c->q.sin_cr, S))
        return 0;
    if (S->kind != MFG_VM_POLYGON) {
        /* A thin set meets the cell only along its pieces: keep those that reach it.
         * Its cap alone cannot decide: a half circle's cap is a hemisphere and an
         * antipodal pair of points has none, so they would be partial in every cell. */
        int64_t m = 0;
        for (int64_t t = 0; t < nin; t++)
            if (thin_piece_meets(S, ein[t], c))
                eout[m++] = ein[t];
        *nout = m;
        return m ? 1 : 0;
    }
    if (S->ir > c->q.cr &&
        mfg_dot3(c->q.cc, S->ic) >= S->cos_ir * c->q.cos_cr + S->sin_ir * c->q.sin_cr + CAP_SLACK_COS)
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
    /* Same partial sets and pieces as the parent: splitting decided nothing here. */
    c->stall = p->depth >= 0 && c->npart == p->npart && c->eoff[c->npart] == p->eoff[p->npart]
                   ? p->stall + 1 : 0;
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
    sweep_goal goal = {threshold, keep_best, eps};
    for (int k = 0; k < 4 && st == MFG_OK; k++) {
        arc_span side = {c->q.v + 3 * k, c->q.v + 3 * ((k + 1) % 4), 0.0, 1.0};
        st = mfg_sweep_edge(W, -1, &side, c->full, c->part, c->npart, &goal);
    }
    for (int64_t t = 0; t < c->npart && st == MFG_OK; t++) {
        int64_t j = c->part[t];
        const sset *S = &W->sets[j];
        for (int64_t u = c->eoff[t]; u < c->eoff[t + 1] && st == MFG_OK; u++) {
            const double *a, *b;
            piece(S, c->eidx[u], &a, &b);
            double r0 = 0.0, r1 = 1.0;
            if (!mfg_polygon_interval(&c->q, a, b, &r0, &r1))
                continue;
            arc_span span = {a, b, r0, r1};
            st = mfg_sweep_edge(W, j, &span, c->full + S->w, c->part, c->npart, &goal);
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
    return wt <= W->best + eps ? mfg_add_candidate(W, wt, x, 0) : MFG_OK;
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
        if (own >= 0 && !mfg_polygon_interval(&c->q, a, b, &r0, &r1))
            continue;
        int64_t niv = mfg_edge_intervals(W, own, a, b, c->part, c->npart), ne = 0;
        for (int64_t i = 0; i < niv; i++) {
            if (W->iv[i].hi < r0 || W->iv[i].lo > r1)
                continue;
            W->ev[ne++] = (event){fmax(W->iv[i].lo, r0), 1, W->iv[i].set};
            W->ev[ne++] = (event){fmin(W->iv[i].hi, r1), 0, W->iv[i].set};
        }
        qsort(W->ev, (size_t)ne, sizeof(event), mfg_cmp_event);
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
                        x[d] = xu[d] - FACE_SAMPLE_OFFSET * n[d];
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

/* A cell meeting at most LEAF_SETS sets partly is swept exactly; cells are not split
 * beyond MAX_DEPTH (a cube face quartered 16 times: cells of ~2e-5 rad), nor once
 * STALL_LEVELS splits in a row left a cell with exactly its parent's partial sets and
 * pieces.  That happens where the sets' boundaries coincide: many maps sharing a
 * boundary circle (a surface's VM and -VM, faces with a common normal) or a vertex.
 * Splitting cannot separate them, the bound stays the same, and every cell along a
 * shared circle would be split down to MAX_DEPTH (2^16 cells per quarter circle);
 * the sweep is exact in a cell of any size and costs the same in the big one. */
#define LEAF_SETS 16
#define MAX_DEPTH 16
#define STALL_LEVELS 3

mfg_status mfg_cell_search(work *W, int mode, double threshold, double eps)
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
        /* no total is known: the fraction is the share of cells taken so far among those
         * taken and queued (it is kept from going back) */
        if (!mfg_prog_poll(W->prog, (double)W->ncells, (double)(W->ncells + h.n))) {
            st = mfg_prog_fail(W->prog);
            break;
        }
        cell *c = heap_pop(&h);
        W->ncells++;
        double lim = keep_best ? W->best : threshold;
        if (mode == MODE_MIN ? c->full > W->best + eps : c->ub < lim - eps) {
            cell_free(c); /* nothing left can reach the limit */
            break;
        }
        if (mode != MODE_LEVEL) { /* the cell's centre: a bound that sharpens pruning */
            double d = c->full;
            for (int64_t t = 0; t < c->npart; t++)
                if (mfg_set_contains(&W->sets[c->part[t]], c->q.cc))
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
        if (c->npart <= LEAF_SETS || c->depth >= MAX_DEPTH || c->stall >= STALL_LEVELS) {
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
