/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* pointclass_grid.c - prepared point classification: a uniform grid over the region whose
 * empty cells answer IN/OUT at once and whose boundary cells keep the exact tolerance test. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mfg_internal.h"
#include "pointclass.h"
#include "predicates.h"

/*
 * Why a grid of reference points.  The paper's swath (slab) method counts crossings of a
 * vertical ray, which needs every edge above the query.  Instead each cell has a
 * reference point r (its centre, or another fixed point of the cell if the centre lies on
 * the boundary) whose parity is known; a query t in the cell has
 *     parity(t) = parity(r) XOR #(edges crossing the segment r-t),
 * and only edges that touch the cell can cross r-t.  Cell lists hold every edge within
 * tol (+ a rounding margin) of the cell, so the same list also decides ON exactly.  Cells
 * with an empty list are answered by their reference parity alone.  The reference
 * parities are propagated cell to cell along the same kind of segments, so building
 * costs one full walk plus work proportional to the list sizes.
 * Every decision goes through the exact predicates, so answers equal the one-shot ones.
 */

/* Per-cell byte: bit 0 parity of the reference point, bit 1 list not empty.  One byte
 * a cell keeps the hot table in cache; the reference position of busy cells is a
 * separate uint16 (which point of the sequence below). */
#define CELL_IN 1u
#define CELL_BUSY 2u

struct mfg_region {
    mfg_ringset rs;
    double tol;
    double gx0, gy0, gx1, gy1; /* grid bounds: contain the tol-grown bounding box */
    double cw, ch, inv_cw, inv_ch;
    double reach;              /* tol + rounding margin: how far a cell list looks */
    int64_t nx, ny;
    uint8_t *cell;             /* nx*ny bytes, see CELL_* */
    uint16_t *refk;            /* nx*ny: reference point index of each cell */
    uint32_t *start;           /* nx*ny + 1 offsets into edges[] */
    uint32_t *edges;           /* edge (slot) ids, ascending within a cell */
    int8_t *rside;             /* per entry: side of the cell's reference point (orient2d) */
};

static inline double round_up_abs(double v) { return v + (fabs(v) * 0x1p-50 + 0x1p-1022); }

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

/* Reference point k of cell (i, j): the centre, then the R2 low-discrepancy sequence
 * (no three of its points are collinear in practice, so E edges can hide at most 2E of
 * them: trying 2E + 16 always finds one off the boundary). */
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
    if (!g->start || !g->cell || !g->refk)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate a grid of %lld cells", (long long)ncells);
    for (int64_t r = 0; r < g->rs.nrings; r++)
        for (int64_t e = g->rs.ring_first[r]; e < g->rs.ring_first[r] + g->rs.ring_edges[r]; e++)
            rasterize_edge(g, e, g->start, NULL);
    uint64_t total = 0;
    for (int64_t c = 0; c < ncells; c++) {
        total += g->start[c + 1];
        if (total > UINT32_MAX)
            return mfg_fail(MFG_ERR_NOMEM, "grid index too large (more than 2^32 entries)");
        g->start[c + 1] = (uint32_t)total;
    }
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

