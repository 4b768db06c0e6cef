/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* pointclass_grid.c - prepared point classification: a uniform grid over the region whose
 * empty cells answer IN/OUT at once; busy cells hold a small quadtree whose leaves are
 * short edge lists or "ordered" slabs searched by bisection.  Every decision is exact. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/mfg_internal.h"
#include "pointclass/pointclass.h"
#include "common/predicates.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/*
 * Why reference points.  The paper's swath (slab) method counts crossings of a vertical
 * ray, which needs every edge above the query.  Instead each cell (and quadtree node) has
 * a reference point r off the boundary whose parity is known; a query t in the cell has
 *     parity(t) = parity(r) XOR #(edges crossing the segment r-t),
 * and only edges that touch the cell can cross r-t.  Cell lists hold every edge within
 * tol (+ a rounding margin, together `reach`) of the cell, so the same list also decides
 * ON exactly.  Cells with an empty list are answered by their reference parity alone.
 * Reference parities are propagated cell to cell, and from a node to its children, along
 * such segments (exact, symbolically perturbed crossing test).
 *
 * Why a quadtree with ordered leaves.  A uniform grid cannot separate dense spikes
 * (a star with 50 000 spikes has ~10^-5 between edges over most of its area), so a busy
 * cell with more than ORDER_MIN edges is
 *  - an ORDERED leaf when every edge of its list spans the cell's x-range (or y-range)
 *    grown by reach, and consecutive edges, sorted bottom to top, are exactly verified
 *    not to meet over that range.  The edges then cut the cell into bands; parity is
 *    constant on a band and flips across each edge, so
 *        parity(t) = P0 XOR #(edges below t)      (P0 fixed once from the reference point),
 *    and the count is a bisection.  Over a slab the disc of radius tol around t can only
 *    reach a farther edge through the nearer ones, so ON needs only the two edges
 *    around t.  The bisection runs on float copies of each edge's height at the two
 *    ends of the slab; when they separate t from both neighbours by more than their
 *    error bound plus tol (scaled by the steepest edge) the answer is certain without
 *    touching the vertices, otherwise the exact predicates decide.
 *  - otherwise, with more than LEAF_LIST_MAX edges, split into four (up to MAX_DEPTH
 *    levels, within an entry budget, and only while the split separates edges), each
 *    child keeping only the edges within reach of it.
 * Other leaves keep the plain exact list scan against the leaf's reference point.
 * Every decision goes through the exact predicates, so answers equal the one-shot ones.
 *
 * Cost: building is one grid pass plus, per busy cell, a sort of its list and a split
 * where the list cannot be ordered (edges ending or crossing inside).  A quadtree level
 * only splits cells holding vertices or crossings and an edge passes O(1) of them per
 * level, so entries grow by O(n) per level: O(n log n) time, memory O(n) per level, at
 * most MAX_DEPTH levels and never more than ENTRY_BUDGET x the grid's entries (which
 * are O(n): ~16 per edge at most).  Lists that splitting cannot part (copies of a
 * segment, overlapping collinear edges) would otherwise double at every level up to
 * that budget: a list of at most LEAF_LIST_MAX distinct segments is a leaf, and a node
 * stops after STALL_MAX splits that copied most of its list to a sibling too.  Measured: the benchmark's star of 50 000 spikes
 * holds 3.7M entries (64 MB) built in ~0.4 s; a smooth ring of 100 000 edges 0.13M.
 * A query reads one byte for an empty cell, else descends a few nodes and scans
 * <= LEAF_LIST_MAX edges or bisects an ordered leaf (O(log m), one line per 8x).
 */

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

/* Visits every cell within reach of edge e (conservatively: possibly a few more).
 * With fill == NULL it counts into start[cell + 1]; otherwise it appends e. */
