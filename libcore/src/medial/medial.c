/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* medial.c - the medial surface's public entry point (issue 9, seed 004 Lee & Lee;
 * design /work/notes/issue9_design.md): input checks, the pipeline elements -> BVH ->
 * octree leaves -> sheets (medial_sheets.c) and junctions (medial_junctions.c) -> the
 * assembly into mfg_medial, and mfg_medial_free.
 *
 * Assembly (design 4.1 - 4.3):
 *   sheets     the connected components of one pair's triangles, vertices compacted;
 *              triangles with a vertex off the pair's bisector (> 1e-9 L) and slivers
 *              (the square prism's side pairs, trimmed to its axis) dropped; each sheet
 *              made coarse within the tolerance (md_sheet_simplify);
 *   seams      the soup's seam segments, each with the elements touching at both of its
 *              ends; per element set the pair whose segments chain into the fewest
 *              polylines (ties: the smallest), pieces joined across 3h, ends snapped to
 *              the junctions within 2h whose set holds the seam's, thinned to
 *              tolerance / 4; plus the degenerate seams chained from the rank-2 points of
 *              the junction search (soup seams lying on them dropped);
 *   junctions  the rank-3 points, equal sets within tolerance merged (the smallest point
 *              kept), nested sets dropped for the larger (the paper's subordinate
 *              junctions);
 *   major/full the pairs of disjoint closures, or every non-incident pair.
 * Every order is a sort on geometry or element ids, so the result is bit-identical for any
 * thread count and triangle order. */
#define _GNU_SOURCE /* sysconf(_SC_NPROCESSORS_ONLN) */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "medial/medial.h"
#include "common/mfg_internal.h"

#define MAX_THREADS 64
/* Junction results of one leaf (the search's cap). */
#define LEAF_JMAX 64
/* Leaves per work unit of the junction stage. */
#define JBLOCK 64

/* ---- small helpers ----------------------------------------------------------------------- */

static int cmp_xyz(const double *a, const double *b)
{
    for (int k = 0; k < 3; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

/* Lexicographic order where coordinates within d count as equal: a seam along x = 30
 * has ends whose x differ by an ulp, and its direction must not hang on that. */
static int cmp_xyz_tol(const double *a, const double *b, double d)
{
    for (int k = 0; k < 3; k++)
        if (fabs(a[k] - b[k]) > d)
            return a[k] < b[k] ? -1 : 1;
    return 0;
}

/* Is the sorted list a (na) a subset of the sorted list b (nb)? */
static int subset_of(const int64_t *a, int64_t na, const int64_t *b, int64_t nb)
{
    int64_t j = 0;
    for (int64_t i = 0; i < na; i++) {
        while (j < nb && b[j] < a[i])
            j++;
        if (j == nb || b[j] != a[i])
            return 0;
        j++;
    }
    return 1;
}

/* A pair in the output: major mode, disjoint closures; full mode, not incident. */
static int output_pair(const md_elements *el, int64_t a, int64_t b, int full)
{
    return full ? !md_incident(el, a, b) : !md_adjacent(el, a, b);
}

/* Does the set hold an output pair? */
static int set_has_output_pair(const md_elements *el, const int64_t *s, int64_t n, int full)
{
    for (int64_t i = 0; i < n; i++)
        for (int64_t j = i + 1; j < n; j++)
            if (output_pair(el, s[i], s[j], full))
                return 1;
    return 0;
}

/* Growable arrays (every failure is out of memory). */
typedef struct dbuf {
    double *v;
    int64_t n, cap;
} dbuf;
typedef struct ibuf {
    int64_t *v;
    int64_t n, cap;
} ibuf;

/* Room for element n of a growable array v of *cap elements of the size given (the
 * capacity doubles from 64): v itself, or the moved block, or NULL when out of memory (v
 * is then untouched). */
static void *grow_for(void *v, int64_t n, int64_t *cap, size_t size)
{
    if (n < *cap)
        return v;
    int64_t c = *cap ? 2 * *cap : 64;
    void *p = realloc(v, (size_t)c * size);
    if (p)
        *cap = c;
    return p;
}

static int dbuf_push(dbuf *b, double x)
{
    double *v = grow_for(b->v, b->n, &b->cap, sizeof *v);
    if (!v)
        return 0;
    b->v = v;
    b->v[b->n++] = x;
    return 1;
}

static int ibuf_push(ibuf *b, int64_t x)
{
    int64_t *v = grow_for(b->v, b->n, &b->cap, sizeof *v);
    if (!v)
        return 0;
    b->v = v;
    b->v[b->n++] = x;
    return 1;
}

/* ---- junction stage: the leaves where >= 4 elements may touch (design 4.3) ---------------- */

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
            int n = md_junction_search(job->el, job->bvh, lo, h, T, nT, job->tol, out, LEAF_JMAX);
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
static mfg_status find_junctions(const md_elements *el, const md_bvh *bvh, const md_leaves *lv,
                                 double tol, int nthreads, md_junction **out, int64_t *nout,
                                 mfg_prog *prog)
{
    jjob job;
    memset(&job, 0, sizeof job);
    job.prog = prog;
    job.caller = pthread_self();
    job.el = el;
    job.bvh = bvh;
    job.lv = lv;
    job.tol = tol;
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
    pthread_t tid[MAX_THREADS];
    int started = 0;
    for (int t = 1; t < nthreads && t < MAX_THREADS; t++) {
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
static int cmp_junction(const void *pa, const void *pb)
{
    const md_junction *a = pa, *b = pb;
    if (a->n != b->n)
        return a->n < b->n ? -1 : 1;
    for (int i = 0; i < a->n; i++)
        if (a->elems[i] != b->elems[i])
            return a->elems[i] < b->elems[i] ? -1 : 1;
    return cmp_xyz(a->x, b->x);
}

static int same_set(const md_junction *a, const md_junction *b)
{
    return a->n == b->n && !memcmp(a->elems, b->elems, (size_t)a->n * sizeof a->elems[0]);
}

/* Merge the rank-3 points in place (design 4.3 step 3): equal sets within tolerance keep
 * the smallest point; a set nested in a larger one's within tolerance is dropped;
 * then the output filter.  Result sorted by point. */
static int cmp_junction_point(const void *pa, const void *pb)
{
    const md_junction *a = pa, *b = pb;
    int c = cmp_xyz(a->x, b->x);
    return c ? c : cmp_junction(pa, pb);
}

static int64_t merge_junctions(const md_elements *el, md_junction *J, int64_t n, double tol,
                               int full)
{
    if (n > 1)
        qsort(J, (size_t)(n), sizeof *J, cmp_junction);
    int64_t m = 0;
    for (int64_t i = 0; i < n; i++) {
        int dup = 0;
        /* equal sets are contiguous; earlier kept ones have smaller points */
        for (int64_t k = m - 1; k >= 0 && same_set(&J[k], &J[i]) && !dup; k--)
            dup = mfg_dist3(J[k].x, J[i].x) <= tol;
        if (!dup)
            J[m++] = J[i];
    }
    int64_t w = 0;
    for (int64_t i = 0; i < m; i++) {
        int nested = 0;
        for (int64_t k = 0; k < m && !nested; k++)
            nested = k != i && J[k].n > J[i].n && mfg_dist3(J[k].x, J[i].x) <= tol &&
                     subset_of(J[i].elems, J[i].n, J[k].elems, J[k].n);
        if (!nested && set_has_output_pair(el, J[i].elems, J[i].n, full))
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
static int64_t snap_junction(const md_junction *J, int64_t nj, const double *p, const int64_t *s,
                             int64_t n, double reach)
{
    int64_t best = -1;
    double bd = INFINITY;
    for (int64_t j = junction_lower_x(J, nj, p[0] - reach); j < nj && J[j].x[0] <= p[0] + reach; j++) {
        double d = mfg_dist3(J[j].x, p);
        if (d <= reach && d < bd && subset_of(s, n, J[j].elems, J[j].n)) {
            bd = d;
            best = j;
        }
    }
    return best;
}

/* ---- sheets -------------------------------------------------------------------------------- */

typedef struct sheet_ref {
    int64_t a, b;      /* the pair */
    int64_t first;     /* index into the sorted triangle list */
    int64_t ntri;
    double minxyz[3];  /* smallest vertex: the order among one pair's components */
} sheet_ref;

static int cmp_sheet(const void *pa, const void *pb)
{
    const sheet_ref *a = pa, *b = pb;
    if (a->a != b->a)
        return a->a < b->a ? -1 : 1;
    if (a->b != b->b)
        return a->b < b->b ? -1 : 1;
    return cmp_xyz(a->minxyz, b->minxyz);
}

/* Triangle order for grouping: by component root (its smallest triangle index). */
typedef struct tri_key {
    int64_t root, t;
} tri_key;

static int cmp_tri_key(const void *pa, const void *pb)
{
    const tri_key *a = pa, *b = pb;
    if (a->root != b->root)
        return a->root < b->root ? -1 : 1;
    return (a->t > b->t) - (a->t < b->t);
}

static double tri_area(const double *p, const double *q, const double *r)
{
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    double c[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

/* The assembly's working state (freed as a whole). */
typedef struct asm_state {
    int64_t *vsheet;   /* soup vertex -> output sheet, or -1 */
    int64_t *parent;   /* union-find over soup triangles */
    tri_key *keys;
    sheet_ref *refs;
    int64_t *vlocal;   /* soup vertex -> local index in its sheet */
} asm_state;

static void asm_free(asm_state *s)
{
    free(s->vsheet);
    free(s->parent);
    free(s->keys);
    free(s->refs);
    free(s->vlocal);
}

static mfg_status build_sheets(const md_elements *el, const md_soup *sp, double h, double tol,
                               int full, mfg_medial *m, asm_state *s, mfg_prog *prog)
{
    int64_t nv = sp->nverts, nt = sp->ntris;
    s->vsheet = malloc((size_t)(nv ? nv : 1) * sizeof(int64_t));
    s->vlocal = malloc((size_t)(nv ? nv : 1) * sizeof(int64_t));
    s->parent = malloc((size_t)(nt ? nt : 1) * sizeof(int64_t));
    s->keys = malloc((size_t)(nt ? nt : 1) * sizeof(tri_key));
    s->refs = malloc((size_t)(nt ? nt : 1) * sizeof(sheet_ref));
    int64_t *first_tri = malloc((size_t)(nv ? nv : 1) * sizeof(int64_t));
    if (!s->vsheet || !s->vlocal || !s->parent || !s->keys || !s->refs || !first_tri) {
        free(first_tri);
        return MFG_ERR_NOMEM;
    }
    for (int64_t v = 0; v < nv; v++) {
        s->vsheet[v] = -1;
        first_tri[v] = -1;
    }
    /* Triangles kept: of an output pair, not below 1e-6 h^2 (design 4.1). */
    double amin = 1e-6 * h * h;
    int64_t pa = -1, pb = -1;
    int pair_out = 0;
    for (int64_t t = 0; t < nt; t++) {
        const int64_t *tv = sp->tris + 3 * t;
        if (sp->tri_pair[2 * t] != pa || sp->tri_pair[2 * t + 1] != pb) { /* runs of one pair */
            pa = sp->tri_pair[2 * t];
            pb = sp->tri_pair[2 * t + 1];
            pair_out = output_pair(el, pa, pb, full);
        }
        int keep = pair_out &&
                   tri_area(sp->xyz + 3 * tv[0], sp->xyz + 3 * tv[1], sp->xyz + 3 * tv[2]) >= amin;
        /* Design 4.1: every vertex equidistant from the pair at its radius within 1e-9 L.
         * A guard: a vertex that is not takes its triangles out rather than spoil the
         * result.  (The extraction's boundary fallback once put one 0.41 off the bisector
         * by the full L-bracket's corner (10, 10, 40); since face_root_near_chord and
         * seam_polish in medial_sheets.c nothing is dropped on the test solids.) */
        for (int k = 0; k < 3 && keep; k++) {
            const double *p = sp->xyz + 3 * tv[k];
            double r = sp->radius[tv[k]];
            keep = fabs(md_dist_car(el, pa, p, NULL) - r) <= 1e-9 * el->diag &&
                   fabs(md_dist_car(el, pb, p, NULL) - r) <= 1e-9 * el->diag;
        }
        s->parent[t] = keep ? t : -1;
    }
    /* Components of one pair's triangles: triangles sharing a vertex (the soup welds a
     * vertex per (pair, lattice edge), so a vertex belongs to one pair). */
    for (int64_t t = 0; t < nt; t++) {
        if (s->parent[t] < 0)
            continue;
        for (int k = 0; k < 3; k++) {
            int64_t v = sp->tris[3 * t + k];
            if (first_tri[v] < 0)
                first_tri[v] = t;
            else
                mfg_uf_union(s->parent, first_tri[v], t);
        }
    }
    free(first_tri);
    int64_t nk = 0;
    for (int64_t t = 0; t < nt; t++)
        if (s->parent[t] >= 0)
            s->keys[nk++] = (tri_key){mfg_uf_find(s->parent, t), t};
    if (nk > 1)
        qsort(s->keys, (size_t)(nk), sizeof *s->keys, cmp_tri_key);
    int64_t nref = 0;
    for (int64_t i = 0; i < nk;) {
        int64_t j = i;
        double area = 0, lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        sheet_ref r;
        r.first = i;
        r.a = sp->tri_pair[2 * s->keys[i].t];
        r.b = sp->tri_pair[2 * s->keys[i].t + 1];
        for (int k = 0; k < 3; k++)
            r.minxyz[k] = INFINITY;
        while (j < nk && s->keys[j].root == s->keys[i].root) {
            const int64_t *tv = sp->tris + 3 * s->keys[j].t;
            area += tri_area(sp->xyz + 3 * tv[0], sp->xyz + 3 * tv[1], sp->xyz + 3 * tv[2]);
            for (int c = 0; c < 3; c++) {
                const double *p = sp->xyz + 3 * tv[c];
                if (cmp_xyz(p, r.minxyz) < 0)
                    memcpy(r.minxyz, p, sizeof r.minxyz);
                for (int k = 0; k < 3; k++) {
                    lo[k] = fmin(lo[k], p[k]);
                    hi[k] = fmax(hi[k], p[k]);
                }
            }
            j++;
        }
        r.ntri = j - i;
        /* Width ~ area / extent: slivers narrower than 1e-3 tolerance are not sheets
         * (the square prism's side pairs, trimmed down to its axis). */
        double ext = mfg_dist3(lo, hi);
        if (ext > 0 && area / ext >= 1e-3 * tol)
            s->refs[nref++] = r;
        i = j;
    }
    if (nref > 1)
        qsort(s->refs, (size_t)(nref), sizeof *s->refs, cmp_sheet);

    /* Counts, then the arrays. */
    int64_t totv = 0, tott = 0;
    for (int64_t r = 0; r < nref; r++) {
        tott += s->refs[r].ntri;
        for (int64_t i = s->refs[r].first; i < s->refs[r].first + s->refs[r].ntri; i++)
            for (int k = 0; k < 3; k++) {
                int64_t v = sp->tris[3 * s->keys[i].t + k];
                if (s->vsheet[v] < 0) {
                    s->vsheet[v] = r;
                    totv++;
                }
            }
    }
    m->nsheets = nref;
    m->sheet_elements = malloc((size_t)(2 * nref + 1) * sizeof(int64_t));
    m->sheet_forms = malloc((size_t)(nref + 1) * sizeof(int32_t));
    m->sheet_vertex_offsets = malloc((size_t)(nref + 1) * sizeof(int64_t));
    m->sheet_triangle_offsets = malloc((size_t)(nref + 1) * sizeof(int64_t));
    m->sheet_vertices = malloc((size_t)(3 * totv + 1) * sizeof(double));
    m->sheet_radii = malloc((size_t)(totv + 1) * sizeof(double));
    m->sheet_triangles = malloc((size_t)(3 * tott + 1) * sizeof(int64_t));
    if (!m->sheet_elements || !m->sheet_forms || !m->sheet_vertex_offsets ||
        !m->sheet_triangle_offsets || !m->sheet_vertices || !m->sheet_radii || !m->sheet_triangles)
        return MFG_ERR_NOMEM;
    /* Each sheet's vertices in ascending soup order (the soup's order is the lattice's). */
    int64_t vo = 0, to = 0;
    m->sheet_vertex_offsets[0] = 0;
    m->sheet_triangle_offsets[0] = 0;
    /* vertices of sheet r: scan the soup once, bucketed by sheet */
    int64_t *cnt = calloc((size_t)(nref + 1), sizeof(int64_t));
    int64_t *label = malloc((size_t)(nv ? nv : 1) * sizeof(int64_t));
    int64_t *vlabel = malloc((size_t)(totv ? totv : 1) * sizeof(int64_t));
    if (!cnt || !label || !vlabel) {
        free(cnt);
        free(label);
        free(vlabel);
        return MFG_ERR_NOMEM;
    }
    md_soup_seam_labels(sp, label);
    for (int64_t v = 0; v < nv; v++)
        if (s->vsheet[v] >= 0)
            cnt[s->vsheet[v] + 1]++;
    for (int64_t r = 0; r < nref; r++)
        cnt[r + 1] += cnt[r];
    for (int64_t r = 0; r <= nref; r++)
        m->sheet_vertex_offsets[r] = cnt[r];
    for (int64_t v = 0; v < nv; v++) {
        int64_t r = s->vsheet[v];
        if (r < 0)
            continue;
        int64_t at = cnt[r]++;
        s->vlocal[v] = at - m->sheet_vertex_offsets[r];
        memcpy(m->sheet_vertices + 3 * at, sp->xyz + 3 * v, 3 * sizeof(double));
        m->sheet_radii[at] = sp->radius[v];
        vlabel[at] = label[v];
    }
    free(cnt);
    free(label);
    vo = totv;
    for (int64_t r = 0; r < nref; r++) {
        const sheet_ref *R = &s->refs[r];
        m->sheet_elements[2 * r] = R->a;
        m->sheet_elements[2 * r + 1] = R->b;
        m->sheet_forms[r] = md_form(el, R->a, R->b);
        for (int64_t i = R->first; i < R->first + R->ntri; i++) {
            for (int k = 0; k < 3; k++)
                m->sheet_triangles[3 * to + k] = s->vlocal[sp->tris[3 * s->keys[i].t + k]];
            to++;
        }
        m->sheet_triangle_offsets[r + 1] = to;
    }
    (void)vo;
    /* Each sheet made coarse within the tolerance (md_sheet_simplify: kept vertices stay
     * where the extraction put them, on the bisector; corners and seams stay), then moved
     * down over the room the sheets before it freed. */
    int64_t wv = 0, wt = 0, v0 = 0, t0 = 0;
    for (int64_t r = 0; r < nref; r++) {
        /* a report per sheet: the first fifth of the assembly */
        if (!mfg_prog_poll(prog, (double)r, 5.0 * (double)nref)) {
            free(vlabel);
            return mfg_prog_fail(prog);
        }
        int64_t v1 = m->sheet_vertex_offsets[r + 1], t1 = m->sheet_triangle_offsets[r + 1];
        int64_t nvr = v1 - v0, ntr = t1 - t0;
        mfg_status st = md_sheet_simplify(el, m->sheet_elements[2 * r], m->sheet_elements[2 * r + 1],
                                          tol, vlabel + v0, &nvr, m->sheet_vertices + 3 * v0,
                                          m->sheet_radii + v0, &ntr, m->sheet_triangles + 3 * t0, NULL);
        if (st != MFG_OK) {
            free(vlabel);
            return st;
        }
        memmove(m->sheet_vertices + 3 * wv, m->sheet_vertices + 3 * v0, (size_t)(3 * nvr) * sizeof(double));
        memmove(m->sheet_radii + wv, m->sheet_radii + v0, (size_t)nvr * sizeof(double));
        memmove(m->sheet_triangles + 3 * wt, m->sheet_triangles + 3 * t0, (size_t)(3 * ntr) * sizeof(int64_t));
        m->sheet_vertex_offsets[r] = wv;
        m->sheet_triangle_offsets[r] = wt;
        wv += nvr;
        wt += ntr;
        v0 = v1;
        t0 = t1;
    }
    m->sheet_vertex_offsets[nref] = wv;
    m->sheet_triangle_offsets[nref] = wt;
    free(vlabel);
    /* Give the freed room back (a failing shrink keeps the larger block). */
    double *dv = realloc(m->sheet_vertices, (size_t)(3 * wv + 1) * sizeof(double));
    if (dv)
        m->sheet_vertices = dv;
    double *dr = realloc(m->sheet_radii, (size_t)(wv + 1) * sizeof(double));
    if (dr)
        m->sheet_radii = dr;
    int64_t *dt = realloc(m->sheet_triangles, (size_t)(3 * wt + 1) * sizeof(int64_t));
    if (dt)
        m->sheet_triangles = dt;
    return MFG_OK;
}

/* ---- pinholes -------------------------------------------------------------------------------- */

/* A directed side (u -> v) of a sheet triangle. */
typedef struct dside {
    int64_t u, v;
} dside;

static int cmp_dside_undirected(const void *pa, const void *pb)
{
    const dside *a = pa, *b = pb;
    int64_t a0 = a->u < a->v ? a->u : a->v, a1 = a->u < a->v ? a->v : a->u;
    int64_t b0 = b->u < b->v ? b->u : b->v, b1 = b->u < b->v ? b->v : b->u;
    if (a0 != b0)
        return a0 < b0 ? -1 : 1;
    if (a1 != b1)
        return a1 < b1 ? -1 : 1;
    return (a->u > b->u) - (a->u < b->u);
}

static int cmp_dside_from(const void *pa, const void *pb)
{
    const dside *a = pa, *b = pb;
    if (a->u != b->u)
        return a->u < b->u ? -1 : 1;
    return (a->v > b->v) - (a->v < b->v);
}

/* Closes the holes of a sheet narrower than tol / 4 (the bounding-box diagonal of the
 * hole's boundary loop, or twice its area over its perimeter for a sliver; the sheet's
 * largest loop, its outline, never).  Rotated off the lattice,
 * the 64-segment cup's bottom sheet had a hole 0.003 wide (tolerance 0.64) where three
 * leaves' trimmed polygons do not quite meet: not a feature of the medial surface at
 * this tolerance, but a boundary with no seam along it.  A hole is closed by a fan of
 * triangles on its loop, oriented with the sheet, spanning points on the bisector across
 * less than the tolerance.  The new triangles go after the sheet's own. */
static mfg_status close_pinholes(mfg_medial *m, double tol)
{
    int64_t maxt = 0;
    for (int64_t r = 0; r < m->nsheets; r++)
        if (m->sheet_triangle_offsets[r + 1] - m->sheet_triangle_offsets[r] > maxt)
            maxt = m->sheet_triangle_offsets[r + 1] - m->sheet_triangle_offsets[r];
    dside *sd = malloc((size_t)(3 * maxt + 1) * sizeof *sd);
    dside *bd = malloc((size_t)(3 * maxt + 1) * sizeof *bd);
    char *used = malloc((size_t)(3 * maxt + 1));
    int64_t *loop = malloc((size_t)(3 * maxt + 1) * sizeof *loop);
    int64_t *loop_off = malloc((size_t)(3 * maxt + 2) * sizeof *loop_off);
    ibuf fill = {0}; /* per new triangle: sheet, then its 3 local vertices */
    mfg_status st = MFG_OK;
    if (!sd || !bd || !used || !loop || !loop_off) {
        st = MFG_ERR_NOMEM;
        goto done;
    }
    for (int64_t r = 0; r < m->nsheets && st == MFG_OK; r++) {
        int64_t t0 = m->sheet_triangle_offsets[r], t1 = m->sheet_triangle_offsets[r + 1];
        const double *V = m->sheet_vertices + 3 * m->sheet_vertex_offsets[r];
        int64_t ns = 0, nb = 0;
        for (int64_t t = t0; t < t1; t++)
            for (int k = 0; k < 3; k++)
                sd[ns++] = (dside){m->sheet_triangles[3 * t + k], m->sheet_triangles[3 * t + (k + 1) % 3]};
        if (ns > 1)
            qsort(sd, (size_t)ns, sizeof *sd, cmp_dside_undirected);
        for (int64_t i = 0; i < ns;) {
            int64_t j = i + 1;
            while (j < ns && !((sd[j].u < sd[j].v ? sd[j].u : sd[j].v) != (sd[i].u < sd[i].v ? sd[i].u : sd[i].v) ||
                               (sd[j].u < sd[j].v ? sd[j].v : sd[j].u) != (sd[i].u < sd[i].v ? sd[i].v : sd[i].u)))
                j++;
            if (j - i == 1)
                bd[nb++] = sd[i];
            i = j;
        }
        if (nb < 6) /* an outline and a hole need >= 3 sides each */
            continue;
        qsort(bd, (size_t)nb, sizeof *bd, cmp_dside_from);
        memset(used, 0, (size_t)nb);
        int64_t nl = 0, nv = 0;
        loop_off[0] = 0;
        for (int64_t e = 0; e < nb; e++) {
            if (used[e])
                continue;
            int64_t start = bd[e].u, cur = e;
            int closed = 0;
            while (!used[cur]) {
                used[cur] = 1;
                loop[nv++] = bd[cur].u;
                if (bd[cur].v == start) {
                    closed = 1;
                    break;
                }
                /* the first unused side leaving the end vertex */
                int64_t lo = 0, hi = nb, w = bd[cur].v;
                while (lo < hi) {
                    int64_t mid = lo + (hi - lo) / 2;
                    if (bd[mid].u < w)
                        lo = mid + 1;
                    else
                        hi = mid;
                }
                while (lo < nb && bd[lo].u == w && used[lo])
                    lo++;
                if (lo == nb || bd[lo].u != w)
                    break;
                cur = lo;
            }
            if (!closed) { /* not a simple loop: leave this sheet alone */
                nl = 0;
                break;
            }
            loop_off[++nl] = nv;
        }
        if (nl < 2)
            continue;
        /* the outline: the loop of the largest box */
        double best = -1;
        int64_t outline = -1;
        double *diag = malloc((size_t)nl * sizeof *diag);
        if (!diag) {
            st = MFG_ERR_NOMEM;
            break;
        }
        for (int64_t l = 0; l < nl; l++) {
            double lo3[3] = {INFINITY, INFINITY, INFINITY}, hi3[3] = {-INFINITY, -INFINITY, -INFINITY};
            for (int64_t i = loop_off[l]; i < loop_off[l + 1]; i++)
                for (int k = 0; k < 3; k++) {
                    lo3[k] = fmin(lo3[k], V[3 * loop[i] + k]);
                    hi3[k] = fmax(hi3[k], V[3 * loop[i] + k]);
                }
            double d = mfg_dist3(lo3, hi3);
            if (d > best) {
                best = d;
                outline = l;
            }
            /* width: the bounding box, or for a sliver 2 area / perimeter (its
             * inradius when a triangle) */
            double nw[3] = {0, 0, 0}, per = 0;
            for (int64_t i = loop_off[l]; i < loop_off[l + 1]; i++) {
                int64_t j = i + 1 < loop_off[l + 1] ? i + 1 : loop_off[l];
                double c[3];
                mfg_cross3(V + 3 * loop[i], V + 3 * loop[j], c);
                for (int k = 0; k < 3; k++)
                    nw[k] += c[k];
                per += mfg_dist3(V + 3 * loop[i], V + 3 * loop[j]);
            }
            diag[l] = per > 0 ? fmin(d, mfg_norm3(nw) / per) : d;
        }
        for (int64_t l = 0; l < nl && st == MFG_OK; l++) {
            int64_t a = loop_off[l], n = loop_off[l + 1] - a;
            if (l == outline || n < 3 || !(diag[l] <= 0.25 * tol))
                continue;
            for (int64_t i = 1; i + 1 < n; i++)
                if (!ibuf_push(&fill, r) || !ibuf_push(&fill, loop[a]) ||
                    !ibuf_push(&fill, loop[a + i + 1]) || !ibuf_push(&fill, loop[a + i]))
                    st = MFG_ERR_NOMEM;
        }
        free(diag);
    }
    if (st != MFG_OK || fill.n == 0)
        goto done;
    {
        int64_t nf = fill.n / 4, tot = m->sheet_triangle_offsets[m->nsheets];
        int64_t *T = malloc((size_t)(3 * (tot + nf) + 1) * sizeof *T);
        if (!T) {
            st = MFG_ERR_NOMEM;
            goto done;
        }
        int64_t w = 0, f = 0;
        for (int64_t r = 0; r < m->nsheets; r++) {
            int64_t t0 = m->sheet_triangle_offsets[r], t1 = m->sheet_triangle_offsets[r + 1];
            memcpy(T + 3 * w, m->sheet_triangles + 3 * t0, (size_t)(3 * (t1 - t0)) * sizeof *T);
            m->sheet_triangle_offsets[r] = w;
            w += t1 - t0;
            for (; f < nf && fill.v[4 * f] == r; f++, w++)
                memcpy(T + 3 * w, fill.v + 4 * f + 1, 3 * sizeof *T);
        }
        m->sheet_triangle_offsets[m->nsheets] = w;
        free(m->sheet_triangles);
        m->sheet_triangles = T;
    }
done:
    free(sd);
    free(bd);
    free(used);
    free(loop);
    free(loop_off);
    free(fill.v);
    return st;
}

/* ---- seams ---------------------------------------------------------------------------------- */

/* Elements of a seam set at most (more: the segment keeps its own 3). */
#define SEAM_EMAX 8

/* A seam segment with its element set and the pair of the sheet it bounds. */
typedef struct seg_ref {
    int64_t e[SEAM_EMAX];
    int32_t ne;
    int32_t kind;
    int64_t pa, pb; /* the pair of the sheet the segment bounds */
    int64_t v0, v1; /* soup vertices, v0 < v1 */
} seg_ref;

static int cmp_set(const int64_t *a, int64_t na, const int64_t *b, int64_t nb)
{
    for (int64_t k = 0; k < na && k < nb; k++)
        if (a[k] != b[k])
            return a[k] < b[k] ? -1 : 1;
    return (na > nb) - (na < nb);
}

static int cmp_seg(const void *pa, const void *pb)
{
    const seg_ref *a = pa, *b = pb;
    int c = cmp_set(a->e, a->ne, b->e, b->ne);
    if (c)
        return c;
    if (a->pa != b->pa)
        return a->pa < b->pa ? -1 : 1;
    if (a->pb != b->pb)
        return a->pb < b->pb ? -1 : 1;
    if (a->v0 != b->v0)
        return a->v0 < b->v0 ? -1 : 1;
    return (a->v1 > b->v1) - (a->v1 < b->v1);
}

/* A polyline under construction. */
typedef struct polyline {
    dbuf pts, rad;
} polyline;

/* Thinning (design 4.2): drop interior points while every dropped point stays within
 * tol of the chord that replaces it. */
static void thin(polyline *pl, double tol)
{
    int64_t n = pl->rad.n;
    if (n <= 2)
        return;
    double *P = pl->pts.v, *R = pl->rad.v;
    int64_t w = 1, a = 0;
    for (int64_t i = 1; i < n;) {
        /* extend the chord a -> j as far as possible */
        int64_t j = i + 1;
        for (; j < n; j++) {
            const double *A = P + 3 * a, *B = P + 3 * j;
            double ab[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]};
            double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
            int ok = 1;
            for (int64_t q = a + 1; q < j && ok; q++) {
                const double *Q = P + 3 * q;
                double aq[3] = {Q[0] - A[0], Q[1] - A[1], Q[2] - A[2]};
                double t = l2 > 0 ? (aq[0] * ab[0] + aq[1] * ab[1] + aq[2] * ab[2]) / l2 : 0;
                t = t < 0 ? 0 : (t > 1 ? 1 : t);
                double d[3] = {aq[0] - t * ab[0], aq[1] - t * ab[1], aq[2] - t * ab[2]};
                ok = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) <= tol;
            }
            if (!ok)
                break;
        }
        int64_t keep = j - 1; /* the farthest point the chord from a reaches */
        memmove(P + 3 * w, P + 3 * keep, 3 * sizeof(double));
        R[w] = R[keep];
        w++;
        a = keep;
        i = keep + 1;
    }
    pl->pts.n = 3 * w;
    pl->rad.n = w;
}

static void polyline_reverse(polyline *pl)
{
    int64_t n = pl->rad.n;
    for (int64_t i = 0; i < n / 2; i++) {
        double t[3], r = pl->rad.v[i];
        memcpy(t, pl->pts.v + 3 * i, sizeof t);
        memcpy(pl->pts.v + 3 * i, pl->pts.v + 3 * (n - 1 - i), sizeof t);
        memcpy(pl->pts.v + 3 * (n - 1 - i), t, sizeof t);
        pl->rad.v[i] = pl->rad.v[n - 1 - i];
        pl->rad.v[n - 1 - i] = r;
    }
}

/* The output seams under construction. */
typedef struct seam_out {
    int64_t n;
    ibuf kinds, pt_off, el_off, elems, ends;
    dbuf pts, rad;
} seam_out;

/* One seam record for the final sort. */
typedef struct seam_rec {
    int64_t e_off, ne, p_off, np, end0, end1;
    int32_t kind;
} seam_rec;

static void seam_out_free(seam_out *o)
{
    free(o->kinds.v);
    free(o->pt_off.v);
    free(o->el_off.v);
    free(o->elems.v);
    free(o->ends.v);
    free(o->pts.v);
    free(o->rad.v);
}

/* Appends a finished polyline as a seam: snapped ends, thinned. */
static int emit_seam(seam_out *o, polyline *pl, const int64_t *set, int64_t ns, int32_t kind,
                     const md_junction *J, int64_t nj, double reach, double tol)
{
    if (pl->rad.n < 1)
        return 1;
    /* Orientation: from the lexicographically smaller end. */
    int64_t n = pl->rad.n;
    if (cmp_xyz_tol(pl->pts.v + 3 * (n - 1), pl->pts.v, 1e-9 * tol) < 0)
        polyline_reverse(pl);
    int64_t e0 = snap_junction(J, nj, pl->pts.v, set, ns, reach);
    int64_t e1 = snap_junction(J, nj, pl->pts.v + 3 * (n - 1), set, ns, reach);
    if (e0 >= 0 && e0 == e1) {
        /* Both ends at one junction and nothing farther than 2h from it: a stub of the
         * seam's polyline where its segments break near the junction, not a seam. */
        int stub = 1;
        for (int64_t i = 0; i < n && stub; i++)
            stub = mfg_dist3(J[e0].x, pl->pts.v + 3 * i) <= reach;
        if (stub)
            return 1;
    }
    /* Snap: the junction point becomes the end (prepended / appended unless the end is
     * already there) - the paper's eq. 3. */
    polyline q = {{0}, {0}};
    int ok = 1;
    if (e0 >= 0 && mfg_dist3(J[e0].x, pl->pts.v) > 0) {
        ok &= dbuf_push(&q.pts, J[e0].x[0]) && dbuf_push(&q.pts, J[e0].x[1]) &&
              dbuf_push(&q.pts, J[e0].x[2]) && dbuf_push(&q.rad, J[e0].r);
    }
    for (int64_t i = 0; i < n && ok; i++)
        ok &= dbuf_push(&q.pts, pl->pts.v[3 * i]) && dbuf_push(&q.pts, pl->pts.v[3 * i + 1]) &&
              dbuf_push(&q.pts, pl->pts.v[3 * i + 2]) && dbuf_push(&q.rad, pl->rad.v[i]);
    if (ok && e1 >= 0 && mfg_dist3(J[e1].x, pl->pts.v + 3 * (n - 1)) > 0)
        ok &= dbuf_push(&q.pts, J[e1].x[0]) && dbuf_push(&q.pts, J[e1].x[1]) &&
              dbuf_push(&q.pts, J[e1].x[2]) && dbuf_push(&q.rad, J[e1].r);
    if (ok && q.rad.n >= 2) {
        thin(&q, tol / 4);
        if (o->n == 0)
            ok &= ibuf_push(&o->pt_off, 0) && ibuf_push(&o->el_off, 0);
        for (int64_t i = 0; i < q.pts.n && ok; i++)
            ok &= dbuf_push(&o->pts, q.pts.v[i]);
        for (int64_t i = 0; i < q.rad.n && ok; i++)
            ok &= dbuf_push(&o->rad, q.rad.v[i]);
        for (int64_t i = 0; i < ns && ok; i++)
            ok &= ibuf_push(&o->elems, set[i]);
        ok = ok && ibuf_push(&o->pt_off, o->rad.n) && ibuf_push(&o->el_off, o->elems.n) &&
             ibuf_push(&o->kinds, kind) && ibuf_push(&o->ends, e0) && ibuf_push(&o->ends, e1);
        if (ok)
            o->n++;
    }
    free(q.pts.v);
    free(q.rad.v);
    return ok;
}

/* The polylines of one seam before they are emitted. */
typedef struct pieces {
    polyline *p;
    int64_t n, cap;
} pieces;

static void pieces_free(pieces *pc)
{
    for (int64_t i = 0; i < pc->n; i++) {
        free(pc->p[i].pts.v);
        free(pc->p[i].rad.v);
    }
    free(pc->p);
}

/* Moves pl into pc (pl is left empty). */
static int pieces_take(pieces *pc, polyline *pl)
{
    polyline *v = grow_for(pc->p, pc->n, &pc->cap, sizeof *v);
    if (!v)
        return 0;
    pc->p = v;
    pc->p[pc->n++] = *pl;
    memset(pl, 0, sizeof *pl);
    return 1;
}

/* Joins pieces whose ends are within gap, the nearest ends first (ties: the earlier
 * pieces), until none is left: the trimmed polygons of neighbouring leaves do not always
 * meet (the L-bracket's smooth seams in full mode break every leaf or two). */
static int pieces_join(pieces *pc, double gap)
{
    for (;;) {
        double best = INFINITY;
        int64_t bi = -1, bj = -1;
        int be = 0;
        for (int64_t i = 0; i < pc->n; i++)
            for (int64_t j = i + 1; j < pc->n; j++)
                for (int e = 0; e < 4; e++) { /* e & 1: i's last end; e & 2: j's last end */
                    const polyline *a = &pc->p[i], *b = &pc->p[j];
                    const double *pa = a->pts.v + ((e & 1) ? 3 * (a->rad.n - 1) : 0);
                    const double *pb = b->pts.v + ((e & 2) ? 3 * (b->rad.n - 1) : 0);
                    double d = mfg_dist3(pa, pb);
                    if (d <= gap && d < best) {
                        best = d;
                        bi = i;
                        bj = j;
                        be = e;
                    }
                }
        if (bi < 0)
            return 1;
        polyline *a = &pc->p[bi], *b = &pc->p[bj];
        if (!(be & 1))
            polyline_reverse(a); /* a now ends at the joined end */
        if (be & 2)
            polyline_reverse(b); /* b now starts there */
        int skip = mfg_dist3(a->pts.v + 3 * (a->rad.n - 1), b->pts.v) == 0;
        for (int64_t i = skip; i < b->rad.n; i++)
            if (!dbuf_push(&a->pts, b->pts.v[3 * i]) || !dbuf_push(&a->pts, b->pts.v[3 * i + 1]) ||
                !dbuf_push(&a->pts, b->pts.v[3 * i + 2]) || !dbuf_push(&a->rad, b->rad.v[i]))
                return 0;
        free(b->pts.v);
        free(b->rad.v);
        memmove(pc->p + bj, pc->p + bj + 1, (size_t)(pc->n - bj - 1) * sizeof *pc->p);
        pc->n--;
    }
}

/* Distance from p to the polyline P (n points). */
static double polyline_dist(const double *P, int64_t n, const double *p)
{
    double best = n ? mfg_dist3(P, p) : INFINITY;
    for (int64_t i = 0; i + 1 < n; i++) {
        const double *A = P + 3 * i, *B = A + 3;
        double ab[3] = {B[0] - A[0], B[1] - A[1], B[2] - A[2]}, ap[3] = {p[0] - A[0], p[1] - A[1], p[2] - A[2]};
        double l2 = ab[0] * ab[0] + ab[1] * ab[1] + ab[2] * ab[2];
        double t = l2 > 0 ? (ap[0] * ab[0] + ap[1] * ab[1] + ap[2] * ab[2]) / l2 : 0;
        t = t < 0 ? 0 : (t > 1 ? 1 : t);
        double q[3] = {A[0] + t * ab[0], A[1] + t * ab[1], A[2] + t * ab[2]};
        best = fmin(best, mfg_dist3(q, p));
    }
    return best;
}

/* Is the polyline within tol of one of the first ndeg seams of o (the degenerate ones),
 * whose set holds the set s?  In full mode the square prism's diagonal sheets end on its
 * axis, and their boundary segments there name 3 of the 4 sides: the axis is the
 * degenerate seam, once. */
static int covered_by_degenerate(const seam_out *o, int64_t ndeg, const polyline *pl,
                                 const int64_t *s, int64_t ns, double tol)
{
    for (int64_t k = 0; k < ndeg; k++) {
        int64_t e0 = o->el_off.v[k], e1 = o->el_off.v[k + 1];
        if (!subset_of(s, ns, o->elems.v + e0, e1 - e0))
            continue;
        const double *P = o->pts.v + 3 * o->pt_off.v[k];
        int64_t np = o->pt_off.v[k + 1] - o->pt_off.v[k], i = 0;
        while (i < pl->rad.n && polyline_dist(P, np, pl->pts.v + 3 * i) <= tol)
            i++;
        if (i == pl->rad.n)
            return 1;
    }
    return 0;
}

/* Chains the segments seg[0 .. n) (one element set, one pair) into polylines, joined
 * across gaps up to gap, into *out. */
static int chain_segments(const md_soup *sp, const seg_ref *seg, int64_t n, double gap,
                          pieces *out)
{
    /* Vertex degrees over this group: a sorted vertex list, adjacency by segment. */
    int64_t *vs = malloc((size_t)(2 * n) * sizeof *vs);
    int64_t *adj_off = calloc((size_t)(2 * n + 1), sizeof *adj_off);
    int64_t *adj = malloc((size_t)(2 * n) * sizeof *adj);
    char *used = calloc((size_t)n, 1);
    int ok = vs && adj_off && adj && used;
    polyline pl = {{0}, {0}};
    pieces pc = {0};
    int64_t nvs = 0;
    if (ok) {
        for (int64_t i = 0; i < n; i++) {
            vs[2 * i] = seg[i].v0;
            vs[2 * i + 1] = seg[i].v1;
        }
        if (2 * n > 1)
            qsort(vs, (size_t)(2 * n), sizeof *vs, mfg_cmp_i64);
        for (int64_t i = 0; i < 2 * n; i++)
            if (nvs == 0 || vs[nvs - 1] != vs[i])
                vs[nvs++] = vs[i];
    }
#define VIDX(v) ((int64_t *)bsearch(&(v), vs, (size_t)nvs, sizeof *vs, mfg_cmp_i64) - vs)
    if (ok) {
        for (int64_t i = 0; i < n; i++) {
            adj_off[VIDX(seg[i].v0) + 1]++;
            adj_off[VIDX(seg[i].v1) + 1]++;
        }
        for (int64_t i = 0; i < nvs; i++)
            adj_off[i + 1] += adj_off[i];
        int64_t *fill = malloc((size_t)(nvs + 1) * sizeof *fill);
        ok = fill != NULL;
        if (ok) {
            memcpy(fill, adj_off, (size_t)(nvs + 1) * sizeof *fill);
            for (int64_t i = 0; i < n; i++) {
                adj[fill[VIDX(seg[i].v0)]++] = i;
                adj[fill[VIDX(seg[i].v1)]++] = i;
            }
            free(fill);
        }
    }
    /* Walk from every vertex of degree != 2 (in vertex order), then the cycles. */
    for (int pass = 0; pass < 2 && ok; pass++)
        for (int64_t vi = 0; vi < nvs && ok; vi++) {
            int64_t deg = adj_off[vi + 1] - adj_off[vi];
            if (pass == 0 && deg == 2)
                continue;
            for (int64_t q = adj_off[vi]; q < adj_off[vi + 1] && ok; q++) {
                int64_t s = adj[q];
                if (used[s])
                    continue;
                pl.pts.n = pl.rad.n = 0;
                int64_t v = vs[vi];
                ok &= dbuf_push(&pl.pts, sp->xyz[3 * v]) && dbuf_push(&pl.pts, sp->xyz[3 * v + 1]) &&
                      dbuf_push(&pl.pts, sp->xyz[3 * v + 2]) && dbuf_push(&pl.rad, sp->radius[v]);
                while (ok && s >= 0) {
                    used[s] = 1;
                    v = seg[s].v0 == v ? seg[s].v1 : seg[s].v0;
                    ok &= dbuf_push(&pl.pts, sp->xyz[3 * v]) && dbuf_push(&pl.pts, sp->xyz[3 * v + 1]) &&
                          dbuf_push(&pl.pts, sp->xyz[3 * v + 2]) && dbuf_push(&pl.rad, sp->radius[v]);
                    int64_t w = VIDX(v), nxt = -1;
                    if (adj_off[w + 1] - adj_off[w] == 2)
                        for (int64_t r = adj_off[w]; r < adj_off[w + 1]; r++)
                            if (!used[adj[r]])
                                nxt = adj[r];
                    s = nxt;
                }
                if (ok)
                    ok = pieces_take(&pc, &pl);
            }
        }
#undef VIDX
    /* The pieces of one seam, joined across the gaps the sampling leaves. */
    if (ok)
        ok = pieces_join(&pc, gap);
    if (ok)
        *out = pc;
    else
        pieces_free(&pc);
    free(pl.pts.v);
    free(pl.rad.v);
    free(vs);
    free(adj_off);
    free(adj);
    free(used);
    return ok;
}

/* The element set of a segment: the elements touching at both of its ends, with the
 * three the sheet extraction named (its boundary points are exact up to rounding, not to
 * 1e-9 L everywhere).  Where a sheet passes into another across a line that 4 elements
 * keep equidistant (a T-section's web sheet {x = 25, x = 35} into {both reflex edges} at
 * y = 10) the extraction names one of two equally near trimming elements per segment;
 * the touching set names all four, so the seam is chained as one. */
/* The touching sets of the soup's vertices, each computed once (a seam vertex ends two
 * segments): off[v] < 0 not yet, else the offset of v's set (cnt[v] ids) in pool. */
typedef struct tcache {
    int64_t *off;
    int32_t *cnt;
    int64_t *pool;
    int64_t n, cap;
} tcache;

/* md_touching_set of soup vertex v (at most MD_JMAX ids), through the cache: the count,
 * -1 on NOMEM. */
static int touching_of(const md_elements *el, const md_bvh *bvh, const md_soup *sp, tcache *tc,
                       int64_t v, const int64_t **set)
{
    if (tc->off[v] < 0) {
        int64_t t[MD_JMAX];
        int n = md_touching_set(el, bvh, sp->xyz + 3 * v, t, MD_JMAX, NULL);
        if (n < 0)
            return -1;
        if (n > MD_JMAX)
            n = MD_JMAX; /* only MD_JMAX were written */
        if (tc->n + n > tc->cap) {
            int64_t cap = tc->cap ? 2 * tc->cap : 1024;
            while (cap < tc->n + n)
                cap *= 2;
            int64_t *p = realloc(tc->pool, (size_t)cap * sizeof *p);
            if (!p)
                return -1;
            tc->pool = p;
            tc->cap = cap;
        }
        memcpy(tc->pool + tc->n, t, (size_t)n * sizeof *t);
        tc->off[v] = tc->n;
        tc->cnt[v] = n;
        tc->n += n;
    }
    *set = tc->pool + tc->off[v];
    return tc->cnt[v];
}

static int segment_set(const md_elements *el, const md_bvh *bvh, const md_soup *sp, tcache *tc,
                       int64_t i, int64_t *set)
{
    const int64_t *s0, *s1;
    const int64_t *own = sp->seg_elems + 3 * i;
    int n0 = touching_of(el, bvh, sp, tc, sp->seg_verts[2 * i], &s0);
    if (n0 < 0)
        return -1;
    int n1 = touching_of(el, bvh, sp, tc, sp->seg_verts[2 * i + 1], &s1);
    if (n1 < 0)
        return -1;
    s0 = tc->pool + tc->off[sp->seg_verts[2 * i]]; /* the pool may have moved */
    int n = 0;
    /* (s0 and s1) or own: merge of sorted lists */
    for (int a = 0, b = 0, c = 0; a < n0 || c < 3;) {
        int64_t v = INT64_MAX;
        if (a < n0)
            v = s0[a];
        if (c < 3 && own[c] < v)
            v = own[c];
        int in_own = c < 3 && own[c] == v, in0 = a < n0 && s0[a] == v;
        while (b < n1 && s1[b] < v)
            b++;
        int in1 = b < n1 && s1[b] == v;
        if (in_own || (in0 && in1)) {
            if (n == SEAM_EMAX) {
                memcpy(set, own, 3 * sizeof *set);
                return 3;
            }
            set[n++] = v;
        }
        a += in0;
        c += in_own;
    }
    return n;
}

/* Seams chained but not yet emitted: their ends are snapped only once every junction is
 * known (recover_junctions below adds the ones the leaf search missed). */
typedef struct pend_seam {
    polyline pl;
    int64_t e[SEAM_EMAX];
    int32_t ne, kind;
} pend_seam;

typedef struct pend_list {
    pend_seam *v;
    int64_t n, cap;
} pend_list;

static void pend_free(pend_list *pl)
{
    for (int64_t i = 0; i < pl->n; i++) {
        free(pl->v[i].pl.pts.v);
        free(pl->v[i].pl.rad.v);
    }
    free(pl->v);
    memset(pl, 0, sizeof *pl);
}

/* Moves the polyline into the list (it is left empty). */
static int pend_take(pend_list *pl, polyline *line, const int64_t *set, int32_t ne, int32_t kind)
{
    pend_seam *v = grow_for(pl->v, pl->n, &pl->cap, sizeof *v);
    if (!v)
        return 0;
    pl->v = v;
    pend_seam *q = &pl->v[pl->n++];
    memset(q, 0, sizeof *q);
    q->pl = *line;
    memset(line, 0, sizeof *line);
    memcpy(q->e, set, (size_t)ne * sizeof *set);
    q->ne = ne;
    q->kind = kind;
    return 1;
}

/* The seams of the soup (design 4.2): per element set, the segments of its smallest pair
 * that bounds an output sheet. */
static int soup_seams(const md_elements *el, const md_bvh *bvh, const md_soup *sp,
                      const asm_state *s, const seam_out *o, int64_t ndeg, double reach,
                      double tol, pend_list *out)
{
    seg_ref *seg = malloc((size_t)(sp->nsegs ? sp->nsegs : 1) * sizeof *seg);
    tcache tc = {malloc((size_t)(sp->nverts ? sp->nverts : 1) * sizeof *tc.off),
                 malloc((size_t)(sp->nverts ? sp->nverts : 1) * sizeof *tc.cnt), NULL, 0, 0};
    if (!seg || !tc.off || !tc.cnt) {
        free(seg);
        free(tc.off);
        free(tc.cnt);
        return 0;
    }
    for (int64_t v = 0; v < sp->nverts; v++)
        tc.off[v] = -1;
    int64_t n = 0;
    for (int64_t i = 0; i < sp->nsegs; i++) {
        int64_t v0 = sp->seg_verts[2 * i], v1 = sp->seg_verts[2 * i + 1];
        if (v0 == v1 || s->vsheet[v0] < 0 || s->vsheet[v1] < 0)
            continue; /* not on an output sheet */
        seg_ref r;
        memset(&r, 0, sizeof r);
        int ne = segment_set(el, bvh, sp, &tc, i, r.e);
        if (ne < 0) {
            free(seg);
            free(tc.off);
            free(tc.cnt);
            free(tc.pool);
            return 0;
        }
        r.ne = ne;
        r.pa = sp->seg_pair[2 * i];
        r.pb = sp->seg_pair[2 * i + 1];
        r.v0 = v0 < v1 ? v0 : v1;
        r.v1 = v0 < v1 ? v1 : v0;
        r.kind = sp->seg_kind[i];
        seg[n++] = r;
    }
    free(tc.off);
    free(tc.cnt);
    free(tc.pool);
    if (n > 1)
        qsort(seg, (size_t)(n), sizeof *seg, cmp_seg);
    /* unique */
    int64_t m = 0;
    for (int64_t i = 0; i < n; i++)
        if (m == 0 || cmp_seg(&seg[m - 1], &seg[i]) != 0)
            seg[m++] = seg[i];
    /* Per element set, the pair whose segments chain into the fewest pieces (ties: the
     * smallest pair, design 4.2): a sheet's trimmed boundary can break between leaves
     * where another sheet's does not (the T-section's web sheet along y = 10). */
    int ok = 1;
    for (int64_t i = 0; i < m && ok;) {
        pieces best = {0};
        int have = 0;
        int64_t k = i;
        while (ok && k < m && !cmp_set(seg[k].e, seg[k].ne, seg[i].e, seg[i].ne)) {
            int64_t j = k;
            while (j < m && !cmp_set(seg[j].e, seg[j].ne, seg[k].e, seg[k].ne) &&
                   seg[j].pa == seg[k].pa && seg[j].pb == seg[k].pb)
                j++;
            pieces pc = {0};
            ok = chain_segments(sp, seg + k, j - k, 1.5 * reach, &pc);
            if (ok && (!have || pc.n < best.n)) {
                pieces_free(&best);
                best = pc;
                have = 1;
            } else if (ok) {
                pieces_free(&pc);
            }
            k = j;
        }
        for (int64_t p = 0; p < best.n && ok; p++)
            if (!covered_by_degenerate(o, ndeg, &best.p[p], seg[i].e, seg[i].ne, tol))
                ok = pend_take(out, &best.p[p], seg[i].e, seg[i].ne, seg[i].kind);
        pieces_free(&best);
        i = k;
    }
    free(seg);
    return ok;
}

/* Degenerate seams from the rank-2 points: per element set, ordered along the tangent,
 * split where consecutive points are more than 2 leaf diagonals apart. */
typedef struct dpt {
    const md_junction *j;
    double t;
} dpt;

static int cmp_dpt(const void *pa, const void *pb)
{
    const dpt *a = pa, *b = pb;
    if (a->t != b->t)
        return a->t < b->t ? -1 : 1;
    return cmp_xyz(a->j->x, b->j->x);
}

static int degenerate_seams(const md_elements *el, md_junction *P, int64_t np, seam_out *o,
                            const md_junction *J, int64_t nj, double h, double tol, int full)
{
    if (np > 1)
        qsort(P, (size_t)(np), sizeof *P, cmp_junction);
    dpt *d = malloc((size_t)(np ? np : 1) * sizeof *d);
    if (!d)
        return 0;
    int ok = 1;
    polyline pl = {{0}, {0}};
    for (int64_t i = 0; i < np && ok;) {
        int64_t j = i;
        while (j < np && same_set(&P[j], &P[i]))
            j++;
        if (set_has_output_pair(el, P[i].elems, P[i].n, full)) {
            /* the group's tangent: the first point's (signed canonically) */
            const double *u = P[i].dir;
            for (int64_t k = i; k < j; k++)
                d[k - i] = (dpt){&P[k], P[k].x[0] * u[0] + P[k].x[1] * u[1] + P[k].x[2] * u[2]};
            int64_t n = j - i;
            if (n > 1)
                qsort(d, (size_t)(n), sizeof *d, cmp_dpt);
            double gap = 2 * sqrt(3.0) * h;
            for (int64_t a = 0; a < n && ok;) {
                int64_t b = a + 1;
                while (b < n && mfg_dist3(d[b - 1].j->x, d[b].j->x) <= gap)
                    b++;
                pl.pts.n = pl.rad.n = 0;
                for (int64_t k = a; k < b && ok; k++) {
                    /* points closer than h / 4 to the last kept one add nothing */
                    if (pl.rad.n && mfg_dist3(pl.pts.v + pl.pts.n - 3, d[k].j->x) < 0.25 * h)
                        continue;
                    ok &= dbuf_push(&pl.pts, d[k].j->x[0]) && dbuf_push(&pl.pts, d[k].j->x[1]) &&
                          dbuf_push(&pl.pts, d[k].j->x[2]) && dbuf_push(&pl.rad, d[k].j->r);
                }
                if (ok)
                    ok = emit_seam(o, &pl, P[i].elems, P[i].n, MFG_MEDIAL_DEGENERATE, J, nj,
                                   2 * h, tol);
                a = b;
            }
        }
        i = j;
    }
    free(pl.pts.v);
    free(pl.rad.v);
    free(d);
    return ok;
}

/* ---- junctions where seams meet (recovery after the leaf search) -------------------------- */

/* A seam end that no junction explains. */
typedef struct free_end {
    double x[3];
    int64_t seam;
    int32_t resolved;
} free_end;

static int cmp_free_end(const void *pa, const void *pb)
{
    const free_end *a = pa, *b = pb;
    int c = cmp_xyz(a->x, b->x);
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
    md_junction *v = grow_for(l->v, l->n, &l->cap, sizeof *v);
    if (!v)
        return 0;
    l->v = v;
    l->v[l->n++] = *j;
    return 1;
}

/* Is there a junction within reach of p whose set holds s: in J (sorted by point) or in
 * the list (short: the junctions found so far by the assembly)? */
static int near_junction(const md_junction *J, int64_t nj, const jlist *add, const double *p,
                         const int64_t *s, int64_t ns, double reach)
{
    if (snap_junction(J, nj, p, s, ns, reach) >= 0)
        return 1;
    for (int64_t i = 0; i < add->n; i++)
        if (mfg_dist3(add->v[i].x, p) <= reach && subset_of(s, ns, add->v[i].elems, add->v[i].n))
            return 1;
    return 0;
}

static int polyline_push(polyline *pl, const double *x, double r)
{
    return dbuf_push(&pl->pts, x[0]) && dbuf_push(&pl->pts, x[1]) && dbuf_push(&pl->pts, x[2]) &&
           dbuf_push(&pl->rad, r);
}

/* Pass 1 of recover_junctions: the unions of the sets of two free seam ends within
 * reach of each other (and the set of a seam of >= 4 elements). */
static int junctions_from_unions(const md_elements *el, const md_bvh *bvh, const pend_list *pl,
                                 const md_junction *J, int64_t nj, double reach, double tol,
                                 jlist *add)
{
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
            if (snap_junction(J, nj, p, ps->e, ps->ne, reach) >= 0)
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
            int r = md_junction_polish(el, bvh, x0, T, nT, lo, 2 * reach, tol, &j);
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
                    subset_of(c->e, c->ne, j.elems, j.n))
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
    int c = cmp_set(x->e, x->ne, y->e, y->ne);
    return c ? c : (a->i > b->i) - (a->i < b->i);
}

/* Steps along a seam of at most this many (a gap of 2^8 half leaves stays open). */
#define TRACE_STEPS 256

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
static int trace_seam(const md_elements *el, const md_bvh *bvh, pend_list *pl, int64_t i,
                      const set_ord *ord, int64_t g0, int64_t g1, const md_junction *J,
                      int64_t nj, jlist *add, double h, double reach, double tol)
{
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
        if (nw <= MD_JMAX && subset_of(S, ns, W, nw)) {
            /* still on the seam */
            if (!polyline_push(L, y, D))
                return 0;
            x = L->pts.v + 3 * n; /* the buffer may have moved */
            step = 0.5 * h;
            if (near_junction(J, nj, add, y, S, ns, reach))
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
                if (fmin(d0, d1) <= reach && !near_junction(J, nj, add, e ? p1 : p0, S, ns, reach)) {
                    /* join: o's near end first */
                    if (e)
                        polyline_reverse(&o->pl);
                    for (int64_t k = 0; k < m; k++)
                        if (!polyline_push(L, o->pl.pts.v + 3 * k, o->pl.rad.v[k]))
                            return 0;
                    free(o->pl.pts.v);
                    free(o->pl.rad.v);
                    memset(&o->pl, 0, sizeof o->pl);
                    if (near_junction(J, nj, add, L->pts.v + 3 * (L->rad.n - 1), S, ns, reach))
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
            if (!subset_of(&W[k], 1, S, ns))
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
            int r = md_junction_polish(el, bvh, mid, T, nT, lo, 2 * step, tol, &j);
            if (r < 0)
                return 0;
            if (r == 1 && j.rank == 3 && subset_of(S, ns, j.elems, j.n)) {
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
                while (k < n && polyline_dist(o->pl.pts.v, o->pl.rad.n, q->pl.pts.v + 3 * k) <= reach)
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
 * the found junctions merged in (merge_junctions; the caller frees it when it differs
 * from its own, also after a failure); the pending seams may be extended and joined.
 * 1, or 0 on NOMEM. */
static int merge_added(const md_elements *el, md_junction **J, int64_t *nj, int *own, jlist *add,
                       double tol, int full)
{
    if (add->n == 0)
        return 1;
    md_junction *all = malloc((size_t)(*nj + add->n) * sizeof *all);
    if (!all)
        return 0;
    if (*nj)
        memcpy(all, *J, (size_t)*nj * sizeof *all);
    memcpy(all + *nj, add->v, (size_t)add->n * sizeof *all);
    int64_t n = merge_junctions(el, all, *nj + add->n, tol, full);
    if (*own)
        free(*J);
    *J = all;
    *nj = n;
    *own = 1;
    add->n = 0;
    return 1;
}

static int recover_junctions(const md_elements *el, const md_bvh *bvh, pend_list *pl,
                             md_junction **J, int64_t *nj, double h, double reach, double tol,
                             int full)
{
    jlist add = {0};
    int own = 0;
    set_ord *ord = malloc((size_t)(pl->n + 1) * sizeof *ord);
    /* the unions' junctions are merged in (sorted by point) before tracing: the walks
     * look them up by their x-slab, and the list they scan holds only their own finds */
    int ok = ord && junctions_from_unions(el, bvh, pl, *J, *nj, reach, tol, &add) &&
             merge_added(el, J, nj, &own, &add, tol, full);
    if (ok) {
        for (int64_t i = 0; i < pl->n; i++)
            ord[i] = (set_ord){pl, i};
        if (pl->n > 1)
            qsort(ord, (size_t)pl->n, sizeof *ord, cmp_set_ord);
    }
    for (int64_t g = 0; g < pl->n && ok;) {
        int64_t g1 = g + 1;
        while (g1 < pl->n && !cmp_set(pl->v[ord[g1].i].e, pl->v[ord[g1].i].ne, pl->v[ord[g].i].e,
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
                polyline_reverse(&ps->pl);
                const double *p = ps->pl.pts.v + 3 * (n - 1);
                if (!near_junction(*J, *nj, &add, p, ps->e, ps->ne, reach))
                    ok = trace_seam(el, bvh, pl, ord[k].i, ord, g, g1, *J, *nj, &add, h, reach, tol);
            }
        }
        if (ok)
            drop_covered_pieces(pl, ord, g, g1, reach);
        g = g1;
    }
    free(ord);
    ok = ok && merge_added(el, J, nj, &own, &add, tol, full);
    free(add.v);
    return ok;
}

/* ---- sheets narrower than the tolerance -------------------------------------------------- */

/* (a, b, seam): the seams whose set holds a pair, for drop_narrow_sheets. */
typedef struct pair_seam {
    int64_t a, b, seam;
} pair_seam;

static int cmp_pair_seam(const void *pa, const void *pb)
{
    const pair_seam *x = pa, *y = pb;
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    return (x->seam > y->seam) - (x->seam < y->seam);
}

/* Is p within d of a seam of ps[lo .. hi)? */
static int near_seams(const seam_out *o, const pair_seam *ps, int64_t lo, int64_t hi,
                      const double *p, double d)
{
    for (int64_t k = lo; k < hi; k++) {
        int64_t i = ps[k].seam, p0 = o->pt_off.v[i], np = o->pt_off.v[i + 1] - p0;
        if (polyline_dist(o->pts.v + 3 * p0, np, p) <= d)
            return 1;
    }
    return 0;
}

/* Drops the sheets that lie within the tolerance of their own seams.  A bisector sheet
 * narrower than a leaf (on a tessellated wall, a facet against a reflex edge of the
 * facing wall: a strip in the edge's Voronoi wedge, 2 pi / n wide) is sampled by the
 * leaves only where it happens to cross them: a rotated 64-segment cup gave 3 592
 * one-triangle sheets, one strip in up to 33 pieces.  Its seams (traced, recover_junctions)
 * already carry it within the tolerance, so such pieces add nothing but clutter.  A sheet
 * goes when, for every triangle (sides at most NARROW_GRID tol / 2), the points of a
 * barycentric grid of spacing <= tol / 2 lie within tol / 2 of seams whose set holds the
 * sheet's pair: every point of it is then within tol / 2 + tol / (2 sqrt 3) < tol of
 * those seams, so the result stays complete within the tolerance. */
#define NARROW_GRID 16
static mfg_status drop_narrow_sheets(const seam_out *o, double tol, mfg_medial *m)
{
    int64_t cnt = 0;
    for (int64_t i = 0; i < o->n; i++) {
        int64_t ne = o->el_off.v[i + 1] - o->el_off.v[i];
        cnt += ne * (ne - 1) / 2;
    }
    pair_seam *ps = malloc((size_t)(cnt + 1) * sizeof *ps);
    if (!ps)
        return MFG_ERR_NOMEM;
    int64_t k = 0;
    for (int64_t i = 0; i < o->n; i++) {
        const int64_t *e = o->elems.v + o->el_off.v[i];
        int64_t ne = o->el_off.v[i + 1] - o->el_off.v[i];
        for (int64_t a = 0; a < ne; a++)
            for (int64_t b = a + 1; b < ne; b++)
                ps[k++] = (pair_seam){e[a] < e[b] ? e[a] : e[b], e[a] < e[b] ? e[b] : e[a], i};
    }
    if (k > 1)
        qsort(ps, (size_t)k, sizeof *ps, cmp_pair_seam);
    int64_t w = 0, wv = 0, wt = 0;
    for (int64_t r = 0; r < m->nsheets; r++) {
        int64_t a = m->sheet_elements[2 * r], b = m->sheet_elements[2 * r + 1];
        int64_t v0 = m->sheet_vertex_offsets[r], v1 = m->sheet_vertex_offsets[r + 1];
        int64_t t0 = m->sheet_triangle_offsets[r], t1 = m->sheet_triangle_offsets[r + 1];
        /* the run of seams holding (a, b) */
        int64_t lo = 0, hi = k;
        while (lo < hi) {
            int64_t mid = lo + (hi - lo) / 2;
            if (ps[mid].a < a || (ps[mid].a == a && ps[mid].b < b))
                lo = mid + 1;
            else
                hi = mid;
        }
        int64_t end = lo;
        while (end < k && ps[end].a == a && ps[end].b == b)
            end++;
        int narrow = end > lo;
        for (int64_t t = t0; t < t1 && narrow; t++) {
            const double *P[3];
            double longest = 0;
            for (int c = 0; c < 3; c++)
                P[c] = m->sheet_vertices + 3 * (v0 + m->sheet_triangles[3 * t + c]);
            for (int c = 0; c < 3; c++)
                longest = fmax(longest, mfg_dist3(P[c], P[(c + 1) % 3]));
            /* the barycentric grid of step 1/g: every point of the triangle lies within
             * longest / (g sqrt 3) <= tol / (2 sqrt 3) of a grid point */
            double g = ceil(longest / (0.5 * tol));
            if (!(g <= NARROW_GRID))
                narrow = 0;
            int gi = narrow ? (int)(g > 1 ? g : 1) : 0;
            for (int i = 0; i <= gi && narrow; i++)
                for (int j = 0; i + j <= gi && narrow; j++) {
                    double u = (double)i / gi, v = (double)j / gi, q[3];
                    for (int x = 0; x < 3; x++)
                        q[x] = P[0][x] + u * (P[1][x] - P[0][x]) + v * (P[2][x] - P[0][x]);
                    narrow = near_seams(o, ps, lo, end, q, 0.5 * tol);
                }
        }
        if (narrow)
            continue;
        /* keep: compact in place */
        memmove(m->sheet_vertices + 3 * wv, m->sheet_vertices + 3 * v0, (size_t)(3 * (v1 - v0)) * sizeof(double));
        memmove(m->sheet_radii + wv, m->sheet_radii + v0, (size_t)(v1 - v0) * sizeof(double));
        memmove(m->sheet_triangles + 3 * wt, m->sheet_triangles + 3 * t0, (size_t)(3 * (t1 - t0)) * sizeof(int64_t));
        m->sheet_elements[2 * w] = a;
        m->sheet_elements[2 * w + 1] = b;
        m->sheet_forms[w] = m->sheet_forms[r];
        m->sheet_vertex_offsets[w] = wv;
        m->sheet_triangle_offsets[w] = wt;
        wv += v1 - v0;
        wt += t1 - t0;
        w++;
    }
    m->sheet_vertex_offsets[w] = wv;
    m->sheet_triangle_offsets[w] = wt;
    m->nsheets = w;
    free(ps);
    return MFG_OK;
}

/* Seam order: by element set, then first point. */
typedef struct seam_sort {
    const seam_out *o;
    int64_t idx;
} seam_sort;

static int cmp_seam(const void *pa, const void *pb)
{
    const seam_sort *a = pa, *b = pb;
    const seam_out *o = a->o;
    int64_t ea = o->el_off.v[a->idx], na = o->el_off.v[a->idx + 1] - ea;
    int64_t eb = o->el_off.v[b->idx], nb = o->el_off.v[b->idx + 1] - eb;
    for (int64_t i = 0; i < na && i < nb; i++)
        if (o->elems.v[ea + i] != o->elems.v[eb + i])
            return o->elems.v[ea + i] < o->elems.v[eb + i] ? -1 : 1;
    if (na != nb)
        return na < nb ? -1 : 1;
    int c = cmp_xyz(o->pts.v + 3 * o->pt_off.v[a->idx], o->pts.v + 3 * o->pt_off.v[b->idx]);
    if (c)
        return c;
    return (a->idx > b->idx) - (a->idx < b->idx);
}

static mfg_status seams_to_public(const seam_out *o, mfg_medial *m)
{
    int64_t n = o->n;
    m->nseams = n;
    int64_t np = o->rad.n, ne = o->elems.n;
    m->seam_kinds = malloc((size_t)(n + 1) * sizeof(int32_t));
    m->seam_point_offsets = malloc((size_t)(n + 1) * sizeof(int64_t));
    m->seam_element_offsets = malloc((size_t)(n + 1) * sizeof(int64_t));
    m->seam_points = malloc((size_t)(3 * np + 1) * sizeof(double));
    m->seam_radii = malloc((size_t)(np + 1) * sizeof(double));
    m->seam_elements = malloc((size_t)(ne + 1) * sizeof(int64_t));
    m->seam_ends = malloc((size_t)(2 * n + 1) * sizeof(int64_t));
    seam_sort *ord = malloc((size_t)(n + 1) * sizeof *ord);
    if (!m->seam_kinds || !m->seam_point_offsets || !m->seam_element_offsets || !m->seam_points ||
        !m->seam_radii || !m->seam_elements || !m->seam_ends || !ord) {
        free(ord);
        return MFG_ERR_NOMEM;
    }
    for (int64_t i = 0; i < n; i++)
        ord[i] = (seam_sort){o, i};
    if (n > 1)
        qsort(ord, (size_t)(n), sizeof *ord, cmp_seam);
    int64_t po = 0, eo = 0;
    m->seam_point_offsets[0] = 0;
    m->seam_element_offsets[0] = 0;
    for (int64_t k = 0; k < n; k++) {
        int64_t i = ord[k].idx;
        int64_t p0 = o->pt_off.v[i], p1 = o->pt_off.v[i + 1];
        int64_t e0 = o->el_off.v[i], e1 = o->el_off.v[i + 1];
        memcpy(m->seam_points + 3 * po, o->pts.v + 3 * p0, (size_t)(3 * (p1 - p0)) * sizeof(double));
        memcpy(m->seam_radii + po, o->rad.v + p0, (size_t)(p1 - p0) * sizeof(double));
        memcpy(m->seam_elements + eo, o->elems.v + e0, (size_t)(e1 - e0) * sizeof(int64_t));
        po += p1 - p0;
        eo += e1 - e0;
        m->seam_point_offsets[k + 1] = po;
        m->seam_element_offsets[k + 1] = eo;
        m->seam_kinds[k] = (int32_t)o->kinds.v[i];
        m->seam_ends[2 * k] = o->ends.v[2 * i];
        m->seam_ends[2 * k + 1] = o->ends.v[2 * i + 1];
    }
    free(ord);
    return MFG_OK;
}

/* ---- elements ---------------------------------------------------------------------------------- */

static mfg_status elements_to_public(const md_elements *el, mfg_medial *m)
{
    int64_t ne = el->nelements;
    m->nelements = ne;
    m->nfaces = el->nfaces;
    m->nedges = el->nedges;
    m->nvertices = el->nverts;
    m->ntriangles = el->nt;
    m->element_kinds = malloc((size_t)(ne + 1) * sizeof(int32_t));
    m->element_convex = malloc((size_t)(ne + 1) * sizeof(int32_t));
    m->face_of_triangle = malloc((size_t)(el->nt + 1) * sizeof(int64_t));
    m->face_planes = malloc((size_t)(4 * el->nfaces + 1) * sizeof(double));
    m->edge_segments = malloc((size_t)(6 * el->nedges + 1) * sizeof(double));
    m->vertex_points = malloc((size_t)(3 * el->nverts + 1) * sizeof(double));
    if (!m->element_kinds || !m->element_convex || !m->face_of_triangle || !m->face_planes ||
        !m->edge_segments || !m->vertex_points)
        return MFG_ERR_NOMEM;
    for (int64_t e = 0; e < ne; e++) {
        int k = md_kind(el, e);
        m->element_kinds[e] = k == MD_FACE ? MFG_ELEM_FACE : (k == MD_EDGE ? MFG_ELEM_EDGE : MFG_ELEM_VERTEX);
        m->element_convex[e] = k == MD_EDGE ? el->edge_convex[e - el->nfaces] : -1;
    }
    memcpy(m->face_of_triangle, el->face_of_triangle, (size_t)el->nt * sizeof(int64_t));
    memcpy(m->face_planes, el->face_plane, (size_t)(4 * el->nfaces) * sizeof(double));
    memcpy(m->edge_segments, el->edge_seg, (size_t)(6 * el->nedges) * sizeof(double));
    memcpy(m->vertex_points, el->vert_xyz, (size_t)(3 * el->nverts) * sizeof(double));
    return MFG_OK;
}

static mfg_status junctions_to_public(const md_junction *J, int64_t nj, mfg_medial *m)
{
    int64_t ne = 0;
    for (int64_t j = 0; j < nj; j++)
        ne += J[j].n;
    m->njunctions = nj;
    m->junction_kinds = malloc((size_t)(nj + 1) * sizeof(int32_t));
    m->junction_points = malloc((size_t)(3 * nj + 1) * sizeof(double));
    m->junction_radii = malloc((size_t)(nj + 1) * sizeof(double));
    m->junction_element_offsets = malloc((size_t)(nj + 1) * sizeof(int64_t));
    m->junction_elements = malloc((size_t)(ne + 1) * sizeof(int64_t));
    if (!m->junction_kinds || !m->junction_points || !m->junction_radii ||
        !m->junction_element_offsets || !m->junction_elements)
        return MFG_ERR_NOMEM;
    int64_t o = 0;
    m->junction_element_offsets[0] = 0;
    for (int64_t j = 0; j < nj; j++) {
        m->junction_kinds[j] = J[j].kind;
        memcpy(m->junction_points + 3 * j, J[j].x, sizeof J[j].x);
        m->junction_radii[j] = J[j].r;
        memcpy(m->junction_elements + o, J[j].elems, (size_t)J[j].n * sizeof(int64_t));
        o += J[j].n;
        m->junction_element_offsets[j + 1] = o;
    }
    return MFG_OK;
}

/* ---- the entry point ------------------------------------------------------------------------------ */

static int thread_count(int32_t nthreads)
{
    long n = nthreads;
    if (n == 0) {
        n = sysconf(_SC_NPROCESSORS_ONLN);
        if (n < 1)
            n = 1;
    }
    return (int)(n > MAX_THREADS ? MAX_THREADS : n);
}

mfg_status mfg_medial_surface(const double *xyz, int64_t nvertices, const int64_t *triangles,
                              int64_t ntriangles, double tolerance, uint32_t flags,
                              int32_t nthreads, mfg_medial **out)
{
    return mfg_medial_surface_p(xyz, nvertices, triangles, ntriangles, tolerance, flags,
                                nthreads, out, NULL);
}

/* Work units between progress reports (counted on the caller's thread only): an octree
 * unit (a cell at the work depth, ~0.1-1 ms), a unit of 16 leaves (~0.2-2 ms), a block of
 * 64 leaves searched for junctions (~0.1-1 ms). */
#define MEDIAL_EVERY_OCTREE 16
#define MEDIAL_EVERY_SHEETS 16
#define MEDIAL_EVERY_JUNCTIONS 16

mfg_status mfg_medial_surface_p(const double *xyz, int64_t nvertices, const int64_t *triangles,
                                int64_t ntriangles, double tolerance, uint32_t flags,
                                int32_t nthreads, mfg_medial **out,
                                const mfg_progress *progress)
{
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "mfg_medial_surface: out is NULL");
    if (flags & ~MFG_MEDIAL_FULL)
        return mfg_fail(MFG_ERR_INVALID, "mfg_medial_surface: unknown flags 0x%x",
                        (unsigned)(flags & ~MFG_MEDIAL_FULL));
    if (nthreads < 0)
        return mfg_fail(MFG_ERR_INVALID, "mfg_medial_surface: nthreads %d < 0", (int)nthreads);
    int full = (flags & MFG_MEDIAL_FULL) != 0, nth = thread_count(nthreads);
    mfg_prog prog;
    mfg_prog_init(&prog, progress, "mfg_medial_surface");
    if (!mfg_prog_stage(&prog, "medial: elements", 0, 0.05, 1))
        return mfg_prog_fail(&prog);
    md_elements el;
    mfg_status st = md_elements_build(xyz, nvertices, triangles, ntriangles, tolerance, &el);
    if (st != MFG_OK)
        return st;
    md_bvh *bvh = NULL;
    md_leaves lv;
    md_soup sp;
    md_junction *J = NULL, *Jall = NULL; /* Jall: J's rank-3 part, or a new array */
    int64_t nJ = 0, nall = 0;
    int own_jall = 0;
    pend_list pend;
    memset(&pend, 0, sizeof pend);
    memset(&lv, 0, sizeof lv);
    memset(&sp, 0, sizeof sp);
    asm_state as;
    memset(&as, 0, sizeof as);
    seam_out so;
    memset(&so, 0, sizeof so);
    mfg_medial *m = calloc(1, sizeof *m);
    const char *stage = "the result";
    if (!m) {
        st = MFG_ERR_NOMEM;
        goto fail;
    }
    stage = "the BVH";
    if ((st = md_bvh_build(&el, &bvh)) != MFG_OK)
        goto fail;
#define MEDIAL_STAGE(name, lo, hi, every)                                                  \
    do {                                                                                   \
        if (!mfg_prog_stage(&prog, name, lo, hi, every)) {                                 \
            st = mfg_prog_fail(&prog);                                                     \
            goto fail;                                                                     \
        }                                                                                  \
    } while (0)
/* A report inside the assembly (its steps are sequential and not split further). */
#define MEDIAL_STEP(done, total)                                                           \
    do {                                                                                   \
        if (!mfg_prog_report(&prog, done, total)) {                                        \
            st = mfg_prog_fail(&prog);                                                     \
            goto fail;                                                                     \
        }                                                                                  \
    } while (0)
    stage = "the octree";
    MEDIAL_STAGE("medial: octree", 0.05, 0.25, MEDIAL_EVERY_OCTREE);
    if ((st = md_octree_build_p(&el, bvh, tolerance, full, nth, &lv, &prog)) != MFG_OK)
        goto fail;
    stage = "the sheets";
    MEDIAL_STAGE("medial: sheets", 0.25, 0.6, MEDIAL_EVERY_SHEETS);
    if ((st = md_sheets_extract_p(&el, bvh, &lv, tolerance, nth, &sp, &prog)) != MFG_OK)
        goto fail;
    stage = "the junctions";
    MEDIAL_STAGE("medial: junctions", 0.6, 0.75, MEDIAL_EVERY_JUNCTIONS);
    if ((st = find_junctions(&el, bvh, &lv, tolerance, nth, &J, &nJ, &prog)) != MFG_OK)
        goto fail;
    stage = "the assembly";
    MEDIAL_STAGE("medial: assembly", 0.75, 1.0, 1);
    double h = lv.lat.h;
    /* rank-2 points (degenerate seams) first, rank-3 after */
    int64_t n2 = 0;
    for (int64_t i = 0; i < nJ; i++)
        if (J[i].rank == 2) {
            md_junction t = J[n2];
            J[n2++] = J[i];
            J[i] = t;
        }
    md_junction *J3 = J + n2;
    int64_t n3 = merge_junctions(&el, J3, nJ - n2, tolerance, full);
    Jall = J3;
    nall = n3;
    if ((st = elements_to_public(&el, m)) != MFG_OK || (st = build_sheets(&el, &sp, h, tolerance, full, m, &as, &prog)) != MFG_OK)
        goto fail;
    MEDIAL_STEP(1, 5);
    /* Degenerate seams first: the soup's seams along them are dropped.  The soup's seams
     * are chained, the junctions the leaves missed are found where they end
     * (recover_junctions), and only then is every seam emitted with its ends snapped; the
     * degenerate seams are emitted again for that (the first pass only says which soup
     * seams they cover). */
    if (!degenerate_seams(&el, J, n2, &so, J3, n3, h, tolerance, full) ||
        !soup_seams(&el, bvh, &sp, &as, &so, so.n, 2 * h, tolerance, &pend)) {
        st = MFG_ERR_NOMEM;
        goto fail;
    }
    MEDIAL_STEP(2, 5);
    int rec = recover_junctions(&el, bvh, &pend, &Jall, &nall, h, 2 * h, tolerance, full);
    own_jall = Jall != J3;
    if (!rec) {
        st = MFG_ERR_NOMEM;
        goto fail;
    }
    MEDIAL_STEP(3, 5);
    seam_out_free(&so);
    memset(&so, 0, sizeof so);
    if (!degenerate_seams(&el, J, n2, &so, Jall, nall, h, tolerance, full)) {
        st = MFG_ERR_NOMEM;
        goto fail;
    }
    for (int64_t i = 0; i < pend.n; i++)
        if (!emit_seam(&so, &pend.v[i].pl, pend.v[i].e, pend.v[i].ne, pend.v[i].kind, Jall, nall,
                       2 * h, tolerance)) {
            st = MFG_ERR_NOMEM;
            goto fail;
        }
    MEDIAL_STEP(4, 5);
    if ((st = drop_narrow_sheets(&so, tolerance, m)) != MFG_OK || (st = close_pinholes(m, tolerance)) != MFG_OK ||
        (st = seams_to_public(&so, m)) != MFG_OK || (st = junctions_to_public(Jall, nall, m)) != MFG_OK)
        goto fail;
    MEDIAL_STAGE("medial: done", 1.0, 1.0, 1);
#undef MEDIAL_STAGE
#undef MEDIAL_STEP
    m->cells_visited = lv.cells_visited;
    m->leaves = lv.nleaves;
    m->leaf_size = h;
    seam_out_free(&so);
    pend_free(&pend);
    if (own_jall)
        free(Jall);
    asm_free(&as);
    free(J);
    md_soup_free(&sp);
    md_leaves_free(&lv);
    md_bvh_free(bvh);
    md_elements_free(&el);
    *out = m;
    mfg_clear_error();
    return MFG_OK;
fail:
    seam_out_free(&so);
    pend_free(&pend);
    if (own_jall)
        free(Jall);
    asm_free(&as);
    free(J);
    md_soup_free(&sp);
    md_leaves_free(&lv);
    md_bvh_free(bvh);
    md_elements_free(&el);
    mfg_medial_free(m);
    if (st == MFG_ERR_NOMEM)
        return mfg_fail(MFG_ERR_NOMEM, "mfg_medial_surface: out of memory building %s", stage);
    return st; /* the stage's own detail stands */
}

void mfg_medial_free(mfg_medial *m)
{
    if (!m)
        return;
    free(m->element_kinds);
    free(m->element_convex);
    free(m->face_of_triangle);
    free(m->face_planes);
    free(m->edge_segments);
    free(m->vertex_points);
    free(m->sheet_elements);
    free(m->sheet_forms);
    free(m->sheet_vertex_offsets);
    free(m->sheet_triangle_offsets);
    free(m->sheet_vertices);
    free(m->sheet_radii);
    free(m->sheet_triangles);
    free(m->seam_kinds);
    free(m->seam_point_offsets);
    free(m->seam_points);
    free(m->seam_radii);
    free(m->seam_element_offsets);
    free(m->seam_elements);
    free(m->seam_ends);
    free(m->junction_kinds);
    free(m->junction_points);
    free(m->junction_radii);
    free(m->junction_element_offsets);
    free(m->junction_elements);
    free(m);
}
