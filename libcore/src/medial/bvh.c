/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* bvh.c - the medial surface's distance field (issue 9; docs/design/medial.md section 2): a
 * bounding-volume hierarchy over the non-degenerate triangles of the merged polyhedron.
 * Nearest queries map the triangle feature that holds the nearest point (Ericson's
 * closest-point regions) to the one element whose relative interior holds it and sign the
 * distance by that element's angle-weighted pseudonormal (Baerentzen & Aanaes); ball
 * queries return the elements whose closure meets a closed ball (the octree's candidate
 * sets, design 3). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "medial/medial.h"
#include "common/mfg_internal.h"

/* Triangles per leaf (design 2). */
#define LEAF_MAX 4
/* Traversal stack: median splits halve every range, so the depth is at most
 * log2(MFG_MAX_COUNT) = 40 and a depth-first walk holds at most depth + 1 nodes. */
#define STACK_MAX 128
/* Raw ball hits gathered before they are sorted and merged into the result. */
#define HIT_BUF 256
/* Box tests only prune: a relative slack keeps a box whose rounded distance exceeds a
 * triangle's inside it by a few ulps from being skipped. */
#define BOX_SLACK (1.0 + 1e-12)

typedef struct bvh_node {
    double lo[3], hi[3];
    int64_t right; /* internal: the right child (the left one is the next node); leaf: first */
    int32_t count; /* leaf: its triangles (1 .. LEAF_MAX); internal: 0 */
} bvh_node;

struct md_bvh {
    int64_t nnodes, ntris, nelements;
    bvh_node *node;
    int64_t *tri;   /* triangle ids (input order), in leaf order */
    double *corner; /* 9 per leaf-ordered triangle: its (rotated) corners */
    double *pseudo; /* 3 per element: the pseudonormal (not normalised) */
};

static double dist2(const double *a, const double *b)
{
    double d[3];
    mfg_sub3(a, b, d);
    return mfg_dot3(d, d);
}

/* ---- closest points ---------------------------------------------------------------- */

/* Triangle features as md_closest_on_tri reports them: corners 0..2 (a, b, c), sides 3..5
 * (a-b, b-c, c-a: side k runs from corner k to corner k + 1, as in md_elements), 6 the
 * interior. */
enum { FEAT_SIDE = 3, FEAT_INTERIOR = 6 };

/* Closest point q of segment ab to p; returns 0 (a), 1 (b) or 2 (between them).  t (may
 * be NULL) receives q's parameter: q = a + t (b - a). */
int md_closest_on_seg(const double *p, const double *a, const double *b, double *q, double *t_out)
{
    double ab[3], ap[3];
    mfg_sub3(b, a, ab);
    mfg_sub3(p, a, ap);
    double t = mfg_dot3(ap, ab), l2 = mfg_dot3(ab, ab);
    if (t <= 0 || !(l2 > 0)) {
        memcpy(q, a, 3 * sizeof *q);
        if (t_out)
            *t_out = 0;
        return 0;
    }
    if (t >= l2) {
        memcpy(q, b, 3 * sizeof *q);
        if (t_out)
            *t_out = 1;
        return 1;
    }
    t /= l2;
    if (t_out)
        *t_out = t;
    for (int k = 0; k < 3; k++)
        q[k] = a[k] + t * ab[k];
    return 2;
}

/* Closest point q of triangle abc to p and the feature holding it: Ericson, Real-Time
 * Collision Detection, 5.1.5 (the Voronoi regions of the corners, then of the sides, by
 * the signs of dot products and their 2x2 determinants).  w (may be NULL) receives q's
 * barycentric weights of a, b, c (wall_thickness.c interpolates radii with them). */
static void set_w(double *w, double wa, double wb, double wc)
{
    if (w) {
        w[0] = wa;
        w[1] = wb;
        w[2] = wc;
    }
}

