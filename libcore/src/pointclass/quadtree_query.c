/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* quadtree_query.c - IN / OUT / ON queries against a prepared region: the grid cell, then
 * a descent of its quadtree to a list scan or an ordered-leaf bisection
 * (split from pointclass_grid.c; see pointclass/quadtree.h). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mfg_internal.h"
#include "pointclass/pointclass.h"
#include "common/predicates.h"
#include "pointclass/quadtree.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/* ---- Queries --------------------------------------------------------------------- */

/* 1 when t is within tol of edge e (exact, after the cheap rejections). */
static inline int edge_within_tol(const mfg_region *g, const mfg_tolbox *box, uint32_t e,
                                  double tx, double ty)
{
    const double *X = g->rs.x, *Y = g->rs.y;
    double ax = X[e], ay = Y[e], bx = X[e + 1], by = Y[e + 1];
    return !((ax < box->xlo && bx < box->xlo) || (ax > box->xhi && bx > box->xhi) ||
             (ay < box->ylo && by < box->ylo) || (ay > box->yhi && by > box->yhi)) &&
           !mfg_far_from_line(tx, ty, ax, ay, bx, by, g->tol) &&
           mfg_segment_within(tx, ty, ax, ay, bx, by, g->tol);
}

static uint8_t classify_list(const mfg_region *g, const uint64_t *hd, double tx, double ty)
{
    const double *X = g->rs.x, *Y = g->rs.y;
    mfg_tolbox box = mfg_tolbox_make(tx, ty, g->tol);
    double rx = word_double(hd[1]), ry = word_double(hd[2]);
    unsigned par = (unsigned)(hd[0] >> 8) & 1u;
    uint32_t m = (uint32_t)(hd[0] >> 32);
    for (uint32_t p = 0; p < m; p++) {
        uint32_t e = (uint32_t)hd[3 + p];
        int side = (int8_t)(uint8_t)(hd[3 + p] >> 32);
        double ax = X[e], ay = Y[e], bx = X[e + 1], by = Y[e + 1];
        if (edge_within_tol(g, &box, e, tx, ty))
            return MFG_ON;
        /* Most edges miss the box of the segment r -> t, or have r and t strictly on
         * one side of their line: neither can cross the segment. */
        if ((ax < rx && ax < tx && bx < rx && bx < tx) || (ax > rx && ax > tx && bx > rx && bx > tx) ||
            (ay < ry && ay < ty && by < ry && by < ty) || (ay > ry && ay > ty && by > ry && by > ty))
            continue;
        if (side != 0 && mfg_orient2d_filter(ax, ay, bx, by, tx, ty) == side)
            continue;
        par ^= (unsigned)mfg_edge_crosses_segment(rx, ry, tx, ty, ax, ay, bx, by);
    }
    return (uint8_t)par;
}

/* Estimated height of level-0 entry k at slab coordinate s (double arithmetic). */
static inline double height_at(const slab_group *lev, uint32_t k, double s)
{
    double l = lev[k / 8].l[k % 8], r = lev[k / 8].r[k % 8];
    return l + s * (r - l);
}

/* How many of a group's 8 estimated heights are below q (floats: only a guess). */
static inline unsigned count_below(const slab_group *h, float s, float q)
{
#if defined(__SSE2__)
    __m128 s4 = _mm_set1_ps(s), q4 = _mm_set1_ps(q);
    __m128 l0 = _mm_load_ps(h->l), l1 = _mm_load_ps(h->l + 4);
    __m128 e0 = _mm_add_ps(l0, _mm_mul_ps(s4, _mm_sub_ps(_mm_load_ps(h->r), l0)));
    __m128 e1 = _mm_add_ps(l1, _mm_mul_ps(s4, _mm_sub_ps(_mm_load_ps(h->r + 4), l1)));
    unsigned mask = (unsigned)_mm_movemask_ps(_mm_cmplt_ps(e0, q4)) |
                    (unsigned)_mm_movemask_ps(_mm_cmplt_ps(e1, q4)) << 4;
    /* popcount of 8 bits */
    mask = mask - ((mask >> 1) & 0x55u);
    mask = (mask & 0x33u) + ((mask >> 2) & 0x33u);
    return (mask + (mask >> 4)) & 0x0fu;
#else
    unsigned t = 0;
    for (int u = 0; u < 8; u++)
        t += h->l[u] + s * (h->r[u] - h->l[u]) < q;
    return t;
#endif
}

