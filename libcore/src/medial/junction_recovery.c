/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* junction_recovery.c - the junctions the leaf search missed (docs/design/medial.md
 * section 4.3, recovery), found where the chained seams end: pass 1 polishes the unions
 * of the sets of two free seam ends within reach of each other; pass 2 traces the ends
 * still free along their seams (md_seam_point) to a junction, another piece of the same
 * seam, or the point where the seam's elements stop touching. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "medial/assembly.h"

/* A seam end that no junction explains. */
typedef struct free_end {
    double x[3];
    int64_t seam;
    int32_t resolved;
} free_end;

static int cmp_free_end(const void *pa, const void *pb)
{
    const free_end *a = pa, *b = pb;
    int c = md_cmp_xyz(a->x, b->x);
    return c ? c : (a->seam > b->seam) - (a->seam < b->seam);
}

/* Sorted union of two sorted sets; its size, or -1 when it exceeds cap. */
static int set_union(const int64_t *a, int na, const int64_t *b, int nb, int64_t *u, int cap)
{
    int n = 0;
    for (int i = 0, j = 0; i < na || j < nb;) {
        int64_t v = j == nb || (i < na && a[i] <= b[j]) ? a[i] : b[j];
        i += i < na && a[i] == v;
        j += j < nb && b[j] == v;
        if (n == cap)
            return -1;
        u[n++] = v;
    }
    return n;
}

/* Junctions found by the assembly, before they are merged with the leaves' ones. */
typedef struct jlist {
    md_junction *v;
    int64_t n, cap;
} jlist;

static int jlist_push(jlist *l, const md_junction *j)
{
    if (!mfg_grow((void **)&l->v, &l->cap, l->n + 1, sizeof *l->v))
        return 0;
    l->v[l->n++] = *j;
    return 1;
}

/* Is there a junction within reach of p whose set holds s: in J (sorted by point) or in
 * the list (short: the junctions found so far by the assembly)? */
static int near_junction(const md_jset *J, const jlist *add, const double *p, const int64_t *s,
                         int64_t ns, double reach)
{
    if (md_snap_junction(J, p, s, ns, reach) >= 0)
        return 1;
    for (int64_t i = 0; i < add->n; i++)
        if (mfg_dist3(add->v[i].x, p) <= reach && md_subset_of(s, ns, add->v[i].elems, add->v[i].n))
            return 1;
    return 0;
}

/* Pass 1 of recover_junctions: the unions of the sets of two free seam ends within
 * reach of each other (and the set of a seam of >= 4 elements). */
static int junctions_from_unions(const md_asm *ax, const pend_list *pl, const md_jset *J,
                                 jlist *add)
{
    const md_elements *el = ax->el;
    const md_bvh *bvh = ax->bvh;
    double reach = ax->reach, tol = ax->tol;
    free_end *fe = malloc((size_t)(2 * pl->n + 1) * sizeof *fe);
    int64_t nfe = 0;
    if (!fe)
        return 0;
    for (int64_t i = 0; i < pl->n; i++) {
        const pend_seam *ps = &pl->v[i];
        int64_t np = ps->pl.rad.n;
        if (np < 1)
            continue;
        for (int end = 0; end < 2; end++) {
            const double *p = ps->pl.pts.v + (end ? 3 * (np - 1) : 0);
            if (md_snap_junction(J, p, ps->e, ps->ne, reach) >= 0)
                continue;
            memcpy(fe[nfe].x, p, sizeof fe[nfe].x);
            fe[nfe].seam = i;
            fe[nfe++].resolved = 0;
        }
    }
    if (nfe > 1)
        qsort(fe, (size_t)nfe, sizeof *fe, cmp_free_end);
    int ok = 1;
    for (int64_t i = 0; i < nfe && ok; i++)
        for (int64_t k = i; k < nfe && fe[k].x[0] <= fe[i].x[0] + reach && ok; k++) {
            if (fe[i].resolved && fe[k].resolved)
                continue;
            const pend_seam *a = &pl->v[fe[i].seam], *b = &pl->v[fe[k].seam];
            int64_t T[MD_JMAX];
            int nT;
            if (k == i) /* a seam of >= 4 elements ends at a junction of its own set */
                nT = a->ne >= 4 ? set_union(a->e, a->ne, a->e, a->ne, T, MD_JMAX) : 0;
            else if (mfg_dist3(fe[i].x, fe[k].x) > reach)
                continue;
            else
                nT = set_union(a->e, a->ne, b->e, b->ne, T, MD_JMAX);
            if (nT < 4)
                continue;
            double x0[3], lo[3];
            for (int c = 0; c < 3; c++) {
                x0[c] = 0.5 * (fe[i].x[c] + fe[k].x[c]);
                lo[c] = x0[c] - reach;
            }
            md_junction j;
            md_jbox box = {el, bvh, lo, 2 * reach, tol};
            int r = md_junction_polish(&box, x0, T, nT, &j);
            if (r < 0 || (r == 1 && j.rank == 3 && !jlist_push(add, &j))) {
                ok = 0;
                break;
            }
            if (r == 0 || j.rank != 3)
                continue;
            /* the free ends this junction explains */
            for (int64_t q = i; q < nfe && fe[q].x[0] <= j.x[0] + reach; q++) {
                const pend_seam *c = &pl->v[fe[q].seam];
                if (!fe[q].resolved && mfg_dist3(fe[q].x, j.x) <= reach &&
                    md_subset_of(c->e, c->ne, j.elems, j.n))
                    fe[q].resolved = 1;
            }
        }
    free(fe);
    return ok;
}