static void rasterize_edge(const mfg_region *g, int64_t e, uint32_t *count, uint32_t *fill)
{
    const double *X = g->rs.x, *Y = g->rs.y;
    double ax = X[e], ay = Y[e], bx = X[e + 1], by = Y[e + 1];
    double d = g->reach;
    double sx0 = fmin(ax, bx), sx1 = fmax(ax, bx);
    int64_t i0 = col_of(g, sx0 - d), i1 = col_of(g, sx1 + d);
    double slope = ax != bx ? (by - ay) / (bx - ax) : 0.0;
    for (int64_t i = i0; i <= i1; i++) {
        double ylo, yhi;
        if (ax == bx) {
            ylo = fmin(ay, by);
            yhi = fmax(ay, by);
        } else {
            /* Part of the segment over this column grown by reach; interpolation error is
             * a few ulps of |by - ay|, far inside the margin in reach. */
            double xa = fmin(fmax(g->gx0 + (double)i * g->cw - d, sx0), sx1);
            double xb = fmin(fmax(g->gx0 + (double)(i + 1) * g->cw + d, sx0), sx1);
            double ya = ay + (xa - ax) * slope, yb = ay + (xb - ax) * slope;
            ylo = fmin(ya, yb);
            yhi = fmax(ya, yb);
        }
        int64_t j0 = row_of(g, ylo - d), j1 = row_of(g, yhi + d);
        for (int64_t j = j0; j <= j1; j++) {
            int64_t c = j * g->nx + i;
            if (fill)
                fill[count[c]++] = (uint32_t)e;
            else
                count[c + 1]++;
        }
    }
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

/* Parity change along r -> t over the union of two sorted cell lists (each edge once). */
static unsigned crossings_between(const mfg_region *g, int64_t c1, int64_t c2, double rx,
                                  double ry, double tx, double ty)
{
    const double *X = g->rs.x, *Y = g->rs.y;
    uint32_t p = g->start[c1], pe = g->start[c1 + 1];
    uint32_t q = g->start[c2], qe = g->start[c2 + 1];
    unsigned par = 0;
    while (p < pe || q < qe) {
        uint32_t e;
        if (q >= qe || (p < pe && g->edges[p] < g->edges[q]))
            e = g->edges[p++];
        else if (p >= pe || g->edges[q] < g->edges[p])
            e = g->edges[q++];
        else {
            e = g->edges[p++];
            q++;
        }
        par ^= (unsigned)mfg_edge_crosses_segment(rx, ry, tx, ty, X[e], Y[e], X[e + 1], Y[e + 1]);
    }
    return par;
}

static mfg_status build_lists(mfg_region *g)
{
    int64_t ncells = g->nx * g->ny;
    g->start = calloc((size_t)ncells + 1, sizeof(uint32_t));
    g->cell = calloc((size_t)ncells, 1);
    g->refk = calloc((size_t)ncells, sizeof(uint16_t));
    g->root = calloc((size_t)ncells, sizeof(uint32_t));
    if (!g->start || !g->cell || !g->refk || !g->root)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate a grid of %lld cells", (long long)ncells);
    for (int64_t r = 0; r < g->rs.nrings; r++)
        for (int64_t e = g->rs.ring_first[r]; e < g->rs.ring_first[r] + g->rs.ring_edges[r]; e++)
            rasterize_edge(g, e, g->start, NULL);
    uint64_t total = 0;
    for (int64_t c = 0; c < ncells; c++) {
        total += g->start[c + 1];
        if (total > UINT32_MAX / 2)
            return mfg_fail(MFG_ERR_NOMEM, "grid index too large (more than 2^31 entries)");
        g->start[c + 1] = (uint32_t)total;
    }
    g->grid_entries = (int64_t)total;
    g->edges = malloc((size_t)(total ? total : 1) * sizeof(uint32_t));
    uint32_t *cursor = malloc((size_t)ncells * sizeof(uint32_t));
    if (!g->edges || !cursor) {
        free(cursor);
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate %llu grid entries", (unsigned long long)total);
    }
    memcpy(cursor, g->start, (size_t)ncells * sizeof(uint32_t));
    for (int64_t r = 0; r < g->rs.nrings; r++)
        for (int64_t e = g->rs.ring_first[r]; e < g->rs.ring_first[r] + g->rs.ring_edges[r]; e++)
            rasterize_edge(g, e, cursor, g->edges);
    free(cursor);
    return MFG_OK;
}

/* 1 when (rx, ry) lies on none of the listed edges (exactly). */
static int off_boundary(const mfg_region *g, const uint32_t *list, uint32_t m, double rx, double ry)
{
    const double *X = g->rs.x, *Y = g->rs.y;
    for (uint32_t p = 0; p < m; p++) {
        uint32_t e = list[p];
        double ax = X[e], ay = Y[e], bx = X[e + 1], by = Y[e + 1];
        if ((ax < rx && bx < rx) || (ax > rx && bx > rx) || (ay < ry && by < ry) ||
            (ay > ry && by > ry))
            continue;
        if (mfg_segment_within(rx, ry, ax, ay, bx, by, 0.0))
            return 0;
    }
    return 1;
}

/* Chooses each busy cell's reference point off the boundary. */
static mfg_status choose_refs(mfg_region *g)
{
    for (int64_t j = 0; j < g->ny; j++)
        for (int64_t i = 0; i < g->nx; i++) {
            int64_t c = j * g->nx + i;
            if (g->start[c] == g->start[c + 1])
                continue;
            uint32_t len = g->start[c + 1] - g->start[c];
            uint32_t limit = len < 30000 ? 2 * len + 16 : 65535;
            unsigned k = 0;
            for (; k < limit; k++) {
                double rx, ry;
                ref_point(g, i, j, k, &rx, &ry);
                if (off_boundary(g, g->edges + g->start[c], len, rx, ry))
                    break;
            }
            if (k == limit)
                return mfg_fail(MFG_ERR_INTERNAL, "no reference point off the boundary in cell %lld", (long long)c);
            g->cell[c] = (uint8_t)CELL_BUSY;
            g->refk[c] = (uint16_t)k;
        }
    return MFG_OK;
}

static mfg_status propagate_parity(mfg_region *g)
{
    double rx, ry, sx, sy;
    ref_point(g, 0, 0, g->refk[0], &rx, &ry);
    uint8_t first = mfg_classify_one(&g->rs, rx, ry, 0.0);
    if (first == MFG_ON)
        return mfg_fail(MFG_ERR_INTERNAL, "reference point on the boundary");
    unsigned par = first == MFG_IN;
    g->cell[0] |= (uint8_t)par;
    for (int64_t i = 1; i < g->nx; i++) {
        ref_point(g, i - 1, 0, g->refk[i - 1], &rx, &ry);
        ref_point(g, i, 0, g->refk[i], &sx, &sy);
        par = (g->cell[i - 1] & CELL_IN) ^ crossings_between(g, i - 1, i, rx, ry, sx, sy);
        g->cell[i] |= (uint8_t)par;
    }
    for (int64_t i = 0; i < g->nx; i++)
        for (int64_t j = 1; j < g->ny; j++) {
            int64_t c0 = (j - 1) * g->nx + i, c1 = j * g->nx + i;
            ref_point(g, i, j - 1, g->refk[c0], &rx, &ry);
            ref_point(g, i, j, g->refk[c1], &sx, &sy);
            par = (g->cell[c0] & CELL_IN) ^ crossings_between(g, c0, c1, rx, ry, sx, sy);
            g->cell[c1] |= (uint8_t)par;
        }
    return MFG_OK;
}

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

/* Groups (of 8 heights) of level j of an ordered leaf with m entries: level j holds the
 * heights of entries (i + 1) 8^j - 1, padded at the end. */
static inline uint32_t level_groups(uint32_t m, unsigned j)
{
    return (uint32_t)(((uint64_t)m + ((uint64_t)1 << (3 * (j + 1))) - 1) >> (3 * (j + 1)));
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
            if (off_boundary(g, cl, cm[q], c[q].rx, c[q].ry))
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
static mfg_status build_trees(mfg_region *g)
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

void mfg_region_free(mfg_region *g)
{
    if (!g)
        return;
    mfg_ringset_free(&g->rs);
    free(g->cell);
    free(g->root);
    free(g->tree);
    free(g->oedge);
    free(g->refk);
    free(g->start);
    free(g->edges);
    free(g);
}

mfg_status mfg_region_new(const double *xy, const int64_t *ring_offsets, int64_t nrings,
                          double tol, mfg_region **out_region)
{
    if (!out_region)
        return mfg_fail(MFG_ERR_NULL, "out_region is NULL");
    mfg_region *g = calloc(1, sizeof *g);
    if (!g)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate a region");
    mfg_status st = mfg_ringset_build(&g->rs, xy, ring_offsets, nrings, tol);
    if (st != MFG_OK) {
        free(g);
        return st;
    }
    if (g->rs.nslots >= (int64_t)UINT32_MAX) {
        mfg_region_free(g);
        return mfg_fail(MFG_ERR_INVALID, "too many vertices for a prepared region (%lld)",
                        (long long)g->rs.nedges);
    }
    g->tol = tol;
    /* Grid bounds: the bounding box grown by tol and by a margin that absorbs every
     * rounding in locating cells; `reach` is how far around a cell its list looks. */
    double x0 = g->rs.minx - tol, x1 = g->rs.maxx + tol;
    double y0 = g->rs.miny - tol, y1 = g->rs.maxy + tol;
    double w = x1 - x0, h = y1 - y0;
    double ext = fmax(w, h);
    if (ext == 0.0) /* one point: any cell size works; keep reference points far from it */
        ext = fmax(fmax(fabs(x0), fabs(y0)), 1.0) * POINT_EXTENT;
    w = fmax(w, ext * MIN_ASPECT);
    h = fmax(h, ext * MIN_ASPECT);
    double margin = GRID_MARGIN_ULPS * GRID_U * (fabs(x0) + fabs(x1) + fabs(y0) + fabs(y1) + w + h);
    margin = fmax(margin, GRID_MARGIN_MIN);
    g->margin = margin;
    g->gx0 = x0 - 2.0 * margin;
    g->gy0 = y0 - 2.0 * margin;
    g->reach = round_up_abs(tol + margin);

    /* About sixteen cells per edge keeps ~97% of queries of a smooth ring in empty
     * cells; one byte per cell keeps the table cache-resident up to ~2M cells. */
    double want = fmin(fmax(16.0 * (double)g->rs.nedges, 64.0), 2097152.0);
    double cw = sqrt(w * h / want);
    /* Long edges (spiky stars) would each fill many cells: an edge enters about
     * (|dx| + |dy|) / cell + 3 cells, so coarsen the grid until the lists stay within
     * ~16 entries per edge on average.  The quadtree refines busy cells further, and
     * fewer, longer ordered leaves cost one more bisection level but less memory
     * (star of 50 000 spikes, 64 rather than 16 entries per edge: 87 -> 64 MB,
     * ~120 -> ~75 ns a query). */
    double sumlen = 0.0;
    for (int64_t r = 0; r < g->rs.nrings; r++)
        for (int64_t e = g->rs.ring_first[r]; e < g->rs.ring_first[r] + g->rs.ring_edges[r]; e++)
            sumlen += fabs(g->rs.x[e + 1] - g->rs.x[e]) + fabs(g->rs.y[e + 1] - g->rs.y[e]);
    double budget = 13.0 * (double)g->rs.nedges + 4096.0;
    if (sumlen / cw > budget)
        cw = sumlen / budget;
    int64_t nx = clamp64((int64_t)ceil(w / cw), 1, 65536);
    int64_t ny = clamp64((int64_t)ceil(h / cw), 1, 65536);
    g->nx = nx;
    g->ny = ny;
    g->cw = (w + 4.0 * margin) / (double)nx;
    g->ch = (h + 4.0 * margin) / (double)ny;
    g->inv_cw = 1.0 / g->cw;
    g->inv_ch = 1.0 / g->ch;
    g->gx1 = g->gx0 + (double)nx * g->cw;
    g->gy1 = g->gy0 + (double)ny * g->ch;
    st = build_lists(g);
    if (st == MFG_OK)
        st = choose_refs(g);
    if (st == MFG_OK)
        st = propagate_parity(g);
    if (st == MFG_OK)
        st = build_trees(g);
    if (st != MFG_OK) {
        mfg_region_free(g);
        return st;
    }
    *out_region = g;
    mfg_clear_error();
    return MFG_OK;
}

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