static uint8_t classify_ordered(const mfg_region *g, const uint64_t *hd, double tx, double ty)
{
    unsigned axis = (unsigned)(hd[0] >> 9) & 1u, levels = (unsigned)(hd[0] >> 16) & 0xffu;
    unsigned par = (unsigned)(hd[0] >> 8) & 1u;
    uint32_t m = (uint32_t)(hd[0] >> 32);
    double tu = axis ? ty : tx, tv = axis ? tx : ty;
    double s = (tu - word_double(hd[1])) * word_double(hd[3]);
    double q = (tv - word_double(hd[2])) * word_double(hd[4]);
    /* Descend the implicit B-tree: in each group of 8 heights count those estimated
     * below t (floats: only a guess, certified or corrected below). */
    const slab_group *lev = (const slab_group *)(hd + TREE_WORDS);
    float sf = (float)s, qf = (float)q;
    uint32_t grp = 0, k = 0;
    for (int j = (int)levels - 1; j >= 0; j--) {
        unsigned t = count_below(lev + grp, sf, qf);
        if (j == 0) {
            k = 8u * grp + t;
            break;
        }
        lev += level_groups(m, (unsigned)j);
        grp = 8u * grp + (t < 7 ? t : 7);
    }
    k = k < m ? k : m;
    /* lev is level 0: the heights in order. */
    double thr = word_double(hd[5]);
    if ((k == 0 || q - height_at(lev, k - 1, s) > thr) && (k == m || height_at(lev, k, s) - q > thr))
        return (uint8_t)((par ^ k) & 1u);
    /* Too close to call on the estimates: exact ranks, then ON against the two edges
     * around t (any other edge within tol would have to be reached through them). */
    const uint32_t *E = g->oedge + hd[6];
    double au, av, bu, bv;
    while (k < m) {
        edge_uv(g, E[k], (int)axis, &au, &av, &bu, &bv);
        int sd = side_uv(au, av, bu, bv, tu, tv);
        if (sd == 0)
            return MFG_ON; /* on the line inside the slab: on the edge */
        if (sd < 0)
            break;
        k++;
    }
    while (k > 0) {
        edge_uv(g, E[k - 1], (int)axis, &au, &av, &bu, &bv);
        int sd = side_uv(au, av, bu, bv, tu, tv);
        if (sd == 0)
            return MFG_ON;
        if (sd > 0)
            break;
        k--;
    }
    mfg_tolbox box = mfg_tolbox_make(tx, ty, g->tol);
    if ((k > 0 && edge_within_tol(g, &box, E[k - 1], tx, ty)) ||
        (k < m && edge_within_tol(g, &box, E[k], tx, ty)))
        return MFG_ON;
    return (uint8_t)((par ^ k) & 1u);
}

