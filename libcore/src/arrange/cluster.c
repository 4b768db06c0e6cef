/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* arrange/cluster.c - The 2-D arrangement of each cluster (the triangles of one plane that
 * touch, and the segments where other planes cut them): its segments crossed, the
 * crossing points made from what the segments lie on (two other planes: a TPI point; a
 * member edge and a plane: LPI; two member edges: SSI), every segment split at the points
 * that lie on it, then triangulated (cdt.c).  Two passes over the clusters, with the
 * exact merge of equal positions between them, so that every cluster sees the same
 * points as its neighbours. */
#include "arrange/arrange.h"

/* Interval padding of the box filters (unit scale; rounded coordinates are within a few
 * ulps of the exact ones): boxes only prune, the tests are exact. */
#define BOX_PAD 0x1p-36

typedef struct lists {
    int64_t *pts;
    int64_t npts, cappts;
    arr_seg *segs;
    int64_t nsegs, capsegs;
    double *uv;       /* approx 2-D coordinates of pts (2 each) */
    int64_t capuv;
} lists;

typedef struct csr {
    int64_t *start;   /* ncl + 1 */
    int64_t *item;
} csr;

static void csr_free(csr *s)
{
    free(s->start);
    free(s->item);
    s->start = s->item = NULL;
}

/* Groups items 0 .. n-1 by key[i] in [0, nk). */
static int csr_build(csr *s, const int64_t *key, int64_t n, int64_t nk)
{
    s->start = calloc((size_t)(nk + 2), sizeof *s->start);
    s->item = malloc((size_t)(n + 1) * sizeof *s->item);
    if (!s->start || !s->item) {
        csr_free(s);
        return 0;
    }
    for (int64_t i = 0; i < n; i++)
        if (key[i] >= 0)
            s->start[key[i] + 2]++;
    for (int64_t k = 0; k < nk; k++)
        s->start[k + 2] += s->start[k + 1];
    for (int64_t i = 0; i < n; i++)
        if (key[i] >= 0)
            s->item[s->start[key[i] + 1]++] = i;
    return 1;
}

static int push_pt(lists *L, int64_t p)
{
    if (L->npts >= L->cappts) {
        int64_t cap = mfg_grown_cap(L->cappts, L->npts + 1, 16);
        int64_t *n = realloc(L->pts, (size_t)cap * sizeof *n);
        if (!n)
            return 0;
        L->pts = n;
        L->cappts = cap;
    }
    L->pts[L->npts++] = p;
    return 1;
}

static int push_seg(lists *L, const arr_seg *s)
{
    if (L->nsegs >= L->capsegs) {
        int64_t cap = mfg_grown_cap(L->capsegs, L->nsegs + 1, 16);
        arr_seg *n = realloc(L->segs, (size_t)cap * sizeof *n);
        if (!n)
            return 0;
        L->segs = n;
        L->capsegs = cap;
    }
    L->segs[L->nsegs++] = *s;
    return 1;
}

static int cmp_seg(const void *a, const void *b)
{
    const arr_seg *s = a, *t = b;
    if (s->p != t->p)
        return s->p < t->p ? -1 : 1;
    if (s->q != t->q)
        return s->q < t->q ? -1 : 1;
    /* member edges first, so the merged segment keeps an explicit support */
    return (s->support >= 0) - (t->support >= 0);
}

/* Segments with p < q, sorted, equal ones merged (deltas summed; an explicit edge support
 * kept when there is one); a segment that changes no multiplicity and lies on no other
 * plane (an inner edge between two member triangles) is dropped. */
