/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sheets.c - the sheets of the medial surface on the analytic bisectors, the sheet
 * extraction stage (issue 9; Lee & Lee, the medial surface of a polyhedron;
 * docs/design/medial.md section 4.1).  For every octree leaf and every pair (a, b) of
 * its P: marching tetrahedra on f_ab = d_a^car - d_b^car over the 6
 * Kuhn tets about the leaf's main diagonal, with every vertex a root of f_ab on its lattice
 * edge (md_root_on_segment, from the edge's smaller lattice point); then each polygon is
 * trimmed where tau < 0, tau = min(region margins of a and b, min over the other candidates
 * c of d_c - d_a^car, and with a BVH the signed distance to the boundary): where tau
 * changes sign along a polygon edge the boundary point is found on f_ab = 0 inside the tet
 * face; where the two ends of a cut are trimmed by different terms, the sheet's corner is
 * inserted (Newton on three equations); the cuts become seam segments.  Every float of a
 * shared vertex depends only on lattice points and the elements, so the leaves that share
 * a lattice edge or a tet face get the same bits, and welding is by key alone. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "medial/sheets.h"
#include "common/mfg_internal.h"

/* Leaves per work unit: the units, not the threads, fix the order of the output. */
#define UNIT_LEAVES 16
/* ... unless all their sides are at most this times h: then they are collapsed. */
#define COLLAPSE_LEN 1e-2

int md_sheet_cmp_key(const vkey *x, const vkey *y)
{
    if (x->a != y->a)
        return x->a < y->a ? -1 : 1;
    if (x->b != y->b)
        return x->b < y->b ? -1 : 1;
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 4; k++)
            if (x->e[i][k] != y->e[i][k])
                return x->e[i][k] < y->e[i][k] ? -1 : 1;
    return (x->c > y->c) - (x->c < y->c);
}

/* ---- growing the unit's buffers -------------------------------------------------------- */

/* The next capacity of a unit's array of cap items that is full. */
static int64_t next_cap(int64_t cap)
{
    return cap ? 2 * cap : 64;
}

int64_t md_sheet_push_vertex(unit_buf *u, const vkey *k, const double *x, double r)
{
    if (u->nv == u->cv) {
        int64_t c = next_cap(u->cv);
        if (!mfg_resize((void **)&u->v, c, sizeof *u->v))
            return -1;
        u->cv = c;
    }
    vrec *v = u->v + u->nv;
    v->k = *k;
    memcpy(v->x, x, sizeof v->x);
    v->r = r;
    return u->nv++;
}

int md_sheet_push_tri(unit_buf *u, int64_t p, int64_t q, int64_t r, int64_t a, int64_t b)
{
    if (u->nt == u->ct) {
        /* An array already grown when the next fails is only larger: still consistent. */
        int64_t c = next_cap(u->ct);
        if (!mfg_resize((void **)&u->t, c, 3 * sizeof *u->t))
            return 0;
        if (!mfg_resize((void **)&u->tp, c, 2 * sizeof *u->tp))
            return 0;
        u->ct = c;
    }
    u->t[3 * u->nt] = p;
    u->t[3 * u->nt + 1] = q;
    u->t[3 * u->nt + 2] = r;
    u->tp[2 * u->nt] = a;
    u->tp[2 * u->nt + 1] = b;
    u->nt++;
    return 1;
}

int md_sheet_push_seg(unit_buf *u, int64_t p, int64_t q, const int64_t *e3, int32_t kind, int64_t a,
                    int64_t b)
{
    if (u->ns == u->cs) {
        int64_t c = next_cap(u->cs);
        if (!mfg_resize((void **)&u->s, c, 2 * sizeof *u->s))
            return 0;
        if (!mfg_resize((void **)&u->se, c, 3 * sizeof *u->se))
            return 0;
        if (!mfg_resize((void **)&u->sk, c, sizeof *u->sk))
            return 0;
        if (!mfg_resize((void **)&u->sp, c, 2 * sizeof *u->sp))
            return 0;
        u->cs = c;
    }
    u->s[2 * u->ns] = p;
    u->s[2 * u->ns + 1] = q;
    memcpy(u->se + 3 * u->ns, e3, 3 * sizeof *e3);
    u->sk[u->ns] = kind;
    u->sp[2 * u->ns] = a;
    u->sp[2 * u->ns + 1] = b;
    u->ns++;
    return 1;
}