int md_closest_on_tri(const double *p, const double *a, const double *b, const double *c,
                      double *q, double *w)
{
    double ab[3], ac[3], ap[3], bp[3], cp[3];
    mfg_sub3(b, a, ab);
    mfg_sub3(c, a, ac);
    mfg_sub3(p, a, ap);
    double d1 = mfg_dot3(ab, ap), d2 = mfg_dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) {
        memcpy(q, a, 3 * sizeof *q);
        set_w(w, 1, 0, 0);
        return 0;
    }
    mfg_sub3(p, b, bp);
    double d3 = mfg_dot3(ab, bp), d4 = mfg_dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) {
        memcpy(q, b, 3 * sizeof *q);
        set_w(w, 0, 1, 0);
        return 1;
    }
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        double v = d1 / (d1 - d3);
        for (int k = 0; k < 3; k++)
            q[k] = a[k] + v * ab[k];
        set_w(w, 1 - v, v, 0);
        return FEAT_SIDE + 0;
    }
    mfg_sub3(p, c, cp);
    double d5 = mfg_dot3(ab, cp), d6 = mfg_dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) {
        memcpy(q, c, 3 * sizeof *q);
        set_w(w, 0, 0, 1);
        return 2;
    }
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        double t = d2 / (d2 - d6);
        for (int k = 0; k < 3; k++)
            q[k] = a[k] + t * ac[k];
        set_w(w, 1 - t, 0, t);
        return FEAT_SIDE + 2;
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int k = 0; k < 3; k++)
            q[k] = b[k] + t * (c[k] - b[k]);
        set_w(w, 0, 1 - t, t);
        return FEAT_SIDE + 1;
    }
    double den = va + vb + vc;
    if (!(den > 0)) {
        /* A sliver whose determinants rounded to nothing: the nearest of its sides. */
        const double *s[4] = {a, b, c, a};
        double best = INFINITY, r[3], t;
        int feat = 0;
        for (int k = 0; k < 3; k++) {
            int f = md_closest_on_seg(p, s[k], s[k + 1], r, &t);
            double d = dist2(p, r);
            if (d < best) {
                best = d;
                memcpy(q, r, 3 * sizeof *q);
                feat = f == 2 ? FEAT_SIDE + k : (k + f) % 3;
                double ws[3] = {0, 0, 0};
                ws[k] = 1 - t;
                ws[(k + 1) % 3] = t;
                set_w(w, ws[0], ws[1], ws[2]);
            }
        }
        return feat;
    }
    double v = vb / den, t = vc / den;
    for (int k = 0; k < 3; k++)
        q[k] = a[k] + v * ab[k] + t * ac[k];
    set_w(w, 1 - v - t, v, t);
    return FEAT_INTERIOR;
}

/* The element whose relative interior holds feature feat of triangle t (design 1.6). */
static int64_t feature_elem(const md_elements *el, int64_t t, int feat)
{
    if (feat == FEAT_INTERIOR)
        return el->face_of_triangle[t];
    if (feat >= FEAT_SIDE)
        return el->side_elem[3 * t + feat - FEAT_SIDE];
    return el->corner_elem[3 * t + feat];
}

/* Squared distance from p to the box (0 inside). */
static double box_dist2(const bvh_node *n, const double *p)
{
    return mfg_box_dist2(n->lo, n->hi, p);
}

/* ---- build ------------------------------------------------------------------------- */

typedef struct morton_rec {
    uint64_t code;
    int64_t t;
} morton_rec;

static int cmp_morton(const void *pa, const void *pb)
{
    const morton_rec *x = pa, *y = pb;
    if (x->code != y->code)
        return x->code < y->code ? -1 : 1;
    return (x->t > y->t) - (x->t < y->t);
}

/* The 21 low bits of v spread to every third bit. */
static uint64_t spread3(uint64_t v)
{
    v &= 0x1fffff;
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
}

/* Node for the leaf-ordered triangles [b, e): preorder, the left child right after its
 * parent; median split of the Morton order (a balanced tree: depth log2(n / LEAF_MAX)). */
static void build_node(md_bvh *h, int64_t b, int64_t e)
{
    int64_t i = h->nnodes++;
    bvh_node *n = &h->node[i];
    for (int k = 0; k < 3; k++) {
        n->lo[k] = INFINITY;
        n->hi[k] = -INFINITY;
    }
    for (int64_t j = b; j < e; j++)
        for (int c = 0; c < 3; c++)
            for (int k = 0; k < 3; k++) {
                double v = h->corner[9 * j + 3 * c + k];
                n->lo[k] = fmin(n->lo[k], v);
                n->hi[k] = fmax(n->hi[k], v);
            }
    if (e - b <= LEAF_MAX) {
        n->right = b;
        n->count = (int32_t)(e - b);
        return;
    }
    int64_t mid = b + (e - b) / 2;
    n->count = 0;
    build_node(h, b, mid);
    h->node[i].right = h->nnodes; /* n may not be used across the recursion's writes */
    build_node(h, mid, e);
}

