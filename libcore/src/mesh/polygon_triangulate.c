/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* polygon_triangulate.c - a polygon with holes cut into triangles on its own vertices.
 *
 * Every hole is joined to the outer loop by a bridge (two copies of the segment between a
 * hole vertex and an outer vertex it sees, checked against every edge with exact
 * orientations), which leaves one weakly simple loop; that loop is cut by ear clipping: a
 * strictly convex corner whose triangle holds no other corner is cut off.  Ear clipping
 * of a loop gives triangles whose boundary is the loop, so triangles that all turn
 * counter-clockwise cover its inside exactly once; no vertex is moved, dropped or added.
 */
#include "mesh/polygon_triangulate.h"

#include <math.h>
#include <stdlib.h>

#include "common/predicates.h"

typedef struct pt_list {
    const double *xy;
    int64_t *idx;  /* node -> point */
    int64_t *next, *prev;
    char *alive;
    char *inrefl;  /* node -> in the list of corners that may block an ear */
    char *dup;     /* node -> another node lies at the same point */
} pt_list;

static double px(const pt_list *L, int64_t i)
{
    return L->xy[2 * L->idx[i]];
}

static double py(const pt_list *L, int64_t i)
{
    return L->xy[2 * L->idx[i] + 1];
}

static int orient(const pt_list *L, int64_t a, int64_t b, int64_t c)
{
    return mfg_orient2d(px(L, a), py(L, a), px(L, b), py(L, b), px(L, c), py(L, c));
}

static int samepos(const pt_list *L, int64_t a, int64_t b)
{
    return px(L, a) == px(L, b) && py(L, a) == py(L, b);
}

/* Does the direction from node v to node q leave v into the region (strictly inside the
 * corner between v's edges; the region lies on the left of the loop)? */
static int inside_cone(const pt_list *L, int64_t v, int64_t q)
{
    int64_t p = L->prev[v], n = L->next[v];
    if (orient(L, p, v, n) > 0)
        return orient(L, p, v, q) > 0 && orient(L, v, n, q) > 0;
    return orient(L, p, v, q) > 0 || orient(L, v, n, q) > 0;
}

/* q on the closed segment ab (a != b in position)? */
static int on_segment(const pt_list *L, int64_t a, int64_t b, int64_t q)
{
    if (orient(L, a, b, q) != 0)
        return 0;
    return fmin(px(L, a), px(L, b)) <= px(L, q) && px(L, q) <= fmax(px(L, a), px(L, b)) &&
           fmin(py(L, a), py(L, b)) <= py(L, q) && py(L, q) <= fmax(py(L, a), py(L, b));
}

/* Do the closed segments ab and cd meet? */
static int segments_meet(const pt_list *L, int64_t a, int64_t b, int64_t c, int64_t d)
{
    int o1 = orient(L, a, b, c), o2 = orient(L, a, b, d);
    int o3 = orient(L, c, d, a), o4 = orient(L, c, d, b);
    if (o1 * o2 < 0 && o3 * o4 < 0)
        return 1;
    return on_segment(L, a, b, c) || on_segment(L, a, b, d) || on_segment(L, c, d, a) ||
           on_segment(L, c, d, b);
}

/* Can the bridge P-M be drawn: inside the region at both ends, meeting no edge of the
 * loops listed in heads (each a node of a circular list, or -1) other than at P and M? */
static int bridge_ok(const pt_list *L, int64_t P, int64_t M, const int64_t *heads, int64_t nheads)
{
    if (!inside_cone(L, P, M) || !inside_cone(L, M, P))
        return 0;
    for (int64_t h = 0; h < nheads; h++) {
        int64_t u = heads[h];
        if (u < 0)
            continue;
        do {
            int64_t w = L->next[u];
            if (u != P && u != M && w != P && w != M) {
                int su = samepos(L, u, P) || samepos(L, u, M);
                int sw = samepos(L, w, P) || samepos(L, w, M);
                if (su && sw)
                    return 0; /* an edge along the bridge */
                if (su || sw) {
                    if (on_segment(L, P, M, su ? w : u))
                        return 0;
                } else if (segments_meet(L, P, M, u, w)) {
                    return 0;
                }
            }
            u = w;
        } while (u != heads[h]);
    }
    return 1;
}

typedef struct pt_cand {
    double d2;
    int64_t node;
} pt_cand;

static int cmp_cand(const void *pa, const void *pb)
{
    const pt_cand *a = pa, *b = pb;
    if (a->d2 != b->d2)
        return a->d2 < b->d2 ? -1 : 1;
    return (a->node > b->node) - (a->node < b->node);
}

typedef struct pt_hole {
    double xmax;
    int64_t loop;
} pt_hole;

