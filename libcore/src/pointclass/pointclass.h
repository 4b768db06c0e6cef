/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* pointclass.h - the ring set shared by the one-shot and the prepared point classifiers. */
#ifndef MFG_POINTCLASS_H
#define MFG_POINTCLASS_H

#include <math.h>
#include <stdint.h>

#include "mfgeom.h"
#include "common/predicates.h"

/* Rings stored as separate x and y arrays (SoA, so the x-band test vectorises), each
 * ring followed by a copy of its first vertex: edge i joins vertex i and i + 1 for
 * every i in [ring_first[r], ring_first[r] + ring_edges[r]). */
typedef struct mfg_ringset {
    double *x, *y;
    int64_t *ring_first, *ring_edges;
    int64_t nrings, nedges, nslots;
    double minx, miny, maxx, maxy;
    /* Optional (one-shot path): per slot the x-extent of edge i in float, rounded
     * outward; the closing slot of each ring holds an empty extent so it is never a
     * candidate.  Halving the width doubles the edges per SIMD compare. */
    float *fxmin, *fxmax;
} mfg_ringset;

/* Validates the public ring arguments and the tolerance, then fills rs.  On failure
 * returns the status (detail recorded) and rs owns nothing. */
mfg_status mfg_ringset_build(mfg_ringset *rs, const double *xy, const int64_t *ring_offsets,
                             int64_t nrings, double tol);
void mfg_ringset_free(mfg_ringset *rs);

/* Builds rs->fxmin / rs->fxmax; MFG_ERR_NOMEM on failure. */
mfg_status mfg_ringset_build_extents(mfg_ringset *rs);

/* Checks npoints query points (pointer, count, finiteness, range). */
mfg_status mfg_check_points(const double *pts, int64_t npoints, const void *out);

/* The tolerance box [tx - tol, tx + tol] x [ty - tol, ty + tol] rounded outward, so that
 * a vertex outside it is certainly farther than tol in x or y. */
typedef struct mfg_tolbox {
    double xlo, xhi, ylo, yhi;
} mfg_tolbox;
mfg_tolbox mfg_tolbox_make(double tx, double ty, double tol);

/* 1 when t is certainly farther than tol from the line through a and b (float filter:
 * |cross| / |b - a| > tol with the L1 length as a bound); 0 means "test exactly". */
static inline int mfg_far_from_line(double tx, double ty, double ax, double ay, double bx,
                                    double by, double tol)
{
    double ux = bx - ax, uy = by - ay;
    double l = ux * (ty - ay), r = uy * (tx - ax);
    double cr = l - r, err = MFG_ORIENT2D_ERR * (fabs(l) + fabs(r));
    double len1 = fabs(ux) + fabs(uy);
    return fabs(cr) - err > tol * len1 * (1.0 + 1e-12);
}

/* 1 when the bounding boxes of the segments a-b and r-t are strictly apart (in x or in
 * y): then the segments cannot meet.  The cheap rejection before any crossing test. */
static inline int mfg_segment_boxes_apart(double rx, double ry, double tx, double ty, double ax,
                                          double ay, double bx, double by)
{
    return (ax < rx && ax < tx && bx < rx && bx < tx) || (ax > rx && ax > tx && bx > rx && bx > tx) ||
           (ay < ry && ay < ty && by < ry && by < ty) || (ay > ry && ay > ty && by > ry && by > ty);
}

/* Classification of one point by the outcode method over all edges. */
uint8_t mfg_classify_one(const mfg_ringset *rs, double tx, double ty, double tol);

/* 1 when edge (a, b) crosses the segment r -> t, counted under a consistent symbolic
 * perturbation so that summing over a closed boundary gives the exact parity change
 * between r and t.  Neither r nor t may lie on the boundary. */
int mfg_edge_crosses_segment(double rx, double ry, double tx, double ty, double ax,
                             double ay, double bx, double by);

#endif
