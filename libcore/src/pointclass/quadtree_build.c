/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* quadtree_build.c - the quadtree of a busy grid cell: list leaves, ordered (slab) leaves
 * certified exactly, and splits into four
 * (split from pointclass_grid.c; see pointclass/quadtree.h). */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mfg_internal.h"
#include "pointclass/pointclass.h"
#include "common/predicates.h"
#include "pointclass/quadtree.h"

/* ---- Quadtree build -------------------------------------------------------------- */

/* A node under construction: its box, its reference point (off the boundary, inside
 * the box) with exact parity, and every edge within reach of the box. */
typedef struct nodebox {
    double x0, y0, x1, y1;
    double rx, ry;
    unsigned par;
    int depth;
    int stall; /* splits in a row that copied most of the list into it and a sibling */
} nodebox;

/* Makes room for `need` elements of `elem` bytes in *arr (capacity *cap, doubling);
 * MFG_ERR_NOMEM (recorded) when that is impossible.  The array is passed as void * and
 * stored back by the caller's macro, so no pointer is type-punned. */
static void *grow_array(void *arr, uint32_t *cap, uint32_t need, size_t elem, mfg_status *st)
{
    *st = MFG_OK;
    if (need <= *cap)
        return arr;
    uint64_t c = *cap ? *cap : 1024;
    while (c < need)
        c *= 2;
    if (c > UINT32_MAX)
        c = UINT32_MAX;
    void *p = realloc(arr, (size_t)c * elem);
    if (!p) {
        *st = mfg_fail(MFG_ERR_NOMEM, "cannot allocate %llu index entries", (unsigned long long)c);
        return arr;
    }
    *cap = (uint32_t)c;
    return p;
}

#define GROW(arr, cap, need, st) ((arr) = grow_array((arr), &(cap), (need), sizeof *(arr), &(st)), (st))

/* Reserves `lines` zeroed lines of the tree; *first receives the first one. */
static mfg_status new_lines(mfg_region *g, uint64_t lines, uint32_t *first)
{
    if (lines > UINT32_MAX / 2 - g->nlines)
        return mfg_fail(MFG_ERR_NOMEM, "prepared region index too large (more than 2^31 lines)");
    uint32_t need = g->nlines + (uint32_t)lines;
    if (need > g->cap_lines) {
        uint64_t c = g->cap_lines ? g->cap_lines : 1024;
        while (c < need)
            c *= 2;
        void *p = realloc(g->tree, (size_t)c * TREE_WORDS * sizeof(uint64_t));
        if (!p)
            return mfg_fail(MFG_ERR_NOMEM, "cannot allocate %llu index lines", (unsigned long long)c);
        g->tree = p;
        g->cap_lines = (uint32_t)c;
    }
    *first = g->nlines;
    memset(g->tree + (size_t)g->nlines * TREE_WORDS, 0, (size_t)lines * TREE_WORDS * sizeof(uint64_t));
    g->nlines = need;
    return MFG_OK;
}

/* 1 when edge e may pass within d of the box (conservative: 0 means certainly farther):
 * box test, then the distance from the box centre to the edge's line against the half
 * diagonal (float bounds rounded outward). */
static int edge_near_box(const mfg_region *g, uint32_t e, double x0, double y0, double x1,
                         double y1, double d)
{
    const double *X = g->rs.x, *Y = g->rs.y;
    double ax = X[e], ay = Y[e], bx = X[e + 1], by = Y[e + 1];
    if (fmax(ax, bx) < x0 - d || fmin(ax, bx) > x1 + d || fmax(ay, by) < y0 - d ||
        fmin(ay, by) > y1 + d)
        return 0;
    double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
    double hw = 0.5 * (x1 - x0), hh = 0.5 * (y1 - y0);
    double ux = bx - ax, uy = by - ay;
    double l = ux * (cy - ay), r = uy * (cx - ax);
    double cr = fabs(l - r) - MFG_ORIENT2D_ERR * (fabs(l) + fabs(r));
    double len = sqrt(ux * ux + uy * uy);
    double lim = (sqrt(hw * hw + hh * hh) + d) * len * (1.0 + SEG_BOX_SLACK);
    /* The centre's rounding (ulps of |x0| + |x1|) is far inside the margin in d. */
    return !(cr > lim);
}