static int cmp_hole(const void *pa, const void *pb)
{
    const pt_hole *a = pa, *b = pb;
    if (a->xmax != b->xmax)
        return a->xmax > b->xmax ? -1 : 1;
    return (a->loop > b->loop) - (a->loop < b->loop);
}

/* Is node r a corner that blocks the ear (a, b, c)?  A corner elsewhere in the ear does;
 * a corner at the same point as a corner X of the ear (the loop touches itself there, or a
 * bridge ends there) does when one of its edges leaves X into the ear's angle at X. */
static int blocks_ear(const pt_list *L, int64_t a, int64_t b, int64_t c, int64_t r)
{
    int at[3] = {samepos(L, r, a), samepos(L, r, b), samepos(L, r, c)};
    if (at[0] || at[1] || at[2]) {
        int64_t q[2] = {L->prev[r], L->next[r]};
        for (int k = 0; k < 2; k++) {
            int sab = orient(L, a, b, q[k]) > 0, sbc = orient(L, b, c, q[k]) > 0,
                sca = orient(L, c, a, q[k]) > 0;
            if ((at[0] && sab && sca) || (at[1] && sab && sbc) || (at[2] && sbc && sca))
                return 1;
        }
        return 0;
    }
    return orient(L, a, b, r) >= 0 && orient(L, b, c, r) >= 0 && orient(L, c, a, r) >= 0;
}

typedef struct pt_xy {
    double x, y;
    int64_t node;
} pt_xy;

static int cmp_xy(const void *pa, const void *pb)
{
    const pt_xy *a = pa, *b = pb;
    if (a->x != b->x)
        return a->x < b->x ? -1 : 1;
    if (a->y != b->y)
        return a->y < b->y ? -1 : 1;
    return (a->node > b->node) - (a->node < b->node);
}

/* The triangulation's working state: the node lists and the scratch arrays of its steps. */
typedef struct pt_work {
    pt_list L;
    pt_xy *byxy;     /* corners sorted by point */
    int64_t *heads;  /* heads[0]: the outer list; heads[1 + h]: hole h, -1 once bridged */
    int64_t nheads;
    pt_hole *holes;  /* the holes, in bridging order */
    pt_cand *cand;   /* bridge candidates by distance */
    int64_t *refl;   /* the corners that may block an ear */
    int64_t nnodes;  /* nodes in use (bridges add two each) */
} pt_work;

/* The loops as circular lists; the outer one is the only one turning counter-clockwise.
 * 1 with *outer and *nholes (W->holes filled), 0 when the loops are not such a region. */
static int load_loops(pt_work *W, const int64_t *loop_start, int64_t nloops, int64_t *outer,
                      int64_t *nholes)
{
    pt_list *L = &W->L;
    const double *xy = L->xy;
    int64_t first = loop_start[0];
    *outer = -1;
    *nholes = 0;
    for (int64_t i = 0; i < nloops; i++) {
        int64_t s = loop_start[i] - first, e = loop_start[i + 1] - first;
        if (e - s < 3)
            return 0;
        double area = 0, xmax = -INFINITY;
        for (int64_t j = s; j < e; j++) {
            int64_t k = j + 1 < e ? j + 1 : s;
            L->idx[j] = first + j;
            L->next[j] = k;
            L->prev[k] = j;
            area += xy[2 * (first + j)] * xy[2 * (first + k) + 1] - xy[2 * (first + k)] * xy[2 * (first + j) + 1];
            xmax = fmax(xmax, xy[2 * (first + j)]);
        }
        if (!(area > 0 || area < 0))
            return 0;
        if (area > 0) {
            if (*outer >= 0)
                return 0;
            *outer = i;
        } else {
            W->holes[*nholes].xmax = xmax;
            W->holes[*nholes].loop = i;
            (*nholes)++;
        }
    }
    return *outer >= 0;
}

/* Joins hole h (nodes s .. e) to the outer list: at a point where they touch, or by a
 * bridge to the nearest corner of the outer list that the hole's rightmost corner sees.
 * 1, or 0 when there is neither. */