void md_bvh_free(md_bvh *h)
{
    if (!h)
        return;
    free(h->node);
    free(h->tri);
    free(h->corner);
    free(h->pseudo);
    free(h);
}

mfg_status md_bvh_build(const md_elements *el, md_bvh **out)
{
    if (!out)
        return mfg_fail(MFG_ERR_NULL, "md_bvh_build: out is NULL");
    *out = NULL;
    if (!el)
        return mfg_fail(MFG_ERR_NULL, "md_bvh_build: the elements are NULL");
    int64_t n = 0;
    for (int64_t t = 0; t < el->nt; t++)
        n += el->face_of_triangle[t] >= 0;
    md_bvh *h = calloc(1, sizeof *h);
    morton_rec *rec = NULL;
    if (!h)
        goto nomem;
    h->ntris = n;
    h->nelements = el->nelements;
    h->node = malloc((size_t)(2 * n + 1) * sizeof *h->node);
    h->tri = malloc((size_t)(n + 1) * sizeof *h->tri);
    h->corner = malloc((size_t)(9 * n + 1) * sizeof *h->corner);
    h->pseudo = calloc((size_t)(3 * el->nelements + 1), sizeof *h->pseudo);
    rec = malloc((size_t)(n + 1) * sizeof *rec);
    if (!h->node || !h->tri || !h->corner || !h->pseudo || !rec)
        goto nomem;

    /* Morton codes of the centroids on a 2^21 grid over their bounding box. */
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t t = 0, m = 0; t < el->nt; t++) {
        if (el->face_of_triangle[t] < 0)
            continue;
        double c[3] = {0, 0, 0};
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                c[k] += el->xyz[3 * el->tris[3 * t + j] + k] / 3.0;
        memcpy(h->corner + 3 * m, c, sizeof c); /* the centroids, for now */
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], c[k]);
            hi[k] = fmax(hi[k], c[k]);
        }
        rec[m].t = t;
        m++;
    }
    for (int64_t m = 0; m < n; m++) {
        uint64_t code = 0;
        for (int k = 0; k < 3; k++) {
            double ext = hi[k] - lo[k];
            double s = ext > 0 ? (h->corner[3 * m + k] - lo[k]) / ext * 2097151.0 : 0.0;
            uint64_t q = s <= 0 ? 0 : (s >= 2097151.0 ? 2097151 : (uint64_t)s);
            code |= spread3(q) << k;
        }
        rec[m].code = code;
    }
    qsort(rec, (size_t)n, sizeof *rec, cmp_morton);
    for (int64_t m = 0; m < n; m++) {
        int64_t t = rec[m].t;
        h->tri[m] = t;
        for (int j = 0; j < 3; j++)
            memcpy(h->corner + 9 * m + 3 * j, el->xyz + 3 * el->tris[3 * t + j], 3 * sizeof(double));
    }
    free(rec);
    rec = NULL;
    if (n > 0)
        build_node(h, 0, n);

    /* Pseudonormals (Baerentzen & Aanaes 2005): a face's normal; an edge's two face
     * normals summed; at a vertex the face normals weighted by the angles of the
     * triangle corners there.  (x - foot) . N > 0 exactly when x is outside, whichever
     * of these elements holds the nearest point. */
    for (int64_t f = 0; f < el->nfaces; f++)
        memcpy(h->pseudo + 3 * f, el->face_plane + 4 * f, 3 * sizeof(double));
    for (int64_t i = 0; i < el->nedges; i++) {
        const double *ni = el->face_plane + 4 * el->edge_faces[2 * i];
        const double *nj = el->face_plane + 4 * el->edge_faces[2 * i + 1];
        for (int k = 0; k < 3; k++)
            h->pseudo[3 * (el->nfaces + i) + k] = ni[k] + nj[k];
    }
    int64_t vbase = el->nfaces + el->nedges;
    for (int64_t t = 0; t < el->nt; t++) {
        int64_t f = el->face_of_triangle[t];
        if (f < 0)
            continue; /* zero area: no share of any vertex's neighbourhood */
        for (int k = 0; k < 3; k++) {
            int64_t v = el->corner_elem[3 * t + k];
            if (v < vbase)
                continue;
            const double *p = el->xyz + 3 * el->tris[3 * t + k];
            double a[3], b[3], c[3];
            mfg_sub3(el->xyz + 3 * el->tris[3 * t + (k + 1) % 3], p, a);
            mfg_sub3(el->xyz + 3 * el->tris[3 * t + (k + 2) % 3], p, b);
            c[0] = a[1] * b[2] - a[2] * b[1];
            c[1] = a[2] * b[0] - a[0] * b[2];
            c[2] = a[0] * b[1] - a[1] * b[0];
            double ang = atan2(sqrt(mfg_dot3(c, c)), mfg_dot3(a, b));
            for (int j = 0; j < 3; j++)
                h->pseudo[3 * v + j] += ang * el->face_plane[4 * f + j];
        }
    }
    *out = h;
    return MFG_OK;

