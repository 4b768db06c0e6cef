/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* junction_search.c - the medial surface's junction stage (docs/design/medial.md section
 * 4.3): the leaves where >= 4 elements may touch, searched in parallel for the points
 * equidistant from them (md_junction_search, junctions.c); the rank-3 points merged
 * (equal sets within tolerance: the smallest point; nested sets dropped for the larger,
 * the paper's subordinate junctions) and the seam ends' snapping to them. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "medial/assembly.h"

/* Junction results of one leaf (the search's cap). */
#define LEAF_JMAX 64
/* Leaves per work unit of the junction stage. */
#define JBLOCK 64

typedef struct jres {
    md_junction *j;
    int64_t n, cap;
} jres;

typedef struct jjob {
    const md_elements *el;
    const md_bvh *bvh;
    const md_leaves *lv;
    double tol;
    int64_t nblocks;
    atomic_llong next;
    jres *res;        /* per block */
    int *failed;      /* per block: 1 out of memory */
    mfg_prog *prog;   /* progress (never NULL here); only the caller's thread reports */
    pthread_t caller;
} jjob;

/* T for a leaf: the elements whose closure comes within D + 2 rho of the centre c, D the
 * distance from c to the boundary (md_bvh_within: the closure-meets-ball set).  Every
 * element touching a ball centred in the cell is in it: its closure distance at c is
 * <= D(x) + rho <= D(c) + 2 rho (both 1-Lipschitz).  Restricted distances (the octree's
 * nT) would miss the L-bracket's (5, 10, 5): there the face Fi and the reflex edge E each
 * hold the centre in their region on one side of y = 10 only. */
static int leaf_T(const md_elements *el, const md_bvh *bvh, const md_leaves *lv,
                  const md_leaf *lf, double c[3], int64_t *T)
{
    double h = lv->lat.h, rho = 0.5 * sqrt(3.0) * h;
    for (int k = 0; k < 3; k++)
        c[k] = lv->lat.origin[k] + h * (double)lf->ijk[k] + 0.5 * h;
    /* Only the leaf's candidates can touch in it (C: every element nearest somewhere in
     * the cell, ascending): fewer than 4, no junction. */
    const int64_t *C = lv->C + lf->C_off;
    if (lf->nC < 4)
        return 0;
    double D = md_bvh_nearest(bvh, el, c, NULL, NULL);
    int64_t W[4 * MD_JMAX];
    int64_t n = md_bvh_within(bvh, el, c, D + 2 * rho, W, 4 * MD_JMAX);
    if (n > 4 * MD_JMAX)
        n = 4 * MD_JMAX;
    int nT = 0;
    for (int64_t i = 0, k = 0; i < n && nT < MD_JMAX; i++) {
        while (k < lf->nC && C[k] < W[i])
            k++;
        if (k < lf->nC && C[k] == W[i])
            T[nT++] = W[i];
    }
    return nT;
}

static void *junction_worker(void *arg)
{
    jjob *job = arg;
    const md_leaves *lv = job->lv;
    md_junction out[LEAF_JMAX];
    int is_caller = pthread_equal(pthread_self(), job->caller) != 0;
    for (;;) {
        if (!mfg_prog_poll_mt(job->prog, is_caller, (double)atomic_load(&job->next),
                              (double)job->nblocks))
            break;
        int64_t b = atomic_fetch_add(&job->next, 1);
        if (b >= job->nblocks)
            break;
        jres *r = &job->res[b];
        int64_t end = (b + 1) * JBLOCK < lv->nleaves ? (b + 1) * JBLOCK : lv->nleaves;
        for (int64_t l = b * JBLOCK; l < end && !job->failed[b]; l++) {
            const md_leaf *lf = &lv->leaf[l];
            int64_t T[MD_JMAX];
            double c[3];
            int nT = leaf_T(job->el, job->bvh, lv, lf, c, T);
            if (nT < 4)
                continue;
            double lo[3], h = lv->lat.h;
            for (int k = 0; k < 3; k++)
                lo[k] = lv->lat.origin[k] + h * (double)lf->ijk[k];
            md_jbox box = {job->el, job->bvh, lo, h, job->tol};
            int n = md_junction_search(&box, T, nT, out, LEAF_JMAX);
            if (n < 0) {
                job->failed[b] = 1;
                break;
            }
            if (n == 0)
                continue;
            if (r->n + n > r->cap) {
                int64_t cap = r->cap ? 2 * r->cap : 16;
                while (cap < r->n + n)
                    cap *= 2;
                md_junction *v = realloc(r->j, (size_t)cap * sizeof *v);
                if (!v) {
                    job->failed[b] = 1;
                    break;
                }
                r->j = v;
                r->cap = cap;
            }
            memcpy(r->j + r->n, out, (size_t)n * sizeof *out);
            r->n += n;
        }
    }
    return NULL;
}

/* All junction and degenerate-seam points of the leaves, in leaf order. */
mfg_status md_find_junctions(const md_asm *ax, const md_leaves *lv, int nthreads,
                             md_junction **out, int64_t *nout, mfg_prog *prog)
{
    jjob job;
    memset(&job, 0, sizeof job);
    job.prog = prog;
    job.caller = pthread_self();
    job.el = ax->el;
    job.bvh = ax->bvh;
    job.lv = lv;
    job.tol = ax->tol;
    job.nblocks = (lv->nleaves + JBLOCK - 1) / JBLOCK;
    atomic_init(&job.next, 0);
    *out = NULL;
    *nout = 0;
    if (job.nblocks == 0)
        return MFG_OK;
    job.res = calloc((size_t)job.nblocks, sizeof *job.res);
    job.failed = calloc((size_t)job.nblocks, sizeof *job.failed);
    mfg_status st = MFG_OK;
    if (!job.res || !job.failed) {
        st = MFG_ERR_NOMEM;
        goto done;
    }
    pthread_t tid[MD_MAX_THREADS];
    int started = 0;
    for (int t = 1; t < nthreads && t < MD_MAX_THREADS; t++) {
        if (pthread_create(&tid[started], NULL, junction_worker, &job) != 0)
            break; /* fewer threads: the same result, the caller does the rest */
        started++;
    }
    junction_worker(&job);
    for (int t = 0; t < started; t++)
        pthread_join(tid[t], NULL);
    int64_t total = 0;
    for (int64_t b = 0; b < job.nblocks; b++) {
        if (job.failed[b])
            st = MFG_ERR_NOMEM;
        total += job.res[b].n;
    }
    if (st == MFG_OK && mfg_prog_stopped(prog))
        st = mfg_prog_fail(prog);
    if (st != MFG_OK)
        goto done;
    md_junction *all = malloc((size_t)(total ? total : 1) * sizeof *all);
    if (!all) {
        st = MFG_ERR_NOMEM;
        goto done;
    }
    int64_t k = 0;
    for (int64_t b = 0; b < job.nblocks; b++) {
        if (job.res[b].n)
            memcpy(all + k, job.res[b].j, (size_t)job.res[b].n * sizeof *all);
        k += job.res[b].n;
    }
    *out = all;
    *nout = total;
done:
    if (job.res)
        for (int64_t b = 0; b < job.nblocks; b++)
            free(job.res[b].j);
    free(job.res);
    free(job.failed);
    return st;
}

/* Junction order: by element set (size, then ids), then by point. */
int md_cmp_junction(const void *pa, const void *pb)
{
    const md_junction *a = pa, *b = pb;
    if (a->n != b->n)
        return a->n < b->n ? -1 : 1;
    for (int i = 0; i < a->n; i++)
        if (a->elems[i] != b->elems[i])
            return a->elems[i] < b->elems[i] ? -1 : 1;
    return md_cmp_xyz(a->x, b->x);
}

int md_same_set(const md_junction *a, const md_junction *b)
{
    return a->n == b->n && !memcmp(a->elems, b->elems, (size_t)a->n * sizeof a->elems[0]);
}

/* Merge the rank-3 points in place (design 4.3 step 3): equal sets within tolerance keep
 * the smallest point; a set nested in a larger one's within tolerance is dropped;
 * then the output filter.  Result sorted by point. */
static int cmp_junction_point(const void *pa, const void *pb)
{
    const md_junction *a = pa, *b = pb;
    int c = md_cmp_xyz(a->x, b->x);
    return c ? c : md_cmp_junction(pa, pb);
}

int64_t md_merge_junctions(const md_asm *ax, md_junction *J, int64_t n)
{
    const md_elements *el = ax->el;
    double tol = ax->tol;
    int full = ax->full;
    if (n > 1)
        qsort(J, (size_t)(n), sizeof *J, md_cmp_junction);
    int64_t m = 0;
    for (int64_t i = 0; i < n; i++) {
        int dup = 0;
        /* equal sets are contiguous; earlier kept ones have smaller points */
        for (int64_t k = m - 1; k >= 0 && md_same_set(&J[k], &J[i]) && !dup; k--)
            dup = mfg_dist3(J[k].x, J[i].x) <= tol;
        if (!dup)
            J[m++] = J[i];
    }
    int64_t w = 0;
    for (int64_t i = 0; i < m; i++) {
        int nested = 0;
        for (int64_t k = 0; k < m && !nested; k++)
            nested = k != i && J[k].n > J[i].n && mfg_dist3(J[k].x, J[i].x) <= tol &&
                     md_subset_of(J[i].elems, J[i].n, J[k].elems, J[k].n);
        if (!nested && md_set_has_output_pair(el, J[i].elems, J[i].n, full))
            J[w++] = J[i];
    }
    if (w > 1)
        qsort(J, (size_t)(w), sizeof *J, cmp_junction_point);
    return w;
}

/* The first junction with x >= x0 (J sorted by point, x first). */
static int64_t junction_lower_x(const md_junction *J, int64_t nj, double x0)
{
    int64_t lo = 0, hi = nj;
    while (lo < hi) {
        int64_t mid = lo + (hi - lo) / 2;
        if (J[mid].x[0] < x0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The junction within reach of p whose set holds s (ascending, n), the nearest; -1 if
 * none.  J sorted by point (merge_junctions): only the slab |x - p_x| <= reach is read. */
int64_t md_snap_junction(const md_jset *Js, const double *p, const int64_t *s, int64_t n,
                         double reach)
{
    const md_junction *J = Js->v;
    int64_t nj = Js->n;
    int64_t best = -1;
    double bd = INFINITY;
    for (int64_t j = junction_lower_x(J, nj, p[0] - reach); j < nj && J[j].x[0] <= p[0] + reach; j++) {
        double d = mfg_dist3(J[j].x, p);
        if (d <= reach && d < bd && md_subset_of(s, n, J[j].elems, J[j].n)) {
            bd = d;
            best = j;
        }
    }
    return best;
}
