/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* quadtree.h - private to the prepared region (pointclass_grid.c, quadtree_build.c,
 * quadtree_query.c): struct mfg_region, its grid and quadtree layout, and the helpers
 * shared between those files.  See pointclass_grid.c for the design. */
#ifndef MFG_QUADTREE_H
#define MFG_QUADTREE_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "common/mfg_internal.h"
#include "common/predicates.h"
#include "pointclass/pointclass.h"

/* Per-cell byte: bit 0 parity of the reference point, bit 1 list not empty.  One byte
 * a cell keeps the hot table in cache. */
#define CELL_IN 1u
#define CELL_BUSY 2u

/* Lists of at most ORDER_MIN edges are scanned; longer ones become ordered leaves when
 * they qualify (a bisection beats a scan), else scanned up to LEAF_LIST_MAX edges, else
 * split. */
#define ORDER_MIN 2
#define LEAF_LIST_MAX 8
#define MAX_DEPTH 16
/* A split that hands most of its list (more than 3/4) to two or more children
 * separated little and copied much: overlapping collinear edges (or a bundle of copies
 * of one segment) part only at their ends, if at all, and splitting them on to
 * MAX_DEPTH costs up to 2^MAX_DEPTH nodes (the bundle lies in two or three children at
 * every level), each sorting and scanning its whole list.  A child that got most of the
 * list along with a sibling is one step "stalled"; after STALL_MAX such steps in a row
 * it stays a list leaf.  A split that hands most of the list to one child only
 * (zooming in on a small feature, or on a vertex many edges share) costs one node per
 * level and is not counted. */
#define STALL_MAX 2
/* Subdivision stops once the quadtree holds this many times the grid's entries. */
#define ENTRY_BUDGET 8

enum { NODE_LIST = 0, NODE_ORDERED = 1, NODE_SPLIT = 2 };

/* Quadtree objects live in one array of 64-byte lines (`tree`), each object starting on
 * a line so that a leaf's header and its first entries arrive together; a reference to
 * an object is its line number (uint32).  Word 0 of every object is its header:
 * bits 0-7 kind, 8 parity, 9 axis, 16-23 bisection levels, 32-63 entry count.
 *  SPLIT:   w1, w2 = split point (mx, my); w3, w4 = the four children's lines (child
 *           bit 0: x >= mx, bit 1: y >= my).
 *  LIST:    w1, w2 = reference point; then one word per edge: slot id (low 32 bits) and
 *           the reference point's side of the edge (orient2d sign, bits 32-39).
 *  ORDERED: w1 u0, w2 v0 (slab origin; u = x, v = y for axis 0, swapped for axis 1),
 *           w3 1/width, w4 1/height, w5 certification threshold, w6 first of the
 *           leaf's slot ids in oedge[] (bottom to top); from line 1 the slab heights
 *           (see below) as an implicit B-tree of 8-entry groups, coarsest level first. */
#define TREE_WORDS 8

/* Rounding allowances (same values as derived in the comments where they are used):
 * SEG_BOX_SLACK   relative slack on a box-to-segment distance bound (sqrt and products);
 * HEIGHT_ERR      128 ulps (2^-46 = 2^7 u) of the magnitudes entering an ordered line's
 *                 heights;
 * EST_MARGIN      a 1 % margin on the height errors of an estimate, EST_FLOAT_ERR its
 *                 float conversion (2^-24 relative, with room) and EST_ABS_ERR an
 *                 absolute floor;
 * TOL_SLACK       relative slack on the tolerance band stored with a line;
 * POINT_EXTENT    a one-point grid's extent, relative to its coordinates;
 * MIN_ASPECT      the shorter side of the grid at least this times the longer;
 * GRID_MARGIN_ULPS * GRID_U   the cell-location margin: 128 ulps of the coordinates
 *                 (GRID_U = u = 2^-53), at least GRID_MARGIN_MIN. */
#define SEG_BOX_SLACK 1e-12
#define HEIGHT_ERR 0x1p-46
#define EST_MARGIN 1.01
#define EST_FLOAT_ERR 0x1p-20
#define EST_ABS_ERR 0x1p-40
#define TOL_SLACK 1e-9
#define POINT_EXTENT 0x1p-20
#define MIN_ASPECT 1e-3
#define GRID_MARGIN_ULPS 128.0
#define GRID_U 0x1p-53
#define GRID_MARGIN_MIN 0x1p-1000

/* Heights of 8 ordered entries' edges at the two ends of the slab, relative to v0 and
 * divided by the leaf's height: one line, l and r apart so that 4-wide SIMD estimates
 * four entries at once. */
typedef struct slab_group {
    float l[8], r[8];
} slab_group;

