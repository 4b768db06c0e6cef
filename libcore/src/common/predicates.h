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

/* Error bound of the orientation filter: with l = (bx - ax)(cy - ay) and
 * r = (by - ay)(cx - ax) in doubles, each product carries <= 3u relative error (two
 * differences, one product) and the subtraction one more, so
 * |(l - r) - exact| <= 4u (|l| + |r|), u = 2^-53. */
#define MFG_ORIENT2D_ERR 4.440892098500626e-16

/* The floating-point filter of mfg_orient2d alone: the sign of the orientation
 * determinant when the rounded value decides it, 0 when it cannot tell (then call
 * mfg_orient2d for the exact answer). */
static inline int mfg_orient2d_filter(double ax, double ay, double bx, double by, double cx,
                                      double cy)
{
    double l = (bx - ax) * (cy - ay), r = (by - ay) * (cx - ax), det = l - r;
    double bound = MFG_ORIENT2D_ERR * ((l < 0 ? -l : l) + (r < 0 ? -r : r));
    return det > bound ? 1 : (-det > bound ? -1 : 0);
}

/* ---- Sphere (3-D vector) predicates: signs are exact for the doubles given, and do
 * not depend on the vectors' lengths, so unnormalised normals can be used as they are. */

/* Sign of det[a, b, c] = a . (b x c): +1 when c lies left of the great circle through
 * a then b (seen from outside the sphere), i.e. a, b, c turn counter-clockwise. */
int mfg_orient3(const double a[3], const double b[3], const double c[3]);

/* Sign of a . b. */
int mfg_dot3_sign(const double a[3], const double b[3]);

/* Sign of (a x b) . (c x d) = (a.c)(b.d) - (a.d)(b.c).  With a = c = q it compares
 * directions in the plane orthogonal to q without projecting anything. */
int mfg_cross_dot_sign(const double a[3], const double b[3], const double c[3],
                       const double d[3]);

/* +1 when b is a positive multiple of a, -1 when a negative multiple, 0 otherwise
 * (exact; a and b must be non-zero). */
int mfg_parallel3(const double a[3], const double b[3]);

/* Sign of Shewchuk's orient3d: det[a - d, b - d, c - d] =
 * det[a,c,d] + det[a,b,c] - det[b,c,d] - det[a,b,d].  +1 when d lies below the plane of
 * a, b, c, i.e. on the side from which a, b, c turn clockwise: for a triangle
 * counter-clockwise seen from outside a solid, +1 means d is on the inner side.  Exact
 * for coordinates allowed by mfg_coord_ok. */
int mfg_orient3d(const double a[3], const double b[3], const double c[3], const double d[3]);

/* Sign of det[a - o, b - o, v] for points o, a, b and a vector v (exact; no point o + v
 * is formed, so it is exact where orient3d(a, b, o + v, o) would need a rounded sum).
 * With v the direction of a line through o: the side on which the line passes the
 * directed segment ab.  With o, a, b a triangle: the sign of its normal
 * (a - o) x (b - o) along v. */
int mfg_orient3d_vec(const double o[3], const double a[3], const double b[3], const double v[3]);

/* a x b with each component computed from exact products (Kahan's trick): nearly
 * parallel vectors still give an accurate direction instead of rounding noise or 0. */
void mfg_cross3_accurate(const double a[3], const double b[3], double out[3]);

#endif
