/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sheet_tet.c - one Kuhn tetrahedron and one octree leaf of the sheet extraction
 * (sheets.c; docs/design/medial.md section 4.1): marching tetrahedra on f_ab over the 6
 * Kuhn tets of the leaf, trimmed polygons into triangles and seam segments. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "medial/sheets.h"
#include "common/mfg_internal.h"

/* Can element e be nearest inside the solid?  Not a convex edge, nor a vertex whose edges
 * are all convex (design 3.3: their regions lie outside).  A sheet trimmed by one of those
 * meets the solid's boundary there (r -> 0): no seam. */
static int inside_element(const md_elements *el, int64_t e)
{
    int k = md_kind(el, e);
    if (k == MD_EDGE)
        return !el->edge_convex[e - el->nfaces];
    if (k == MD_VERTEX) {
        int64_t j = e - el->nfaces - el->nedges;
        for (int64_t q = el->vert_edge_offsets[j]; q < el->vert_edge_offsets[j + 1]; q++)
            if (!el->edge_convex[el->vert_edges[q] - el->nfaces])
                return !el->vert_region_empty[j];
        return 0;
    }
    return 1;
}

/* The seam kind of a boundary trimmed by element t: a sub-element of a or b whose region
 * ended is SMOOTH, any element not incident to either is BRANCH. */
static int32_t seam_kind(const md_elements *el, int64_t a, int64_t b, int64_t t)
{
    return md_incident(el, t, a) || md_incident(el, t, b) ? MFG_MEDIAL_SMOOTH : MFG_MEDIAL_BRANCH;
}

/* Marching tets on tet (v[0..3], local corners, each a bit-superset of the previous):
 * the polygon of f = 0, oriented with its normal towards f > 0, clipped to tau >= 0,
 * fanned from its smallest key, and its clip edges as seam segments.  0 on NOMEM. */