static void merge_segs(lists *L)
{
    for (int64_t i = 0; i < L->nsegs; i++) {
        arr_seg *s = &L->segs[i];
        if (s->p > s->q) {
            int64_t t = s->p;
            s->p = s->q;
            s->q = t;
            s->delta = -s->delta;
        }
    }
    if (L->nsegs > 1)
        qsort(L->segs, (size_t)L->nsegs, sizeof *L->segs, cmp_seg);
    int64_t n = 0;
    for (int64_t i = 0; i < L->nsegs;) {
        arr_seg m = L->segs[i];
        int plane = m.support >= 0;
        int64_t j = i + 1;
        for (; j < L->nsegs && L->segs[j].p == m.p && L->segs[j].q == m.q; j++) {
            m.delta += L->segs[j].delta;
            plane |= L->segs[j].support >= 0;
            if (m.support >= 0 && L->segs[j].support < 0) {
                m.support = -1;
                m.ea = L->segs[j].ea;
                m.eb = L->segs[j].eb;
            }
        }
        if (m.delta != 0 || plane) {
            if (m.support < 0 && plane && m.delta == 0) {
                /* keep it as a constraint; its support for crossings stays the edge */
            }
            L->segs[n++] = m;
        }
        i = j;
    }
    L->nsegs = n;
}

static void unique_pts(lists *L)
{
    if (L->npts > 1)
        qsort(L->pts, (size_t)L->npts, sizeof *L->pts, mfg_cmp_i64);
    int64_t n = 0;
    for (int64_t i = 0; i < L->npts; i++)
        if (n == 0 || L->pts[n - 1] != L->pts[i])
            L->pts[n++] = L->pts[i];
    L->npts = n;
}

/* The cluster's points and segments, on canonical point ids. */
static int gather(arr_ctx *c, int64_t cl, const csr *members, const csr *segrec,
                  const csr *ptrec, lists *L)
{
    const arr_table *T = &c->T;
    L->npts = L->nsegs = 0;
    for (int64_t m = members->start[cl]; m < members->start[cl + 1]; m++) {
        const int64_t *V = c->tri + 3 * members->item[m];
        for (int k = 0; k < 3; k++) {
            arr_seg s;
            s.p = arr_canon(T, V[k]);
            s.q = arr_canon(T, V[(k + 1) % 3]);
            s.support = -1;
            s.ea = V[k];
            s.eb = V[(k + 1) % 3];
            s.delta = 1;
            if (!push_pt(L, s.p) || (s.p != s.q && !push_seg(L, &s)))
                return 0;
        }
    }
    for (int64_t r = segrec->start[cl]; r < segrec->start[cl + 1]; r++) {
        arr_seg s = c->seg[segrec->item[r]];
        s.p = arr_canon(T, s.p);
        s.q = arr_canon(T, s.q);
        if (!push_pt(L, s.p) || !push_pt(L, s.q) || (s.p != s.q && !push_seg(L, &s)))
            return 0;
    }
    for (int64_t r = ptrec->start[cl]; r < ptrec->start[cl + 1]; r++)
        if (!push_pt(L, arr_canon(T, c->pt[ptrec->item[r]])))
            return 0;
    unique_pts(L);
    merge_segs(L);
    return 1;
}

/* Approximate 2-D coordinates of the cluster's points (for the box filters). */
static int approx_uv(arr_ctx *c, lists *L, int axis)
{
    if (L->capuv < L->npts) {
        double *n = realloc(L->uv, (size_t)(2 * L->npts) * sizeof *n);
        if (!n)
            return 0;
        L->uv = n;
        L->capuv = L->npts;
    }
    arr_points P = arr_view(&c->T);
    for (int64_t i = 0; i < L->npts; i++) {
        double x[3];
        arr_coords(&P, L->pts[i], x);
        L->uv[2 * i] = x[(axis + 1) % 3];
        L->uv[2 * i + 1] = x[(axis + 2) % 3];
    }
    return 1;
}

static int64_t local_of(const lists *L, int64_t p)
{
    int64_t lo = 0, hi = L->npts - 1;
    while (lo <= hi) {
        int64_t m = (lo + hi) / 2;
        if (L->pts[m] == p)
            return m;
        if (L->pts[m] < p)
            lo = m + 1;
        else
            hi = m - 1;
    }
    return -1;
}

/* ---- Pass A: crossings ---------------------------------------------------------------- */

typedef struct seg_box {
    double lo[2], hi[2];
    int64_t s;
} seg_box;

