/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* element_distances.c - the distances of the boundary elements (elements.c; Lee & Lee, the
 * medial surface of a polyhedron; docs/design/medial.md section 1): carrier distances,
 * region margins, distances restricted to the Voronoi regions (the paper's special
 * bisectors, Fig. 3), incidence and adjacency, and the brute-force touching set. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "medial/medial.h"
#include "mesh/mesh.h"
#include "common/mfg_internal.h"
#include "common/predicates.h"

double md_dist_car(const md_elements *el, int64_t e, const double x[3], double grad[3])
{
    int kind = md_kind(el, e);
    if (kind == MD_FACE) {
        const double *pl = el->face_plane + 4 * e;
        if (grad)
            for (int k = 0; k < 3; k++)
                grad[k] = -pl[k];
        return pl[3] - mfg_dot3(pl, x);
    }
    double r[3];
    if (kind == MD_EDGE) {
        int64_t i = e - el->nfaces;
        const double *A = el->edge_seg + 6 * i, *u = el->edge_dir + 3 * i;
        double d[3];
        mfg_sub3(x, A, d);
        double t = mfg_dot3(d, u);
        for (int k = 0; k < 3; k++)
            r[k] = d[k] - t * u[k];
    } else {
        mfg_sub3(x, el->vert_xyz + 3 * (e - el->nfaces - el->nedges), r);
    }
    double d = mfg_norm3(r);
    if (grad)
        for (int k = 0; k < 3; k++)
            grad[k] = d > 0 ? r[k] / d : 0.0;
    return d;
}

/* Distance from x to segment ab (3-D). */
static double seg_dist(const double *x, const double *a, const double *b)
{
    return sqrt(mfg_seg_dist2(x, a, b));
}

/* ---- side trees ---------------------------------------------------------------------------- */

/* Faces with more sides than this get a side tree; below it the plain loops are faster. */
#define MD_SIDE_TREE_MIN 24
/* Sides per leaf. */
#define SIDE_LEAF 4

/* A node of a face's side tree: the box of its sides (exact min / max of their ends) and
 * either two children (kid >= 0: kid and kid + 1, relative to the face's first node) or,
 * as a leaf (kid < 0), positions side_tree_perm[lo .. hi). */
typedef struct md_side_node {
    double lo[3], hi[3];
    int64_t kid, first, count;
} md_side_node;

static const double *side_end(const md_elements *el, int64_t q, int which)
{
    int64_t sd = el->face_sides[q], t = sd / 3, k = sd % 3;
    return el->xyz + 3 * el->tris[3 * t + (which ? (k + 1) % 3 : k)];
}

/* Median split of perm[lo .. hi) along the box's longest axis, by side midpoints: a
 * selection by repeated partition (quickselect) keeps the build O(n log n). */
static void side_select(const md_elements *el, int64_t *perm, int64_t lo, int64_t hi, int64_t nth, int ax)
{
    while (hi - lo > 1) {
        int64_t mid = lo + (hi - lo) / 2;
        double piv = side_end(el, perm[mid], 0)[ax] + side_end(el, perm[mid], 1)[ax];
        int64_t i = lo, j = hi - 1;
        while (i <= j) {
            while (side_end(el, perm[i], 0)[ax] + side_end(el, perm[i], 1)[ax] < piv)
                i++;
            while (side_end(el, perm[j], 0)[ax] + side_end(el, perm[j], 1)[ax] > piv)
                j--;
            if (i <= j) {
                int64_t t = perm[i];
                perm[i++] = perm[j];
                perm[j--] = t;
            }
        }
        if (nth <= j)
            hi = j + 1;
        else if (nth >= i)
            lo = i;
        else
            return;
    }
}

/* Builds the subtree of perm[lo .. hi) at node index at (relative to N); returns the
 * next free node index. */
static int64_t side_tree_node(const md_elements *el, md_side_node *N, int64_t at, int64_t next,
                              int64_t *perm, int64_t lo, int64_t hi, int64_t base)
{
    md_side_node *n = N + at;
    for (int k = 0; k < 3; k++) {
        n->lo[k] = INFINITY;
        n->hi[k] = -INFINITY;
    }
    for (int64_t i = lo; i < hi; i++)
        for (int w = 0; w < 2; w++) {
            const double *p = side_end(el, perm[i], w);
            for (int k = 0; k < 3; k++) {
                n->lo[k] = fmin(n->lo[k], p[k]);
                n->hi[k] = fmax(n->hi[k], p[k]);
            }
        }
    if (hi - lo <= SIDE_LEAF) {
        n->kid = -1;
        n->first = lo - base;
        n->count = hi - lo;
        return next;
    }
    int ax = 0;
    for (int k = 1; k < 3; k++)
        if (n->hi[k] - n->lo[k] > n->hi[ax] - n->lo[ax])
            ax = k;
    int64_t mid = lo + (hi - lo) / 2;
    side_select(el, perm, lo, hi, mid, ax);
    n->kid = next;
    n->first = n->count = 0;
    int64_t kid = next;
    next = side_tree_node(el, N, kid, next + 2, perm, lo, mid, base);
    return side_tree_node(el, N, kid + 1, next, perm, mid, hi, base);
}