static int do_tet(ctx *c, const int *v, int tet)
{
    int pos[4], neg[4], np = 0, nn = 0;
    for (int i = 0; i < 4; i++) {
        if (c->f[v[i]] >= 0)
            pos[np++] = v[i];
        else
            neg[nn++] = v[i];
    }
    if (np == 0 || nn == 0)
        return 1;
    int e[4][2], ne = 0; /* polygon vertices as lattice edges (corner, corner) */
    if (np == 1 || nn == 1) {
        int lone = np == 1 ? pos[0] : neg[0];
        const int *oth = np == 1 ? neg : pos;
        for (int i = 0; i < 3; i++) {
            e[ne][0] = lone;
            e[ne][1] = oth[i];
            ne++;
        }
    } else {
        int cyc[4][2] = {{pos[0], neg[0]}, {pos[0], neg[1]}, {pos[1], neg[1]}, {pos[1], neg[0]}};
        memcpy(e, cyc, sizeof cyc);
        ne = 4;
    }
    /* Orientation, exactly on local corner coordinates (doubled): the Newell normal of the
     * polygon of edge midpoints against the direction from the negative corners to the
     * positive ones.  The midpoint polygon is never degenerate. */
    long m[4][3], nrm[3] = {0, 0, 0}, dir[3] = {0, 0, 0};
    for (int i = 0; i < ne; i++)
        for (int d = 0; d < 3; d++)
            m[i][d] = ((e[i][0] >> d) & 1) + ((e[i][1] >> d) & 1);
    for (int i = 0; i < ne; i++) {
        const long *p = m[i], *q = m[(i + 1) % ne];
        nrm[0] += (p[1] - q[1]) * (p[2] + q[2]);
        nrm[1] += (p[2] - q[2]) * (p[0] + q[0]);
        nrm[2] += (p[0] - q[0]) * (p[1] + q[1]);
    }
    for (int d = 0; d < 3; d++) {
        for (int i = 0; i < np; i++)
            dir[d] += nn * ((pos[i] >> d) & 1);
        for (int i = 0; i < nn; i++)
            dir[d] -= np * ((neg[i] >> d) & 1);
    }
    if (nrm[0] * dir[0] + nrm[1] * dir[1] + nrm[2] * dir[2] < 0)
        for (int i = 0; i < ne / 2; i++) {
            int t0 = e[i][0], t1 = e[i][1];
            e[i][0] = e[ne - 1 - i][0];
            e[i][1] = e[ne - 1 - i][1];
            e[ne - 1 - i][0] = t0;
            e[ne - 1 - i][1] = t1;
        }
    int pvi[4];
    for (int i = 0; i < ne; i++) {
        int lo = e[i][0], hi = e[i][1];
        if ((lo & hi) != lo) { /* order the edge from its smaller lattice point */
            int t = lo;
            lo = hi;
            hi = t;
        }
        pvi[i] = md_sheet_edge_vertex(c, lo, hi);
        if (pvi[i] < 0)
            return 0;
    }
    /* Clip to tau >= 0 (Sutherland-Hodgman on the cycle). */
    int out[8], exit_after[8], no = 0;
    for (int i = 0; i < ne; i++) {
        int u = pvi[i], w = pvi[(i + 1) % ne];
        int in_u = c->pv[u].tau >= 0, in_w = c->pv[w].tau >= 0;
        if (in_u) {
            exit_after[no] = 0;
            out[no++] = u;
        }
        if (in_u != in_w) {
            int bp = md_sheet_boundary_point(c, u, w);
            if (bp < 0)
                return 0;
            exit_after[no] = in_u;
            out[no++] = bp;
        }
    }
    if (no < 3)
        return 1;
    /* Clip edges: a corner of the sheet where the trimming changes (inserted when it is
     * found), and the seam segments along them. */
    unit_buf *ub = c->out;
    int poly[16], n2 = 0;
    int64_t segt[16]; /* the element trimming the edge from poly[i] to the next, or < 0 */
    for (int i = 0; i < no; i++) {
        poly[n2] = out[i];
        segt[n2] = -1;
        if (exit_after[i]) {
            const pvert *p = c->pv + out[i], *q = c->pv + out[(i + 1) % no];
            double x[3], D;
            if ((p->arg != q->arg || p->argk != q->argk) && md_sheet_corner_point(c, p, q, x, &D)) {
                segt[n2++] = p->arg;
                vkey k;
                memset(&k, 0xff, sizeof k);
                k.a = c->a;
                k.b = c->b;
                memcpy(k.e[0], c->cijk[0], sizeof c->cijk[0]);
                k.e[0][3] = 8 + tet;
                k.e[1][0] = i;
                k.c = -3;
                pvert *j = c->pv + c->npv;
                j->rec = md_sheet_push_vertex(ub, &k, x, D);
                if (j->rec < 0)
                    return 0;
                j->tau = 0.0;
                j->arg = -1;
                j->argk = TRIM_NU;
                j->lo = j->hi = -1;
                poly[n2] = c->npv++;
                segt[n2] = q->arg;
            } else if (p->arg == q->arg) {
                segt[n2] = p->arg;
            }
            /* Otherwise no corner in this leaf: the kept region's boundary left the polygon
             * between samples (near the boundary of the solid, or a junction beside this
             * polygon), and the chord is on no seam. */
        }
        n2++;
    }
    for (int i = 0; i < n2; i++) {
        int64_t t = segt[i];
        if (t < 0 || !inside_element(c->el, t))
            continue; /* not a clip edge, or the sheet meets the solid's boundary */
        int64_t e3[3] = {c->a, c->b, t};
        for (int x = 0; x < 2; x++)
            for (int y = 0; y < 2 - x; y++)
                if (e3[y] > e3[y + 1]) {
                    int64_t sw = e3[y];
                    e3[y] = e3[y + 1];
                    e3[y + 1] = sw;
                }
        if (!md_sheet_push_seg(ub, c->pv[poly[i]].rec, c->pv[poly[(i + 1) % n2]].rec, e3,
                      seam_kind(c->el, c->a, c->b, t), c->a, c->b))
            return 0;
    }
    int *out_ = poly;
    no = n2;
    int s0 = 0;
    for (int i = 1; i < no; i++)
        if (md_sheet_cmp_key(&ub->v[c->pv[out_[i]].rec].k, &ub->v[c->pv[out_[s0]].rec].k) < 0)
            s0 = i;
    for (int i = 1; i + 1 < no; i++) {
        int64_t p = c->pv[out_[s0]].rec, q = c->pv[out_[(s0 + i) % no]].rec;
        int64_t r = c->pv[out_[(s0 + i + 1) % no]].rec;
        if (!md_sheet_push_tri(ub, p, q, r, c->a, c->b))
            return 0;
    }
    return 1;
}