mfg_status mfg_region_classify(const mfg_region *g, const double *pts, int64_t npoints,
                               uint8_t *out)
{
    if (!g)
        return mfg_fail(MFG_ERR_NULL, "region is NULL");
    mfg_status st = mfg_check_points(pts, npoints, out);
    if (st != MFG_OK)
        return st;
    /* Blocks of points: a first pass answers the empty cells and prefetches the roots
     * of the busy ones, so that the memory latency of several queries overlaps. */
    enum { BLOCK = 16 };
    for (int64_t k0 = 0; k0 < npoints; k0 += BLOCK) {
        int64_t kn = npoints - k0 < BLOCK ? npoints - k0 : BLOCK;
        const uint64_t *leaf[BLOCK];
        for (int64_t b = 0; b < kn; b++) {
            double tx = pts[2 * (k0 + b)], ty = pts[2 * (k0 + b) + 1];
            leaf[b] = NULL;
            if (!(tx >= g->gx0 && tx <= g->gx1 && ty >= g->gy0 && ty <= g->gy1)) {
                out[k0 + b] = MFG_OUT;
                continue;
            }
            int64_t i = (int64_t)((tx - g->gx0) * g->inv_cw);
            int64_t j = (int64_t)((ty - g->gy0) * g->inv_ch);
            i = i < g->nx ? i : g->nx - 1;
            j = j < g->ny ? j : g->ny - 1;
            int64_t c = j * g->nx + i;
            unsigned info = g->cell[c];
            if (!(info & CELL_BUSY)) {
                out[k0 + b] = (uint8_t)(info & CELL_IN);
                continue;
            }
            leaf[b] = g->tree + (size_t)g->root[c] * TREE_WORDS;
#if defined(__GNUC__) || defined(__clang__)
            __builtin_prefetch(leaf[b]); /* (a second line: more misses in flight, slower) */
#endif
        }
        for (int64_t b = 0; b < kn; b++) {
            const uint64_t *hd = leaf[b];
            if (!hd)
                continue;
            double tx = pts[2 * (k0 + b)], ty = pts[2 * (k0 + b) + 1];
            while ((hd[0] & 0xffu) == NODE_SPLIT) {
                unsigned q = (unsigned)(tx >= word_double(hd[1])) + 2u * (unsigned)(ty >= word_double(hd[2]));
                uint32_t kid = (uint32_t)(hd[3 + (q >> 1)] >> (32 * (q & 1u)));
                hd = g->tree + (size_t)kid * TREE_WORDS;
            }
            out[k0 + b] = (hd[0] & 0xffu) == NODE_LIST ? classify_list(g, hd, tx, ty)
                                                       : classify_ordered(g, hd, tx, ty);
        }
    }
    mfg_clear_error();
    return MFG_OK;
}

mfg_status mfg_region_info(const mfg_region *g, struct mfg_region_info *out)
{
    if (!g || !out)
        return mfg_fail(MFG_ERR_NULL, "region or out is NULL");
    struct mfg_region_info r;
    memset(&r, 0, sizeof r);
    int64_t ncells = g->nx * g->ny;
    for (int64_t c = 0; c < ncells; c++)
        r.edge_cells += (g->cell[c] & CELL_BUSY) != 0;
    r.columns = g->nx;
    r.rows = g->ny;
    r.grid_entries = g->grid_entries;
    r.list_entries = g->nlist;
    r.ordered_entries = g->nord;
    r.edge_entries = g->nlist + (int64_t)g->nord;
    r.nodes = g->nsplit + g->nlistleaves + g->nordleaves;
    r.list_leaves = g->nlistleaves;
    r.ordered_leaves = g->nordleaves;
    r.max_depth = g->max_depth;
    r.max_list = g->max_leaf;
    r.bytes = (int64_t)sizeof *g + ncells * (int64_t)(sizeof(uint8_t) + sizeof(uint32_t)) +
              (int64_t)g->nlines * TREE_WORDS * (int64_t)sizeof(uint64_t) +
              (int64_t)g->nord * (int64_t)sizeof(uint32_t) +
              g->rs.nslots * 2 * (int64_t)sizeof(double) + g->rs.nrings * 2 * (int64_t)sizeof(int64_t);
    *out = r;
    mfg_clear_error();
    return MFG_OK;
}

mfg_status mfg_region_stats(const mfg_region *g, int64_t stats_out[4])
{
    if (!g || !stats_out)
        return mfg_fail(MFG_ERR_NULL, "region or stats_out is NULL");
    struct mfg_region_info r;
    mfg_status st = mfg_region_info(g, &r);
    if (st != MFG_OK)
        return st;
    stats_out[0] = r.columns;
    stats_out[1] = r.rows;
    stats_out[2] = r.edge_cells;
    stats_out[3] = r.edge_entries;
    return MFG_OK;
}