/* Chooses each busy cell's reference point off the boundary. */
static mfg_status choose_refs(mfg_region *g)
{
    const double *X = g->rs.x, *Y = g->rs.y;
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
                uint32_t p = g->start[c];
                for (; p < g->start[c + 1]; p++) {
                    uint32_t e = g->edges[p];
                    if (mfg_segment_within(rx, ry, X[e], Y[e], X[e + 1], Y[e + 1], 0.0))
                        break;
                }
                if (p == g->start[c + 1])
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

/* For every cell entry, the side of the edge's line the cell's reference point is on:
 * a query on the same side cannot have the edge cross its segment to the reference, so
 * one orientation test replaces the crossing test for most edges. */
static mfg_status reference_sides(mfg_region *g)
{
    const double *X = g->rs.x, *Y = g->rs.y;
    int64_t ncells = g->nx * g->ny;
    g->rside = malloc((size_t)(g->start[ncells] + 1));
    if (!g->rside)
        return mfg_fail(MFG_ERR_NOMEM, "cannot allocate the grid's reference sides");
    for (int64_t c = 0; c < ncells; c++) {
        if (g->start[c] == g->start[c + 1])
            continue;
        double rx, ry;
        ref_point(g, c % g->nx, c / g->nx, g->refk[c], &rx, &ry);
        for (uint32_t p = g->start[c]; p < g->start[c + 1]; p++) {
            uint32_t e = g->edges[p];
            g->rside[p] = (int8_t)mfg_orient2d(X[e], Y[e], X[e + 1], Y[e + 1], rx, ry);
        }
    }
    return MFG_OK;
}

void mfg_region_free(mfg_region *g)
{
    if (!g)
        return;
    mfg_ringset_free(&g->rs);
    free(g->cell);
    free(g->rside);
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
        ext = fmax(fmax(fabs(x0), fabs(y0)), 1.0) * 0x1p-20;
    w = fmax(w, ext * 1e-3);
    h = fmax(h, ext * 1e-3);
    double margin = 128.0 * 0x1p-53 * (fabs(x0) + fabs(x1) + fabs(y0) + fabs(y1) + w + h);
    margin = fmax(margin, 0x1p-1000);
    g->gx0 = x0 - 2.0 * margin;
    g->gy0 = y0 - 2.0 * margin;
    g->reach = round_up_abs(tol + margin);

    /* About sixteen cells per edge keeps ~97% of queries of a smooth ring in empty
     * cells; one byte per cell keeps the table cache-resident up to ~2M cells. */
    double want = fmin(fmax(16.0 * (double)g->rs.nedges, 64.0), 2097152.0);
    double cw = sqrt(w * h / want);
    /* Long edges (spiky stars) would each fill many cells: an edge enters about
     * (|dx| + |dy|) / cell + 3 cells, so coarsen the grid until the lists stay within
     * 64 entries per edge on average. */
    double sumlen = 0.0;
    for (int64_t r = 0; r < g->rs.nrings; r++)
        for (int64_t e = g->rs.ring_first[r]; e < g->rs.ring_first[r] + g->rs.ring_edges[r]; e++)
            sumlen += fabs(g->rs.x[e + 1] - g->rs.x[e]) + fabs(g->rs.y[e + 1] - g->rs.y[e]);
    double budget = 61.0 * (double)g->rs.nedges + 4096.0;
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
        st = reference_sides(g);
    if (st != MFG_OK) {
        mfg_region_free(g);
        return st;
    }
    *out_region = g;
    mfg_clear_error();
    return MFG_OK;
}

static uint8_t classify_in_cell(const mfg_region *g, int64_t i, int64_t j, double tx, double ty)
{
    int64_t c = j * g->nx + i;
    unsigned info = g->cell[c];
    if (!(info & CELL_BUSY))
        return (uint8_t)(info & CELL_IN);
    const double *X = g->rs.x, *Y = g->rs.y;
    mfg_tolbox box = mfg_tolbox_make(tx, ty, g->tol);
    double rx, ry;
    ref_point(g, i, j, g->refk[c], &rx, &ry);
    unsigned par = info & CELL_IN;
    for (uint32_t p = g->start[c]; p < g->start[c + 1]; p++) {
        uint32_t e = g->edges[p];
        double ax = X[e], ay = Y[e], bx = X[e + 1], by = Y[e + 1];
        if (!((ax < box.xlo && bx < box.xlo) || (ax > box.xhi && bx > box.xhi) ||
              (ay < box.ylo && by < box.ylo) || (ay > box.yhi && by > box.yhi)) &&
            !mfg_far_from_line(tx, ty, ax, ay, bx, by, g->tol) &&
            mfg_segment_within(tx, ty, ax, ay, bx, by, g->tol))
            return MFG_ON;
        /* Most edges miss the box of the segment r -> t, or have r and t strictly on
         * one side of their line: neither can cross the segment. */
        if (mfg_segment_boxes_apart(rx, ry, tx, ty, ax, ay, bx, by))
            continue;
        if (g->rside[p] != 0 && mfg_orient2d_filter(ax, ay, bx, by, tx, ty) == g->rside[p])
            continue;
        par ^= (unsigned)mfg_edge_crosses_segment(rx, ry, tx, ty, ax, ay, bx, by);
    }
    return (uint8_t)par;
}

mfg_status mfg_region_classify(const mfg_region *g, const double *pts, int64_t npoints,
                               uint8_t *out)
{
    if (!g)
        return mfg_fail(MFG_ERR_NULL, "region is NULL");
    mfg_status st = mfg_check_points(pts, npoints, out);
    if (st != MFG_OK)
        return st;
    for (int64_t k = 0; k < npoints; k++) {
        double tx = pts[2 * k], ty = pts[2 * k + 1];
        if (!(tx >= g->gx0 && tx <= g->gx1 && ty >= g->gy0 && ty <= g->gy1)) {
            out[k] = MFG_OUT;
            continue;
        }
        int64_t i = (int64_t)((tx - g->gx0) * g->inv_cw);
        int64_t j = (int64_t)((ty - g->gy0) * g->inv_ch);
        i = i < g->nx ? i : g->nx - 1;
        j = j < g->ny ? j : g->ny - 1;
        out[k] = classify_in_cell(g, i, j, tx, ty);
    }
    mfg_clear_error();
    return MFG_OK;
}

mfg_status mfg_region_stats(const mfg_region *g, int64_t stats_out[4])
{
    if (!g || !stats_out)
        return mfg_fail(MFG_ERR_NULL, "region or stats_out is NULL");
    int64_t busy = 0, ncells = g->nx * g->ny;
    for (int64_t c = 0; c < ncells; c++)
        busy += (g->cell[c] & CELL_BUSY) != 0;
    stats_out[0] = g->nx;
    stats_out[1] = g->ny;
    stats_out[2] = busy;
    stats_out[3] = (int64_t)g->start[ncells];
    return MFG_OK;
}