static int cmp_box(const void *a, const void *b)
{
    const seg_box *x = a, *y = b;
    if (x->lo[0] != y->lo[0])
        return x->lo[0] < y->lo[0] ? -1 : 1;
    return x->s < y->s ? -1 : x->s > y->s;
}

static int64_t crossing_point(arr_ctx *c, int64_t cl, const arr_seg *a, const arr_seg *b)
{
    const arr_cluster *K = &c->cl[cl];
    if (a->support < 0 && b->support < 0)
        return arr_ssi(&c->T, a->ea, a->eb, b->ea, b->eb, K->axis);
    if (a->support < 0 || b->support < 0) {
        const arr_seg *e = a->support < 0 ? a : b, *p = a->support < 0 ? b : a;
        return arr_lpi(&c->T, e->ea, e->eb, p->support, c->tri + 3 * c->cl[p->support].rep);
    }
    int64_t id[3] = {cl, a->support, b->support};
    int64_t plane[3][3];
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            plane[i][k] = c->tri[3 * c->cl[id[i]].rep + k];
    return arr_tpi(&c->T, id, plane);
}

/* Every proper crossing of two of the cluster's segments becomes a point record. */
static int crossings(arr_ctx *c, int64_t cl, lists *L, seg_box **boxes, int64_t *capboxes)
{
    if (L->nsegs < 2)
        return 1;
    int axis = c->cl[cl].axis;
    if (!approx_uv(c, L, axis))
        return 0;
    if (*capboxes < L->nsegs) {
        seg_box *n = realloc(*boxes, (size_t)L->nsegs * sizeof *n);
        if (!n)
            return 0;
        *boxes = n;
        *capboxes = L->nsegs;
    }
    seg_box *B = *boxes;
    for (int64_t i = 0; i < L->nsegs; i++) {
        int64_t p = local_of(L, L->segs[i].p), q = local_of(L, L->segs[i].q);
        for (int k = 0; k < 2; k++) {
            B[i].lo[k] = fmin(L->uv[2 * p + k], L->uv[2 * q + k]) - BOX_PAD;
            B[i].hi[k] = fmax(L->uv[2 * p + k], L->uv[2 * q + k]) + BOX_PAD;
        }
        B[i].s = i;
    }
    if (L->nsegs > 1)
        qsort(B, (size_t)L->nsegs, sizeof *B, cmp_box);
    arr_points P = arr_view(&c->T);
    for (int64_t i = 0; i < L->nsegs; i++) {
        for (int64_t j = i + 1; j < L->nsegs && B[j].lo[0] <= B[i].hi[0]; j++) {
            if (B[j].lo[1] > B[i].hi[1] || B[j].hi[1] < B[i].lo[1])
                continue;
            const arr_seg *a = &L->segs[B[i].s], *b = &L->segs[B[j].s];
            if (a->p == b->p || a->p == b->q || a->q == b->p || a->q == b->q)
                continue;
            if (a->support >= 0 && a->support == b->support)
                continue; /* both on one line */
            int o1 = arr_orient2d(&P, a->p, a->q, b->p, axis);
            int o2 = arr_orient2d(&P, a->p, a->q, b->q, axis);
            if (o1 * o2 >= 0)
                continue;
            int o3 = arr_orient2d(&P, b->p, b->q, a->p, axis);
            int o4 = arr_orient2d(&P, b->p, b->q, a->q, axis);
            if (o3 * o4 >= 0)
                continue;
            int64_t x = crossing_point(c, cl, a, b);
            if (x < 0 || !arr_add_point_record(c, cl, x))
                return 0;
            P = arr_view(&c->T); /* the table may have moved */
        }
    }
    return 1;
}

/* ---- Pass B: split, triangulate ------------------------------------------------------- */

typedef struct pt_sort {
    double u;
    int64_t i;
} pt_sort;

static int cmp_ptsort(const void *a, const void *b)
{
    const pt_sort *x = a, *y = b;
    if (x->u != y->u)
        return x->u < y->u ? -1 : 1;
    return x->i < y->i ? -1 : x->i > y->i;
}