static int join_hole(pt_work *W, int64_t s, int64_t e, int64_t h)
{
    pt_list *L = &W->L;
    pt_xy *byxy = W->byxy;
    pt_cand *cand = W->cand;
    int64_t *heads = W->heads;
    int64_t M = s;
    for (int64_t j = s + 1; j < e; j++)
        if (px(L, j) > px(L, M) || (px(L, j) == px(L, M) && py(L, j) > py(L, M)))
            M = j;
    int64_t P = -1;
    int touch = 0;
    /* a hole that touches the outer list (holes bridged so far included) at a point is
     * joined to it there, without a bridge, where its corner lies inside the outer
     * one's (a bridge elsewhere would cut the region in two at that point) */
    int64_t nb = 0, u = heads[0];
    do {
        byxy[nb].x = px(L, u);
        byxy[nb].y = py(L, u);
        byxy[nb].node = u;
        nb++;
        u = L->next[u];
    } while (u != heads[0]);
    qsort(byxy, (size_t)nb, sizeof *byxy, cmp_xy);
    for (int64_t j = s; j < e && P < 0; j++) {
        pt_xy key = {px(L, j), py(L, j), -1};
        int64_t lo = 0, hi = nb; /* first entry not below key */
        while (lo < hi) {
            int64_t mid = lo + (hi - lo) / 2;
            if (cmp_xy(&byxy[mid], &key) < 0)
                lo = mid + 1;
            else
                hi = mid;
        }
        for (int64_t k = lo; k < nb && byxy[k].x == key.x && byxy[k].y == key.y && P < 0; k++) {
            int64_t q = byxy[k].node;
            if (inside_cone(L, q, L->next[j]) && inside_cone(L, j, L->next[q])) {
                P = q;
                M = j;
                touch = 1;
            }
        }
    }
    /* else a bridge to the nearest corner of the outer list that M sees */
    int64_t nc = 0;
    u = heads[0];
    do {
        double dx = px(L, u) - px(L, M), dy = py(L, u) - py(L, M);
        cand[nc].d2 = dx * dx + dy * dy;
        cand[nc].node = u;
        nc++;
        u = L->next[u];
    } while (u != heads[0] && P < 0);
    if (P < 0)
        qsort(cand, (size_t)nc, sizeof *cand, cmp_cand);
    for (int64_t k = 0; k < nc && P < 0; k++) {
        int64_t q = cand[k].node;
        if (!samepos(L, q, M) && bridge_ok(L, q, M, heads, W->nheads))
            P = q;
    }
    if (P < 0)
        return 0;
    int64_t Pn = L->next[P], Mp = L->prev[M];
    if (touch) {
        int64_t Mn = L->next[M];
        L->next[P] = Mn;
        L->prev[Mn] = P;
        L->next[M] = Pn;
        L->prev[Pn] = M;
    } else {
        int64_t M2 = W->nnodes++, P2 = W->nnodes++;
        L->idx[M2] = L->idx[M];
        L->idx[P2] = L->idx[P];
        L->next[P] = M;
        L->prev[M] = P;
        L->next[Mp] = M2;
        L->prev[M2] = Mp;
        L->next[M2] = P2;
        L->prev[P2] = M2;
        L->next[P2] = Pn;
        L->prev[Pn] = P2;
    }
    heads[1 + h] = -1; /* part of the outer list now */
    return 1;
}

/* Ear clipping of the one loop left (heads[0]): 1 with the triangles in tri and *ntri,
 * 0 when no triangulation was found. */