int md_side_trees_build(md_elements *el)
{
    int64_t nf = el->nfaces, total = 0;
    el->side_tree_offsets = malloc((size_t)(nf + 1) * sizeof *el->side_tree_offsets);
    if (!el->side_tree_offsets)
        return 0;
    el->side_tree_offsets[0] = 0;
    for (int64_t f = 0; f < nf; f++) {
        int64_t ns = el->face_side_offsets[f + 1] - el->face_side_offsets[f];
        total += ns > MD_SIDE_TREE_MIN ? 2 * ns : 0; /* a binary tree of ns leaves at most */
        el->side_tree_offsets[f + 1] = total;
    }
    int64_t nq = el->face_side_offsets[nf];
    el->side_nodes = malloc((size_t)(total + 1) * sizeof *el->side_nodes);
    el->side_tree_perm = malloc((size_t)(nq + 1) * sizeof *el->side_tree_perm);
    if (!el->side_nodes || !el->side_tree_perm)
        return 0;
    for (int64_t q = 0; q < nq; q++)
        el->side_tree_perm[q] = q;
    for (int64_t f = 0; f < nf; f++) {
        int64_t n0 = el->side_tree_offsets[f];
        if (el->side_tree_offsets[f + 1] == n0)
            continue;
        int64_t q0 = el->face_side_offsets[f], q1 = el->face_side_offsets[f + 1];
        side_tree_node(el, el->side_nodes + n0, 0, 1, el->side_tree_perm, q0, q1, q0);
    }
    return 1;
}

/* Squared distance from p to the box of node n. */
static double box_dist2(const md_side_node *n, const double *p)
{
    return mfg_box_dist2(n->lo, n->hi, p);
}

/* The nearest boundary side of face f to p: its distance, and in *q its position in
 * face_sides -- the first of the nearest in that order, as the plain loop finds it, so
 * the result is the same bit for bit with or without a tree. */
static double nearest_side(const md_elements *el, int64_t f, const double *p, int64_t *qbest)
{
    double best = INFINITY;
    int64_t bq = -1, q0 = el->face_side_offsets[f];
    int64_t n0 = el->side_tree_offsets[f], nn = el->side_tree_offsets[f + 1] - n0;
    if (nn == 0) {
        for (int64_t q = q0; q < el->face_side_offsets[f + 1]; q++) {
            double d = seg_dist(p, side_end(el, q, 0), side_end(el, q, 1));
            if (d < best) {
                best = d;
                bq = q;
            }
        }
        *qbest = bq;
        return best;
    }
    const md_side_node *N = el->side_nodes + n0;
    const int64_t *perm = el->side_tree_perm + q0;
    int64_t stack[128], top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const md_side_node *n = N + stack[--top];
        /* a box no nearer than the best (with a margin for rounding: a tie must still be
         * seen, the smaller position wins it) holds nothing to take */
        if (box_dist2(n, p) > best * best * (1 + 1e-9))
            continue;
        if (n->kid < 0) {
            for (int64_t i = n->first; i < n->first + n->count; i++) {
                int64_t q = perm[i];
                double d = seg_dist(p, side_end(el, q, 0), side_end(el, q, 1));
                if (d < best || (d == best && q < bq)) {
                    best = d;
                    bq = q;
                }
            }
            continue;
        }
        /* the nearer child last, so it is taken first */
        int64_t a = n->kid, b = n->kid + 1;
        if (box_dist2(N + a, p) < box_dist2(N + b, p)) {
            int64_t t = a;
            a = b;
            b = t;
        }
        if (top + 2 <= (int64_t)(sizeof stack / sizeof *stack)) {
            stack[top++] = a;
            stack[top++] = b;
        }
    }
    *qbest = bq;
    return best;
}