typedef struct on_seg {
    int64_t p;
    int ax;
    const arr_points *P;
} on_seg;

/* Splits every segment at the cluster's points strictly inside it: 1, 0 when out of
 * memory, -1 when the progress callback asked to stop. */
static int split_segments(arr_ctx *c, int64_t cl, lists *L, pt_sort **ps, int64_t *capps,
                          int64_t **inside, int64_t *capin)
{
    int axis = c->cl[cl].axis;
    if (!approx_uv(c, L, axis))
        return 0;
    if (*capps < L->npts) {
        pt_sort *n = realloc(*ps, (size_t)L->npts * sizeof *n);
        if (!n)
            return 0;
        *ps = n;
        *capps = L->npts;
    }
    pt_sort *S = *ps;
    for (int64_t i = 0; i < L->npts; i++) {
        S[i].u = L->uv[2 * i];
        S[i].i = i;
    }
    if (L->npts > 1)
        qsort(S, (size_t)L->npts, sizeof *S, cmp_ptsort);
    arr_points P = arr_view(&c->T);
    int64_t nseg0 = L->nsegs;
    for (int64_t si = 0; si < nseg0; si++) {
        /* one cluster can hold most of the work (the rounded passes of a sweep: 10^4
         * segments among near-collinear points, tens of seconds): a cancel is heard here
         * too, not only between clusters */
        if ((si & 63) == 63 &&
            !mfg_prog_poll(c->prog, 0.3 * (double)c->ncl + 0.7 * (double)cl, (double)c->ncl))
            return -1;
        arr_seg s = L->segs[si];
        int64_t lp = local_of(L, s.p), lq = local_of(L, s.q);
        double ulo = fmin(L->uv[2 * lp], L->uv[2 * lq]) - BOX_PAD;
        double uhi = fmax(L->uv[2 * lp], L->uv[2 * lq]) + BOX_PAD;
        double vlo = fmin(L->uv[2 * lp + 1], L->uv[2 * lq + 1]) - BOX_PAD;
        double vhi = fmax(L->uv[2 * lp + 1], L->uv[2 * lq + 1]) + BOX_PAD;
        /* the coordinate along which the segment's ends differ orders its points */
        int ax = (axis + 1) % 3;
        int dir = arr_cmp(&P, s.p, s.q, ax);
        if (dir == 0) {
            ax = (axis + 2) % 3;
            dir = arr_cmp(&P, s.p, s.q, ax);
        }
        int64_t lo = 0, hi = L->npts;
        while (lo < hi) { /* first point with u >= ulo */
            int64_t m = (lo + hi) / 2;
            if (S[m].u < ulo)
                lo = m + 1;
            else
                hi = m;
        }
        int64_t nin = 0;
        for (int64_t k = lo; k < L->npts && S[k].u <= uhi; k++) {
            int64_t li = S[k].i;
            double v = L->uv[2 * li + 1];
            if (v < vlo || v > vhi)
                continue;
            int64_t x = L->pts[li];
            if (x == s.p || x == s.q)
                continue;
            if (arr_orient2d(&P, s.p, s.q, x, axis) != 0)
                continue;
            if (arr_cmp(&P, s.p, x, ax) != dir || arr_cmp(&P, x, s.q, ax) != dir)
                continue;
            if (nin >= *capin) {
                int64_t cap = mfg_grown_cap(*capin, nin + 1, 16);
                int64_t *n = realloc(*inside, (size_t)cap * sizeof *n);
                if (!n)
                    return 0;
                *inside = n;
                *capin = cap;
            }
            (*inside)[nin++] = x;
        }
        if (nin == 0)
            continue;
        /* order the inner points from p to q (insertion sort: few points) */
        int64_t *in = *inside;
        for (int64_t a = 1; a < nin; a++) {
            int64_t x = in[a], b = a - 1;
            while (b >= 0 && arr_cmp(&P, x, in[b], ax) == dir) { /* x comes before in[b] */
                in[b + 1] = in[b];
                b--;
            }
            in[b + 1] = x;
        }
        /* the segment becomes p -> in[0], then the rest appended */
        int64_t prev = s.p;
        for (int64_t a = 0; a <= nin; a++) {
            arr_seg t = s;
            t.p = prev;
            t.q = a < nin ? in[a] : s.q;
            prev = t.q;
            if (a == 0)
                L->segs[si] = t;
            else if (!push_seg(L, &t))
                return 0;
        }
    }
    merge_segs(L);
    return 1;
}