/* Pending seams ordered by element set (ties: index): the seams of one set are a run. */
typedef struct set_ord {
    const pend_list *pl;
    int64_t i;
} set_ord;

static int cmp_set_ord(const void *pa, const void *pb)
{
    const set_ord *a = pa, *b = pb;
    const pend_seam *x = &a->pl->v[a->i], *y = &b->pl->v[b->i];
    int c = md_cmp_set(x->e, x->ne, y->e, y->ne);
    return c ? c : (a->i > b->i) - (a->i < b->i);
}

/* Steps along a seam of at most this many (a gap of 2^8 half leaves stays open). */
#define TRACE_STEPS 256

/* The recovery's working state: the pending seams, their order by element set, the
 * junctions known (merged, sorted by point) and those found since. */
typedef struct rec_ctx {
    const md_asm *ax;
    pend_list *pl;
    const set_ord *ord;
    md_jset J;
    jlist add;
} rec_ctx;

/* Pass 2 of recover_junctions: seam i traced on from its last point (design 4.3,
 * tracing).  A seam narrower than a leaf (the 5 000-triangle cup's seams between two
 * wall facets and a floor corner vertex, in a wedge 2 pi / 625 wide) is sampled by the
 * leaves in pieces, and a piece's free end lies in the middle of its seam.  From there
 * the seam is followed on the curve itself: a step of h / 2 along the tangent, then
 * md_seam_point back onto the curve (exact up to rounding, like every sampled point).
 * The walk ends
 *   - near a junction whose set holds the seam's (emit_seam snaps to it);
 *   - near the free end of another piece of the same set (the pieces are joined, and the
 *     walk goes on from the joined piece's far end; alongside a piece whose near end has a
 *     junction it goes on to that junction, and drop_covered_pieces removes the piece);
 *   - where the seam's elements stop touching (another element is nearer, or one leaves
 *     its Voronoi region): the junction of the seam's set plus that element lies within the
 *     last step, md_junction_polish places it, it is added and becomes the end;
 *   - after TRACE_STEPS steps, or when the curve cannot be followed (left free).
 * Returns 0 on NOMEM. */
