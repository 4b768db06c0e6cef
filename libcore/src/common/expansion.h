/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* expansion.h - exact floating-point expansion arithmetic (after Shewchuk, "Adaptive
 * Precision Floating-Point Arithmetic and Fast Robust Geometric Predicates", 1997), the
 * one copy shared by the exact predicates of common/ and arrange/.  Written for mfgeom.
 *
 * An expansion is an array of doubles whose exact sum is the value it stands for; the
 * components are non-overlapping (no two share a bit position) and ordered by increasing
 * magnitude, so its sign is the sign of its last (largest) component.  Every routine
 * here removes zero components and returns a length >= 1 (the value zero is the
 * one-component expansion {0}).
 *
 * The routines are exact as long as no product's rounding error falls below the
 * smallest subnormal 2^-1074 and nothing overflows: the callers guarantee it by bounding
 * their inputs (predicates.h: mfg_coord_ok ranges; arrange/implicit.h: the 2^-50 grid).
 * They rely on IEEE round-to-nearest-even double arithmetic without excess precision or
 * contraction (the build passes -ffp-contract=off): that keeps the "strongly
 * non-overlapping" property which expn_sum needs from every routine's output. */
#ifndef MFG_EXPANSION_H
#define MFG_EXPANSION_H

#include <math.h>

/* a + b = *x + *y exactly (Knuth's TwoSum): *x the rounded sum, *y its rounding error. */
static inline void expn_two_sum(double a, double b, double *x, double *y)
{
    double s = a + b;
    double bv = s - a;
    double av = s - bv;
    *x = s;
    *y = (a - av) + (b - bv);
}

/* a * b = *x + *y exactly: the fma returns the rounding error of the product. */
static inline void expn_two_product(double a, double b, double *x, double *y)
{
    double p = a * b;
    *x = p;
    *y = fma(a, b, -p);
}

/* h = a - b exactly, as an expansion of 1 or 2 components; returns the length. */
static inline int expn_diff(double a, double b, double *h)
{
    double x, y;
    expn_two_sum(a, -b, &x, &y);
    if (y == 0.0) {
        h[0] = x;
        return 1;
    }
    h[0] = y;
    h[1] = x;
    return 2;
}

/* h = a * b exactly, as an expansion of 1 or 2 components; returns the length. */
static inline int expn_product(double a, double b, double *h)
{
    double x, y;
    expn_two_product(a, b, &x, &y);
    if (y == 0.0) {
        h[0] = x;
        return 1;
    }
    h[0] = y;
    h[1] = x;
    return 2;
}

/* h = e + b; h needs elen + 1 slots and may not alias e (Shewchuk's GROW-EXPANSION). */
int expn_grow(int elen, const double *e, double b, double *h);

/* h = e + f in one merge pass (Shewchuk's FAST-EXPANSION-SUM); h needs elen + flen
 * slots (at least 1) and may not alias e or f.  elen or flen may be 0. */
int expn_sum(int elen, const double *e, int flen, const double *f, double *h);

/* h = e - f, as expn_sum with f negated on the fly; same slots and aliasing rules. */
int expn_diff_expansions(int elen, const double *e, int flen, const double *f, double *h);

/* h = e * b (Shewchuk's SCALE-EXPANSION); h needs 2 * elen slots, may not alias e. */
int expn_scale(int elen, const double *e, double b, double *h);

/* h = e * f: the longer one scaled by each component of the shorter, the partial
 * products summed as they come.  h, s1 and s2 each need 2 * elen * flen slots, or fewer
 * when the caller knows a smaller bound on the length of every partial sum (as arrange/
 * does from the bit span of its values); none may alias e or f. */
int expn_mul(int elen, const double *e, int flen, const double *f, double *h, double *s1,
             double *s2);

/* Rewrites e in place as an equal expansion with, usually, far fewer components, whose
 * largest component approximates the value to within one ulp (Shewchuk's COMPRESS). */
int expn_compress(int elen, double *e);

/* Sign (-1, 0, +1) of the value of e. */
static inline int expn_sign(int elen, const double *e)
{
    for (int i = elen - 1; i >= 0; i--)
        if (e[i] != 0.0)
            return e[i] > 0.0 ? 1 : -1;
    return 0;
}

/* e = -e in place. */
static inline void expn_negate(int elen, double *e)
{
    for (int i = 0; i < elen; i++)
        e[i] = -e[i];
}

#endif