typedef struct work {
    lists L;
    seg_box *boxes;
    int64_t capboxes;
    pt_sort *ps;
    int64_t capps;
    int64_t *inside;
    int64_t capin;
} work;

static void work_free(work *w)
{
    free(w->L.pts);
    free(w->L.segs);
    free(w->L.uv);
    free(w->boxes);
    free(w->ps);
    free(w->inside);
}

/* One member and nothing else cut it: the face is the triangle itself. */
static int lone_triangle(int64_t cl, const csr *members, const lists *L)
{
    if (members->start[cl + 1] - members->start[cl] != 1 || L->npts != 3 || L->nsegs != 3)
        return 0;
    for (int64_t i = 0; i < 3; i++)
        if (L->segs[i].support >= 0)
            return 0;
    return 1;
}

static int push_face(arr_ctx *c, const arr_face *f)
{
    if (c->nface >= c->capface) {
        int64_t cap = mfg_grown_cap(c->capface, c->nface + 1, 16);
        arr_face *n = realloc(c->face, (size_t)cap * sizeof *n);
        if (!n)
            return 0;
        c->face = n;
        c->capface = cap;
    }
    c->face[c->nface++] = *f;
    return 1;
}

int arr_push_face(arr_ctx *c, const arr_face *f)
{
    return push_face(c, f);
}

int arr_clusters(arr_ctx *c)
{
    csr members = {NULL, NULL}, segrec = {NULL, NULL}, ptrec = {NULL, NULL};
    work w;
    memset(&w, 0, sizeof w);
    int dd = arr_dedupe(&c->T, c->prog);
    if (dd < 0)
        goto cancelled;
    int ok = dd && csr_build(&members, c->tcluster, c->ntri, c->ncl) &&
             csr_build(&segrec, c->segcl, c->nseg, c->ncl) &&
             csr_build(&ptrec, c->ptcl, c->npt, c->ncl);
    if (!ok)
        goto nomem;
    /* the stage's progress: pass A the first 30 %, pass B the rest */
    for (int64_t cl = 0; cl < c->ncl; cl++) {
        if (!mfg_prog_poll(c->prog, 0.3 * (double)cl, (double)c->ncl))
            goto cancelled;
        if (!gather(c, cl, &members, &segrec, &ptrec, &w.L) ||
            !crossings(c, cl, &w.L, &w.boxes, &w.capboxes))
            goto nomem;
        if (arr_over_budget(c))
            goto fail;
    }
    csr_free(&ptrec);
    dd = arr_dedupe(&c->T, c->prog);
    if (dd < 0)
        goto cancelled;
    if (!dd || !csr_build(&ptrec, c->ptcl, c->npt, c->ncl))
        goto nomem;
    for (int64_t cl = 0; cl < c->ncl; cl++) {
        if (!mfg_prog_poll(c->prog, 0.3 * (double)c->ncl + 0.7 * (double)cl, (double)c->ncl))
            goto cancelled;
        if (!gather(c, cl, &members, &segrec, &ptrec, &w.L))
            goto nomem;
        if (lone_triangle(cl, &members, &w.L)) {
            const int64_t *V = c->tri + 3 * members.item[members.start[cl]];
            arr_face f;
            for (int k = 0; k < 3; k++)
                f.v[k] = arr_canon(&c->T, V[k]);
            f.cluster = cl;
            f.mult = 1;
            if (!push_face(c, &f))
                goto nomem;
            continue;
        }
        int sp = split_segments(c, cl, &w.L, &w.ps, &w.capps, &w.inside, &w.capin);
        if (sp < 0)
            goto cancelled;
        if (!sp)
            goto nomem;
#ifdef ARR_DEBUG
        if (getenv("ARR_DEBUG_CL") && atoll(getenv("ARR_DEBUG_CL")) == cl) {
            fprintf(stderr, "cluster %lld: %lld points, %lld segments\n", (long long)cl, (long long)w.L.npts, (long long)w.L.nsegs);
            for (int64_t q = 0; q < w.L.npts; q++) fprintf(stderr, " pt %lld", (long long)w.L.pts[q]);
            fprintf(stderr, "\n");
            for (int64_t q = 0; q < w.L.nsegs; q++) fprintf(stderr, " seg %lld-%lld sup %lld delta %d\n", (long long)w.L.segs[q].p, (long long)w.L.segs[q].q, (long long)w.L.segs[q].support, w.L.segs[q].delta);
        }
        int64_t nf0 = c->nface;
#endif
        if (!arr_cdt_cluster(c, cl, w.L.pts, w.L.npts, w.L.segs, w.L.nsegs)) {
            if (c->st == MFG_OK)
                goto nomem;
            goto fail;
        }
#ifdef ARR_DEBUG
        if (getenv("ARR_DEBUG_CL") && atoll(getenv("ARR_DEBUG_CL")) == cl)
            for (int64_t q = nf0; q < c->nface; q++) fprintf(stderr, " face %lld %lld %lld mult %d\n", (long long)c->face[q].v[0], (long long)c->face[q].v[1], (long long)c->face[q].v[2], c->face[q].mult);
#endif
    }
    csr_free(&members);
    csr_free(&segrec);
    csr_free(&ptrec);
    work_free(&w);
    return 1;
nomem:
    c->st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
    goto fail;
cancelled:
    c->st = MFG_ERR_CANCELLED;
fail:
    csr_free(&members);
    csr_free(&segrec);
    csr_free(&ptrec);
    work_free(&w);
    return 0;
}