typedef struct sortkey {
    double key;
    uint32_t e;
} sortkey;

static int cmp_key(const void *p, const void *q)
{
    const sortkey *a = p, *b = q;
    if (a->key != b->key)
        return a->key < b->key ? -1 : 1;
    return a->e < b->e ? -1 : (a->e > b->e);
}

/* 1 when f lies strictly above e over the whole common u-range of the two (each given
 * with au < bu): the difference of their heights is linear there, so it is enough that
 * it is >= 0 at both ends of that range and > 0 at one of them (a shared endpoint or an
 * endpoint touching the other edge gives 0 at its end). */
static int strictly_above(double eau, double eav, double ebu, double ebv, double fau,
                          double fav, double fbu, double fbv)
{
    /* A shared endpoint (every pair of a spike's edges) is 0 without a predicate. */
    int sl = eau == fau && eav == fav ? 0
             : eau >= fau             ? -side_uv(fau, fav, fbu, fbv, eau, eav)
                                      : side_uv(eau, eav, ebu, ebv, fau, fav);
    int sr = ebu == fbu && ebv == fbv ? 0
             : ebu <= fbu             ? -side_uv(fau, fav, fbu, fbv, ebu, ebv)
                                      : side_uv(eau, eav, ebu, ebv, fbu, fbv);
    return sl >= 0 && sr >= 0 && (sl > 0 || sr > 0);
}

/* Bisection levels of an ordered leaf with m entries: groups of 8, so 8^levels >= m. */
static unsigned ordered_levels(uint32_t m)
{
    unsigned d = 1;
    while (((uint64_t)1 << (3 * d)) < m)
        d++;
    return d;
}

/* Tries to make the leaf for box b an ORDERED leaf on axis `axis`; returns 1 (and its
 * line in *out) on success, 0 when the list does not qualify, -1 on allocation failure
 * (status recorded in *st). */
