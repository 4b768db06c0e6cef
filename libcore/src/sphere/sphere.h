/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* sphere.h - helpers for the spherical algorithms (only for constructing output;
 * decisions go through predicates.h): bearings, the scrambled visiting order and the
 * smallest enclosing cap.  The one place for each helper that visibility.c and the
 * maxisect_*.c files share; plain 3-vector arithmetic is in common/vec3.h. */
#ifndef MFG_SPHERE_H
#define MFG_SPHERE_H

#include <math.h>
#include <stdint.h>

#include "common/vec3.h"

/* Bearing of y about the axis c, measured counter-clockwise (seen from outside, looking
 * at c) from the half meridian through v, in [0, 2 pi).  c need not be unit. */
static inline double mfg_bearing3(const double c[3], const double v[3], const double y[3])
{
    double p[3], q[3], x[3];
    mfg_cross3(c, v, p);
    mfg_cross3(c, y, q);
    mfg_cross3(p, q, x);
    double t = atan2(mfg_dot3(x, c), mfg_dot3(p, q));
    return t < 0.0 ? t + 2 * MFG_PI : t;
}

/* A fixed stride coprime to m (m >= 1) visits every index of 0..m-1 exactly once, in a
 * scrambled order (i -> i + stride mod m): incremental hulls and Welzl's algorithm then
 * see extreme points early, as with a random permutation, with no memory.  The stride
 * starts near m / golden ratio and moves to the next odd number until gcd(stride, m) = 1
 * (a stride sharing a factor with m would visit only m / gcd of the indices). */
static inline int64_t mfg_scramble_stride(int64_t m)
{
    if (m <= 2)
        return 1;
    int64_t s = (int64_t)((double)m * 0.6180339887498949) | 1;
    for (;;) {
        int64_t x = s, y = m;
        while (y) {
            int64_t r = x % y;
            x = y;
            y = r;
        }
        if (x == 1)
            return s;
        s += 2;
        if (s >= m)
            return 1;
    }
}

/* Smallest cap containing the k >= 1 unit vectors pts (Welzl's algorithm on the sphere,
 * incremental form): centre c and cos(angular radius).  Meaningful for points inside
 * an open hemisphere.  The points are visited in the scrambled order of
 * mfg_scramble_stride, so points listed along a boundary still take linear time.  Each membership test has a slack of
 * MFG_CAP_SLACK in the cosine, so a few vectors may lie that much outside: callers that
 * need every point inside widen the radius by the largest mfg_angle3 afterwards. */
#define MFG_CAP_SLACK 1e-14
void mfg_enclosing_cap(const double *pts, int64_t k, double c[3], double *cosr);

#endif