nomem:
    free(rec);
    md_bvh_free(h);
    return mfg_fail(MFG_ERR_NOMEM, "out of memory building the BVH of %lld triangles",
                    (long long)n);
}

/* ---- nearest ----------------------------------------------------------------------- */

double md_bvh_nearest(const md_bvh *h, const md_elements *el, const double x[3],
                      int64_t *elem, int *inside)
{
    double best2 = INFINITY, foot[3] = {0, 0, 0};
    int64_t best_e = -1;
    if (h->ntris > 0) {
        int64_t stack[STACK_MAX];
        double sd2[STACK_MAX];
        int sp = 0;
        stack[sp] = 0;
        sd2[sp++] = box_dist2(&h->node[0], x);
        while (sp > 0) {
            sp--;
            /* Equal distances are kept (the smaller id wins a tie), hence > and not >=. */
            if (sd2[sp] > best2 * BOX_SLACK)
                continue;
            const bvh_node *n = &h->node[stack[sp]];
            if (n->count > 0) {
                for (int64_t j = n->right; j < n->right + n->count; j++) {
                    const double *c = h->corner + 9 * j;
                    double q[3];
                    int feat = md_closest_on_tri(x, c, c + 3, c + 6, q, NULL);
                    double d2 = dist2(x, q);
                    if (d2 > best2)
                        continue;
                    int64_t e = feature_elem(el, h->tri[j], feat);
                    if (d2 < best2 || e < best_e) {
                        best2 = d2;
                        best_e = e;
                        memcpy(foot, q, sizeof foot);
                    }
                }
                continue;
            }
            int64_t l = stack[sp] + 1, r = n->right;
            double dl = box_dist2(&h->node[l], x), dr = box_dist2(&h->node[r], x);
            /* The nearer child on top: it is searched first and tightens best2. */
            if (dl <= dr) {
                stack[sp] = r, sd2[sp++] = dr;
                stack[sp] = l, sd2[sp++] = dl;
            } else {
                stack[sp] = l, sd2[sp++] = dl;
                stack[sp] = r, sd2[sp++] = dr;
            }
        }
    }
    if (elem)
        *elem = best_e;
    if (inside) {
        /* On the boundary (x == foot) counts as inside: callers prune only what is
         * surely outside. */
        double d[3];
        mfg_sub3(x, foot, d);
        *inside = best_e >= 0 && !(mfg_dot3(d, h->pseudo + 3 * best_e) > 0);
    }
    return sqrt(best2);
}

/* ---- within ------------------------------------------------------------------------ */

/* The sorted, duplicate-free ids > floor met so far, at most cap of them (the smallest);
 * truncated once a larger one had to be dropped.  Raw hits wait in buf. */
typedef struct hit_set {
    int64_t *dst;
    int64_t n, cap, floor;
    int truncated, nbuf;
    int64_t buf[HIT_BUF];
} hit_set;

/* Merges the buffered hits into dst (sorted, unique), keeping the smallest cap. */
static void hits_flush(hit_set *s)
{
    if (s->nbuf == 0)
        return;
    qsort(s->buf, (size_t)s->nbuf, sizeof *s->buf, mfg_cmp_i64);
    int64_t m = 0;
    for (int i = 0; i < s->nbuf; i++)
        if (m == 0 || s->buf[m - 1] != s->buf[i])
            s->buf[m++] = s->buf[i];
    s->nbuf = 0;
    int64_t u = 0; /* the union's size */
    for (int64_t i = 0, j = 0; i < s->n || j < m; u++) {
        if (j == m || (i < s->n && s->dst[i] < s->buf[j]))
            i++;
        else if (i == s->n || s->buf[j] < s->dst[i])
            j++;
        else
            i++, j++;
    }
    /* Backwards in place: the write index never falls below the read index in dst. */
    int64_t i = s->n - 1, j = m - 1;
    for (int64_t w = u - 1; w >= 0; w--) {
        int64_t v;
        if (j < 0 || (i >= 0 && s->dst[i] > s->buf[j]))
            v = s->dst[i--];
        else if (i < 0 || s->buf[j] > s->dst[i])
            v = s->buf[j--];
        else
            v = s->dst[i--], j--;
        if (w < s->cap)
            s->dst[w] = v;
    }
    if (u > s->cap)
        s->truncated = 1;
    s->n = u < s->cap ? u : s->cap;
}