/* Side q's part of the winding number of p about face f (Sunday's rule, exact). */
static int side_winding(const md_elements *el, int64_t q, const double *p, int i0, int i1)
{
    const double *a = side_end(el, q, 0), *b = side_end(el, q, 1);
    if (a[i1] <= p[i1]) {
        if (b[i1] > p[i1] && mfg_orient2d(a[i0], a[i1], b[i0], b[i1], p[i0], p[i1]) > 0)
            return 1;
    } else if (b[i1] <= p[i1] && mfg_orient2d(a[i0], a[i1], b[i0], b[i1], p[i0], p[i1]) < 0) {
        return -1;
    }
    return 0;
}

/* Is the projection p of a point on face f's plane inside the face?  Winding number of
 * its boundary sides (outer loop and holes) after dropping the dominant axis (Sunday's
 * rule with exact orientations): O(boundary sides), not O(triangles).  The dropped axis
 * may mirror the face, which flips the winding's sign but not whether it is 0.  With a
 * side tree only the sides whose box meets the ray from p along +i0 are visited: a side
 * wholly before p along i0, or not spanning p's i1, adds exactly 0 (p lies strictly on
 * its outer side), so the count is the same. */
static int face_contains(const md_elements *el, int64_t f, const double *p)
{
    int ax = el->face_axis[f], i0 = (ax + 1) % 3, i1 = (ax + 2) % 3;
    int64_t wn = 0, q0 = el->face_side_offsets[f];
    int64_t n0 = el->side_tree_offsets[f], nn = el->side_tree_offsets[f + 1] - n0;
    if (nn == 0) {
        for (int64_t q = q0; q < el->face_side_offsets[f + 1]; q++)
            wn += side_winding(el, q, p, i0, i1);
        return wn != 0;
    }
    const md_side_node *N = el->side_nodes + n0;
    const int64_t *perm = el->side_tree_perm + q0;
    int64_t stack[128], top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const md_side_node *n = N + stack[--top];
        if (n->hi[i0] < p[i0] || n->lo[i1] > p[i1] || n->hi[i1] < p[i1])
            continue;
        if (n->kid < 0) {
            for (int64_t i = n->first; i < n->first + n->count; i++)
                wn += side_winding(el, perm[i], p, i0, i1);
        } else if (top + 2 <= (int64_t)(sizeof stack / sizeof *stack)) {
            stack[top++] = n->kid;
            stack[top++] = n->kid + 1;
        }
    }
    return wn != 0;
}

double md_region_margin(const md_elements *el, int64_t e, const double x[3], int64_t *which)
{
    int kind = md_kind(el, e);
    int64_t w = -1;
    double m;
    if (kind == MD_FACE) {
        const double *pl = el->face_plane + 4 * e;
        double s = pl[3] - mfg_dot3(pl, x), p[3];
        for (int k = 0; k < 3; k++)
            p[k] = x[k] + s * pl[k];
        int64_t q;
        double best = nearest_side(el, e, p, &q);
        if (q >= 0)
            w = el->side_elem[el->face_sides[q]];
        /* On the boundary (best == 0) the foot is in the closed face. */
        m = best == 0 || face_contains(el, e, p) ? best : -best;
        if (s < m) {
            m = s;
            w = -1;
        }
    } else if (kind == MD_EDGE) {
        int64_t i = e - el->nfaces;
        const double *A = el->edge_seg + 6 * i, *u = el->edge_dir + 3 * i;
        double d[3];
        mfg_sub3(x, A, d);
        double t = mfg_dot3(d, u);
        double c[4] = {t, el->edge_len[i] - t, -mfg_dot3(el->edge_w + 6 * i, d),
                       -mfg_dot3(el->edge_w + 6 * i + 3, d)};
        int64_t ids[4] = {el->edge_ends[2 * i], el->edge_ends[2 * i + 1], el->edge_faces[2 * i],
                          el->edge_faces[2 * i + 1]};
        m = c[0];
        w = ids[0];
        for (int k = 1; k < 4; k++)
            if (c[k] < m) {
                m = c[k];
                w = ids[k];
            }
    } else {
        int64_t j = e - el->nfaces - el->nedges;
        if (el->vert_region_empty[j]) {
            m = -INFINITY;
        } else {
            const double *V = el->vert_xyz + 3 * j;
            double d[3];
            mfg_sub3(x, V, d);
            m = INFINITY;
            for (int64_t q = el->vert_edge_offsets[j]; q < el->vert_edge_offsets[j + 1]; q++) {
                int64_t ed = el->vert_edges[q], i = ed - el->nfaces;
                /* d_k: the edge's direction away from V. */
                double sgn = el->edge_ends[2 * i] == e ? 1.0 : -1.0;
                double c = -sgn * mfg_dot3(d, el->edge_dir + 3 * i);
                if (c < m) {
                    m = c;
                    w = ed;
                }
            }
        }
    }
    if (which)
        *which = w;
    return m;
}

