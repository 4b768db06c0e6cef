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

/* Is the projection p of a point on face f's plane inside the face?  Winding number of
 * its boundary sides (outer loop and holes) after dropping the dominant axis (Sunday's
 * rule with exact orientations): O(boundary sides), not O(triangles).  The dropped axis
 * may mirror the face, which flips the winding's sign but not whether it is 0. */
static int face_contains(const md_elements *el, int64_t f, const double *p)
{
    int ax = el->face_axis[f], i0 = (ax + 1) % 3, i1 = (ax + 2) % 3;
    int64_t wn = 0;
    for (int64_t q = el->face_side_offsets[f]; q < el->face_side_offsets[f + 1]; q++) {
        int64_t sd = el->face_sides[q], t = sd / 3, k = sd % 3;
        const double *a = el->xyz + 3 * el->tris[3 * t + k];
        const double *b = el->xyz + 3 * el->tris[3 * t + (k + 1) % 3];
        if (a[i1] <= p[i1]) {
            if (b[i1] > p[i1] && mfg_orient2d(a[i0], a[i1], b[i0], b[i1], p[i0], p[i1]) > 0)
                wn++;
        } else if (b[i1] <= p[i1] && mfg_orient2d(a[i0], a[i1], b[i0], b[i1], p[i0], p[i1]) < 0) {
            wn--;
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
        double best = INFINITY;
        for (int64_t q = el->face_side_offsets[e]; q < el->face_side_offsets[e + 1]; q++) {
            int64_t sd = el->face_sides[q], t = sd / 3, k = sd % 3;
            double d = seg_dist(p, el->xyz + 3 * el->tris[3 * t + k],
                                el->xyz + 3 * el->tris[3 * t + (k + 1) % 3]);
            if (d < best) {
                best = d;
                w = el->side_elem[sd];
            }
        }
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