static int try_ordered(mfg_region *g, const nodebox *b, const uint32_t *list, uint32_t m,
                       int axis, sortkey *keys, uint32_t *out, mfg_status *st)
{
    double u0 = axis ? b->y0 : b->x0, u1 = axis ? b->y1 : b->x1;
    double v0 = axis ? b->x0 : b->y0, v1 = axis ? b->x1 : b->y1;
    double w = u1 - u0, h = v1 - v0;
    /* The normalised slab coordinate of a query stays within [-1/8, 9/8] (see E below). */
    if (!(w >= 8.0 * g->margin && h >= 8.0 * g->margin))
        return 0;
    double lo = u0 - g->reach, hi = u1 + g->reach, uc = 0.5 * (u0 + u1);
    for (uint32_t p = 0; p < m; p++) {
        double au, av, bu, bv;
        edge_uv(g, list[p], axis, &au, &av, &bu, &bv);
        if (!(au < lo && bu > hi))
            return 0;
        keys[p].key = av + (uc - au) * ((bv - av) / (bu - au));
        keys[p].e = list[p];
    }
    qsort(keys, m, sizeof *keys, cmp_key);
    double tu = axis ? b->ry : b->rx, tv = axis ? b->rx : b->ry;
    unsigned rank = 0;
    double eau = 0, eav = 0, ebu = 0, ebv = 0;
    double inv_w = 1.0 / w, inv_h = 1.0 / h;
    double emax = 0.0, vmax = 0.0, sec = 1.0;
    for (uint32_t p = 0; p < m; p++) {
        double au, av, bu, bv;
        edge_uv(g, keys[p].e, axis, &au, &av, &bu, &bv);
        if (p > 0 && !strictly_above(eau, eav, ebu, ebv, au, av, bu, bv))
            return 0;
        eau = au; eav = av; ebu = bu; ebv = bv;
        /* The reference point is off the boundary and inside the slab: never 0. */
        rank += side_uv(au, av, bu, bv, tu, tv) > 0;
        double slope = (bv - av) / (bu - au);
        double yl = (av + (u0 - au) * slope - v0) * inv_h;
        double yr = (av + (u1 - au) * slope - v0) * inv_h;
        if (!(fabs(yl) <= 0x1p20 && fabs(yr) <= 0x1p20)) /* nearly parallel to v: no use */
            return 0;
        keys[p].key = yl; /* the sort key is no longer needed: keep yl, recompute yr */
        /* Each height: a handful of roundings of magnitude |av| + |bv| + |v0| (the
         * change u0 - au times the slope is at most |bv - av|); 128 ulps of that bound
         * them. */
        emax = fmax(emax, HEIGHT_ERR * (fabs(av) + fabs(bv) + fabs(v0)) * inv_h);
        vmax = fmax(vmax, fabs(yl) + fabs(yr));
        sec = fmax(sec, sqrt(1.0 + slope * slope));
    }
    /* Qualifies: lay out the header line and the bisection levels. */
    unsigned levels = ordered_levels(m);
    uint64_t lines = 1;
    for (unsigned j = 0; j < levels; j++)
        lines += level_groups(m, j);
    if (g->nord > UINT32_MAX / 2 - m) {
        *st = mfg_fail(MFG_ERR_NOMEM, "prepared region index too large (more than 2^31 entries)");
        return -1;
    }
    uint32_t line;
    if ((*st = new_lines(g, lines, &line)) != MFG_OK ||
        GROW(g->oedge, g->cap_oedge, g->nord + m, *st) != MFG_OK)
        return -1;
    /* Estimate at a query: est = l + s (r - l) with |s| <= 9/8 + tiny; the errors of l
     * and r enter at most (|1 - s| + |s|) < 4 times; float conversion <= 2^-24 relative;
     * the double steps and the rounding of the query's own normalised coordinates a
     * few ulps of vmax. */
    double E = 5.0 * emax * EST_MARGIN + EST_FLOAT_ERR * vmax + EST_ABS_ERR;
    uint64_t *hd = g->tree + (size_t)line * TREE_WORDS;
    hd[0] = tree_header(NODE_ORDERED, (b->par ^ rank) & 1u, (unsigned)axis, levels, m);
    hd[1] = double_word(u0);
    hd[2] = double_word(v0);
    hd[3] = double_word(inv_w);
    hd[4] = double_word(inv_h);
    hd[5] = double_word((E + g->tol * sec * (1.0 + TOL_SLACK) * inv_h) * (1.0 + TOL_SLACK));
    hd[6] = g->nord;
    slab_group *lev = (slab_group *)(hd + TREE_WORDS);
    for (int j = (int)levels - 1; j >= 0; j--) {
        uint32_t n = level_groups(m, (unsigned)j) * 8u;
        for (uint32_t i = 0; i < n; i++) {
            uint64_t src = ((uint64_t)(i + 1) << (3 * j)) - 1;
            float *l = &lev[i / 8].l[i % 8], *r = &lev[i / 8].r[i % 8];
            if (src < m) {
                double au, av, bu, bv;
                edge_uv(g, keys[src].e, axis, &au, &av, &bu, &bv);
                double slope = (bv - av) / (bu - au);
                *l = (float)keys[src].key;
                *r = (float)((av + (u1 - au) * slope - v0) * inv_h);
            } else {
                *l = *r = FLT_MAX; /* above every query */
            }
        }
        lev += n / 8;
    }
    for (uint32_t p = 0; p < m; p++)
        g->oedge[g->nord + p] = keys[p].e;
    g->nord += m;
    g->nordleaves++;
    *out = line;
    return 1;
}

