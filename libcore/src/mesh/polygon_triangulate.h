/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* polygon_triangulate.h - private: triangulation of a polygon with holes that keeps every
 * vertex (also collinear ones) and adds none, with exact orientation predicates. */
#ifndef MFG_POLYGON_TRIANGULATE_H
#define MFG_POLYGON_TRIANGULATE_H

#include <stdint.h>

/*
 * Triangulates the region bounded by nloops closed loops of 2-D points: loop i is the
 * points xy[2 j], xy[2 j + 1] for j in [loop_start[i], loop_start[i + 1]), the region on
 * the left of every loop (one counter-clockwise outer loop, any number of clockwise holes,
 * in any order).  A point may occur several times (a loop touching itself or another loop
 * at a vertex); each occurrence is its own corner.  Loops must not cross each other or
 * themselves.
 *
 * On success returns 1 and writes *ntri triangles to tri (3 indices each, into the points;
 * every triangle strictly counter-clockwise; room for n - 2 + 2 (nloops - 1) of them, n
 * the number of points): n - 2 + 2 (nloops - 1), less 2 for every hole that touches the
 * rest at a point instead of being joined to it by a bridge.  Every point is a corner of
 * some triangle.  Returns 0 when the loops are not such a region or no triangulation was
 * found (then tri is scratch), -1 when out of memory.  A loop that touches itself so that
 * the region falls apart at that point (two lobes) is not triangulated: pass the lobes as
 * loops of their own regions.
 */
int mfg_polygon_triangulate(const double *xy, const int64_t *loop_start, int64_t nloops,
                            int64_t *tri, int64_t *ntri);

#endif
