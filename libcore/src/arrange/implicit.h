/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* arrange/implicit.h - The points of a mesh arrangement and exact predicates on them.
 *
 * An arrangement of triangles (arrange/) needs, besides the input ("explicit") vertices,
 * the points where the triangles cut each other.  Those are never rounded: each is kept
 * as the construction that defines it from explicit vertices only (never from another
 * implicit point), so every predicate is the sign of a polynomial of bounded degree in the
 * explicit coordinates, decided exactly (after Attene's "indirect predicates" and Cherchi
 * et al., "Interactive and robust mesh booleans", 2022):
 *
 *   ARR_EXPLICIT  vertex v[0]                                          degree X 1, W 0
 *   ARR_LPI       the line through v[0], v[1] crossing the plane of    degree X 4, W 3
 *                 the triangle v[2], v[3], v[4]
 *   ARR_TPI       the three planes of the triangles (v[0..2]),         degree X 7, W 6
 *                 (v[3..5]), (v[6..8])
 *   ARR_SSI       two segments v[0]v[1] and v[2]v[3] of one plane      degree X 3, W 2
 *                 crossing: the point on the line v[0]v[1] whose
 *                 projection (dropping coordinate `axis`) is where the
 *                 projections of the two lines cross
 *   ARR_LIFT      the point of the plane of triangle v[0..2] whose     degree X 3, W 2
 *                 coordinates other than `axis` are lift[0], lift[1]
 *                 (in the order (axis+1)%3, (axis+2)%3)
 *
 * Each is a rational point X / W with homogeneous coordinates (X0, X1, X2, W), W != 0
 * for a valid construction (the caller only builds one whose denominator is non-zero:
 * a line that crosses the plane, three planes meeting in one point, two segments that
 * are not parallel in the projection, a plane not parallel to `axis`).
 *
 * Exactness needs bounded coordinates: every explicit coordinate (and lift[]) must be an
 * integer multiple of 2^-ARR_GRID_LOG2 with magnitude at most ARR_COORD_MAX.  Then every
 * monomial of the predicates below (degree <= 20) is a multiple of 2^-1000 and at most
 * ~2^130 in magnitude, so double expansions represent every intermediate value exactly
 * (no underflow, no overflow).  The caller snaps its coordinates to that grid.
 *
 * Every predicate first evaluates the polynomial in floating point with a rigorous error
 * bound (a filter) and only when the bound cannot certify the sign evaluates it exactly
 * with expansion arithmetic (common/expansion.h).  Pure functions of their arguments: no
 * state is kept, safe to call from several threads on one const table.
 */
#ifndef MFG_ARRANGE_IMPLICIT_H
#define MFG_ARRANGE_IMPLICIT_H

#include <stdint.h>

#define ARR_GRID_LOG2 50
#define ARR_COORD_MAX 16.0

typedef enum arr_kind {
    ARR_EXPLICIT = 0,
    ARR_LPI = 1,
    ARR_TPI = 2,
    ARR_SSI = 3,
    ARR_LIFT = 4
} arr_kind;

/* One point.  v[] are indices into the explicit coordinates (arr_points.xyz). */
typedef struct arr_point {
    uint8_t kind;       /* arr_kind */
    uint8_t axis;       /* ARR_SSI, ARR_LIFT: the dropped coordinate 0, 1 or 2 */
    int64_t v[9];
    double lift[2];     /* ARR_LIFT only */
    /* Filter data, filled by arr_point_prepare: the homogeneous coordinates (X0, X1, X2,
     * W) rounded, and for each an absolute bound on its error. */
    double h[4];
    double herr[4];
} arr_point;

/* The points of one arrangement: the explicit coordinates and the points (explicit
 * vertices may appear as ARR_EXPLICIT points; the predicates take point indices). */
typedef struct arr_points {
    const double *xyz;  /* 3 per explicit vertex, on the grid (see above) */
    int64_t nxyz;
    arr_point *pts;
    int64_t npts;
} arr_points;

/* Fills p->h and p->herr from the construction (call once after setting kind, axis, v,
 * lift).  Returns 1, or 0 when the denominator W is exactly zero (no such point). */
int arr_point_prepare(const double *xyz, arr_point *p);

/* Sign of orient3d(a, b, c, q) for explicit vertices a, b, c (indices into xyz) and the
 * point q (index into pts), with the convention of mfg_orient3d: +1 when q lies below
 * the plane of a, b, c (the side from which a, b, c turn clockwise). */
int arr_orient3d(const arr_points *P, int64_t a, int64_t b, int64_t c, int64_t q);

/* Sign of the orientation of the points p, q, r projected by dropping coordinate axis,
 * with coordinates ((axis+1)%3, (axis+2)%3): +1 when they turn counter-clockwise, i.e.
 * the sign of the axis component of (q - p) x (r - p). */
int arr_orient2d(const arr_points *P, int64_t p, int64_t q, int64_t r, int axis);

/* Sign of p[axis] - q[axis]. */
int arr_cmp(const arr_points *P, int64_t p, int64_t q, int axis);

/* 1 when p and q are the same position (exactly), else 0. */
int arr_same(const arr_points *P, int64_t p, int64_t q);

/* The coordinates of p rounded to doubles (within 2 ulps of the exact value). */
void arr_coords(const arr_points *P, int64_t p, double out[3]);

#endif
