/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* arrange/pairs.c - Where two triangles meet.  Triangles of one plane that touch form a
 * cluster (their overlaps are resolved in the cluster's own 2-D arrangement); two
 * triangles of different planes meet in a segment or a point of the line where their
 * planes cross, found exactly: orient3d signs of the corners, end points where edges
 * cross the other plane (LPI points, keyed by the edge and the other cluster so that every
 * triangle of that edge gets the same point), and their order along the line. */
#include "arrange/arrange.h"

/* ---- Records ------------------------------------------------------------------------ */

static int add_seg(arr_ctx *c, int64_t cl, int64_t p, int64_t q, int64_t support)
{
    if (c->nseg >= c->capseg) {
        int64_t cap = mfg_grown_cap(c->capseg, c->nseg + 1, 16);
        arr_seg *ns = realloc(c->seg, (size_t)cap * sizeof *ns);
        if (!ns)
            return 0;
        c->seg = ns;
        int64_t *nc = realloc(c->segcl, (size_t)cap * sizeof *nc);
        if (!nc)
            return 0;
        c->segcl = nc;
        c->capseg = cap;
    }
    arr_seg *s = &c->seg[c->nseg];
    s->p = p;
    s->q = q;
    s->support = support;
    s->ea = s->eb = -1;
    s->delta = 0;
    c->segcl[c->nseg++] = cl;
    return 1;
}

int arr_add_point_record(arr_ctx *c, int64_t cl, int64_t p)
{
    if (c->npt >= c->cappt) {
        int64_t cap = mfg_grown_cap(c->cappt, c->npt + 1, 16);
        int64_t *np = realloc(c->pt, (size_t)cap * sizeof *np);
        if (!np)
            return 0;
        c->pt = np;
        int64_t *nc = realloc(c->ptcl, (size_t)cap * sizeof *nc);
        if (!nc)
            return 0;
        c->ptcl = nc;
        c->cappt = cap;
    }
    c->pt[c->npt] = p;
    c->ptcl[c->npt++] = cl;
    return 1;
}

/* ---- Stage 1: coplanar clusters, candidate pairs ------------------------------------ */

typedef struct cand {
    int64_t i, j;
} cand;

typedef struct pass1 {
    arr_ctx *c;
    int64_t *uf;     /* union-find over triangles: coplanar and touching */
    cand *keep;      /* pairs of different planes that may meet */
    int64_t nkeep, capkeep;
    int64_t polls;
    int nomem;
} pass1;

static const double *X(const arr_ctx *c, int64_t v)
{
    return c->T.xyz + 3 * v;
}

/* 1 when point id p is one of the triangle's corners (explicit vertex ids are point ids). */
static int is_corner(const int64_t *A, int64_t p)
{
    return p == A[0] || p == A[1] || p == A[2];
}

/* orient3d of vertex id v against triangle A: 0 at once when v is one of A's corners
 * (the exact stage of a zero is the slow one). */
static int side_of_plane(const arr_ctx *c, const int64_t *A, int64_t v)
{
    if (v == A[0] || v == A[1] || v == A[2])
        return 0;
    const double *a = X(c, A[0]), *b = X(c, A[1]), *d = X(c, A[2]), *x = X(c, v);
    /* a plane x_k = const (a cap perpendicular to a coordinate axis, a box's face) holds
     * v exactly when v's x_k is that constant: the zero without the exact stage, which
     * the thousands of coplanar pairs of a revolved cap would otherwise all reach */
    for (int k = 0; k < 3; k++)
        if (a[k] == b[k] && a[k] == d[k] && x[k] == a[k])
            return 0;
    return mfg_orient3d(a, b, d, x);
}

/* 1 when the signs (one per corner) are all > 0 or all < 0, ignoring the corners of a
 * common vertex (shared[k]): then the triangle meets the plane at most at that vertex. */
static int one_side(const int *s, const int *shared)
{
    int pos = 0, neg = 0, zero = 0;
    for (int k = 0; k < 3; k++) {
        if (shared[k])
            continue;
        pos += s[k] > 0;
        neg += s[k] < 0;
        zero += s[k] == 0;
    }
    return zero == 0 && (pos == 0 || neg == 0) && pos + neg > 0;
}

static int pass1_pair(void *user, int64_t i, int64_t j)
{
    pass1 *P = user;
    arr_ctx *c = P->c;
    if ((++P->polls & 1023) == 0 && !mfg_prog_poll(c->prog, 0, 1))
        return 0;
    if (c->tcluster[i] < 0 || c->tcluster[j] < 0)
        return 1;
    const int64_t *A = c->tri + 3 * i, *B = c->tri + 3 * j;
    int ashared[3], bshared[3], nshared = 0;
    for (int k = 0; k < 3; k++) {
        bshared[k] = B[k] == A[0] || B[k] == A[1] || B[k] == A[2];
        ashared[k] = A[k] == B[0] || A[k] == B[1] || A[k] == B[2];
        nshared += bshared[k];
    }
    if (nshared == 3) { /* the same corners: one plane (they add up or cancel) */
        mfg_uf_union(P->uf, i, j);
        return 1;
    }
    if (nshared == 2) {
        /* a common edge: one plane (a cluster) or they meet in that edge only */
        for (int k = 0; k < 3; k++)
            if (!bshared[k] && side_of_plane(c, A, B[k]) == 0)
                mfg_uf_union(P->uf, i, j);
        return 1;
    }
    int sb[3], sa[3];
    for (int k = 0; k < 3; k++)
        sb[k] = side_of_plane(c, A, B[k]);
    if (sb[0] == 0 && sb[1] == 0 && sb[2] == 0) {
        /* one plane: touching or overlapping is resolved in the cluster's arrangement
         * (boxes that overlap are enough: a cluster may hold pieces that do not touch) */
        mfg_uf_union(P->uf, i, j);
        return 1;
    }
    /* B's other corners strictly on one side of A's plane: they meet at most at the
     * common vertex (or not at all), which both have already */
    if (one_side(sb, bshared))
        return 1;
    for (int k = 0; k < 3; k++)
        sa[k] = side_of_plane(c, B, A[k]);
    if (one_side(sa, ashared))
        return 1;
    if (P->nkeep >= P->capkeep) {
        int64_t cap = mfg_grown_cap(P->capkeep, P->nkeep + 1, 16);
        cand *nk = realloc(P->keep, (size_t)cap * sizeof *nk);
        if (!nk) {
            P->nomem = 1;
            return 0;
        }
        P->keep = nk;
        P->capkeep = cap;
    }
    P->keep[P->nkeep].i = i;
    P->keep[P->nkeep].j = j;
    P->nkeep++;
    return 1;
}

/* ---- Stage 2: the meeting of two triangles of different planes ----------------------- */

/* The points of triangle t on the plane of cluster `other` (signs s of t's corners
 * against that plane): one or two point ids into out; returns how many (0: none). */
static int on_plane(arr_ctx *c, int64_t t, const int *s, int64_t other, int64_t *out)
{
    const int64_t *V = c->tri + 3 * t;
    const int64_t *R = c->tri + 3 * c->cl[other].rep;
    int n = 0;
    for (int k = 0; k < 3 && n < 2; k++) {
        if (s[k] == 0)
            out[n++] = V[k];
        int k1 = (k + 1) % 3;
        if (n < 2 && s[k] * s[k1] < 0) {
            int64_t p = arr_lpi(&c->T, V[k], V[k1], other, R);
            if (p < 0)
                return -1;
            out[n++] = p;
        }
    }
    return n;
}

/* An axis along which the line of the two planes is not perpendicular, found from the
 * points themselves: two distinct points of the line differ in such a coordinate, and in
 * no other.  -1 when every point given is the same position. */
static int line_axis(const arr_points *P, const double *dir, const int64_t *pts, int n)
{
    int order[3] = {0, 1, 2};
    double a[3] = {fabs(dir[0]), fabs(dir[1]), fabs(dir[2])};
    for (int i = 0; i < 2; i++)
        for (int j = i + 1; j < 3; j++)
            if (a[order[j]] > a[order[i]]) {
                int t = order[i];
                order[i] = order[j];
                order[j] = t;
            }
    for (int o = 0; o < 3; o++) {
        int k = order[o];
        for (int i = 1; i < n; i++)
            if (arr_cmp(P, pts[0], pts[i], k) != 0)
                return k;
    }
    return -1;
}

static void approx_normal(const arr_ctx *c, int64_t t, double n[3])
{
    const int64_t *V = c->tri + 3 * t;
    double e1[3], e2[3];
    mfg_sub3(X(c, V[1]), X(c, V[0]), e1);
    mfg_sub3(X(c, V[2]), X(c, V[0]), e2);
    mfg_cross3(e1, e2, n);
}

static int meet_points(arr_ctx *c, int64_t i, int64_t j);

/* Where triangles i and j of different planes meet (records for both clusters); the
 * points made only to find out that they meet at a common vertex or not at all are
 * dropped again. */
static int meet(arr_ctx *c, int64_t i, int64_t j)
{
    int64_t mark = c->T.npts, nseg = c->nseg, npt = c->npt;
    int r = meet_points(c, i, j);
    if (r == 1 && c->nseg == nseg && c->npt == npt)
        arr_truncate(&c->T, mark);
    return r;
}

static int meet_points(arr_ctx *c, int64_t i, int64_t j)
{
    const int64_t *A = c->tri + 3 * i, *B = c->tri + 3 * j;
    int64_t ci = c->tcluster[i], cj = c->tcluster[j];
    int sb[3], sa[3];
    for (int k = 0; k < 3; k++) {
        sb[k] = side_of_plane(c, A, B[k]);
        sa[k] = side_of_plane(c, B, A[k]);
    }
    int64_t I[2], J[2];
    int ni = on_plane(c, i, sa, cj, I), nj = on_plane(c, j, sb, ci, J);
    if (ni < 0 || nj < 0)
        return 0;
    if (ni == 0 || nj == 0)
        return 1;
    if (ni == 1)
        I[1] = I[0];
    if (nj == 1)
        J[1] = J[0];
    double na[3], nb[3], dir[3];
    approx_normal(c, i, na);
    approx_normal(c, j, nb);
    mfg_cross3(na, nb, dir);
    arr_points P = arr_view(&c->T);
    int64_t all[4] = {I[0], I[1], J[0], J[1]};
    int k = line_axis(&P, dir, all, 4);
    if (k < 0) { /* one position: the triangles touch at a point */
        if (is_corner(A, I[0]) && is_corner(B, I[0]))
            return 1; /* a common vertex: both have it */
        return arr_add_point_record(c, ci, I[0]) && arr_add_point_record(c, cj, I[0]);
    }
    if (arr_cmp(&P, I[0], I[1], k) > 0) {
        int64_t t = I[0];
        I[0] = I[1];
        I[1] = t;
    }
    if (arr_cmp(&P, J[0], J[1], k) > 0) {
        int64_t t = J[0];
        J[0] = J[1];
        J[1] = t;
    }
    int64_t lo = arr_cmp(&P, I[0], J[0], k) >= 0 ? I[0] : J[0];
    int64_t hi = arr_cmp(&P, I[1], J[1], k) <= 0 ? I[1] : J[1];
    int s = arr_cmp(&P, lo, hi, k);
#ifdef ARR_DEBUG
    if (getenv("ARR_DEBUG_PAIRS")) {
        double a0[3], a1[3], b0[3], b1[3], xl[3], xh[3];
        arr_coords(&P, I[0], a0); arr_coords(&P, I[1], a1); arr_coords(&P, J[0], b0); arr_coords(&P, J[1], b1);
        arr_coords(&P, lo, xl); arr_coords(&P, hi, xh);
        fprintf(stderr, "meet %lld %lld (cl %lld %lld) axis %d I %lld(%g %g %g)-%lld(%g %g %g) J %lld(%g %g %g)-%lld(%g %g %g) -> s %d lo %lld hi %lld\n",
                (long long)i, (long long)j, (long long)ci, (long long)cj, k, (long long)I[0], a0[0], a0[1], a0[2], (long long)I[1], a1[0], a1[1], a1[2],
                (long long)J[0], b0[0], b0[1], b0[2], (long long)J[1], b1[0], b1[1], b1[2], s, (long long)lo, (long long)hi);
    }
#endif
    if (s > 0)
        return 1;
    if (s == 0) {
        if (is_corner(A, lo) && is_corner(B, lo))
            return 1;
        return arr_add_point_record(c, ci, lo) && arr_add_point_record(c, cj, lo);
    }
    return add_seg(c, ci, lo, hi, cj) && add_seg(c, cj, lo, hi, ci);
}

/* ---- The stage ----------------------------------------------------------------------- */

int arr_pairs(arr_ctx *c, arr_bvh *bvh)
{
    int64_t nt = c->ntri;
    pass1 P;
    memset(&P, 0, sizeof P);
    P.c = c;
    P.uf = malloc((size_t)(nt + 1) * sizeof *P.uf);
    if (!P.uf) {
        c->st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
        return 0;
    }
    for (int64_t t = 0; t < nt; t++)
        P.uf[t] = t;
    int r = arr_bvh_pairs(bvh, pass1_pair, &P);
    if (r <= 0 || P.nomem) {
        free(P.uf);
        free(P.keep);
        if (r == 0 && !P.nomem && mfg_prog_stopped(c->prog))
            c->st = MFG_ERR_CANCELLED;
        else
            c->st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
        return 0;
    }
    /* clusters, numbered in order of their smallest triangle */
    int64_t *id = malloc((size_t)(nt + 1) * sizeof *id);
    c->cl = malloc((size_t)(nt + 1) * sizeof *c->cl);
    if (!id || !c->cl) {
        free(id);
        free(P.uf);
        free(P.keep);
        c->st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
        return 0;
    }
    c->ncl = 0;
    for (int64_t t = 0; t < nt; t++)
        id[t] = -1;
    for (int64_t t = 0; t < nt; t++) {
        if (c->tcluster[t] < 0)
            continue;
        int64_t root = mfg_uf_find(P.uf, t);
        if (id[root] < 0) {
            id[root] = c->ncl;
            arr_cluster *K = &c->cl[c->ncl++];
            K->rep = t; /* the root is the smallest id of its set, visited first */
            /* the axis of the normal's largest component, among those whose projected
             * orientation is exactly non-zero (a sliver's rounded normal may lie) */
            double n[3];
            approx_normal(c, t, n);
            int order[3] = {0, 1, 2};
            for (int a = 0; a < 2; a++)
                for (int b = a + 1; b < 3; b++)
                    if (fabs(n[order[b]]) > fabs(n[order[a]])) {
                        int tmp = order[a];
                        order[a] = order[b];
                        order[b] = tmp;
                    }
            const int64_t *V = c->tri + 3 * t;
            arr_points Pv = arr_view(&c->T);
            K->axis = order[0];
            K->sign = 0;
            for (int o = 0; o < 3 && K->sign == 0; o++) {
                K->axis = order[o];
                K->sign = arr_orient2d(&Pv, V[0], V[1], V[2], order[o]);
            }
        }
        c->tcluster[t] = id[root];
    }
    free(id);
    free(P.uf);
    for (int64_t k = 0; k < P.nkeep; k++) {
        if ((k & 255) == 0 && !mfg_prog_poll(c->prog, (double)k, (double)P.nkeep)) {
            free(P.keep);
            c->st = MFG_ERR_CANCELLED;
            return 0;
        }
        if ((k & 255) == 0 && arr_over_budget(c)) {
            free(P.keep);
            return 0;
        }
        if (!meet(c, P.keep[k].i, P.keep[k].j)) {
            free(P.keep);
            c->st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
            return 0;
        }
    }
    free(P.keep);
    return 1;
}