/* Distance from p to triangle abc: the plane's foot when it falls inside, otherwise the
 * nearest of the three sides. */
static double tri_dist(const double *p, const double *a, const double *b, const double *c)
{
    double ab[3], ac[3], n[3], ap[3];
    mfg_sub3(b, a, ab);
    mfg_sub3(c, a, ac);
    mfg_sub3(p, a, ap);
    mfg_cross3(ab, ac, n);
    double nn = mfg_dot3(n, n);
    if (nn > 0) {
        /* Barycentric signs of the foot: each side's cross product against n. */
        double bp[3], cp[3], t[3], bc[3], ca[3];
        mfg_sub3(p, b, bp);
        mfg_sub3(p, c, cp);
        mfg_sub3(c, b, bc);
        mfg_sub3(a, c, ca);
        mfg_cross3(ab, ap, t);
        int in = mfg_dot3(t, n) >= 0;
        mfg_cross3(bc, bp, t);
        in = in && mfg_dot3(t, n) >= 0;
        mfg_cross3(ca, cp, t);
        in = in && mfg_dot3(t, n) >= 0;
        if (in)
            return fabs(mfg_dot3(ap, n)) / sqrt(nn);
    }
    return fmin(seg_dist(p, a, b), fmin(seg_dist(p, b, c), seg_dist(p, c, a)));
}

double md_dist_closed(const md_elements *el, int64_t e, const double x[3])
{
    int kind = md_kind(el, e);
    if (kind == MD_FACE) {
        double best = INFINITY;
        for (int64_t q = el->face_tri_offsets[e]; q < el->face_tri_offsets[e + 1]; q++) {
            const int64_t *tv = el->tris + 3 * el->face_tris[q];
            best = fmin(best, tri_dist(x, el->xyz + 3 * tv[0], el->xyz + 3 * tv[1],
                                       el->xyz + 3 * tv[2]));
        }
        return best;
    }
    if (kind == MD_EDGE) {
        const double *A = el->edge_seg + 6 * (e - el->nfaces);
        return seg_dist(x, A, A + 3);
    }
    double d[3];
    mfg_sub3(x, el->vert_xyz + 3 * (e - el->nfaces - el->nedges), d);
    return mfg_norm3(d);
}

double md_dist(const md_elements *el, int64_t e, const double x[3])
{
    if (md_region_margin(el, e, x, NULL) < 0)
        return INFINITY;
    return md_dist_car(el, e, x, NULL);
}

static int in_sorted(const int64_t *l, int64_t n, int64_t v)
{
    int64_t lo = mfg_lower_bound_i64(l, n, v);
    return lo < n && l[lo] == v;
}

static int in_bound(const md_elements *el, int64_t e, int64_t v)
{
    int64_t o = el->bound_offsets[e];
    return in_sorted(el->bound + o, el->bound_offsets[e + 1] - o, v);
}

int md_incident(const md_elements *el, int64_t a, int64_t b)
{
    return a == b || in_bound(el, a, b) || in_bound(el, b, a);
}

int md_adjacent(const md_elements *el, int64_t a, int64_t b)
{
    if (md_incident(el, a, b))
        return 1;
    const int64_t *la = el->bound + el->bound_offsets[a], *lb = el->bound + el->bound_offsets[b];
    int64_t na = el->bound_offsets[a + 1] - el->bound_offsets[a];
    int64_t nb = el->bound_offsets[b + 1] - el->bound_offsets[b];
    for (int64_t i = 0, j = 0; i < na && j < nb;) {
        if (la[i] == lb[j])
            return 1;
        if (la[i] < lb[j])
            i++;
        else
            j++;
    }
    return 0;
}

int64_t md_nearest_set_brute(const md_elements *el, const double x[3], double delta,
                             int64_t *out, double *D)
{
    double best = INFINITY;
    for (int64_t e = 0; e < el->nelements; e++) {
        double d = md_dist(el, e, x);
        if (d < best)
            best = d;
    }
    int64_t n = 0;
    if (best < INFINITY)
        for (int64_t e = 0; e < el->nelements; e++)
            if (md_dist(el, e, x) <= best + delta)
                out[n++] = e;
    if (D)
        *D = best;
    return n;
}