/* ---- A chain in one plane ---------------------------------------------------------------- */

int arr_planar_chain(arr_ctx *c, const int64_t *seg, int64_t nseg)
{
    work w;
    memset(&w, 0, sizeof w);
    /* the segments (explicit ends), their crossings, then again on the merged points */
    for (int pass = 0; pass < 2; pass++) {
        w.L.npts = w.L.nsegs = 0;
        for (int64_t i = 0; i < nseg; i++) {
            arr_seg s;
            s.ea = seg[2 * i];
            s.eb = seg[2 * i + 1];
            s.p = arr_canon(&c->T, s.ea);
            s.q = arr_canon(&c->T, s.eb);
            s.support = -1;
            s.delta = 1;
            if (!push_pt(&w.L, s.p) || !push_pt(&w.L, s.q) || (s.p != s.q && !push_seg(&w.L, &s)))
                goto nomem;
        }
        for (int64_t r = 0; r < c->npt; r++)
            if (!push_pt(&w.L, arr_canon(&c->T, c->pt[r])))
                goto nomem;
        unique_pts(&w.L);
        merge_segs(&w.L);
        if (pass == 0) {
            if (!crossings(c, 0, &w.L, &w.boxes, &w.capboxes))
                goto nomem;
            int dd = arr_dedupe(&c->T, c->prog);
            if (dd < 0) {
                c->st = MFG_ERR_CANCELLED;
                work_free(&w);
                return 0;
            }
            if (!dd)
                goto nomem;
        }
    }
    int sp = split_segments(c, 0, &w.L, &w.ps, &w.capps, &w.inside, &w.capin);
    if (sp < 0) {
        c->st = MFG_ERR_CANCELLED;
        work_free(&w);
        return 0;
    }
    if (!sp)
        goto nomem;
    if (!arr_cdt_cluster(c, 0, w.L.pts, w.L.npts, w.L.segs, w.L.nsegs)) {
        work_free(&w);
        if (c->st == MFG_OK)
            c->st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
        return 0;
    }
    work_free(&w);
    return 1;
nomem:
    work_free(&w);
    c->st = mfg_fail(MFG_ERR_NOMEM, "arrangement: out of memory");
    return 0;
}