static void hits_add(hit_set *s, int64_t id)
{
    if (id <= s->floor)
        return;
    if (s->n > 0) {
        /* Already kept (the common case: a face met by many of its triangles)? */
        int64_t lo = 0, hi = s->n;
        while (lo < hi) {
            int64_t mid = lo + (hi - lo) / 2;
            if (s->dst[mid] < id)
                lo = mid + 1;
            else
                hi = mid;
        }
        if (lo < s->n && s->dst[lo] == id)
            return;
        if (lo == s->n && s->n == s->cap) {
            s->truncated = 1; /* beyond the smallest cap ids */
            return;
        }
    } else if (s->cap == 0) {
        s->truncated = 1;
        return;
    }
    s->buf[s->nbuf++] = id;
    if (s->nbuf == HIT_BUF)
        hits_flush(s);
}

/* Every element whose closure meets B(x, R), into s: the face of each triangle within R,
 * and the edge and vertex elements of its sides and corners that are within R (each
 * element's closure is a union of triangle sides and corners, so none is missed). */
static void within_walk(const md_bvh *h, const md_elements *el, const double x[3], double R,
                        hit_set *s)
{
    double R2 = R * R;
    int64_t stack[STACK_MAX];
    int sp = 0;
    stack[sp++] = 0;
    while (sp > 0) {
        const bvh_node *n = &h->node[stack[--sp]];
        if (box_dist2(n, x) > R2 * BOX_SLACK)
            continue;
        if (n->count == 0) {
            stack[sp++] = n->right;
            stack[sp++] = (int64_t)(n - h->node) + 1;
            continue;
        }
        for (int64_t j = n->right; j < n->right + n->count; j++) {
            const double *c = h->corner + 9 * j;
            double q[3];
            md_closest_on_tri(x, c, c + 3, c + 6, q, NULL);
            if (!(dist2(x, q) <= R2))
                continue;
            int64_t t = h->tri[j];
            hits_add(s, el->face_of_triangle[t]);
            for (int k = 0; k < 3; k++) {
                int64_t se = el->side_elem[3 * t + k], ce = el->corner_elem[3 * t + k];
                if (se >= el->nfaces) {
                    md_closest_on_seg(x, c + 3 * k, c + 3 * ((k + 1) % 3), q, NULL);
                    if (dist2(x, q) <= R2)
                        hits_add(s, se);
                }
                /* A corner inside an edge chain lies in that edge's closure too. */
                if (ce >= el->nfaces && dist2(x, c + 3 * k) <= R2)
                    hits_add(s, ce);
            }
        }
    }
}

int64_t md_bvh_within(const md_bvh *h, const md_elements *el, const double x[3], double R,
                      int64_t *out, int64_t cap)
{
    if (h->ntris == 0 || !(R >= 0))
        return 0;
    hit_set s;
    s.dst = out;
    s.cap = out && cap > 0 ? cap : 0;
    s.n = 0;
    s.floor = -1;
    s.truncated = 0;
    s.nbuf = 0;
    within_walk(h, el, x, R, &s);
    hits_flush(&s);
    int64_t total = s.n;
    if (!s.truncated)
        return total;
    /* More than cap: count the rest window by window (no allocation, so the query stays
     * const and cannot fail).  A caller with room for nelements ids never comes here. */
    int64_t win[2 * HIT_BUF];
    int64_t floor = s.n > 0 ? out[s.n - 1] : -1;
    for (;;) {
        s.dst = win;
        s.cap = 2 * HIT_BUF;
        s.n = 0;
        s.floor = floor;
        s.truncated = 0;
        s.nbuf = 0;
        within_walk(h, el, x, R, &s);
        hits_flush(&s);
        total += s.n;
        if (!s.truncated)
            return total;
        floor = win[s.n - 1];
    }
}
