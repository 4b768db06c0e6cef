/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* seam_assembly.c - the medial surface's seams (docs/design/medial.md section 4.2): the
 * soup's seam segments, each with the elements touching at both of its ends; per element
 * set the pair whose segments chain into the fewest polylines (ties: the smallest),
 * pieces joined across 3h, ends snapped to the junctions within 2h whose set holds the
 * seam's, thinned to tolerance / 4; plus the degenerate seams chained from the rank-2
 * points of the junction search (soup seams lying on them dropped). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "medial/assembly.h"

/* A seam segment with its element set and the pair of the sheet it bounds. */
typedef struct seg_ref {
    int64_t e[SEAM_EMAX];
    int32_t ne;
    int32_t kind;
    int64_t pa, pb; /* the pair of the sheet the segment bounds */
    int64_t v0, v1; /* soup vertices, v0 < v1 */
} seg_ref;

static int cmp_seg(const void *pa, const void *pb)
{
    const seg_ref *a = pa, *b = pb;
    int c = md_cmp_set(a->e, a->ne, b->e, b->ne);
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

/* The points of a polyline and the thinning tolerance (chord_holds). */
typedef struct chord_ctx {
    const double *P;
    double tol;
} chord_ctx;

/* Do the points strictly between a and j stay within tol of the chord a -> j? */
static int chord_holds(const void *ctx, int64_t a, int64_t j)
{
    const chord_ctx *cc = ctx;
    for (int64_t q = a + 1; q < j; q++)
        if (!(sqrt(mfg_seg_dist2(cc->P + 3 * q, cc->P + 3 * a, cc->P + 3 * j)) <= cc->tol))
            return 0;
    return 1;
}

/* Thinning (design 4.2): drop interior points while every dropped point stays within
 * tol of the chord that replaces it, each chord from the last kept point reaching as far
 * as mfg_farthest_chord finds (O(n log n) on a straight seam; extending the chord one
 * point at a time was O(n^2), 38 % of the 12-triangle box at L / 10^4, whose seams have
 * a point per leaf). */
static void thin(polyline *pl, double tol)
{
    int64_t n = pl->rad.n;
    if (n <= 2)
        return;
    double *P = pl->pts.v, *R = pl->rad.v;
    chord_ctx cc = {P, tol};
    int64_t w = 1, a = 0;
    while (a < n - 1) {
        int64_t keep = mfg_farthest_chord(a, n - 1, chord_holds, &cc);
        memmove(P + 3 * w, P + 3 * keep, 3 * sizeof(double));
        R[w] = R[keep];
        w++;
        a = keep;
    }
    pl->pts.n = 3 * w;
    pl->rad.n = w;
}

void md_polyline_reverse(polyline *pl)
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

void md_seam_out_free(seam_out *o)
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
int md_emit_seam(const md_asm *ax, const md_jset *Js, seam_out *o, polyline *pl,
                 const int64_t *set, int64_t ns, int32_t kind)
{
    const md_junction *J = Js->v;
    double reach = ax->reach, tol = ax->tol;
    if (pl->rad.n < 1)
        return 1;
    /* Orientation: from the lexicographically smaller end. */
    int64_t n = pl->rad.n;
    if (md_cmp_xyz_tol(pl->pts.v + 3 * (n - 1), pl->pts.v, MD_ROUND_REL * tol) < 0)
        md_polyline_reverse(pl);
    int64_t e0 = md_snap_junction(Js, pl->pts.v, set, ns, reach);
    int64_t e1 = md_snap_junction(Js, pl->pts.v + 3 * (n - 1), set, ns, reach);
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
    if (!mfg_grow((void **)&pc->p, &pc->cap, pc->n + 1, sizeof *pc->p))
        return 0;
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
            md_polyline_reverse(a); /* a now ends at the joined end */
        if (be & 2)
            md_polyline_reverse(b); /* b now starts there */
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

double md_polyline_dist(const double *P, int64_t n, const double *p)
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
        if (!md_subset_of(s, ns, o->elems.v + e0, e1 - e0))
            continue;
        const double *P = o->pts.v + 3 * o->pt_off.v[k];
        int64_t np = o->pt_off.v[k + 1] - o->pt_off.v[k], i = 0;
        while (i < pl->rad.n && md_polyline_dist(P, np, pl->pts.v + 3 * i) <= tol)
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

void md_pend_free(pend_list *pl)
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
    if (!mfg_grow((void **)&pl->v, &pl->cap, pl->n + 1, sizeof *pl->v))
        return 0;
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
int md_soup_seams(const md_asm *ax, const md_soup *sp, const asm_state *s, const seam_out *o,
                  int64_t ndeg, pend_list *out)
{
    const md_elements *el = ax->el;
    const md_bvh *bvh = ax->bvh;
    double reach = ax->reach, tol = ax->tol;
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
        while (ok && k < m && !md_cmp_set(seg[k].e, seg[k].ne, seg[i].e, seg[i].ne)) {
            int64_t j = k;
            while (j < m && !md_cmp_set(seg[j].e, seg[j].ne, seg[k].e, seg[k].ne) &&
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
    return md_cmp_xyz(a->j->x, b->j->x);
}

int md_degenerate_seams(const md_asm *ax, md_junction *P, int64_t np, const md_jset *J,
                        seam_out *o)
{
    double h = ax->h;
    if (np > 1)
        qsort(P, (size_t)(np), sizeof *P, md_cmp_junction);
    dpt *d = malloc((size_t)(np ? np : 1) * sizeof *d);
    if (!d)
        return 0;
    int ok = 1;
    polyline pl = {{0}, {0}};
    for (int64_t i = 0; i < np && ok;) {
        int64_t j = i;
        while (j < np && md_same_set(&P[j], &P[i]))
            j++;
        if (md_set_has_output_pair(ax->el, P[i].elems, P[i].n, ax->full)) {
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
                    ok = md_emit_seam(ax, J, o, &pl, P[i].elems, P[i].n, MFG_MEDIAL_DEGENERATE);
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