static mfg_status make_list_leaf(mfg_region *g, const nodebox *b, const uint32_t *list,
                                 uint32_t m, uint32_t *out)
{
    const double *X = g->rs.x, *Y = g->rs.y;
    uint32_t line;
    mfg_status st = new_lines(g, (3 + (uint64_t)m + TREE_WORDS - 1) / TREE_WORDS, &line);
    if (st != MFG_OK)
        return st;
    uint64_t *hd = g->tree + (size_t)line * TREE_WORDS;
    hd[0] = tree_header(NODE_LIST, b->par, 0, 0, m);
    hd[1] = double_word(b->rx);
    hd[2] = double_word(b->ry);
    for (uint32_t p = 0; p < m; p++) {
        uint32_t e = list[p];
        /* The side of the reference point: a query on the same side cannot have the
         * edge cross its segment to the reference, so one orientation test replaces the
         * crossing test for most edges. */
        int side = mfg_orient2d(X[e], Y[e], X[e + 1], Y[e + 1], b->rx, b->ry);
        hd[3 + p] = (uint64_t)e | (uint64_t)(uint8_t)(int8_t)side << 32;
    }
    g->nlist += m;
    g->nlistleaves++;
    if ((int64_t)m > g->max_leaf)
        g->max_leaf = m;
    *out = line;
    return MFG_OK;
}

static uint64_t entries_used(const mfg_region *g) { return (uint64_t)g->nlist + g->nord; }

/* 1 when a child's list of mc edges holds most (more than 3/4) of its parent's m. */
static inline int mostly(uint32_t mc, uint32_t m) { return 4 * (uint64_t)mc > 3 * (uint64_t)m; }

/* Edge e's endpoints, the lexicographically smaller first, so that copies of one
 * segment (in either direction) give the same four numbers. */
static inline void seg_ends(const mfg_region *g, uint32_t e, double k[4])
{
    const double *X = g->rs.x, *Y = g->rs.y;
    int swap = X[e + 1] < X[e] || (X[e + 1] == X[e] && Y[e + 1] < Y[e]);
    uint32_t a = swap ? e + 1 : e, b = swap ? e : e + 1;
    k[0] = X[a], k[1] = Y[a], k[2] = X[b], k[3] = Y[b];
}

/* The number of geometrically distinct segments in the list (copies of one segment, in
 * either direction, and zero-length edges at one point count once): no split can ever
 * part copies, so this is what splitting can reduce.  A hash set over the endpoints'
 * bits (+0.0 for -0.0, so equal numbers hash alike): O(m).  -1 when out of memory
 * (recorded). */
static int64_t distinct_segments(const mfg_region *g, const uint32_t *list, uint32_t m)
{
    uint64_t size = 16;
    while (size < 2 * (uint64_t)m)
        size *= 2;
    uint32_t *slot = malloc((size_t)size * sizeof *slot);
    if (!slot) {
        mfg_fail(MFG_ERR_NOMEM, "cannot allocate a table of %u segments", m);
        return -1;
    }
    memset(slot, 0xFF, (size_t)size * sizeof *slot); /* UINT32_MAX: empty */
    int64_t n = 0;
    for (uint32_t p = 0; p < m; p++) {
        double k[4], o[4];
        seg_ends(g, list[p], k);
        uint64_t h = UINT64_C(0x9E3779B97F4A7C15);
        for (int i = 0; i < 4; i++)
            h = (h ^ double_word(k[i] + 0.0)) * UINT64_C(0xBF58476D1CE4E5B9);
        uint64_t i = (h ^ (h >> 31)) & (size - 1);
        for (;; i = (i + 1) & (size - 1)) {
            if (slot[i] == UINT32_MAX) {
                slot[i] = list[p];
                n++;
                break;
            }
            seg_ends(g, slot[i], o);
            if (o[0] == k[0] && o[1] == k[1] && o[2] == k[2] && o[3] == k[3])
                break; /* a copy */
        }
    }
    free(slot);
    return n;
}