static int trace_seam(rec_ctx *rc, int64_t i, int64_t g0, int64_t g1)
{
    const md_elements *el = rc->ax->el;
    const md_bvh *bvh = rc->ax->bvh;
    double h = rc->ax->h, reach = rc->ax->reach, tol = rc->ax->tol;
    pend_list *pl = rc->pl;
    const set_ord *ord = rc->ord;
    const md_jset *J = &rc->J;
    jlist *add = &rc->add;
    pend_seam *ps = &pl->v[i];
    polyline *L = &ps->pl;
    const int64_t *S = ps->e;
    int ns = ps->ne;
    double step = 0.5 * h;
    for (int it = 0; it < TRACE_STEPS; it++) {
        int64_t n = L->rad.n;
        if (n < 2)
            return 1;
        double *x = L->pts.v + 3 * (n - 1), t[3];
        mfg_sub3(x, x - 3, t);
        double lt = mfg_norm3(t);
        if (!(lt > 0))
            return 1;
        for (int k = 0; k < 3; k++)
            t[k] /= lt;
        double y0[3], y[3], dir[3];
        for (int k = 0; k < 3; k++)
            y0[k] = x[k] + step * t[k];
        int on = md_seam_point(el, S, ns, y0, y, dir);
        double adv[3];
        mfg_sub3(y, x, adv);
        if (!on || !(mfg_dot3(adv, t) > 0.1 * step)) {
            if (step < h / 64)
                return 1;
            step *= 0.5;
            continue;
        }
        int64_t W[MD_JMAX];
        double D;
        int nw = md_touching_set(el, bvh, y, W, MD_JMAX, &D);
        if (nw < 0)
            return 0;
        if (nw <= MD_JMAX && md_subset_of(S, ns, W, nw)) {
            /* still on the seam */
            if (!polyline_push(L, y, D))
                return 0;
            x = L->pts.v + 3 * n; /* the buffer may have moved */
            step = 0.5 * h;
            if (near_junction(J, add, y, S, ns, reach))
                return 1;
            /* another piece of this seam within reach */
            for (int64_t g = g0; g < g1; g++) {
                int64_t q = ord[g].i;
                pend_seam *o = &pl->v[q];
                int64_t m = o->pl.rad.n;
                if (q == i || m < 1)
                    continue;
                const double *p0 = o->pl.pts.v, *p1 = o->pl.pts.v + 3 * (m - 1);
                double d0 = mfg_dist3(p0, y), d1 = mfg_dist3(p1, y);
                int e = d0 <= d1 ? 0 : 1;
                if (fmin(d0, d1) <= reach && !near_junction(J, add, e ? p1 : p0, S, ns, reach)) {
                    /* join: o's near end first */
                    if (e)
                        md_polyline_reverse(&o->pl);
                    for (int64_t k = 0; k < m; k++)
                        if (!polyline_push(L, o->pl.pts.v + 3 * k, o->pl.rad.v[k]))
                            return 0;
                    free(o->pl.pts.v);
                    free(o->pl.rad.v);
                    memset(&o->pl, 0, sizeof o->pl);
                    if (near_junction(J, add, L->pts.v + 3 * (L->rad.n - 1), S, ns, reach))
                        return 1;
                    break; /* go on from the far end */
                }
            }
            continue;
        }
        /* The seam's set stops touching between x and y: the junction of S and one more
         * element (nearer at y, or a sub-element whose region y entered) lies there. */
        int64_t cand[MD_JMAX + 8];
        int nc = 0;
        for (int k = 0; k < nw && k < MD_JMAX; k++)
            if (!md_subset_of(&W[k], 1, S, ns))
                cand[nc++] = W[k];
        for (int k = 0; k < ns && nc < MD_JMAX + 8; k++) {
            int64_t which = -1;
            if (md_region_margin(el, S[k], y, &which) < 0 && which >= 0)
                cand[nc++] = which;
        }
        double mid[3], lo[3];
        for (int k = 0; k < 3; k++) {
            mid[k] = 0.5 * (x[k] + y[k]);
            lo[k] = mid[k] - step;
        }
        for (int c = 0; c < nc; c++) {
            int64_t T[MD_JMAX];
            int nT = set_union(S, ns, &cand[c], 1, T, MD_JMAX);
            if (nT < 4)
                continue;
            md_junction j;
            md_jbox box = {el, bvh, lo, 2 * step, tol};
            int r = md_junction_polish(&box, mid, T, nT, &j);
            if (r < 0)
                return 0;
            if (r == 1 && j.rank == 3 && md_subset_of(S, ns, j.elems, j.n)) {
                if (!jlist_push(add, &j) || !polyline_push(L, j.x, j.r))
                    return 0;
                return 1;
            }
        }
        if (step < h / 64)
            return 1;
        step *= 0.5;
    }
    return 1;
}

/* After tracing, a piece of a seam that lies within reach of another piece of the same
 * set along its whole length says nothing the other does not (a fragment the walk went
 * past on its way to the junction): it is removed, the shortest first. */
static void drop_covered_pieces(pend_list *pl, const set_ord *ord, int64_t g0, int64_t g1,
                                double reach)
{
    for (;;) {
        int64_t best = -1, bn = INT64_MAX;
        for (int64_t g = g0; g < g1; g++) {
            pend_seam *q = &pl->v[ord[g].i];
            int64_t n = q->pl.rad.n;
            if (n < 1 || n >= bn)
                continue;
            for (int64_t h = g0; h < g1; h++) {
                const pend_seam *o = &pl->v[ord[h].i];
                if (h == g || o->pl.rad.n < 2 || o->pl.rad.n < n)
                    continue;
                int64_t k = 0;
                while (k < n && md_polyline_dist(o->pl.pts.v, o->pl.rad.n, q->pl.pts.v + 3 * k) <= reach)
                    k++;
                if (k == n) {
                    best = g;
                    bn = n;
                    break;
                }
            }
        }
        if (best < 0)
            return;
        pend_seam *q = &pl->v[ord[best].i];
        free(q->pl.pts.v);
        free(q->pl.rad.v);
        memset(&q->pl, 0, sizeof q->pl);
    }
}