struct mfg_region {
    mfg_ringset rs;
    double tol;
    double gx0, gy0, gx1, gy1; /* grid bounds: contain the tol-grown bounding box */
    double cw, ch, inv_cw, inv_ch;
    double margin;             /* absorbs every rounding in locating cells and nodes */
    double reach;              /* tol + margin: how far a cell or node list looks */
    int64_t nx, ny;
    uint8_t *cell;             /* nx*ny bytes, see CELL_* */
    uint32_t *root;            /* nx*ny: line of the quadtree root of a busy cell */
    uint64_t *tree;            /* quadtree objects, TREE_WORDS words a line (64-byte aligned) */
    uint32_t nlines, cap_lines;
    uint32_t *oedge;           /* ORDERED entries: slot ids, bottom to top */
    uint32_t nord, cap_oedge;
    uint64_t entry_budget;
    int64_t grid_entries, max_depth, max_leaf, nlist, nsplit, nlistleaves, nordleaves;
    /* build-time only: the grid's cell lists */
    uint16_t *refk;            /* nx*ny: reference point index of each cell */
    uint32_t *start;           /* nx*ny + 1 offsets into edges[] */
    uint32_t *edges;           /* edge (slot) ids, ascending within a cell */
};

static inline uint64_t tree_header(unsigned kind, unsigned par, unsigned axis, unsigned levels,
                                   uint32_t count)
{
    return (uint64_t)kind | (uint64_t)(par & 1u) << 8 | (uint64_t)(axis & 1u) << 9 |
           (uint64_t)levels << 16 | (uint64_t)count << 32;
}

static inline double word_double(uint64_t w)
{
    double d;
    memcpy(&d, &w, sizeof d);
    return d;
}

static inline uint64_t double_word(double d)
{
    uint64_t w;
    memcpy(&w, &d, sizeof w);
    return w;
}

/* v moved up by 4 ulps of |v| (plus the smallest normal double for results near zero):
 * covers the few roundings of a bound computed in double. */
#define ROUND_UP_REL 0x1p-50
#define ROUND_TINY 0x1p-1022
static inline double round_up_abs(double v) { return v + (fabs(v) * ROUND_UP_REL + ROUND_TINY); }

static inline int64_t clamp64(int64_t v, int64_t lo, int64_t hi)
{
    return v < lo ? lo : (v > hi ? hi : v);
}

static inline int64_t col_of(const mfg_region *g, double x)
{
    double f = floor((x - g->gx0) * g->inv_cw);
    if (!(f >= 0.0))
        return 0;
    return f >= (double)g->nx ? g->nx - 1 : (int64_t)f;
}

static inline int64_t row_of(const mfg_region *g, double y)
{
    double f = floor((y - g->gy0) * g->inv_ch);
    if (!(f >= 0.0))
        return 0;
    return f >= (double)g->ny ? g->ny - 1 : (int64_t)f;
}

/* Point k of the reference sequence in the box [x0, x0 + w] x [y0, y0 + h]: the centre,
 * then the R2 low-discrepancy sequence (no three of its points are collinear in
 * practice, so E edges can hide at most 2E of them: trying 2E + 16 always finds one
 * off the boundary). */
static inline void seq_point(double x0, double y0, double w, double h, unsigned k, double *rx,
                             double *ry)
{
    double fx = 0.5 + (double)k * 0.7548776662466927, fy = 0.5 + (double)k * 0.5698402909980532;
    fx -= floor(fx);
    fy -= floor(fy);
    *rx = x0 + fx * w;
    *ry = y0 + fy * h;
}

/* Reference point k of grid cell (i, j). */
static inline void ref_point(const mfg_region *g, int64_t i, int64_t j, unsigned k, double *rx,
                             double *ry)
{
    double fx = 0.5 + (double)k * 0.7548776662466927, fy = 0.5 + (double)k * 0.5698402909980532;
    fx -= floor(fx);
    fy -= floor(fy);
    *rx = g->gx0 + ((double)i + fx) * g->cw;
    *ry = g->gy0 + ((double)j + fy) * g->ch;
}


/* The slab axis swap: u, v are (x, y) for axis 0 and (y, x) for axis 1. */
static inline void edge_uv(const mfg_region *g, uint32_t e, int axis, double *au, double *av,
                           double *bu, double *bv)
{
    const double *U = axis ? g->rs.y : g->rs.x, *V = axis ? g->rs.x : g->rs.y;
    double pu = U[e], pv = V[e], qu = U[e + 1], qv = V[e + 1];
    if (pu <= qu) {
        *au = pu; *av = pv; *bu = qu; *bv = qv;
    } else {
        *au = qu; *av = qv; *bu = pu; *bv = pv;
    }
}

/* Side of t (in u, v) of edge e directed towards increasing u: +1 above, -1 below, 0 on
 * its line (exact). */
static inline int side_uv(double au, double av, double bu, double bv, double tu, double tv)
{
    int s = mfg_orient2d_filter(au, av, bu, bv, tu, tv);
    return s ? s : mfg_orient2d(au, av, bu, bv, tu, tv);
}

/* Groups (of 8 heights) of level j of an ordered leaf with m entries: level j holds the
 * heights of entries (i + 1) 8^j - 1, padded at the end. */
static inline uint32_t level_groups(uint32_t m, unsigned j)
{
    return (uint32_t)(((uint64_t)m + ((uint64_t)1 << (3 * (j + 1))) - 1) >> (3 * (j + 1)));
}

/* pointclass_grid.c: 1 when (rx, ry) lies on none of the listed edges (exactly). */
int mfg_pc_off_boundary(const mfg_region *g, const uint32_t *list, uint32_t m, double rx,
                        double ry);

/* quadtree_build.c: builds the quadtree of every busy cell, then drops the grid's lists
 * and moves the tree to 64-byte aligned memory. */
mfg_status mfg_qt_build_trees(mfg_region *g);

#endif
