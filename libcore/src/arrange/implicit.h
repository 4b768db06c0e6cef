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
 * integer multiple of 2^-ARR_GRID_LOG2 with magnitude at most ARR_COORD_MAX (arr_on_grid).
 * Then every monomial of the predicates below (degree <= 20) is a multiple of 2^-1000 and
 * below 2^130 in magnitude, so double expansions represent every intermediate value
 * exactly (no underflow, no overflow).  The caller snaps its coordinates to that grid.
 * The degrees, with dX = the degree of a point's X (1 explicit, 4 LPI, 7 TPI, 3 SSI and
 * LIFT) and dW = dX - 1 that of its W:
 *
 *   arr_orient3d(a, b, c, q)     2 + dX(q)                   at most  9 (q a TPI)
 *   arr_orient2d(p, q, r)        dX(p) + dX(q) + dX(r) - 1   at most 20 (three TPIs)
 *   arr_cmp, arr_same            dX(p) + dW(q)               at most 13 (two TPIs)
 *
 * Every predicate first evaluates the polynomial in floating point with a rigorous error
 * bound (a filter) and only when the bound cannot certify the sign evaluates it exactly
 * with expansion arithmetic (common/expansion.h).  Pure functions of their arguments: no
 * state is kept, safe to call from several threads on one const table.  No allocation:
 * the exact stage works in fixed stack buffers sized for the worst case the grid allows,
 * up to about 110 KB of stack for arr_orient2d of three TPIs (the filter needs none).
 *
 * Inputs off the grid (or not finite) break the precondition: arr_point_prepare refuses
 * such a point (returns 0), and a predicate whose exact stage finds an explicit vertex off
 * the grid returns the sign of its rounded value instead (never a crash, but no promise).
 */
#ifndef MFG_ARRANGE_IMPLICIT_H
#define MFG_ARRANGE_IMPLICIT_H

#include <stdint.h>

#define ARR_GRID_LOG2 50
#define ARR_COORD_MAX 16.0

/* 1 when x is on the grid: finite, |x| <= ARR_COORD_MAX, an integer multiple of
 * 2^-ARR_GRID_LOG2 (the scaling by a power of two is exact). */
static inline int arr_on_grid(double x)
{
    if (!(x >= -ARR_COORD_MAX && x <= ARR_COORD_MAX))
        return 0;
    double s = x * 0x1p50; /* 2^ARR_GRID_LOG2 */
    return s == (double)(int64_t)s;
}

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
    uint8_t xok;        /* x holds the rounded coordinates (arr_coords; 0 from arr_point_prepare) */
    int64_t v[9];
    double lift[2];     /* ARR_LIFT only */
    /* Filter data, filled by arr_point_prepare: the homogeneous coordinates (X0, X1, X2,
     * W) rounded, and for each an absolute bound on its error. */
    double h[4];
    double herr[4];
    /* arr_coords' answer, kept: a point near a degenerate construction needs the exact
     * quotient, and the clusters, triangulations and windings ask for it again and again
     * (a 10k torus at 90 degrees spent 40 % of its arrangement recomputing them) */
    double x[3];
} arr_point;

/* The last exact coordinates computed, by point id (implicit_exact.c). */
typedef struct arr_exact_cache arr_exact_cache;

/* The points of one arrangement: the explicit coordinates and the points (explicit
 * vertices may appear as ARR_EXPLICIT points; the predicates take point indices). */
typedef struct arr_points {
    const double *xyz;  /* 3 per explicit vertex, on the grid (see above) */
    int64_t nxyz;
    arr_point *pts;
    int64_t npts;
    arr_exact_cache *xc; /* NULL: none */
} arr_points;

/* Fills p->h and p->herr from the construction (call once after setting kind, axis, v,
 * lift).  Returns 1, or 0 when the denominator W is exactly zero (no such point), when
 * kind or axis is out of range, or when a coordinate or lift is off the grid.  On return
 * 1 the sign of h[3] is the sign of W (decided exactly when the rounded value could not
 * tell), so |h[3]| > herr[3]. */
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

