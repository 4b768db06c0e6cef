/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* axis2d/assemble.c - the result: short junction-junction branches contracted, canonical
 * order.  Overview and file map: axis2d/axis2d.h. */
#include "axis2d/axis2d.h"

/* ---- the result: short junction-junction branches contracted, canonical order -------- */

typedef struct { double x, y, r; int64_t id; } ma_jkey;

static int cmp_jkey(const void *pa, const void *pb)
{
    const ma_jkey *a = pa, *b = pb;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    if (a->y != b->y)
        return a->y < b->y ? -1 : 1;
    if (a->r != b->r)
        return a->r < b->r ? -1 : 1;
    return (a->id > b->id) - (a->id < b->id);
}

typedef struct { int64_t a, c; double ex, ey, mx, my; int64_t b; int flip; } ma_bkey;

static int cmp_bkey(const void *pa, const void *pb)
{
    const ma_bkey *a = pa, *b = pb;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    if (a->c != b->c)
        return a->c < b->c ? -1 : 1;
    double ka[4] = {a->ex, a->ey, a->mx, a->my}, kb[4] = {b->ex, b->ey, b->mx, b->my};
    for (int i = 0; i < 4; i++)
        if (ka[i] != kb[i])
            return ka[i] < kb[i] ? -1 : 1;
    return (a->b > b->b) - (a->b < b->b);
}

typedef struct { double len; int64_t b; } ma_lkey;

static int cmp_lkey(const void *pa, const void *pb)
{
    const ma_lkey *a = pa, *b = pb;
    if (a->len != b->len)
        return a->len < b->len ? -1 : 1;
    return (a->b > b->b) - (a->b < b->b);
}

/* The flat result.  Junctions joined by a branch shorter than tol are one junction when
 * the group so joined spans less than tol (contracted in order of length, so a branch
 * closing a cycle is kept: the cycle around a tiny hole stays): the representative is the member touching the most elements (then the
 * lowest (x, y)), the elements the union, the degree the branch ends at it; the ends of the other
 * branches are moved onto it (by < tol, radius its own).  Canonical order: junctions by
 * (x, y, r); a branch runs from its lower junction (a leaf end last), self-loops from the
 * side with the lower second sample, and branches are sorted by (start junction, end
 * junction -- leaves after all junctions --, far end point, middle sample). */