static void unit_free(unit_buf *u)
{
    free(u->v);
    free(u->t);
    free(u->tp);
    free(u->s);
    free(u->se);
    free(u->sk);
    free(u->sp);
}

/* The doubled area of the triangle p q r. */
static double tri_area2(const double *p, const double *q, const double *r)
{
    double u[3] = {q[0] - p[0], q[1] - p[1], q[2] - p[2]};
    double v[3] = {r[0] - p[0], r[1] - p[1], r[2] - p[2]};
    double n[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    return sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* ---- threads ------------------------------------------------------------------------------ */

typedef struct job {
    const md_elements *el;
    const md_bvh *bvh;
    const md_leaves *lv;
    md_leaf_index li;
    int64_t nunits;
    unit_buf *units;
    atomic_llong next;
    atomic_int failed;
    mfg_prog *prog;   /* progress (NULL: none); only the caller's thread reports */
    pthread_t caller;
} job;

static void *worker(void *arg)
{
    job *j = arg;
    ctx *c = malloc(sizeof *c);
    if (c) {
        c->cb = NULL;
        c->capC = 0;
        c->li = &j->li;
    }
    int is_caller = pthread_equal(pthread_self(), j->caller) != 0;
    for (;;) {
        if (!mfg_prog_poll_mt(j->prog, is_caller, (double)atomic_load(&j->next),
                              (double)j->nunits))
            break;
        long long u = atomic_fetch_add(&j->next, 1);
        if (u >= j->nunits || atomic_load(&j->failed))
            break;
        unit_buf *ub = j->units + u;
        if (!c) {
            ub->st = MFG_ERR_NOMEM;
            atomic_store(&j->failed, 1);
            break;
        }
        int64_t end = (u + 1) * UNIT_LEAVES;
        if (end > j->lv->nleaves)
            end = j->lv->nleaves;
        for (int64_t i = u * UNIT_LEAVES; i < end && ub->st == MFG_OK; i++)
            ub->st = md_sheet_leaf(j->el, j->bvh, j->lv, j->lv->leaf + i, ub, c);
        if (ub->st != MFG_OK)
            atomic_store(&j->failed, 1);
    }
    if (c)
        free(c->cb);
    free(c);
    return NULL;
}

/* ---- merge ------------------------------------------------------------------------------- */

typedef struct sref {
    const vrec *r;
    int64_t g; /* global record index: unit order, then the unit's own order */
} sref;

static int cmp_sref(const sref *x, const sref *y)
{
    int c = md_sheet_cmp_key(&x->r->k, &y->r->k);
    return c ? c : (x->g > y->g) - (x->g < y->g);
}

/* Sorts s[0..n) by cmp_sref (a total order: g is unique), with tmp of n / 2 + 1 items: a merge
 * sort with the comparison inlined, about twice as fast as qsort's indirect calls on the
 * millions of records of a large part. */
static void sort_srefs(sref *s, sref *tmp, int64_t n)
{
    if (n <= 16) {
        for (int64_t i = 1; i < n; i++) {
            sref v = s[i];
            int64_t j = i;
            for (; j > 0 && cmp_sref(&v, s + j - 1) < 0; j--)
                s[j] = s[j - 1];
            s[j] = v;
        }
        return;
    }
    int64_t m = n / 2;
    sort_srefs(s, tmp, m);
    sort_srefs(s + m, tmp, n - m);
    if (cmp_sref(s + m - 1, s + m) <= 0)
        return; /* already in order (records of one leaf often are) */
    memcpy(tmp, s, (size_t)m * sizeof *s);
    int64_t i = 0, j = m, k = 0;
    while (i < m && j < n)
        s[k++] = cmp_sref(s + j, tmp + i) < 0 ? s[j++] : tmp[i++];
    while (i < m)
        s[k++] = tmp[i++];
}

void md_soup_free(md_soup *s)
{
    if (!s)
        return;
    free(s->xyz);
    free(s->radius);
    free(s->tris);
    free(s->tri_pair);
    free(s->seg_verts);
    free(s->seg_elems);
    free(s->seg_kind);
    free(s->seg_pair);
    memset(s, 0, sizeof *s);
}

/* A vertex no seam passes through: a root on a lattice edge (key c = -2) or the centre of
 * a coarse plane leaf's fan (c = -4, sheet_coarse.c).  A coarse leaf whose polygon is a
 * corner of its cube cut off within rounding of a lattice point (the turned cuboid) fans
 * triangles below amin from its centre, where a leaf of side h would have one triangle of
 * three roots: both must collapse alike, or the neighbours' sides about the point stay
 * open (a pinhole). */
static int inner_key(const vrec *r)
{
    return r->k.c == -2 || r->k.c == -4;
}

/* Welds the units' records by key (ids in key order), collapses the tiny triangles, drops
 * degenerate triangles and unreferenced vertices, and writes the soup in unit order. */
static mfg_status merge(const unit_buf *units, int64_t nunits, double h, md_soup *out)
{
    int64_t N = 0, NT = 0, NS = 0;
    for (int64_t u = 0; u < nunits; u++) {
        N += units[u].nv;
        NT += units[u].nt;
        NS += units[u].ns;
    }
    mfg_status st = MFG_ERR_NOMEM;
    sref *sr = malloc((size_t)(N ? N : 1) * sizeof *sr);
    int64_t *gid = malloc((size_t)(N ? N : 1) * sizeof *gid);
    int64_t *rep = malloc((size_t)(N ? N : 1) * sizeof *rep);   /* id -> representative */
    int64_t *newid = malloc((size_t)(N ? N : 1) * sizeof *newid);
    int64_t *uoff = malloc((size_t)(nunits + 1) * sizeof *uoff);
    const vrec **recs = malloc((size_t)(N ? N : 1) * sizeof *recs);
    sref *tmp = malloc((size_t)(N / 2 + 1) * sizeof *tmp);
    md_soup s;
    memset(&s, 0, sizeof s);
    s.tris = malloc((size_t)(NT ? 3 * NT : 1) * sizeof *s.tris);
    s.tri_pair = malloc((size_t)(NT ? 2 * NT : 1) * sizeof *s.tri_pair);
    s.seg_verts = malloc((size_t)(NS ? 2 * NS : 1) * sizeof *s.seg_verts);
    s.seg_elems = malloc((size_t)(NS ? 3 * NS : 1) * sizeof *s.seg_elems);
    s.seg_kind = malloc((size_t)(NS ? NS : 1) * sizeof *s.seg_kind);
    s.seg_pair = malloc((size_t)(NS ? 2 * NS : 1) * sizeof *s.seg_pair);
    if (!sr || !gid || !rep || !newid || !uoff || !recs || !tmp || !s.tris || !s.tri_pair || !s.seg_verts ||
        !s.seg_elems || !s.seg_kind || !s.seg_pair)
        goto done;
    uoff[0] = 0;
    for (int64_t u = 0; u < nunits; u++) {
        uoff[u + 1] = uoff[u] + units[u].nv;
        for (int64_t i = 0; i < units[u].nv; i++) {
            sr[uoff[u] + i].r = units[u].v + i;
            sr[uoff[u] + i].g = uoff[u] + i;
            recs[uoff[u] + i] = units[u].v + i;
        }
    }
    sort_srefs(sr, tmp, N);
    int64_t nid = 0;
    for (int64_t i = 0; i < N; i++) {
        if (i == 0 || md_sheet_cmp_key(&sr[i].r->k, &sr[i - 1].r->k) != 0)
            rep[nid++] = sr[i].g;
        gid[sr[i].g] = nid - 1;
    }
    double amin = MD_AREA_DROP * h * h, lmax = COLLAPSE_LEN * h;
    /* Where the sheet passes within rounding of a lattice point, the roots on the Kuhn
     * edges there crowd about it and the tets give triangles below amin with all sides
     * short: dropping one leaves a pinhole (the T-section's {z1, E} by (33.94, 54.02,
     * 35.84) at tol 1 % L).  Such a triangle of three roots (or coarse fan centres,
     * inner_key) is collapsed instead: its vertices become one (the smallest id, a vertex
     * on the bisector), so that its neighbours' sides weld and they close the hole; the
     * order of the unions does not matter.  Boundary points and corners (the seams' vertices) never move: a tiny
     * triangle at a seam is dropped as before (moving a vertex of the T-section's seam of
     * four elements gave a spurious seam of three). */
    for (int64_t i = 0; i < nid; i++)
        newid[i] = i; /* union-find parents here; reset below */
    for (int64_t u = 0; u < nunits; u++) {
        const unit_buf *ub = units + u;
        for (int64_t t = 0; t < ub->nt; t++) {
            int64_t g[3];
            for (int k = 0; k < 3; k++)
                g[k] = gid[uoff[u] + ub->t[3 * t + k]];
            const double *x0 = recs[rep[g[0]]]->x, *x1 = recs[rep[g[1]]]->x;
            const double *x2 = recs[rep[g[2]]]->x;
            int roots = inner_key(recs[rep[g[0]]]) && inner_key(recs[rep[g[1]]]) &&
                        inner_key(recs[rep[g[2]]]);
            if (roots && 0.5 * tri_area2(x0, x1, x2) < amin && mfg_dist3(x0, x1) <= lmax &&
                mfg_dist3(x1, x2) <= lmax && mfg_dist3(x2, x0) <= lmax) {
                mfg_uf_union(newid, g[0], g[1]);
                mfg_uf_union(newid, g[0], g[2]);
            }
        }
    }
    for (int64_t i = 0; i < nid; i++)
        rep[i] = rep[mfg_uf_find(newid, i)];
    for (int64_t i = 0; i < N; i++)
        gid[i] = mfg_uf_find(newid, gid[i]);
    for (int64_t i = 0; i < nid; i++)
        newid[i] = -1;
    for (int64_t u = 0; u < nunits; u++) {
        const unit_buf *ub = units + u;
        for (int64_t t = 0; t < ub->nt; t++) {
            int64_t g[3];
            for (int k = 0; k < 3; k++)
                g[k] = gid[uoff[u] + ub->t[3 * t + k]];
            if (g[0] == g[1] || g[1] == g[2] || g[0] == g[2])
                continue;
            if (0.5 * tri_area2(recs[rep[g[0]]]->x, recs[rep[g[1]]]->x, recs[rep[g[2]]]->x) < amin)
                continue;
            memcpy(s.tris + 3 * s.ntris, g, sizeof g);
            s.tri_pair[2 * s.ntris] = ub->tp[2 * t];
            s.tri_pair[2 * s.ntris + 1] = ub->tp[2 * t + 1];
            s.ntris++;
            for (int k = 0; k < 3; k++)
                newid[g[k]] = 0;
        }
        for (int64_t t = 0; t < ub->ns; t++) {
            int64_t g0 = gid[uoff[u] + ub->s[2 * t]], g1 = gid[uoff[u] + ub->s[2 * t + 1]];
            if (g0 == g1)
                continue;
            s.seg_verts[2 * s.nsegs] = g0;
            s.seg_verts[2 * s.nsegs + 1] = g1;
            memcpy(s.seg_elems + 3 * s.nsegs, ub->se + 3 * t, 3 * sizeof(int64_t));
            s.seg_kind[s.nsegs] = ub->sk[t];
            s.seg_pair[2 * s.nsegs] = ub->sp[2 * t];
            s.seg_pair[2 * s.nsegs + 1] = ub->sp[2 * t + 1];
            s.nsegs++;
            newid[g0] = newid[g1] = 0;
        }
    }
    for (int64_t i = 0; i < nid; i++)
        if (newid[i] == 0)
            newid[i] = s.nverts++;
    s.xyz = malloc((size_t)(s.nverts ? 3 * s.nverts : 1) * sizeof *s.xyz);
    s.radius = malloc((size_t)(s.nverts ? s.nverts : 1) * sizeof *s.radius);
    if (!s.xyz || !s.radius)
        goto done;
    for (int64_t i = 0; i < nid; i++)
        if (newid[i] >= 0) {
            const vrec *r = recs[rep[i]];
            memcpy(s.xyz + 3 * newid[i], r->x, sizeof r->x);
            s.radius[newid[i]] = r->r;
        }
    for (int64_t t = 0; t < 3 * s.ntris; t++)
        s.tris[t] = newid[s.tris[t]];
    for (int64_t t = 0; t < 2 * s.nsegs; t++)
        s.seg_verts[t] = newid[s.seg_verts[t]];
    *out = s;
    memset(&s, 0, sizeof s);
    st = MFG_OK;
done:
    md_soup_free(&s);
    free(sr);
    free(gid);
    free(rep);
    free(newid);
    free(uoff);
    free(recs);
    free(tmp);
    return st;
}

mfg_status md_sheets_extract(const md_elements *el, const md_bvh *bvh, const md_leaves *leaves,
                             double tolerance, int nthreads, md_soup *out)
{
    return md_sheets_extract_p(el, bvh, leaves, tolerance, nthreads, out, NULL);
}

mfg_status md_sheets_extract_p(const md_elements *el, const md_bvh *bvh, const md_leaves *leaves,
                               double tolerance, int nthreads, md_soup *out, mfg_prog *prog)
{
    (void)tolerance; /* the leaf side h sets every threshold here */
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "md_sheets_extract: out is NULL");
    memset(out, 0, sizeof *out);
    if (!el || !leaves)
        return mfg_fail(MFG_ERR_NULL, "md_sheets_extract: elements or leaves NULL");
    int64_t nunits = (leaves->nleaves + UNIT_LEAVES - 1) / UNIT_LEAVES;
    job j;
    j.el = el;
    j.bvh = bvh;
    j.lv = leaves;
    j.nunits = nunits;
    j.prog = prog;
    j.caller = pthread_self();
    j.units = calloc((size_t)(nunits ? nunits : 1), sizeof *j.units);
    if (!j.units || !md_leaf_index_build(leaves, &j.li)) {
        free(j.units);
        return mfg_fail(MFG_ERR_NOMEM, "md_sheets_extract: out of memory");
    }
    atomic_init(&j.next, 0);
    atomic_init(&j.failed, 0);
    int nt = nthreads < 1 ? 1 : nthreads;
    if (nt > 64)
        nt = 64;
    if (nt > nunits)
        nt = nunits > 0 ? (int)nunits : 1;
    pthread_t tid[64];
    int started = 0;
    for (int i = 1; i < nt; i++) {
        if (pthread_create(tid + started, NULL, worker, &j) != 0)
            break; /* fewer threads: the same output, later */
        started++;
    }
    worker(&j);
    for (int i = 0; i < started; i++)
        pthread_join(tid[i], NULL);
    mfg_status st = MFG_OK;
    for (int64_t u = 0; u < nunits && st == MFG_OK; u++)
        st = j.units[u].st;
    if (st == MFG_OK && atomic_load(&j.failed))
        st = MFG_ERR_NOMEM; /* a worker without its context stopped before any unit */
    int cancelled = st == MFG_OK && prog && mfg_prog_stopped(prog);
    if (cancelled)
        st = MFG_ERR_CANCELLED;
    if (st == MFG_OK)
        st = merge(j.units, nunits, leaves->lat.h, out);
    for (int64_t u = 0; u < nunits; u++)
        unit_free(j.units + u);
    free(j.units);
    md_leaf_index_free(&j.li);
    if (st != MFG_OK) {
        memset(out, 0, sizeof *out);
        if (cancelled)
            return mfg_prog_fail(prog);
        return mfg_fail(st, "md_sheets_extract: out of memory");
    }
    return MFG_OK;
}