/* The coordinates of p rounded to doubles (within 2 ulps of the exact value; in fact
 * within 1 ulp when the filter cannot certify 2). */
void arr_coords(const arr_points *P, int64_t p, double out[3]);

/* ---- Lower level: the two stages separately (tests, and callers that batch) --------
 * A *_filter function returns the sign when the floating-point bound certifies it and 0
 * when it cannot tell (it never certifies a zero).  A *_exact function evaluates the
 * polynomial with expansions, with no filter and no shortcut (the public predicates above
 * also answer 0 at once for a point that lies on a plane or line by construction, e.g. an
 * LPI point against its own triangle), and returns ARR_NOT_EXACT when an input is off
 * the grid.  The public predicate is the shortcut, then the filter, then the exact
 * stage. */
#define ARR_NOT_EXACT 2

int arr_orient3d_filter(const arr_points *P, int64_t a, int64_t b, int64_t c, int64_t q);
int arr_orient3d_exact(const arr_points *P, int64_t a, int64_t b, int64_t c, int64_t q);
int arr_orient2d_filter(const arr_points *P, int64_t p, int64_t q, int64_t r, int axis);
int arr_orient2d_exact(const arr_points *P, int64_t p, int64_t q, int64_t r, int axis);
int arr_cmp_filter(const arr_points *P, int64_t p, int64_t q, int axis);
int arr_cmp_exact(const arr_points *P, int64_t p, int64_t q, int axis);
/* 1 same, 0 different, ARR_NOT_EXACT off the grid. */
int arr_same_exact(const arr_points *P, int64_t p, int64_t q);
/* The coordinates of p within one ulp, from its exact homogeneous coordinates (X / W
 * rounded, then one Newton step on the exact residual).  Returns 1, or 0 when an input
 * is off the grid or W is zero (out is then untouched). */
int arr_coords_exact(const arr_points *P, int64_t p, double out[3]);

/* Capacity in doubles of an expansion holding a value of degree d in the explicit
 * coordinates: its components are multiples of 2^(-50 d) below 2^(6 d + 10), and those of
 * a non-overlapping expansion occupy distinct bit positions (see implicit_exact.c). */
#define ARR_EXP_CAP(d) (56 * (d) + 24)

/* The exact homogeneous coordinates X0, X1, X2, W of a point: c[k][0 .. n[k]-1] is an
 * expansion (non-overlapping, increasing magnitude, compressed) of the value.  About
 * 13 KB: mind the stack when keeping several. */
typedef struct arr_exact {
    int n[4];
    double c[4][ARR_EXP_CAP(7)];
} arr_exact;

/* A cache of exact coordinates for the predicates' exact stage: the segments of one
 * cluster are compared pairwise, so the same few implicit points are expanded again and
 * again (a star prism's second rounding pass spent over 60 % of its time there).  The
 * predicates use it through arr_points.xc; its slots take memory only once used (a few
 * MB).  arr_exact_cache_drop forgets the points from id on (arr_truncate: the ids are
 * given again). */
arr_exact_cache *arr_exact_cache_new(void);
void arr_exact_cache_free(arr_exact_cache *xc);
void arr_exact_cache_drop(arr_exact_cache *xc, int64_t id);

/* 1 when p's kind and axis are valid and every coordinate (and lift) its construction
 * reads is on the grid: the precondition of exactness. */
int arr_point_valid(const double *xyz, const arr_point *p);

/* Fills *out with the exact homogeneous coordinates of p's construction (p->h and herr
 * are not used, p need not be prepared).  Returns 1, or 0 when kind or axis is out of
 * range or an input is off the grid.  W may be zero (an invalid construction). */
int arr_point_exact(const double *xyz, const arr_point *p, arr_exact *out);

#endif