mfg_status ma_assemble(const ma_ctx *C, struct mfg_medial_axis **out)
{
    const ma_elems *E = &C->E;
    int64_t nb = C->boff.n, ns = C->px.n, nj = C->nj;
    mfg_status st = MFG_OK;
    size_t zb = (size_t)(nb + 1), zj = (size_t)(nj + 1);
    int64_t *par = malloc(zj * sizeof *par), *rep = malloc(zj * sizeof *rep);
    int64_t *newid = malloc(zj * sizeof *newid), *deg = calloc(zj, sizeof *deg);
    int64_t *mhead = malloc(zj * sizeof *mhead), *mnext = malloc(zj * sizeof *mnext);
    int8_t *gone = calloc(zb, 1);
    ma_lkey *lk = malloc(zb * sizeof *lk);
    ma_jkey *jk = malloc(zj * sizeof *jk);
    ma_bkey *bk = malloc(zb * sizeof *bk);
    int64_t *eids = malloc((size_t)(C->jelem.n + 1) * sizeof *eids);
    double *gx0 = malloc(zj * sizeof *gx0), *gx1 = malloc(zj * sizeof *gx1);
    double *gy0 = malloc(zj * sizeof *gy0), *gy1 = malloc(zj * sizeof *gy1);
    int8_t *wide = malloc(zj);
    struct mfg_medial_axis *A = calloc(1, sizeof *A);
    if (!par || !rep || !newid || !deg || !mhead || !mnext || !gone || !lk || !jk || !bk ||
        !eids || !gx0 || !gx1 || !gy0 || !gy1 || !wide || !A) {
        st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (result)");
        goto fail;
    }
    /* contract the short junction-junction branches */
    int64_t nl = 0;
    for (int64_t j = 0; j < nj; j++)
        par[j] = j;
    for (int64_t b = 0; b < nb; b++) {
        int64_t lo = C->boff.v[b], hi = b + 1 < nb ? C->boff.v[b + 1] : ns;
        int64_t j0 = C->bend.v[2 * b], j1 = C->bend.v[2 * b + 1];
        if (j0 < 0 || j1 < 0 || j0 == j1)
            continue;
        double len = 0;
        for (int64_t i = lo; i + 1 < hi && len < C->tol; i++)
            len += hypot(C->px.v[i + 1] - C->px.v[i], C->py.v[i + 1] - C->py.v[i]);
        if (len < C->tol)
            lk[nl].len = len, lk[nl].b = b, nl++;
    }
    qsort(lk, (size_t)nl, sizeof *lk, cmp_lkey);
    /* A group of junctions joined by short branches is contracted only when it spans less
     * than tol (its box's diagonal): every end then moves by < tol.  A chain of short
     * branches can run far - around the hole of an annulus at a tolerance above the
     * junctions' spacing it was the whole loop, contracted to one junction, and the leaf
     * branches started 15 away from their corner (issue 22). */
    for (int64_t i = 0; i < nl; i++)
        mfg_uf_union(par, C->bend.v[2 * lk[i].b], C->bend.v[2 * lk[i].b + 1]);
    for (int64_t j = 0; j < nj; j++) {
        gx0[j] = gx1[j] = C->J[j].x;
        gy0[j] = gy1[j] = C->J[j].y;
    }
    for (int64_t j = 0; j < nj; j++) {
        int64_t r = mfg_uf_find(par, j);
        gx0[r] = fmin(gx0[r], C->J[j].x), gx1[r] = fmax(gx1[r], C->J[j].x);
        gy0[r] = fmin(gy0[r], C->J[j].y), gy1[r] = fmax(gy1[r], C->J[j].y);
    }
    for (int64_t j = 0; j < nj; j++) {
        int64_t r = mfg_uf_find(par, j);
        wide[j] = !(hypot(gx1[r] - gx0[r], gy1[r] - gy0[r]) < C->tol);
    }
    for (int64_t j = 0; j < nj; j++)
        par[j] = j;
    for (int64_t i = 0; i < nl; i++) {
        int64_t b = lk[i].b;
        if (wide[C->bend.v[2 * b]])
            continue;
        int64_t r0 = mfg_uf_find(par, C->bend.v[2 * b]), r1 = mfg_uf_find(par, C->bend.v[2 * b + 1]);
        if (r0 == r1)
            continue;
        par[r0 > r1 ? r0 : r1] = r0 > r1 ? r1 : r0;
        gone[b] = 1;
    }
    /* representatives and canonical junction order */
    for (int64_t j = 0; j < nj; j++)
        rep[j] = mhead[j] = -1;
    for (int64_t j = nj - 1; j >= 0; j--) { /* most elements, then lowest (x, y): not the
                                               tracing order, which follows the input's */
        int64_t r = mfg_uf_find(par, j), k = rep[r];
        const ma_junction *A = &C->J[j], *B = k >= 0 ? &C->J[k] : NULL;
        if (!B || A->nelem > B->nelem ||
            (A->nelem == B->nelem && (A->x < B->x || (A->x == B->x && A->y < B->y))))
            rep[r] = j;
        mnext[j] = mhead[r], mhead[r] = j;
    }
    int64_t nk = 0;
    for (int64_t j = 0; j < nj; j++)
        if (par[j] == j) {
            const ma_junction *J = &C->J[rep[j]];
            jk[nk].x = J->x, jk[nk].y = J->y, jk[nk].r = J->r, jk[nk].id = j, nk++;
        }
    qsort(jk, (size_t)nk, sizeof *jk, cmp_jkey);
    for (int64_t k = 0; k < nk; k++)
        newid[jk[k].id] = k;
    /* branches: ends mapped, orientation, order */
    int64_t nbo = 0, nso = 0;
    for (int64_t b = 0; b < nb; b++) {
        if (gone[b])
            continue;
        int64_t lo = C->boff.v[b], hi = b + 1 < nb ? C->boff.v[b + 1] : ns;
        int64_t j0 = C->bend.v[2 * b], j1 = C->bend.v[2 * b + 1];
        int64_t a = j0 >= 0 ? newid[mfg_uf_find(par, j0)] : INT64_MAX;
        int64_t c = j1 >= 0 ? newid[mfg_uf_find(par, j1)] : INT64_MAX;
        int flip = c < a;
        if (a == c && hi - lo >= 3) { /* a self-loop, or both ends leaves */
            int64_t p = a == INT64_MAX ? lo : lo + 1, q = a == INT64_MAX ? hi - 1 : hi - 2;
            flip = C->px.v[q] < C->px.v[p] || (C->px.v[q] == C->px.v[p] && C->py.v[q] < C->py.v[p]);
        }
        ma_bkey *K = &bk[nbo++];
        K->a = flip ? c : a, K->c = flip ? a : c, K->b = b, K->flip = flip;
        int64_t far = flip ? lo : hi - 1, mid = lo + (hi - lo) / 2;
        K->ex = C->px.v[far], K->ey = C->py.v[far], K->mx = C->px.v[mid], K->my = C->py.v[mid];
        if (K->a != INT64_MAX)
            deg[K->a]++;
        if (K->c != INT64_MAX)
            deg[K->c]++;
        nso += hi - lo;
    }
    qsort(bk, (size_t)nbo, sizeof *bk, cmp_bkey);
    /* the flat arrays */
    A->nbranches = nbo, A->npoints = nso, A->njunctions = nk;
    A->branch_offsets = malloc((size_t)(nbo + 1) * sizeof(int64_t));
    A->points = malloc((size_t)(2 * nso + 1) * sizeof(double));
    A->radii = malloc((size_t)(nso + 1) * sizeof(double));
    A->branch_ends = malloc((size_t)(2 * nbo + 1) * sizeof(int64_t));
    A->junction_points = malloc((size_t)(2 * nk + 1) * sizeof(double));
    A->junction_radii = malloc((size_t)(nk + 1) * sizeof(double));
    A->junction_degree = malloc((size_t)(nk + 1) * sizeof(int64_t));
    A->junction_offsets = malloc((size_t)(nk + 1) * sizeof(int64_t));
    A->junction_elements = malloc((size_t)(C->jelem.n + 1) * sizeof(int64_t));
    if (!A->branch_offsets || !A->points || !A->radii || !A->branch_ends ||
        !A->junction_points || !A->junction_radii || !A->junction_degree ||
        !A->junction_offsets || !A->junction_elements) {
        st = mfg_fail(MFG_ERR_NOMEM, "medial axis: out of memory (result)");
        goto fail;
    }
    int64_t o = 0;
    for (int64_t k = 0; k < nbo; k++) {
        const ma_bkey *K = &bk[k];
        int64_t lo = C->boff.v[K->b], hi = K->b + 1 < nb ? C->boff.v[K->b + 1] : ns;
        A->branch_offsets[k] = o;
        A->branch_ends[2 * k] = K->a == INT64_MAX ? -1 : K->a;
        A->branch_ends[2 * k + 1] = K->c == INT64_MAX ? -1 : K->c;
        for (int64_t i = 0; i < hi - lo; i++, o++) {
            int64_t s = K->flip ? hi - 1 - i : lo + i;
            A->points[2 * o] = C->px.v[s], A->points[2 * o + 1] = C->py.v[s];
            A->radii[o] = C->pr.v[s];
        }
        for (int e = 0; e < 2; e++) { /* ends onto their (representative) junction */
            int64_t j = A->branch_ends[2 * k + e], s = e ? o - 1 : A->branch_offsets[k];
            if (j < 0)
                continue;
            const ma_junction *J = &C->J[rep[jk[j].id]];
            A->points[2 * s] = J->x, A->points[2 * s + 1] = J->y, A->radii[s] = J->r;
        }
    }
    A->branch_offsets[nbo] = o;
    int64_t oe = 0;
    for (int64_t k = 0; k < nk; k++) {
        const ma_junction *J = &C->J[rep[jk[k].id]];
        A->junction_points[2 * k] = J->x, A->junction_points[2 * k + 1] = J->y;
        A->junction_radii[k] = J->r;
        A->junction_degree[k] = deg[k];
        A->junction_offsets[k] = oe;
        int64_t ne = 0;
        for (int64_t j = mhead[jk[k].id]; j >= 0; j = mnext[j]) { /* the members */
            for (int64_t i = 0; i < C->J[j].nelem; i++) {
                int64_t e = C->jelem.v[C->J[j].first_elem + i];
                eids[ne++] = is_seg(E, e) ? E->orig[e] : -1 - E->orig[E->vk[e - E->ns]];
            }
        }
        qsort(eids, (size_t)ne, sizeof *eids, mfg_cmp_i64);
        for (int64_t i = 0; i < ne; i++)
            if (i == 0 || eids[i] != eids[i - 1])
                A->junction_elements[oe++] = eids[i];
    }
    A->junction_offsets[nk] = oe;
    *out = A;
    A = NULL;
fail:
    mfg_medial_axis_free(A);
    free(par), free(rep), free(newid), free(deg), free(mhead), free(mnext), free(gone);
    free(lk), free(jk), free(bk);
    free(eids), free(gx0), free(gx1), free(gy0), free(gy1), free(wide);
    return st;
}