static int clip_ears(pt_work *W, int64_t *tri, int64_t *ntri)
{
    pt_list *L = &W->L;
    pt_xy *byxy = W->byxy;
    int64_t *refl = W->refl, nnodes = W->nnodes;
    /* the corners that can block an ear: reflex ones, and every corner at a point that
     * holds several */
    int64_t m = 0, nrefl = 0, u0 = W->heads[0], u = u0;
    do {
        byxy[m].x = px(L, u);
        byxy[m].y = py(L, u);
        byxy[m].node = u;
        m++;
        u = L->next[u];
    } while (u != u0 && m <= nnodes);
    if (m != nnodes)
        return 0;
    qsort(byxy, (size_t)m, sizeof *byxy, cmp_xy);
    for (int64_t k = 0; k + 1 < m; k++)
        if (byxy[k].x == byxy[k + 1].x && byxy[k].y == byxy[k + 1].y)
            L->dup[byxy[k].node] = L->dup[byxy[k + 1].node] = 1;
    m = 0;
    do {
        L->alive[u] = 1;
        m++;
        if (L->dup[u] || orient(L, L->prev[u], u, L->next[u]) <= 0) {
            refl[nrefl++] = u;
            L->inrefl[u] = 1;
        }
        u = L->next[u];
    } while (u != u0);
    if (m != nnodes)
        return 0;
    int64_t nt = 0, stall = 0, cur = u0;
    while (m > 3) {
        int64_t a = L->prev[cur], c = L->next[cur];
        int ear = orient(L, a, cur, c) > 0;
        if (ear) {
            double x0 = fmin(px(L, a), fmin(px(L, cur), px(L, c)));
            double x1 = fmax(px(L, a), fmax(px(L, cur), px(L, c)));
            double y0 = fmin(py(L, a), fmin(py(L, cur), py(L, c)));
            double y1 = fmax(py(L, a), fmax(py(L, cur), py(L, c)));
            int64_t keep = 0;
            for (int64_t k = 0; k < nrefl; k++) {
                int64_t r = refl[k];
                /* corners gone or turned convex leave the list as it is scanned */
                if (!L->alive[r] || (!L->dup[r] && orient(L, L->prev[r], r, L->next[r]) > 0)) {
                    L->inrefl[r] = 0;
                    continue;
                }
                refl[keep++] = r;
                if (!ear || r == a || r == cur || r == c)
                    continue;
                if (px(L, r) < x0 || px(L, r) > x1 || py(L, r) < y0 || py(L, r) > y1)
                    continue;
                if (blocks_ear(L, a, cur, c, r))
                    ear = 0;
            }
            nrefl = keep;
        }
        if (ear) {
            tri[3 * nt] = L->idx[a];
            tri[3 * nt + 1] = L->idx[cur];
            tri[3 * nt + 2] = L->idx[c];
            nt++;
            L->next[a] = c;
            L->prev[c] = a;
            L->alive[cur] = 0;
            m--;
            stall = 0;
            /* a corner that became reflex (possible only where the loop touches itself)
             * must be looked at again */
            if (!L->inrefl[a] && orient(L, L->prev[a], a, c) <= 0) {
                refl[nrefl++] = a;
                L->inrefl[a] = 1;
            }
            if (!L->inrefl[c] && orient(L, a, c, L->next[c]) <= 0) {
                refl[nrefl++] = c;
                L->inrefl[c] = 1;
            }
            cur = a;
        } else {
            cur = c;
            if (++stall > m)
                return 0;
        }
    }
    int64_t a = L->prev[cur], c = L->next[cur];
    if (orient(L, a, cur, c) <= 0)
        return 0;
    tri[3 * nt] = L->idx[a];
    tri[3 * nt + 1] = L->idx[cur];
    tri[3 * nt + 2] = L->idx[c];
    nt++;
    if (nt != nnodes - 2)
        return 0;
    *ntri = nt;
    return 1;
}

int mfg_polygon_triangulate(const double *xy, const int64_t *loop_start, int64_t nloops,
                            int64_t *tri, int64_t *ntri)
{
    *ntri = 0;
    if (nloops < 1)
        return 0;
    int64_t n = loop_start[nloops] - loop_start[0];
    int64_t first = loop_start[0];
    int64_t cap = n + 2 * (nloops - 1);
    pt_work W;
    pt_list *L = &W.L;
    L->xy = xy;
    L->idx = malloc((size_t)(cap + 1) * sizeof *L->idx);
    L->next = malloc((size_t)(cap + 1) * sizeof *L->next);
    L->prev = malloc((size_t)(cap + 1) * sizeof *L->prev);
    L->alive = calloc((size_t)(cap + 1), 1);
    L->inrefl = calloc((size_t)(cap + 1), 1);
    L->dup = calloc((size_t)(cap + 1), 1);
    W.byxy = malloc((size_t)(cap + 1) * sizeof *W.byxy);
    W.heads = malloc((size_t)(nloops + 1) * sizeof *W.heads);
    W.holes = malloc((size_t)(nloops + 1) * sizeof *W.holes);
    W.cand = malloc((size_t)(cap + 1) * sizeof *W.cand);
    W.refl = malloc((size_t)(cap + 1) * sizeof *W.refl);
    int rc = 0;
    if (!L->idx || !L->next || !L->prev || !L->alive || !L->inrefl || !L->dup || !W.byxy ||
        !W.heads || !W.holes || !W.cand || !W.refl) {
        rc = -1;
        goto done;
    }
    int64_t outer, nholes;
    if (!load_loops(&W, loop_start, nloops, &outer, &nholes))
        goto done;
    qsort(W.holes, (size_t)nholes, sizeof *W.holes, cmp_hole);
    W.nheads = 0;
    W.heads[W.nheads++] = loop_start[outer] - first;
    for (int64_t h = 0; h < nholes; h++)
        W.heads[W.nheads++] = loop_start[W.holes[h].loop] - first;
    W.nnodes = n;
    for (int64_t h = 0; h < nholes; h++) {
        int64_t s = loop_start[W.holes[h].loop] - first, e = loop_start[W.holes[h].loop + 1] - first;
        if (!join_hole(&W, s, e, h))
            goto done;
    }
    rc = clip_ears(&W, tri, ntri);
done:
    free(L->idx);
    free(L->next);
    free(L->prev);
    free(L->alive);
    free(L->inrefl);
    free(L->dup);
    free(W.byxy);
    free(W.heads);
    free(W.holes);
    free(W.cand);
    free(W.refl);
    return rc;
}