/* The 6 Kuhn tets of the unit cube about its main diagonal 0 -> 7: one per order of the
 * axes, each a monotone path of corners. */
static const int KUHN[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                               {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};

/* The position of element e in the leaf's C (ascending), or -1. */
static int c_index(const ctx *c, int64_t e)
{
    int lo = 0, hi = c->nC;
    while (lo < hi) {
        int mid = lo + (hi - lo) / 2;
        if (c->C[mid] < e)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo < c->nC && c->C[lo] == e ? lo : -1;
}

mfg_status md_sheet_leaf(const md_elements *el, const md_bvh *bvh, const md_leaves *lv,
                          const md_leaf *L, unit_buf *ub, ctx *c)
{
    if (L->level > 0)
        return md_sheet_coarse_leaf(el, lv, c->li, L, ub);
    c->el = el;
    c->bvh = bvh;
    c->C = lv->C + L->C_off;
    c->nC = L->nC;
    c->out = ub;
    c->h = lv->lat.h;
    for (int k = 0; k < 8; k++)
        for (int d = 0; d < 3; d++) {
            c->cijk[k][d] = L->ijk[d] + ((k >> d) & 1);
            c->cx[k][d] = lv->lat.origin[d] + lv->lat.h * (double)c->cijk[k][d];
        }
    /* Every point evaluated for this leaf (corners grown by h / 2 included) lies within
     * 2h of its centre. */
    c->deep = 0;
    for (int d = 0; d < 3; d++)
        c->ctr[d] = lv->lat.origin[d] + lv->lat.h * ((double)L->ijk[d] + 0.5);
    if (bvh && L->nP > 0) {
        c->sdc = md_sheet_signed_dist(c, c->ctr);
        c->deep = c->sdc > 2 * lv->lat.h;
    }
    if (L->nC > c->capC) {
        cbound *g = realloc(c->cb, (size_t)L->nC * sizeof *g);
        if (!g)
            return MFG_ERR_NOMEM;
        c->cb = g;
        c->capC = L->nC;
    }
    for (int i = 0; i < L->nC; i++)
        c->cb[i].g = c->cb[i].m = c->cb[i].d = NAN;
    for (int p = 0; p < L->nP; p++) {
        c->a = lv->P[L->P_off + 2 * p];
        c->b = lv->P[L->P_off + 2 * p + 1];
        c->ia = c_index(c, c->a);
        c->ib = c_index(c, c->b);
        int npos = 0;
        for (int k = 0; k < 8; k++) {
            c->f[k] = md_dist_car(el, c->a, c->cx[k], NULL) - md_dist_car(el, c->b, c->cx[k], NULL);
            npos += c->f[k] >= 0;
        }
        if (npos == 0 || npos == 8)
            continue;
        c->have_ex = 0;
        if (!md_sheet_pair_shows(c))
            continue;
        for (int i = 0; i < 64; i++)
            c->slot[i] = -1;
        c->npv = 0;
        c->nbp = 0;
        for (int t = 0; t < 6; t++)
            if (!do_tet(c, KUHN[t], t))
                return MFG_ERR_NOMEM;
    }
    return MFG_OK;
}