/* Builds the object for box b and its list (every edge within reach of b); *out
 * receives its line. */
static mfg_status build_node(mfg_region *g, const nodebox *b, const uint32_t *list, uint32_t m,
                             uint32_t *out)
{
    if (b->depth > g->max_depth)
        g->max_depth = b->depth;
    if (m <= ORDER_MIN)
        return make_list_leaf(g, b, list, m, out);
    sortkey *keys = malloc((size_t)m * sizeof *keys);
    if (!keys)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate %u sort keys", m);
    mfg_status st = MFG_OK;
    /* Both axes can qualify (edges at 45 degrees): try first the axis along which the
     * edges extend more, whose heights are flatter and certify more queries. */
    const double *X = g->rs.x, *Y = g->rs.y;
    double sx = 0.0, sy = 0.0;
    for (uint32_t p = 0; p < m; p++) {
        sx += fabs(X[list[p] + 1] - X[list[p]]);
        sy += fabs(Y[list[p] + 1] - Y[list[p]]);
    }
    int first_axis = sy > sx;
    int r = try_ordered(g, b, list, m, first_axis, keys, out, &st);
    if (r == 0)
        r = try_ordered(g, b, list, m, !first_axis, keys, out, &st);
    free(keys);
    if (r < 0)
        return st;
    if (r > 0)
        return MFG_OK;
    double w = b->x1 - b->x0, h = b->y1 - b->y0;
    if (m <= LEAF_LIST_MAX || b->depth >= MAX_DEPTH || b->stall >= STALL_MAX ||
        entries_used(g) + m > g->entry_budget ||
        !(w >= 64.0 * g->margin && h >= 64.0 * g->margin))
        return make_list_leaf(g, b, list, m, out);
    /* Copies of a segment stay together in every child: a list of few distinct
     * segments is as short as splitting can make it. */
    int64_t nd = distinct_segments(g, list, m);
    if (nd < 0)
        return MFG_ERR_NOMEM;
    if (nd <= LEAF_LIST_MAX)
        return make_list_leaf(g, b, list, m, out);

    /* Split into four: each child keeps the edges within reach of it and a reference
     * point off them, whose parity follows from the parent's along the segment between
     * the two (inside the parent, so only the parent's edges can cross it).  A split
     * that leaves most edges in every child (edges through one point, or a tol wider
     * than the gaps) only multiplies entries: then the list stays a leaf. */
    uint32_t *sub = malloc((size_t)m * 4 * sizeof(uint32_t));
    if (!sub)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate a node list of %u edges", m);
    double mx = 0.5 * (b->x0 + b->x1), my = 0.5 * (b->y0 + b->y1);
    nodebox c[4];
    uint32_t cm[4];
    uint64_t sum = 0;
    for (int q = 0; q < 4; q++) {
        c[q].x0 = (q & 1) ? mx : b->x0;
        c[q].x1 = (q & 1) ? b->x1 : mx;
        c[q].y0 = (q & 2) ? my : b->y0;
        c[q].y1 = (q & 2) ? b->y1 : my;
        c[q].depth = b->depth + 1;
        cm[q] = 0;
        for (uint32_t p = 0; p < m; p++)
            if (edge_near_box(g, list[p], c[q].x0, c[q].y0, c[q].x1, c[q].y1, g->reach))
                sub[(size_t)q * m + cm[q]++] = list[p];
        sum += cm[q];
    }
    int nfull = 0;
    for (int q = 0; q < 4; q++)
        nfull += mostly(cm[q], m);
    for (int q = 0; q < 4; q++)
        c[q].stall = !mostly(cm[q], m) ? 0 : b->stall + (nfull >= 2);
    if (sum > 3 * (uint64_t)m) {
        free(sub);
        return make_list_leaf(g, b, list, m, out);
    }
    uint32_t line = 0, kid[4] = {0, 0, 0, 0};
    st = new_lines(g, 1, &line);
    for (int q = 0; q < 4 && st == MFG_OK; q++) {
        const uint32_t *cl = sub + (size_t)q * m;
        uint32_t limit = cm[q] < 30000 ? 2 * cm[q] + 16 : 65535, t = 0;
        for (; t < limit; t++) {
            seq_point(c[q].x0, c[q].y0, c[q].x1 - c[q].x0, c[q].y1 - c[q].y0, t, &c[q].rx, &c[q].ry);
            if (mfg_pc_off_boundary(g, cl, cm[q], c[q].rx, c[q].ry))
                break;
        }
        if (t == limit) {
            st = mfg_fail(MFG_ERR_INTERNAL, "no reference point off the boundary in a quadtree node");
            break;
        }
        unsigned par = b->par;
        for (uint32_t p = 0; p < m; p++) {
            uint32_t e = list[p];
            par ^= (unsigned)mfg_edge_crosses_segment(b->rx, b->ry, c[q].rx, c[q].ry, X[e], Y[e], X[e + 1], Y[e + 1]);
        }
        c[q].par = par & 1u;
        st = build_node(g, &c[q], cl, cm[q], &kid[q]);
    }
    free(sub);
    if (st != MFG_OK)
        return st;
    uint64_t *hd = g->tree + (size_t)line * TREE_WORDS;
    hd[0] = tree_header(NODE_SPLIT, 0, 0, 0, 0);
    hd[1] = double_word(mx);
    hd[2] = double_word(my);
    hd[3] = (uint64_t)kid[0] | (uint64_t)kid[1] << 32;
    hd[4] = (uint64_t)kid[2] | (uint64_t)kid[3] << 32;
    g->nsplit++;
    *out = line;
    return MFG_OK;
}

