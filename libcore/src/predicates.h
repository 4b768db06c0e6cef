/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* predicates.h - exact 2-D geometric predicates: a floating-point filter with an exact
 * expansion-arithmetic fallback (after Shewchuk), so a predicate never lies. */
#ifndef MFG_PREDICATES_H
#define MFG_PREDICATES_H

/* Sign (-1, 0, +1) of the orientation determinant (b - a) x (c - a):
 * +1 when a, b, c turn counter-clockwise. */
int mfg_orient2d(double ax, double ay, double bx, double by, double cx, double cy);

/* Sign of the dot product (b - a) . (c - a). */
int mfg_dot2d(double ax, double ay, double bx, double by, double cx, double cy);

/* 1 when the Euclidean distance from t to the closed segment ab is <= tol, else 0.
 * Exact for inputs within MFG_MAX_COORD, barring underflow of intermediate products. */
int mfg_segment_within(double tx, double ty, double ax, double ay, double bx, double by,
                       double tol);

#endif