/* The junctions found (add, emptied) merged into *J (*nj); *own: *J is this stage's. */
static int merge_added(const md_asm *ax, md_junction **J, int64_t *nj, int *own, jlist *add)
{
    if (add->n == 0)
        return 1;
    md_junction *all = malloc((size_t)(*nj + add->n) * sizeof *all);
    if (!all)
        return 0;
    if (*nj)
        memcpy(all, *J, (size_t)*nj * sizeof *all);
    memcpy(all + *nj, add->v, (size_t)add->n * sizeof *all);
    int64_t n = md_merge_junctions(ax, all, *nj + add->n);
    if (*own)
        free(*J);
    *J = all;
    *nj = n;
    *own = 1;
    add->n = 0;
    return 1;
}

/* The junctions the leaf search missed, found where seams end (design 4.3, recovery).
 * The leaf search tries subsets of the elements near a leaf; on a wall tessellated finer
 * than the tolerance (the 5 000-triangle cup: facets 0.2 wide at tolerance 0.32) dozens
 * of near-parallel facets are near every leaf, its MAX_SUBSETS run out before the right
 * four are tried, and the seams meeting there end free.  But each seam names its
 * elements, and seams that meet at a junction name the junction's set between them: two
 * seams {a, b, c} and {a, b, d} ending within reach of each other span {a, b, c, d}.
 * Gauss-Newton from the midpoint of their ends (md_junction_polish) places the point and
 * accepts it only where every element of the union touches and >= 4 do, at rank 3.  A
 * junction found resolves every free end within reach whose set it holds, so each
 * meeting point is polished about once.  Then the ends still free are traced along their
 * seams (trace_seam).  *J (nj, merged and sorted by point) is replaced by a new array with
 * the found junctions merged in (md_merge_junctions; the caller frees it when it differs
 * from its own, also after a failure); the pending seams may be extended and joined.
 * 1, or 0 on NOMEM. */
int md_recover_junctions(const md_asm *ax, pend_list *pl, md_junction **J, int64_t *nj)
{
    rec_ctx rc;
    memset(&rc, 0, sizeof rc);
    rc.ax = ax;
    rc.pl = pl;
    int own = 0;
    double reach = ax->reach;
    set_ord *ord = malloc((size_t)(pl->n + 1) * sizeof *ord);
    rc.ord = ord;
    /* the unions' junctions are merged in (sorted by point) before tracing: the walks
     * look them up by their x-slab, and the list they scan holds only their own finds */
    md_jset J0 = {*J, *nj};
    int ok = ord && junctions_from_unions(ax, pl, &J0, &rc.add) &&
             merge_added(ax, J, nj, &own, &rc.add);
    rc.J = (md_jset){*J, *nj};
    if (ok) {
        for (int64_t i = 0; i < pl->n; i++)
            ord[i] = (set_ord){pl, i};
        if (pl->n > 1)
            qsort(ord, (size_t)pl->n, sizeof *ord, cmp_set_ord);
    }
    for (int64_t g = 0; g < pl->n && ok;) {
        int64_t g1 = g + 1;
        while (g1 < pl->n && !md_cmp_set(pl->v[ord[g1].i].e, pl->v[ord[g1].i].ne, pl->v[ord[g].i].e,
                                      pl->v[ord[g].i].ne))
            g1++;
        for (int64_t k = g; k < g1 && ok; k++) {
            pend_seam *ps = &pl->v[ord[k].i];
            if (ps->kind == MFG_MEDIAL_DEGENERATE || ps->ne < 3)
                continue;
            for (int end = 0; end < 2 && ok; end++) {
                int64_t n = ps->pl.rad.n;
                if (n < 2)
                    break;
                /* the end to trace becomes the last point: the first, then the other */
                md_polyline_reverse(&ps->pl);
                const double *p = ps->pl.pts.v + 3 * (n - 1);
                if (!near_junction(&rc.J, &rc.add, p, ps->e, ps->ne, reach))
                    ok = trace_seam(&rc, ord[k].i, g, g1);
            }
        }
        if (ok)
            drop_covered_pieces(pl, ord, g, g1, reach);
        g = g1;
    }
    free(ord);
    ok = ok && merge_added(ax, J, nj, &own, &rc.add);
    free(rc.add.v);
    return ok;
}