/* Builds the quadtree of every busy cell, then drops the grid's lists and moves the
 * tree to 64-byte aligned memory (a line per cache line). */
mfg_status mfg_qt_build_trees(mfg_region *g)
{
    int64_t ncells = g->nx * g->ny;
    uint64_t budget = (uint64_t)ENTRY_BUDGET * (uint64_t)g->grid_entries + 4096u;
    g->entry_budget = budget < UINT32_MAX / 4 ? budget : UINT32_MAX / 4;
    for (int64_t c = 0; c < ncells; c++) {
        if (!(g->cell[c] & CELL_BUSY))
            continue;
        int64_t i = c % g->nx, j = c / g->nx;
        nodebox b;
        b.x0 = g->gx0 + (double)i * g->cw;
        b.x1 = g->gx0 + (double)(i + 1) * g->cw;
        b.y0 = g->gy0 + (double)j * g->ch;
        b.y1 = g->gy0 + (double)(j + 1) * g->ch;
        ref_point(g, i, j, g->refk[c], &b.rx, &b.ry);
        b.par = g->cell[c] & CELL_IN;
        b.depth = 0;
        b.stall = 0;
        mfg_status st = build_node(g, &b, g->edges + g->start[c], g->start[c + 1] - g->start[c], &g->root[c]);
        if (st != MFG_OK)
            return st;
    }
    free(g->edges);
    free(g->start);
    free(g->refk);
    g->edges = NULL;
    g->start = NULL;
    g->refk = NULL;
    size_t bytes = ((size_t)g->nlines + 1) * TREE_WORDS * sizeof(uint64_t);
    uint64_t *aligned = aligned_alloc(64, bytes);
    if (!aligned)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate %zu bytes of index", bytes);
    if (g->nlines)
        memcpy(aligned, g->tree, (size_t)g->nlines * TREE_WORDS * sizeof(uint64_t));
    free(g->tree);
    g->tree = aligned;
    return MFG_OK;
}
